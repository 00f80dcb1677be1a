//! Helpers shared by the tests of this folder: scratch directories and files under cargo's
//! temporary directory for integration tests, the fixtures under `tests/data`, and the
//! command line.
// Each test binary uses some of them.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh, empty directory `dir` (a relative path) under the tests' temporary directory.
pub fn scratch(dir: &str) -> PathBuf {
    let path = absent(dir);
    std::fs::create_dir_all(&path).unwrap();
    path
}

/// The path `dir` (relative) under the tests' temporary directory, with nothing there.
pub fn absent(dir: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(dir);
    let _ = std::fs::remove_dir_all(&path);
    path
}

/// The file `name` in the directory `dir` under the tests' temporary directory (created if
/// missing; other files in it stay), holding `contents`.
pub fn write(dir: &str, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, contents).unwrap();
    path
}

/// The fixture at `path` under `tests/data`.
pub fn fixture(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(path)
}

/// The `tire-gap` binary run with `args`, to its end.
pub fn tire_gap<S: AsRef<OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tire-gap"))
        .args(args)
        .output()
        .unwrap()
}

/// The entries of `dir`, sorted.
pub fn files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v
}

/// The names of the entries of `dir`, sorted.
pub fn listing(dir: &Path) -> Vec<String> {
    files(dir)
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect()
}
