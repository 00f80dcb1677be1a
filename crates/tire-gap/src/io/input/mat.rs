//! Tire Test Consortium run files as MATLAB MAT-files (`.mat`, level 5 as MATLAB 7 and later
//! write them, usually with zlib-compressed variables).
//!
//! A TTC MAT-file holds one numeric column per channel, named as in the ASCII files (`ET`,
//! `V`, `SA`, `FZ`, `AMBTMP`, ...), a struct `channel` whose fields `name` and `units` list the
//! channels and their units (cell arrays of text, or text matrices), and the text variables
//! `tireid`, `testid` and `source`. The columns go through the ASCII reader's channel code
//! (`super::ttc::read_channels`): same channels, units, SAE-to-paper signs and notes.
//!
//! Units come from `channel.units`. A file without them is read with TTC's SI units assumed
//! (`s kph rpm deg deg cm cm kPa N N N Nm Nm none none degC ... none none`), said in a note.
//! The tire is `tireid`; the run id comes from the file name, else from `source`.
//!
//! Arrays are decoded by the `matrw` crate. The file's top-level elements are split and
//! inflated here first (so a corrupt or truncated download is an error that names the byte
//! offset), and each variable is decoded on its own: one that cannot be decoded is named in
//! a note, or in the error when the run needs it. Big-endian files and v7.3 (HDF5) files are
//! refused with a message saying so. Messages give the sample number (row of the channel
//! arrays) where an ASCII file's would give a line.

use std::cell::Cell;
use std::io::Read;
use std::panic::{self, AssertUnwindSafe};
use std::sync::Once;

use matrw::{MatVariable, MatlabType};

use super::mat_layout::MI_MATRIX;
use super::mat_sweeps;
use super::mat_text;
use super::ttc::{self, Columns, Header, SI_UNITS};
use super::{InputError, Loaded};

/// The start of every MAT-file of level 5 (MATLAB 5 to 7.x).
const MAGIC: &[u8] = b"MATLAB 5.0 MAT-file";
/// A MATLAB 7.3 file (HDF5 inside).
const MAGIC_HDF5: &[u8] = b"MATLAB 7.3 MAT-file";
/// Header bytes: 116 of text, 8 of subsystem offset, 2 of version, 2 of endian indicator.
const HEADER: usize = 128;
/// Data type of a zlib-compressed element.
const MI_COMPRESSED: u32 = 15;
/// The most bytes a file's compressed variables may inflate to, together (a TTC run is tens
/// of megabytes).
const MAX_INFLATED: u64 = 2 << 30;

/// A file's variables by name, in file order.
type Variables = Vec<(String, MatVariable)>;

/// Variables that describe the run rather than hold a channel.
const META: [&str; 4] = ["channel", "tireid", "testid", "source"];

/// Whether `bytes` start as a MAT-file of level 5 or 7.3 does.
pub fn looks_like(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC) || bytes.starts_with(MAGIC_HDF5)
}

/// Reads a TTC MAT-file held in memory; `source` names it (its file name gives the run id).
pub fn read_bytes(bytes: &[u8], source: &str) -> Result<Loaded, InputError> {
    read_run(bytes, source).map(|(loaded, _)| loaded)
}

/// Reads a TTC MAT-file held in memory, with the tire its `tireid` names.
pub(crate) fn read_run(bytes: &[u8], source: &str) -> Result<(Loaded, Option<String>), InputError> {
    let err = |m: String| InputError::new(source, m);
    let (mut vars, broken) = variables(bytes).map_err(err)?;
    let listed = listed_channels(&broken, source)?;
    let mut notes = Vec::new();
    if listed.is_none() {
        mat_sweeps::flatten(&mut vars, &mut notes);
    }
    let meta = Meta::read(&vars, &broken, listed.is_some());
    let tire = meta
        .tireid
        .as_deref()
        .and_then(|t| ttc::tire_identity(t, None));
    if let Some(t) = &tire {
        notes.push(format!("tire: {t}"));
    }
    if let Some(test) = &meta.testid {
        notes.push(format!("test: {test} (testid)"));
    }

    let header = match listed {
        Some(h) => h,
        None => channels(&vars, &mut notes).map_err(|m| err(m).in_column("channel"))?,
    };
    if header.names.is_empty() {
        return Err(err(no_channels(&vars, &broken)));
    }
    note_left_out(&vars, &header, &broken, &meta.read_as_text, &mut notes);

    let run = ttc::run_id(source, meta.origin.as_deref().and_then(ttc::run_number));
    let loaded = ttc::read_channels(source, &header, run, notes, |needed| {
        channel_columns(&mut vars, &header, &broken, needed, source)
    })
    .map_err(|mut e| {
        // No lines in a MAT-file: the "line" is the sample.
        if let Some(k) = e.line.take() {
            e.message = format!("sample {k}: {}", e.message);
        }
        e
    })?;
    Ok((loaded, tire))
}

