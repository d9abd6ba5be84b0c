//! Compile-fail tests: scheme mistakes become compile errors at the
//! offending token. Regenerate the expected output with
//! `TRYBUILD=overwrite cargo test -p tessgen-macros --test ui`.

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
