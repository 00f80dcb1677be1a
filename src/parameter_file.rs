//! `parameterFile`: locating it (a `file:` URI, an absolute path, or a name relative to the
//! resources folder or else to the working directory), reading it, parsing its parameters.
//!
//! Only regular files of at most [`MAX_BYTES`] are read. A FIFO would block the simulation
//! until a writer appears and a device such as `/dev/zero` never ends, so the path is checked
//! before it is opened, the opened file is checked again (the path may have changed in
//! between), and the read is bounded even if the file grows.

use std::fs::{File, Metadata};
use std::io::Read;
use std::path::{Path, PathBuf};

use mf87::Params;

use crate::resource_uri::file_uri_to_path;

/// Largest parameter file read \[bytes\] (1 MiB; a parameter set is a few kB).
pub const MAX_BYTES: u64 = 1 << 20;

/// The file `parameterFile = file` names and its parameters, or an error message naming the
/// file.
pub(crate) fn load(file: &str, resources: Option<&Path>) -> Result<(PathBuf, Params), String> {
    let path = locate(file, resources);
    let text =
        read(&path).map_err(|why| format!("parameterFile {file:?} ({}): {why}", path.display()))?;
    let params =
        Params::from_json(&text).map_err(|e| format!("parameterFile {}: {e}", path.display()))?;
    Ok((path, params))
}

/// A `file:` URI, an absolute path, or a name relative to `resources` (if it exists there)
/// or else to the working directory.
fn locate(file: &str, resources: Option<&Path>) -> PathBuf {
    if let Some(path) = file_uri_to_path(file) {
        return path;
    }
    let path = Path::new(file);
    if path.is_relative()
        && let Some(in_resources) = resources.map(|r| r.join(path))
        && in_resources.exists()
    {
        return in_resources;
    }
    path.to_path_buf()
}

/// The text of the regular file at `path`, or why it cannot be used.
fn read(path: &Path) -> Result<String, String> {
    // Before opening: opening a FIFO for reading blocks until a writer appears.
    let before = std::fs::metadata(path).map_err(|e| format!("cannot read it: {e}"))?;
    check(&before)?;
    let file = open(path).map_err(|e| format!("cannot open it: {e}"))?;
    let opened = file
        .metadata()
        .map_err(|e| format!("cannot read it: {e}"))?;
    check(&opened)?;
    let mut bytes = Vec::new();
    file.take(MAX_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read it: {e}"))?;
    if bytes.len() as u64 > MAX_BYTES {
        return Err(format!(
            "it grew beyond {MAX_BYTES} bytes while being read (the limit for a parameter file)"
        ));
    }
    String::from_utf8(bytes).map_err(|e| format!("it is not UTF-8 text: {e}"))
}

/// A regular file of at most [`MAX_BYTES`].
fn check(meta: &Metadata) -> Result<(), String> {
    if !meta.is_file() {
        return Err(format!(
            "it is {}, not a regular file",
            kind(meta.file_type())
        ));
    }
    if meta.len() > MAX_BYTES {
        return Err(format!(
            "it has {} bytes; a parameter file may have at most {MAX_BYTES} bytes",
            meta.len()
        ));
    }
    Ok(())
}

/// Opens for reading without blocking on a FIFO (it is then refused by [`check`]).
#[cfg(unix)]
fn open(path: &Path) -> std::io::Result<File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
}

#[cfg(not(unix))]
fn open(path: &Path) -> std::io::Result<File> {
    File::open(path)
}

fn kind(t: std::fs::FileType) -> &'static str {
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "a special file"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_files_are_read_and_others_refused() {
        let dir = std::env::temp_dir().join(format!("p87 read {}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("small.json");
        std::fs::write(&file, "{}").unwrap();
        assert_eq!(read(&file).unwrap(), "{}");
        let err = read(&dir).unwrap_err();
        assert!(err.contains("a directory, not a regular file"), "{err}");
        let err = read(&dir.join("missing.json")).unwrap_err();
        assert!(err.starts_with("cannot read it"), "{err}");
        std::fs::write(&file, [0xff, 0xfe]).unwrap();
        assert!(read(&file).unwrap_err().contains("not UTF-8"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