/// Why a MAT-file gives no channel: what it holds instead.
fn no_channels(vars: &[(String, MatVariable)], broken: &[Undecoded]) -> String {
    let kind = |v: &MatVariable| match v {
        MatVariable::NumericArray(_) => "array",
        MatVariable::Structure(_) | MatVariable::StructureArray(_) => "struct",
        MatVariable::CellArray(_) => "cell array",
        _ => "other",
    };
    let held: Vec<String> = vars
        .iter()
        .map(|(n, v)| format!("{n} ({})", kind(v)))
        .collect();
    let undecoded = if broken.is_empty() {
        String::new()
    } else {
        format!(
            "; {} element(s) could not be decoded ({}): MATLAB objects such as a table or \
             timetable, which only MATLAB reads",
            broken.len(),
            list(broken)
        )
    };
    format!(
        "no TTC channel found: the file holds {}{undecoded}. A TTC MAT-file holds one numeric \
         vector per channel (ET, V, SA, IA, FZ, FX, FY, MZ, SR, ...; a number appended, as in \
         ET1, is read too), or structs of such vectors, one per sweep; save a table's columns as \
         variables (save(file, '-struct', ...) of table2struct(t, 'ToScalar', true)) or export \
         it as .csv",
        if held.is_empty() {
            "no variable".to_string()
        } else {
            held.join(", ")
        }
    )
}

/// The undecoded element whose variable is `name` (ignoring case).
fn undecoded<'a>(broken: &'a [Undecoded], name: &str) -> Option<&'a Undecoded> {
    broken.iter().find(|b| {
        b.name
            .as_deref()
            .is_some_and(|n| n.eq_ignore_ascii_case(name))
    })
}

/// The channel names and units of a struct `channel` that `matrw` cannot decode, read by
/// `mat_text` as text lists; `None` when `channel` was decoded or is absent. The units are
/// in the file: none are assumed when they cannot be read.
fn listed_channels(broken: &[Undecoded], source: &str) -> Result<Option<Header>, InputError> {
    let err = |m: String| InputError::new(source, m);
    let Some(b) = undecoded(broken, "channel") else {
        return Ok(None);
    };
    let fields = mat_text::struct_texts(&b.element).map_err(|m| {
        err(format!(
            "{b}; read as text lists: {m}: the channels' names and units are unknown \
             (read the run's .dat file instead)"
        ))
        .in_column("channel")
    })?;
    let field = |f: &str| {
        fields
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(f))
            .map(|(_, v)| v.clone())
    };
    match (field("name"), field("units")) {
        (Some(names), Some(units)) if names.len() == units.len() => Ok(Some(Header {
            names,
            units,
            unit_line: None,
        })),
        (names, units) => Err(err(format!(
            "{b}; read as text lists, channel.name holds {} and channel.units {} \
             entries: the channels' units are unknown (read the run's .dat file instead)",
            names.map_or(0, |n| n.len()),
            units.map_or(0, |u| u.len())
        ))
        .in_column("channel")),
    }
}

/// The text variables describing the run, and which undecoded elements were read as text.
struct Meta {
    tireid: Option<String>,
    testid: Option<String>,
    origin: Option<String>,
    /// Elements `matrw` could not decode but read here as text.
    read_as_text: Vec<&'static str>,
}

