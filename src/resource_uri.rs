//! `file:` URIs (the FMU's `fmuResourceLocation`, a parameter file given as a URI) to paths
//! of the system the FMU runs on.
//!
//! Accepted (RFC 8089 and the spellings importers really pass):
//! - `file:///p`, `file:/p`, `file://localhost/p`: a local absolute path;
//! - a drive letter, `file:///C:/p`, `file:/C:/p`, `file://localhost/C:/p`, or the old
//!   `file:///C|/p`: on Windows `C:\p`; on POSIX systems there are no drives, so no path;
//! - a host, `file://server/share/p` (and the 4-slash `file:////server/share/p`): on Windows
//!   the UNC path `\\server\share\p`; on POSIX systems no path;
//! - percent escapes (`%20`) anywhere in the path, decoded as UTF-8.

use std::path::PathBuf;

/// Which system's path rules apply.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PathStyle {
    Posix,
    Windows,
}

impl PathStyle {
    /// The system this library was built for.
    const HOST: PathStyle = if cfg!(windows) {
        PathStyle::Windows
    } else {
        PathStyle::Posix
    };
}

/// The path a `file:` URI names on this system, or `None` if it is not a `file:` URI or
/// names nothing here (see the module's list).
pub(crate) fn file_uri_to_path(uri: &str) -> Option<PathBuf> {
    file_uri_to_path_string(uri, PathStyle::HOST).map(PathBuf::from)
}

/// [`file_uri_to_path`] under the rules of `style`, as text.
fn file_uri_to_path_string(uri: &str, style: PathStyle) -> Option<String> {
    let scheme = uri.get(..5)?;
    if !scheme.eq_ignore_ascii_case("file:") {
        return None;
    }
    let rest = &uri[5..];
    // Query and fragment are not part of a path.
    let rest = &rest[..rest.find(['?', '#']).unwrap_or(rest.len())];
    let (host, path) = match rest.strip_prefix("//") {
        Some(after) => {
            let slash = after.find('/').unwrap_or(after.len());
            after.split_at(slash)
        }
        None => ("", rest),
    };
    let host = if host.eq_ignore_ascii_case("localhost") {
        ""
    } else {
        host
    };
    let path = percent_decode(path)?;
    if !host.is_empty() {
        return unc(&percent_decode(host)?, &path, style);
    }
    // `file:////server/share/p`: an empty authority followed by a UNC path.
    if let Some(unc_rest) = path.strip_prefix("//") {
        let (server, share_path) = unc_rest.split_at(unc_rest.find('/')?);
        return unc(server, share_path, style);
    }
    if !path.starts_with('/') {
        return None;
    }
    match (drive(&path), style) {
        (Some((letter, tail)), PathStyle::Windows) => {
            Some(format!("{letter}:{}", tail.replace('/', "\\")))
        }
        (Some(_), PathStyle::Posix) => None,
        (None, PathStyle::Windows) => Some(path.replace('/', "\\")),
        (None, PathStyle::Posix) => Some(path),
    }
}

/// `\\server\share\...` on Windows; elsewhere a remote host names nothing.
fn unc(server: &str, path: &str, style: PathStyle) -> Option<String> {
    match style {
        PathStyle::Windows if !server.is_empty() && path.len() > 1 => {
            Some(format!("\\\\{server}{}", path.replace('/', "\\")))
        }
        _ => None,
    }
}

/// A leading `/C:` or `/C|` (followed by `/` or the end): the drive letter and the rest.
fn drive(path: &str) -> Option<(char, &str)> {
    let bytes = path.as_bytes();
    let is_drive = bytes.len() >= 3
        && bytes[1].is_ascii_alphabetic()
        && matches!(bytes[2], b':' | b'|')
        && (bytes.len() == 3 || bytes[3] == b'/');
    if !is_drive {
        return None;
    }
    let tail = &path[3..];
    Some((
        char::from(bytes[1]).to_ascii_uppercase(),
        if tail.is_empty() { "/" } else { tail },
    ))
}

fn percent_decode(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = text.get(i + 1..i + 3)?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::PathStyle::{Posix, Windows};
    use super::*;

    fn both(uri: &str) -> (Option<String>, Option<String>) {
        (
            file_uri_to_path_string(uri, Posix),
            file_uri_to_path_string(uri, Windows),
        )
    }

    fn some(posix: &str, windows: &str) -> (Option<String>, Option<String>) {
        (Some(posix.into()), Some(windows.into()))
    }

    #[test]
    fn local_absolute_paths_in_all_common_spellings() {
        let expect = some("/tmp/my fmu/resources", "\\tmp\\my fmu\\resources");
        for uri in [
            "file:///tmp/my%20fmu/resources",
            "file:/tmp/my%20fmu/resources",
            "file://localhost/tmp/my%20fmu/resources",
            "FILE://LocalHost/tmp/my%20fmu/resources",
            "file:///tmp/my%20fmu/resources?x=1#frag",
        ] {
            assert_eq!(both(uri), expect, "{uri}");
        }
    }

    #[test]
    fn drive_letters_become_windows_paths_and_nothing_on_posix() {
        for uri in [
            "file:///C:/my%20fmu/resources",
            "file:/C:/my%20fmu/resources",
            "file://localhost/C:/my%20fmu/resources",
            "file:///c|/my%20fmu/resources",
        ] {
            assert_eq!(
                both(uri),
                (None, Some("C:\\my fmu\\resources".into())),
                "{uri}"
            );
        }
        assert_eq!(both("file:///D:/"), (None, Some("D:\\".into())));
        assert_eq!(both("file:///D:"), (None, Some("D:\\".into())));
        // A directory named like a drive further down is just a name.
        assert_eq!(
            both("file:///data/C:/x"),
            some("/data/C:/x", "\\data\\C:\\x")
        );
        // Not a drive: two letters.
        assert_eq!(both("file:///CD:/x"), some("/CD:/x", "\\CD:\\x"));
    }

    #[test]
    fn hosts_become_unc_paths_on_windows_only() {
        let expect = (None, Some("\\\\server\\share\\my fmu\\resources".into()));
        assert_eq!(both("file://server/share/my%20fmu/resources"), expect);
        assert_eq!(both("file:////server/share/my%20fmu/resources"), expect);
        assert_eq!(both("file://server"), (None, None));
        assert_eq!(both("file://server/"), (None, None));
    }

    #[test]
    fn what_is_not_a_file_uri_gives_no_path() {
        for uri in [
            "/tmp/plain",
            "C:\\plain",
            "http://host/x",
            "file:relative/x",
            "file:///bad%zz",
            "file:///bad%",
            "file:///bad%ff%fe", // not UTF-8
            "fil",
            "",
        ] {
            assert_eq!(both(uri), (None, None), "{uri:?}");
        }
    }

    #[test]
    fn percent_escapes_decode_as_utf8() {
        assert_eq!(
            both("file:///tmp/Reifen%C3%BC%25/r"),
            some("/tmp/Reifenü%/r", "\\tmp\\Reifenü%\\r")
        );
    }
}
