//! Writing files, for the command line, synth and the figures alike: the failure type with
//! its kind, whole-or-nothing writes, and the checks of output paths made before any work
//! starts.

use std::io::Write;
use std::path::{Path, PathBuf};

/// What kind of failure a [`Failure`] is; each front end maps it to its own signal (the
/// command line's `main` to an exit code, the Python package to an exception's `kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FailureKind {
    /// Unreadable file, missing column, bad value, bad arguments, data that cannot support a
    /// diagnosis.
    BadInput,
    /// An output could not be made or written (file, directory, stream).
    Output,
    /// The report is made, but an output asked for (parameter file, figures) could not be
    /// written; the report says which and why.
    Incomplete,
    /// The work was stopped on request before it ended.
    Cancelled,
}

/// An error to report, with its kind.
#[derive(Debug)]
pub struct Failure {
    pub kind: FailureKind,
    pub message: String,
}

pub fn bad_input(message: impl Into<String>) -> Failure {
    Failure {
        kind: FailureKind::BadInput,
        message: message.into(),
    }
}

/// An output that could not be made or written.
pub fn output_failure(message: impl Into<String>) -> Failure {
    Failure {
        kind: FailureKind::Output,
        message: message.into(),
    }
}

/// A temporary sibling of `path`, hidden and unique to this process.
fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.partial", std::process::id()))
}

/// Writes `text` to `path` through a temporary sibling renamed into place, so `path` is
/// either written whole or left as it was, and no temporary file is left behind.
pub fn write_whole(path: &Path, text: &[u8]) -> Result<(), Failure> {
    let tmp = temporary(path);
    let written = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .and_then(|mut f| f.write_all(text).and_then(|()| f.sync_all()))
        .and_then(|()| std::fs::rename(&tmp, path));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        output_failure(format!("cannot write {}: {e}", path.display()))
    })
}

/// The directory a new file at `path` would be created in.
fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Whether a file can be created in the existing directory `dir` (tried, then removed).
fn check_writable(dir: &Path, what: &str) -> Result<(), Failure> {
    let probe = temporary(&dir.join("tire-gap-probe"));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map(|_| {
            let _ = std::fs::remove_file(&probe);
        })
        .map_err(|e| output_failure(format!("cannot write {what}: {}: {e}", dir.display())))
}

/// Whether `a` and `b` name the same existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// Checks, before any work, that the parameter file can be written at `path`: a file (not a
/// directory or device) in an existing, writable directory, and none of the `inputs`.
pub fn check_file_target(path: &Path, option: &str, inputs: &[PathBuf]) -> Result<(), Failure> {
    let shown = path.display();
    if let Some(input) = inputs.iter().find(|i| same_file(path, i)) {
        return Err(bad_input(format!(
            "{option} {shown}: that is the input file {}; writing there would overwrite the data",
            input.display()
        )));
    }
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => {
            return Err(bad_input(format!(
                "{option} {shown}: is a directory; give the file to write, e.g. {}",
                path.join("fitted.json").display()
            )));
        }
        Ok(m) if !m.is_file() => {
            return Err(bad_input(format!(
                "{option} {shown}: is not a regular file (a pipe or device)"
            )));
        }
        _ => {}
    }
    let dir = parent_of(path);
    if !dir.is_dir() {
        return Err(output_failure(format!(
            "cannot write {option} {shown}: the directory {} does not exist",
            dir.display()
        )));
    }
    check_writable(dir, &format!("{option} {shown}"))
}

/// Checks, before any work, that figures can be written into `dir`: it is a directory or can
/// be created as one (its nearest existing ancestor is a writable directory), and no input
/// file inside it has a name the figures use.
pub fn check_dir_target(
    dir: &Path,
    option: &str,
    inputs: &[PathBuf],
    is_output_name: impl Fn(&str) -> bool,
) -> Result<(), Failure> {
    let mut existing = dir;
    loop {
        match std::fs::metadata(existing) {
            Ok(m) if m.is_dir() => break,
            Ok(_) => {
                return Err(output_failure(format!(
                    "cannot write {option} {}: {} is not a directory",
                    dir.display(),
                    existing.display()
                )));
            }
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::NotFound | std::io::ErrorKind::NotADirectory
                ) =>
            {
                existing = parent_of(existing);
                if existing == Path::new(".") && !existing.is_dir() {
                    return Err(output_failure(format!(
                        "cannot write {option} {}: no existing parent directory",
                        dir.display()
                    )));
                }
            }
            Err(e) => {
                return Err(output_failure(format!(
                    "cannot write {option} {}: {e}",
                    dir.display()
                )));
            }
        }
    }
    if let Some(input) = inputs.iter().find(|i| {
        parent_of(i) == dir
            && i.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(&is_output_name)
    }) {
        return Err(bad_input(format!(
            "{option} {}: the input file {} would be overwritten by a figure",
            dir.display(),
            input.display()
        )));
    }
    check_writable(existing, &format!("{option} {}", dir.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("tire-gap-output-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn whole_or_nothing_and_no_temporary_left() {
        let dir = scratch("whole");
        let target = dir.join("out.json");
        write_whole(&target, b"{}").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"{}");
        // A directory in the way: refused, nothing left beside it.
        let sub = dir.join("sub");
        std::fs::create_dir(&sub).unwrap();
        assert!(write_whole(&sub, b"x").is_err());
        assert_eq!(listing(&dir), vec!["out.json", "sub"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn file_targets_are_checked() {
        let dir = scratch("targets");
        let input = dir.join("data.csv");
        std::fs::write(&input, "run\n").unwrap();
        let inputs = vec![input.clone()];
        let e = check_file_target(&input, "--params", &inputs).unwrap_err();
        assert_eq!(e.kind, FailureKind::BadInput);
        assert!(e.message.contains("is the input file"), "{}", e.message);
        // The same file by another name.
        let other = dir.join(".").join("data.csv");
        assert!(check_file_target(&other, "--params", &inputs).is_err());
        let e = check_file_target(&dir, "--params", &inputs).unwrap_err();
        assert!(e.message.contains("is a directory"), "{}", e.message);
        let e = check_file_target(&dir.join("no/such/x.json"), "--params", &inputs).unwrap_err();
        assert_eq!(e.kind, FailureKind::Output);
        assert!(check_file_target(&dir.join("fitted.json"), "--params", &inputs).is_ok());
        // The probe leaves nothing behind.
        assert_eq!(listing(&dir), vec!["data.csv"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn directory_targets_are_checked() {
        let dir = scratch("dirs");
        let file = dir.join("f.txt");
        std::fs::write(&file, "x").unwrap();
        let svg = |n: &str| n.ends_with(".svg");
        assert!(check_dir_target(&dir.join("new/deeper"), "--plots", &[], svg).is_ok());
        let e = check_dir_target(&file.join("sub"), "--plots", &[], svg).unwrap_err();
        assert!(e.message.contains("is not a directory"), "{}", e.message);
        let clash = dir.join("regions.svg");
        std::fs::write(&clash, "x").unwrap();
        let e = check_dir_target(&dir, "--plots", &[clash], svg).unwrap_err();
        assert!(e.message.contains("would be overwritten"), "{}", e.message);
        assert!(!dir.join("new").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