impl Meta {
    /// Reads `tireid`, `testid` and `source`, by `matrw` or else as text by `mat_text`;
    /// `channel_listed` says `channel` was read as text lists.
    fn read(vars: &[(String, MatVariable)], broken: &[Undecoded], channel_listed: bool) -> Self {
        let mut read_as_text: Vec<&'static str> = Vec::new();
        if channel_listed {
            read_as_text.push("channel");
        }
        let mut text_of = |name: &'static str| {
            find(vars, name)
                .and_then(|v| texts(v).ok())
                .or_else(|| {
                    let t = mat_text::texts(&undecoded(broken, name)?.element, 0).ok()?;
                    read_as_text.push(name);
                    Some(t)
                })
                .map(|t| t.join(" "))
        };
        let tireid = text_of("tireid");
        let testid = text_of("testid");
        let origin = text_of("source");
        Meta {
            tireid,
            testid,
            origin,
            read_as_text,
        }
    }
}

/// Notes the variables not listed as channels and the elements neither decoded nor read
/// as text.
fn note_left_out(
    vars: &[(String, MatVariable)],
    header: &Header,
    broken: &[Undecoded],
    read_as_text: &[&str],
    notes: &mut Vec<String>,
) {
    let unread: Vec<&str> = vars
        .iter()
        .map(|(n, _)| n.as_str())
        .filter(|n| {
            !META.iter().any(|m| m.eq_ignore_ascii_case(n))
                && !header.names.iter().any(|c| c.eq_ignore_ascii_case(n))
        })
        .collect();
    if !unread.is_empty() {
        notes.push(format!(
            "variables not read (not listed in channel.name): {}",
            unread.join(" ")
        ));
    }
    let left_out: Vec<Undecoded> = broken
        .iter()
        .filter(|b| {
            !b.name
                .as_deref()
                .is_some_and(|n| read_as_text.iter().any(|r| r.eq_ignore_ascii_case(n)))
        })
        .cloned()
        .collect();
    if !left_out.is_empty() {
        notes.push(format!(
            "{} element(s) of the file could not be decoded and were left out: {}",
            left_out.len(),
            list(&left_out)
        ));
    }
}

/// The values of the `needed` channels (indices into `header.names`), each a variable of
/// finite numbers, all of one length; each variable is freed once read.
fn channel_columns(
    vars: &mut [(String, MatVariable)],
    header: &Header,
    broken: &[Undecoded],
    needed: &[usize],
    source: &str,
) -> Result<Columns, InputError> {
    let err = |m: String| InputError::new(source, m);
    let mut values = Vec::with_capacity(needed.len());
    let mut first: Option<(&str, usize)> = None;
    for &i in needed {
        let name = header.names[i].as_str();
        let Some(k) = vars.iter().position(|(n, _)| n.eq_ignore_ascii_case(name)) else {
            let message = match (undecoded(broken, name), broken.is_empty()) {
                (Some(b), _) => format!("{b}"),
                (None, true) => format!(
                    "channel {name} is listed in channel.name but the file has no variable {name}"
                ),
                (None, false) => format!(
                    "channel {name} is listed in channel.name but the file has no variable \
                     {name} (undecoded elements: {})",
                    list(broken)
                ),
            };
            return Err(err(message).in_column(name));
        };
        let column = numbers(&vars[k].1)
            .map_err(|m| err(format!("variable {name}: {m}")).in_column(name))?;
        if let Some(row) = column.iter().position(|v| !v.is_finite()) {
            return Err(err(format!(
                "sample {}: {name} is {}: every sample needs a finite value",
                row + 1,
                column[row]
            ))
            .in_column(name));
        }
        // Free each channel once read: a run is tens of megabytes.
        vars[k].1 = MatVariable::Null;
        match first {
            Some((f, n)) if n != column.len() => {
                return Err(err(format!(
                    "channel {name} has {} samples but {f} has {n}: every channel needs one \
                     value per sample",
                    column.len()
                ))
                .in_column(name));
            }
            None => first = Some((name, column.len())),
            _ => {}
        }
        values.push(column);
    }
    let n = first.map_or(0, |f| f.1);
    Ok(Columns {
        values,
        lines: (1..=n).collect(),
    })
}

