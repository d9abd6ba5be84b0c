//! Writing generated files into a directory and checking a directory against
//! them, byte for byte: what `Builder::write` and `tessgen generate [--check]`
//! do, usable from build scripts and CI jobs without the CLI.

use crate::error::BuildError;
use std::collections::BTreeSet;
use std::io::ErrorKind;
use std::path::{Path, PathBuf};

/// One emitted file, path relative to the output directory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GeneratedFile {
    pub path: String,
    pub contents: Vec<u8>,
}

/// One way a directory differs from the generated files. Paths are relative,
/// `/`-separated, as in [`GeneratedFile::path`].
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Mismatch {
    /// Present with other contents.
    Differs(String),
    /// Generated but not present.
    Missing(String),
    /// Present but not generated.
    Extra(String),
}

impl Mismatch {
    pub fn path(&self) -> &str {
        match self {
            Mismatch::Differs(p) | Mismatch::Missing(p) | Mismatch::Extra(p) => p,
        }
    }
}

impl Mismatch {
    /// What is wrong, in a word or two.
    pub fn kind(&self) -> &'static str {
        match self {
            Mismatch::Differs(_) => "differs",
            Mismatch::Missing(_) => "missing",
            Mismatch::Extra(_) => "not generated",
        }
    }
}

fn io_error(path: &Path, source: std::io::Error) -> BuildError {
    BuildError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Compare `dir` with `files`: every generated file must exist with the same
/// bytes, and every file under `dir` must be generated unless its relative
/// path is listed in `ignore`. Sorted by path. A missing `dir` makes every
/// file missing.
pub fn check(
    dir: &Path,
    files: &[GeneratedFile],
    ignore: &[&str],
) -> Result<Vec<Mismatch>, BuildError> {
    let mut out = Vec::new();
    for f in files {
        let path = dir.join(&f.path);
        match std::fs::read(&path) {
            Ok(bytes) if bytes == f.contents => {}
            Ok(_) => out.push(Mismatch::Differs(f.path.clone())),
            Err(e) if e.kind() == ErrorKind::NotFound => {
                out.push(Mismatch::Missing(f.path.clone()))
            }
            Err(e) => return Err(io_error(&path, e)),
        }
    }
    out.extend(
        extra_files(dir, files, ignore)?
            .into_iter()
            .map(Mismatch::Extra),
    );
    out.sort_by(|a, b| a.path().cmp(b.path()));
    Ok(out)
}

/// Files under `dir` (recursively) that are neither generated nor ignored.
pub fn extra_files(
    dir: &Path,
    files: &[GeneratedFile],
    ignore: &[&str],
) -> Result<Vec<String>, BuildError> {
    let known: BTreeSet<&str> = files
        .iter()
        .map(|f| f.path.as_str())
        .chain(ignore.iter().copied())
        .collect();
    let mut found = Vec::new();
    if dir.exists() {
        walk(dir, "", &mut found)?;
    }
    found.retain(|p| !known.contains(p.as_str()));
    found.sort();
    Ok(found)
}

/// Every non-directory entry under `dir`, as `prefix`-relative `/`-separated paths.
fn walk(dir: &Path, prefix: &str, out: &mut Vec<String>) -> Result<(), BuildError> {
    let entries = std::fs::read_dir(dir).map_err(|e| io_error(dir, e))?;
    for entry in entries {
        let entry = entry.map_err(|e| io_error(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let rel = if prefix.is_empty() {
            name
        } else {
            format!("{prefix}/{name}")
        };
        let kind = entry.file_type().map_err(|e| io_error(&entry.path(), e))?;
        if kind.is_dir() {
            walk(&entry.path(), &rel, out)?;
        } else {
            out.push(rel);
        }
    }
    Ok(())
}

/// Write `files` under `dir`, creating directories; files whose contents are
/// already right are left untouched (so their mtimes do not change).
/// Returns the relative paths actually written.
pub fn write(dir: &Path, files: &[GeneratedFile]) -> Result<Vec<String>, BuildError> {
    let mut written = Vec::new();
    for f in files {
        let path: PathBuf = dir.join(&f.path);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| io_error(parent, e))?;
        }
        if std::fs::read(&path).ok().as_deref() != Some(&f.contents[..]) {
            std::fs::write(&path, &f.contents).map_err(|e| io_error(&path, e))?;
            written.push(f.path.clone());
        }
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(path: &str, contents: &str) -> GeneratedFile {
        GeneratedFile {
            path: path.into(),
            contents: contents.as_bytes().to_vec(),
        }
    }

    #[test]
    fn write_then_check() {
        let dir = std::env::temp_dir().join(format!("tessgen-outdir-unit-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let files = vec![file("a/x.txt", "x"), file("y.txt", "y")];
        assert!(check(&dir, &files, &[]).unwrap().len() == 2);
        assert_eq!(write(&dir, &files).unwrap(), vec!["a/x.txt", "y.txt"]);
        assert!(
            write(&dir, &files).unwrap().is_empty(),
            "unchanged files are not rewritten"
        );
        assert_eq!(check(&dir, &files, &[]).unwrap(), vec![]);
        std::fs::write(dir.join("README.md"), "hand-written").unwrap();
        std::fs::write(dir.join("a/stale.txt"), "old").unwrap();
        std::fs::write(dir.join("y.txt"), "z").unwrap();
        std::fs::remove_file(dir.join("a/x.txt")).unwrap();
        assert_eq!(
            check(&dir, &files, &["README.md"]).unwrap(),
            vec![
                Mismatch::Extra("a/stale.txt".into()),
                Mismatch::Missing("a/x.txt".into()),
                Mismatch::Differs("y.txt".into()),
            ]
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
