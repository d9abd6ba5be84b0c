//! Replays every checked-in fuzz input (`fuzz/corpus/<target>/`: seeds and
//! the minimised AFL corpus; `fuzz/regressions/<target>/`: each crash or
//! hang a fuzzing run found, after its fix) through its target, so `cargo
//! test` keeps what fuzzing established. A panic fails the test naming the
//! file.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

type Target = fn(&[u8]) -> bool;

const TARGETS: [(&str, Target); 4] = [
    ("obj", tessgen_fuzz::obj),
    ("mesh", tessgen_fuzz::mesh),
    ("tags", tessgen_fuzz::tags),
    ("scheme", tessgen_fuzz::scheme),
];

/// Inputs replayed, per target the inputs that went all the way through,
/// and the failures.
fn replay(dir: &str) -> (usize, Vec<(&'static str, usize)>, Vec<String>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    let mut count = 0;
    let mut through = Vec::new();
    let mut failures = Vec::new();
    for (name, target) in TARGETS {
        let mut ok = 0;
        let Ok(entries) = std::fs::read_dir(root.join(name)) else {
            continue;
        };
        let mut files: Vec<_> = entries.flatten().map(|e| e.path()).collect();
        files.sort();
        for path in files {
            if path
                .file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with('.'))
            {
                continue;
            }
            let Ok(data) = std::fs::read(&path) else {
                failures.push(format!("{}: unreadable", path.display()));
                continue;
            };
            count += 1;
            match catch_unwind(AssertUnwindSafe(|| target(&data))) {
                Ok(true) => ok += 1,
                Ok(false) => {}
                Err(_) => failures.push(format!("{name}: {} panicked", path.display())),
            }
        }
        through.push((name, ok));
    }
    (count, through, failures)
}

#[test]
fn corpus_replays_without_a_panic() {
    let (count, through, failures) = replay("corpus");
    assert!(failures.is_empty(), "{failures:#?}");
    assert!(count >= 30, "only {count} corpus inputs found");
    // The seeds reach the end of every target (the checked-in meshes load,
    // the built-in schemes compile, the seed meshes tessellate), so a
    // change that makes a target refuse everything fails here.
    eprintln!("went all the way through: {through:?}");
    for (name, ok) in through {
        assert!(ok >= 2, "only {ok} {name} inputs went all the way through");
    }
}

#[test]
fn regressions_replay_without_a_panic() {
    let (_, _, failures) = replay("regressions");
    assert!(failures.is_empty(), "{failures:#?}");
}