/// A top-level element that could not be decoded: its variable name when that can be read.
#[derive(Debug, Clone)]
struct Undecoded {
    name: Option<String>,
    /// Where it is and what is wrong.
    what: String,
    /// The array element's bytes (inflated), when it was one.
    element: Vec<u8>,
}

impl std::fmt::Display for Undecoded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.name {
            Some(n) => write!(f, "variable {n} ({})", self.what),
            None => write!(f, "{}", self.what),
        }
    }
}

fn list(broken: &[Undecoded]) -> String {
    broken
        .iter()
        .map(|b| b.to_string())
        .collect::<Vec<_>>()
        .join("; ")
}

/// The variable name of an array element (tag and data, uncompressed), read from its third
/// sub-element, if it is there and a plain name.
fn element_name(element: &[u8]) -> Option<String> {
    let word = |i: usize| -> Option<u32> {
        Some(u32::from_le_bytes(
            element.get(i..i.checked_add(4)?)?.try_into().ok()?,
        ))
    };
    let mut at = 8;
    let mut data = &element[..0];
    for _ in 0..3 {
        let tag = word(at)?;
        if tag >> 16 != 0 {
            // Small sub-element: size in the upper half of the tag, data in the next 4 bytes.
            data = element.get(at + 4..at + 4 + (tag >> 16) as usize)?;
            at += 8;
        } else {
            let size = word(at + 4)? as usize;
            data = element.get(at + 8..(at + 8).checked_add(size)?)?;
            at += 8 + size.div_ceil(8) * 8;
        }
    }
    let name = std::str::from_utf8(data).ok()?;
    let plain = !name.is_empty()
        && name.len() <= 64
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    plain.then(|| name.to_string())
}

/// The channel names and units: from `channel.name` / `channel.units`, else the numeric
/// variables named as TTC channels with SI units assumed (noted).
fn channels(vars: &[(String, MatVariable)], notes: &mut Vec<String>) -> Result<Header, String> {
    let channel = find(vars, "channel");
    let names = channel.and_then(|c| struct_field(c, "name")).transpose()?;
    let Some(names) = names else {
        return Ok(channels_by_name(vars, channel.is_some(), notes));
    };
    let units = match channel.and_then(|c| struct_field(c, "units")) {
        Some(Ok(units)) if units.len() == names.len() => units,
        Some(Ok(units)) => {
            return Err(format!(
                "channel.name lists {} channels but channel.units {} units",
                names.len(),
                units.len()
            ));
        }
        failed => {
            let why = match failed {
                Some(Err(m)) => format!("channel.units cannot be read ({m})"),
                _ => "the struct channel has no field units".to_string(),
            };
            let mut units = Vec::new();
            for n in &names {
                units.push(assumed_unit(n).ok_or_else(|| {
                    format!("{why}, and {n} is not a TTC channel whose unit could be assumed")
                })?);
            }
            notes.push(format!("{why}: TTC's SI units assumed ({})", si_list()));
            units
        }
    };
    Ok(Header {
        names,
        units,
        unit_line: None,
    })
}

/// The texts of field `f` (ignoring case) of a struct, one per channel; of a struct array,
/// one per element. `None` when `s` is neither or lacks the field.
fn struct_field(s: &MatVariable, f: &str) -> Option<Result<Vec<String>, String>> {
    match s {
        MatVariable::Structure(st) => st
            .value
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(f))
            .map(|(_, v)| texts(v)),
        // A struct array: one channel per element.
        MatVariable::StructureArray(sa) => sa
            .value
            .iter()
            .map(|e| match e {
                MatVariable::Structure(st) => st
                    .value
                    .iter()
                    .find(|(k, _)| k.eq_ignore_ascii_case(f))
                    .map(|(_, v)| texts(v).map(|t| t.join(" "))),
                _ => None,
            })
            .collect::<Option<Result<Vec<String>, String>>>(),
        _ => None,
    }
}

/// The SI unit assumed for a TTC channel (ignoring case).
fn assumed_unit(name: &str) -> Option<String> {
    let channel = ttc::canonical_of(name)?;
    SI_UNITS
        .iter()
        .find(|(n, _)| *n == channel)
        .map(|(_, u)| u.to_string())
}

/// The assumed SI units as `name unit` pairs, for notes.
fn si_list() -> String {
    SI_UNITS
        .iter()
        .map(|(n, u)| format!("{n} {u}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Without a channel list: the numeric vectors named as TTC channels, SI units assumed
/// (noted); `has_channel` says a struct `channel` exists (without field `name`).
fn channels_by_name(
    vars: &[(String, MatVariable)],
    has_channel: bool,
    notes: &mut Vec<String>,
) -> Header {
    let mut header = Header {
        names: Vec::new(),
        units: Vec::new(),
        unit_line: None,
    };
    for (n, v) in vars {
        if let (Some(u), MatVariable::NumericArray(_)) = (assumed_unit(n), v) {
            header.names.push(n.clone());
            header.units.push(u);
        }
    }
    let why = if has_channel {
        "the struct channel has no field name"
    } else {
        "there is no struct channel"
    };
    notes.push(format!(
        "{why}: channels taken from the variables named as TTC channels, in TTC's SI \
         units (assumed: {})",
        si_list()
    ));
    header
}

/// The variable named `name` (ignoring case).
fn find<'a>(vars: &'a [(String, MatVariable)], name: &str) -> Option<&'a MatVariable> {
    vars.iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .map(|(_, v)| v)
}

/// The text a variable holds: one entry for a text row, one per row of a text matrix, one
/// per cell of a cell array of texts. Trailing blanks (MATLAB's padding) are dropped.
fn texts(v: &MatVariable) -> Result<Vec<String>, String> {
    match v {
        MatVariable::NumericArray(a) => {
            let chars = match &a.value {
                MatlabType::UTF8(c) | MatlabType::UTF16(c) => c,
                _ => return Err("numbers where text was expected".to_string()),
            };
            let rows = match a.dim.as_slice() {
                [r, c] if *r > 1 && r * c == chars.len() => *r,
                _ => 1,
            };
            let cols = chars.len() / rows;
            Ok((0..rows)
                .map(|r| {
                    let row: String = (0..cols).map(|c| chars[r + rows * c]).collect();
                    row.trim_end().to_string()
                })
                .collect())
        }
        MatVariable::CellArray(c) => c
            .value
            .iter()
            .map(|cell| texts(cell).map(|t| t.join(" ")))
            .collect(),
        _ => Err("not a text or a cell array of texts".to_string()),
    }
}

/// A numeric vector's values as reals.
fn numbers(v: &MatVariable) -> Result<Vec<f64>, String> {
    let MatVariable::NumericArray(a) = v else {
        return Err("not a numeric array".to_string());
    };
    if a.value_cmp.is_some() {
        return Err("complex numbers".to_string());
    }
    if a.dim.iter().filter(|&&d| d > 1).count() > 1 {
        return Err(format!(
            "a {} array, not one column",
            a.dim
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join("x")
        ));
    }
    fn real<T: Copy + Into<f64>>(v: &[T]) -> Vec<f64> {
        v.iter().map(|&x| x.into()).collect()
    }
    Ok(match &a.value {
        MatlabType::F64(v) => v.clone(),
        MatlabType::F32(v) => real(v),
        MatlabType::I8(v) => real(v),
        MatlabType::U8(v) => real(v),
        MatlabType::I16(v) => real(v),
        MatlabType::U16(v) => real(v),
        MatlabType::I32(v) => real(v),
        MatlabType::U32(v) => real(v),
        // 64-bit integers: exact up to 2^53, as any value a TTC channel holds.
        MatlabType::I64(v) => v.iter().map(|&x| x as f64).collect(),
        MatlabType::U64(v) => v.iter().map(|&x| x as f64).collect(),
        MatlabType::UTF8(_) | MatlabType::UTF16(_) => return Err("text, not numbers".into()),
        MatlabType::BOOL(_) => return Err("true/false values, not numbers".into()),
    })
}

/// The file's variables, in file order, and a description of each element that could not
/// be decoded. Errors: not a MAT-file of level 5, big-endian, truncated or corrupt elements.
fn variables(bytes: &[u8]) -> Result<(Variables, Vec<Undecoded>), String> {
    let end = elements_end(bytes)?;
    let mut vars = Vec::new();
    let mut broken = Vec::new();
    let mut inflated: u64 = 0;
    let mut at = HEADER;
    let word = |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    while at < end {
        if end - at < 8 {
            if bytes[at..end].iter().all(|&b| b == 0) {
                break;
            }
            return Err(format!("the file ends inside an element tag at byte {at}"));
        }
        let (kind, size) = (word(at), word(at + 4) as usize);
        let body = at + 8;
        let stop = body
            .checked_add(size)
            .filter(|&s| s <= end)
            .ok_or_else(|| {
                format!(
                    "the element at byte {at} claims {size} bytes but the file has {} after it: \
                     the file is truncated or corrupt",
                    end - body
                )
            })?;
        let element = match kind {
            MI_COMPRESSED => inflate(&bytes[body..stop], at, &mut inflated)?,
            MI_MATRIX => bytes[at..stop].to_vec(),
            other => {
                broken.push(Undecoded {
                    name: None,
                    what: format!("byte {at}: data type {other}, not an array"),
                    element: Vec::new(),
                });
                Vec::new()
            }
        };
        if !element.is_empty() {
            match decode(&element) {
                Ok(mut v) => vars.append(&mut v),
                Err(m) => broken.push(Undecoded {
                    name: element_name(&element),
                    what: format!("byte {at}: {m}"),
                    element,
                }),
            }
        }
        // Uncompressed elements are padded to 8 bytes; compressed ones are not.
        at = if kind == MI_COMPRESSED {
            stop
        } else {
            stop.div_ceil(8).saturating_mul(8)
        };
    }
    Ok((vars, broken))
}

/// Checks the header (magic text, length, little-endian) and returns where the elements
/// end: at the subsystem data when there is some, else at the end of the file.
fn elements_end(bytes: &[u8]) -> Result<usize, String> {
    if bytes.starts_with(MAGIC_HDF5) {
        return Err(
            "a MATLAB 7.3 MAT-file (HDF5 inside), which tire-gap does not read: save \
                    it with save(..., '-v7') or use the run's .dat file"
                .to_string(),
        );
    }
    if !bytes.starts_with(MAGIC) {
        return Err(format!(
            "not a MATLAB MAT-file: it does not start with \"{}\"",
            String::from_utf8_lossy(MAGIC)
        ));
    }
    if bytes.len() < HEADER {
        return Err(format!(
            "{} bytes: too short for a MAT-file (its header alone is {HEADER})",
            bytes.len()
        ));
    }
    match &bytes[126..128] {
        b"IM" => {}
        b"MI" => {
            return Err(
                "a big-endian MAT-file, which tire-gap does not read: re-save it \
                        on a little-endian machine or use the run's .dat file"
                    .to_string(),
            );
        }
        other => {
            return Err(format!(
                "bytes 126-127 are {other:?}, not the endian indicator \"IM\": not a MAT-file"
            ));
        }
    }
    // Subsystem data (MATLAB objects) follow the variables; zeros or blanks when absent.
    let offset = u64::from_le_bytes(bytes[116..124].try_into().unwrap_or([0; 8]));
    Ok(usize::try_from(offset)
        .ok()
        .filter(|&o| o > HEADER && o < bytes.len())
        .unwrap_or(bytes.len()))
}

/// Inflates the compressed element at byte `at`, adding its size to `inflated`, the total
/// so far, which may not pass [`MAX_INFLATED`].
fn inflate(compressed: &[u8], at: usize, inflated: &mut u64) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    flate2::read::ZlibDecoder::new(compressed)
        .take(MAX_INFLATED - *inflated + 1)
        .read_to_end(&mut out)
        .map_err(|e| format!("the compressed element at byte {at} cannot be inflated: {e}"))?;
    *inflated += out.len() as u64;
    if *inflated > MAX_INFLATED {
        return Err(format!(
            "the compressed variables inflate to more than {} MiB",
            MAX_INFLATED >> 20
        ));
    }
    Ok(out)
}

/// Decodes one element (tag and data, uncompressed) with `matrw`, as a file of its own.
fn decode(element: &[u8]) -> Result<Variables, String> {
    super::mat_layout::check(element).map_err(|m| format!("cannot be decoded ({m})"))?;
    let mut file = Vec::with_capacity(HEADER + element.len() + 8);
    file.extend_from_slice(&format!("{:<116}", "MATLAB 5.0 MAT-file, tire-gap").into_bytes());
    file.extend_from_slice(&[0; 8]);
    file.extend_from_slice(&[0x00, 0x01]);
    file.extend_from_slice(b"IM");
    file.extend_from_slice(element);
    file.resize(file.len().div_ceil(8) * 8, 0);
    match quietly(|| matrw::load_matfile_from_u8(&file)) {
        Some(Ok(m)) => Ok(m.into_iter().collect()),
        Some(Err(e)) => Err(format!(
            "cannot be decoded ({})",
            first_line(&e.to_string())
        )),
        None => Err("cannot be decoded (malformed array)".to_string()),
    }
}

/// The first informative line of a decoder message, without terminal colour codes.
fn first_line(message: &str) -> String {
    let mut plain = String::new();
    let mut chars = message.chars();
    while let Some(c) = chars.next() {
        if c == '\u{1b}' {
            // Skip "ESC [ ... letter".
            for c in chars.by_ref() {
                if c.is_ascii_alphabetic() {
                    break;
                }
            }
        } else {
            plain.push(c);
        }
    }
    plain
        .lines()
        .map(|l| l.trim_matches(|c: char| !c.is_alphanumeric()))
        .find(|l| l.contains("Error:"))
        .or_else(|| plain.lines().map(str::trim).find(|l| !l.is_empty()))
        .unwrap_or("")
        .chars()
        .take(200)
        .collect()
}

thread_local! {
    /// Whether this thread is decoding an array, whose panics are caught and reported.
    static DECODING: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f`, turning a panic into `None`. `matrw` panics on some malformed arrays (bad
/// dimensions, unknown element types): the panic is caught here, and the panic hook stays
/// silent for it (other panics are reported as before).
fn quietly<T>(f: impl FnOnce() -> T) -> Option<T> {
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if !DECODING.with(Cell::get) {
                previous(info);
            }
        }));
    });
    DECODING.with(|d| d.set(true));
    let result = panic::catch_unwind(AssertUnwindSafe(f));
    DECODING.with(|d| d.set(false));
    result.ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_that_are_not_level_5_are_refused() {
        let e = variables(b"MATLAB 7.3 MAT-file, Platform: GLNXA64").unwrap_err();
        assert!(e.contains("HDF5"), "{e}");
        let e = variables(b"ET V FZ\n").unwrap_err();
        assert!(e.contains("not a MATLAB MAT-file"), "{e}");
        let e = variables(b"MATLAB 5.0 MAT-file, short").unwrap_err();
        assert!(e.contains("too short"), "{e}");
        let mut big = format!("{:<116}", "MATLAB 5.0 MAT-file, x").into_bytes();
        big.extend_from_slice(&[0; 8]);
        big.extend_from_slice(&[0x01, 0x00]);
        big.extend_from_slice(b"MI");
        let e = variables(&big).unwrap_err();
        assert!(e.contains("big-endian"), "{e}");
    }

    #[test]
    fn an_empty_file_has_no_variables_and_a_truncated_element_is_an_error() {
        let mut file = format!("{:<116}", "MATLAB 5.0 MAT-file, x").into_bytes();
        file.extend_from_slice(&[0; 8]);
        file.extend_from_slice(&[0x00, 0x01]);
        file.extend_from_slice(b"IM");
        let (vars, broken) = variables(&file).unwrap();
        assert!(vars.is_empty() && broken.is_empty());
        file.extend_from_slice(&[14, 0, 0, 0, 200, 0, 0, 0, 1, 2, 3]);
        let e = variables(&file).unwrap_err();
        assert!(e.contains("byte 128 claims 200 bytes"), "{e}");
    }

    /// An uncompressed double column named `X` whose dimensions say `rows` x 1, holding
    /// `values`.
    fn column_element(rows: u32, values: &[f64]) -> Vec<u8> {
        named_column("X", rows, values)
    }

    /// As [`column_element`], named `name` (up to 8 characters).
    fn named_column(name: &str, rows: u32, values: &[f64]) -> Vec<u8> {
        let mut body = Vec::new();
        // Array flags (miUINT32, 8 bytes): class 6 = double.
        body.extend_from_slice(&[6, 0, 0, 0, 8, 0, 0, 0, 6, 0, 0, 0, 0, 0, 0, 0]);
        // Dimensions (miINT32, 8 bytes).
        body.extend_from_slice(&[5, 0, 0, 0, 8, 0, 0, 0]);
        body.extend_from_slice(&rows.to_le_bytes());
        body.extend_from_slice(&1u32.to_le_bytes());
        // The name (miINT8), padded to 8 bytes.
        body.extend_from_slice(&[1, 0, 0, 0, name.len() as u8, 0, 0, 0]);
        body.extend_from_slice(format!("{name:\0<8}").as_bytes());
        // Real part (miDOUBLE).
        body.extend_from_slice(&9u32.to_le_bytes());
        body.extend_from_slice(&(8 * values.len() as u32).to_le_bytes());
        for v in values {
            body.extend_from_slice(&v.to_le_bytes());
        }
        let mut element = Vec::new();
        element.extend_from_slice(&MI_MATRIX.to_le_bytes());
        element.extend_from_slice(&(body.len() as u32).to_le_bytes());
        element.extend_from_slice(&body);
        element
    }

    #[test]
    fn arrays_decode_and_a_malformed_one_is_an_error_not_a_panic() {
        let vars = decode(&column_element(3, &[1.5, -2.0, 4.25])).unwrap();
        assert_eq!(vars.len(), 1);
        assert_eq!(vars[0].0, "X");
        assert_eq!(numbers(&vars[0].1).unwrap(), [1.5, -2.0, 4.25]);
        // Dimensions that do not match the data make matrw panic: caught, reported.
        let bad = column_element(5, &[1.5, -2.0, 4.25]);
        let e = decode(&bad).unwrap_err();
        assert_eq!(e, "cannot be decoded (malformed array)");
        // Its name is still read, for the message.
        assert_eq!(element_name(&bad).as_deref(), Some("X"));
        assert_eq!(element_name(&bad[..30]), None);
    }

    #[test]
    fn an_undecodable_channel_struct_is_refused_not_replaced_by_assumed_units() {
        let mut file = format!("{:<116}", "MATLAB 5.0 MAT-file, x").into_bytes();
        file.extend_from_slice(&[0; 8]);
        file.extend_from_slice(&[0x00, 0x01]);
        file.extend_from_slice(b"IM");
        file.extend(named_column("FZ", 2, &[-1000.0, -1100.0]));
        file.extend(named_column("SA", 2, &[1.0, 2.0]));
        file.extend(named_column("FY", 2, &[-50.0, -90.0]));
        // Without `channel`: SI units assumed, noted.
        let (l, tire) = read_run(&file, "B1run2.mat").unwrap();
        assert_eq!(tire, None);
        assert_eq!(l.dataset.fz, vec![1000.0, 1100.0].into());
        assert!(
            l.notes
                .iter()
                .any(|n| n.contains("there is no struct channel"))
        );
        // With a `channel` that cannot be decoded: refused.
        file.extend(named_column("channel", 3, &[1.0]));
        let e = read_run(&file, "B1run2.mat").unwrap_err();
        assert_eq!(e.column.as_deref(), Some("channel"));
        assert!(
            e.message.starts_with("variable channel (byte ")
                && e.message.contains("cannot be decoded")
                && e.message.contains(".dat file instead"),
            "{e}"
        );
    }

    #[test]
    fn decoder_messages_lose_colour_codes() {
        assert_eq!(
            first_line("binrw error \n \u{1b}[1mError: no variants matched at 0x0\u{1b}[22m\n"),
            "Error: no variants matched at 0x0"
        );
    }
}
