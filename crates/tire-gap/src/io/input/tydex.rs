//! TYDEX (`.tdx`) measurement files, one file = one run.
//!
//! Sections start with `**` (`**HEADER`, `**COMMENTS`, `**CONSTANTS`, `**MEASURCHANNELS`,
//! `**MEASURDATA`, `**END`); lines starting with `!` are comments. A `**MEASURCHANNELS`
//! line is `name, description, unit, factor, offset`, in the fixed columns of the format
//! (name 1-10, description 11-40, unit 41-50, numbers after) or simply separated by blanks.
//! A `**MEASURDATA` row holds one number per channel, in channel order.
//!
//! **Scaling.** A stored number `raw` means `raw * factor + offset` in the channel's unit
//! (factor 1 and offset 0 when absent), which [`crate::io::units`] then converts to internal
//! units. Some writers put two offsets after the factor; those files are accepted only
//! when both are zero, since their meaning differs between writers.
//!
//! **Channels used** (first present name wins; names ignore case):
//!
//! | quantity    | channels                          |
//! |-------------|-----------------------------------|
//! | time        | `RUNTIME`                         |
//! | speed       | `LONGVEL`, `TRAJVELW`             |
//! | Fz          | `FZW`, `FZ`, `FZH`                |
//! | alpha       | `SLIPANGL`                        |
//! | kappa       | `LONGSLIP`                        |
//! | gamma       | `INCLANGL`                        |
//! | pressure    | `INFLPRES`                        |
//! | temperature | `TREADTMP`, `TYRETEMP`, `SURFTEMP` (tread, not `AMBITEMP` or `TRCKTEMP`) |
//! | Fx          | `FXW`, `FX`, `FXH`                |
//! | Fy          | `FYW`, `FY`, `FYH`                |
//! | Mz          | `MZW`, `MZ`, `MZH`                |
//!
//! An input quantity (load, slips, camber, speed, pressure, temperature) with no channel
//! but a numeric `**CONSTANTS` entry of the same name is held at that constant.
//!
//! **Axes.** TYDEX W (and H) axes follow ISO: x forward, y left, z up. tire-gap works in
//! the axes of the 1987 paper (y right, z down), with the same mapping as the FMU's
//! `isoSignConvention`: `Fy = -FYW`, `Mz = -MZW`; slip angle, camber, slip and Fx keep
//! their sign. The load is taken positive in compression: if the median of the Fz channel
//! is negative the channel is negated (noted).
//!
//! **Run id.** An integer `MEASID` in `**HEADER` or `**CONSTANTS`, else 1.

use super::table::{self, Column, Spelling, Table};
use super::{InputError, Loaded};
use crate::data::Quantity;
use crate::io::units::{self, Conversion};
use crate::quantiles::median;

/// TYDEX channel names per quantity, by preference.
const CHANNELS: &[(Quantity, &[&str])] = &[
    (Quantity::Time, &["RUNTIME"]),
    (Quantity::Speed, &["LONGVEL", "TRAJVELW"]),
    (Quantity::Fz, &["FZW", "FZ", "FZH"]),
    (Quantity::Alpha, &["SLIPANGL"]),
    (Quantity::Kappa, &["LONGSLIP"]),
    (Quantity::Gamma, &["INCLANGL"]),
    (Quantity::Pressure, &["INFLPRES"]),
    (Quantity::Temperature, &["TREADTMP", "TYRETEMP", "SURFTEMP"]),
    (Quantity::Fx, &["FXW", "FX", "FXH"]),
    (Quantity::Fy, &["FYW", "FY", "FYH"]),
    (Quantity::Mz, &["MZW", "MZ", "MZH"]),
];

/// Quantities a constant may stand in for (inputs, never measured outputs).
const CONSTANT_INPUTS: [Quantity; 7] = [
    Quantity::Fz,
    Quantity::Alpha,
    Quantity::Kappa,
    Quantity::Gamma,
    Quantity::Speed,
    Quantity::Pressure,
    Quantity::Temperature,
];

/// The preferred channel name of each quantity.
pub fn channel_name(q: Quantity) -> &'static str {
    CHANNELS
        .iter()
        .find(|(k, _)| *k == q)
        .map_or("MEASID", |(_, names)| names[0])
}

const SPELLING: Spelling = Spelling {
    fz_missing: (
        "FZW",
        "channel FZW (or FZ, FZH) or constant FZW, the vertical load",
    ),
    name: channel_name,
};

/// The quantity a channel name maps to, with its rank (0 = preferred).
fn quantity_of(name: &str) -> Option<(Quantity, usize)> {
    CHANNELS.iter().find_map(|(q, names)| {
        names
            .iter()
            .position(|n| n.eq_ignore_ascii_case(name))
            .map(|rank| (*q, rank))
    })
}

/// A `name description unit numbers...` line split into its parts.
#[derive(Debug, Clone, PartialEq)]
struct Definition {
    name: String,
    unit: String,
    numbers: Vec<String>,
}

/// The ways a definition line can be read, most trusted first: the format's fixed
/// columns; blank-separated tokens (trailing numbers, the unit before them); the same
/// with no unit; the first number taken as the unit (`1` is a unit and a factor).
fn readings(line: &str, max_numbers: usize) -> Vec<Definition> {
    let mut out = Vec::new();
    let tokens: Vec<&str> = line.split_whitespace().collect();
    let Some(&first) = tokens.first() else {
        return out;
    };
    let chars: Vec<char> = line.chars().collect();
    let field = |a: usize, b: usize| -> String {
        chars[a.min(chars.len())..b.min(chars.len())]
            .iter()
            .collect::<String>()
            .trim()
            .to_string()
    };
    if chars.len() > 40 && field(0, 10) == first {
        let rest = field(50, chars.len());
        let numbers: Vec<String> = rest.split_whitespace().map(str::to_string).collect();
        if numbers.len() <= max_numbers {
            out.push(Definition {
                name: first.to_string(),
                unit: strip_brackets(&field(40, 50)),
                numbers,
            });
        }
    }
    // Trailing numeric tokens are the numbers; the token before them is the unit.
    let mut end = tokens.len();
    while end > 1
        && tokens.len() - end < max_numbers
        && table::parse_number(tokens[end - 1]).is_ok()
    {
        end -= 1;
    }
    let numbers: Vec<String> = tokens[end..].iter().map(|t| t.to_string()).collect();
    let middle = &tokens[1..end];
    let unit = match middle {
        [.., "deg", t] if t.eq_ignore_ascii_case("c") || t.eq_ignore_ascii_case("f") => {
            format!("deg {t}")
        }
        [_, .., u] => strip_brackets(u),
        [u] if Quantity::ALL
            .iter()
            .any(|q| units::conversion(*q, &strip_brackets(u)).is_some()) =>
        {
            strip_brackets(u)
        }
        _ => String::new(),
    };
    let mut alternatives = vec![(unit, numbers.clone()), (String::new(), numbers.clone())];
    // A numeric unit ("1") is indistinguishable from a factor: try it as the unit too.
    if let Some((first_number, rest)) = numbers.split_first() {
        alternatives.push((first_number.clone(), rest.to_vec()));
    }
    for (unit, numbers) in alternatives {
        let d = Definition {
            name: first.to_string(),
            unit,
            numbers,
        };
        if !out.contains(&d) {
            out.push(d);
        }
    }
    out
}

fn strip_brackets(u: &str) -> String {
    u.trim()
        .trim_start_matches(['[', '('])
        .trim_end_matches([']', ')'])
        .to_string()
}

/// A channel of `**MEASURCHANNELS` as used here.
struct Channel {
    name: String,
    line: usize,
    /// Quantity, rank among its names, and conversion from stored number to internal.
    mapped: Option<(Quantity, usize, Conversion)>,
}

/// Reads a mapped definition (channel or constant): the first reading whose unit is
/// accepted for `q` and whose numbers parse and pass `check`; on failure, the error of
/// the most trusted reading.
fn mapped_definition<T>(
    line_text: &str,
    q: Quantity,
    max_numbers: usize,
    check: impl Fn(&[f64]) -> Result<T, String>,
) -> Result<(Conversion, T), String> {
    let mut first_error = None;
    for d in readings(line_text, max_numbers) {
        let Some(conv) = units::conversion(q, &d.unit) else {
            first_error.get_or_insert_with(|| {
                format!(
                    "unit \"{}\" is not accepted for {}; accepted units: {}",
                    d.unit,
                    q.name(),
                    units::accepted_list(q)
                )
            });
            continue;
        };
        let checked = d
            .numbers
            .iter()
            .map(|s| table::parse_number(s))
            .collect::<Result<Vec<f64>, String>>()
            .and_then(|numbers| check(&numbers));
        match checked {
            Ok(t) => return Ok((conv, t)),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    Err(first_error.unwrap_or_else(|| "cannot read this definition".to_string()))
}

/// The stored-number scaling of a channel from its numbers: factor, then offset(s).
fn scaling(numbers: &[f64]) -> Result<Conversion, String> {
    let factor = numbers.first().copied().unwrap_or(1.0);
    let offset = numbers.get(1).copied().unwrap_or(0.0);
    if factor == 0.0 {
        return Err("conversion factor is 0".to_string());
    }
    if numbers.len() > 2 && numbers[1..].iter().any(|&o| o != 0.0) {
        return Err(
            "factor followed by two offsets: only `factor offset` is supported (physical = raw * factor + offset)"
                .to_string(),
        );
    }
    Ok(Conversion {
        scale: factor,
        offset,
    })
}

/// Reads TYDEX text as one run; `source` names the file in messages and in the dataset.
pub fn read_str(text: &str, source: &str) -> Result<Loaded, InputError> {
    let err = |m: String| InputError::new(source, m);
    if text.trim().is_empty() {
        return Err(err("the file is empty".into()));
    }
    let sections = Sections::split(text, source)?;
    let channels = read_channel_definitions(&sections.channel_lines, source)?;
    let mut notes = Vec::new();
    let used = choose_channels(&channels, &mut notes);
    let mut tbl = read_rows(&sections.rows, &channels, &used, source)?;
    apply_constants(&sections.constants, &mut tbl, &mut notes, source)?;
    to_paper_axes(&mut tbl, &mut notes);
    let n = tbl.lines.len();
    let (label, run) = run_id(&sections, source)?;
    tbl.run = Some((label.to_string(), vec![run; n]));

    let dataset = table::finish(source, tbl, &SPELLING, &mut notes)?;
    Ok(Loaded {
        dataset,
        notes,
        sources: Vec::new(),
    })
}

/// The lines of a TYDEX file by section, each with its 1-based line number.
struct Sections<'a> {
    header: Vec<(usize, &'a str)>,
    constants: Vec<(usize, &'a str)>,
    channel_lines: Vec<(usize, &'a str)>,
    /// `**MEASURDATA` rows, trimmed.
    rows: Vec<(usize, &'a str)>,
}

impl<'a> Sections<'a> {
    /// Splits the text into sections up to `**END`, skipping blank and comment lines;
    /// fails when the channel or data section is missing or empty.
    fn split(text: &'a str, source: &str) -> Result<Self, InputError> {
        let err = |m: String| InputError::new(source, m);
        let mut section = String::new();
        let mut seen = Vec::new();
        let mut s = Sections {
            header: Vec::new(),
            constants: Vec::new(),
            channel_lines: Vec::new(),
            rows: Vec::new(),
        };
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let trimmed = raw.trim();
            if let Some(rest) = trimmed.strip_prefix("**") {
                section = rest
                    .split_whitespace()
                    .next()
                    .unwrap_or("")
                    .to_ascii_uppercase();
                if section == "END" {
                    break;
                }
                seen.push(section.clone());
                continue;
            }
            if trimmed.is_empty() || trimmed.starts_with('!') {
                continue;
            }
            match section.as_str() {
                "HEADER" => s.header.push((line, raw)),
                "CONSTANTS" => s.constants.push((line, raw)),
                "MEASURCHANNELS" => s.channel_lines.push((line, raw)),
                "MEASURDATA" => s.rows.push((line, trimmed)),
                _ => {}
            }
        }
        if !seen.iter().any(|s| s == "MEASURCHANNELS") {
            return Err(err("no **MEASURCHANNELS section".into()));
        }
        if s.channel_lines.is_empty() {
            return Err(err("**MEASURCHANNELS defines no channels".into()));
        }
        if !seen.iter().any(|s| s == "MEASURDATA") {
            return Err(err("no **MEASURDATA section".into()));
        }
        if s.rows.is_empty() {
            return Err(err("no data rows in **MEASURDATA".into()));
        }
        Ok(s)
    }
}

/// Reads the `**MEASURCHANNELS` lines: names must be unique; a channel tire-gap uses
/// gets its conversion from stored number to internal units.
fn read_channel_definitions(
    channel_lines: &[(usize, &str)],
    source: &str,
) -> Result<Vec<Channel>, InputError> {
    let err = |m: String| InputError::new(source, m);
    let mut channels: Vec<Channel> = Vec::new();
    for &(line, text) in channel_lines {
        let name = text.split_whitespace().next().unwrap_or("").to_string();
        let at = |m: String| err(m).at_line(line).in_column(&name);
        if let Some(other) = channels.iter().find(|c| c.name.eq_ignore_ascii_case(&name)) {
            return Err(at(format!(
                "duplicate channel (first defined at line {})",
                other.line
            )));
        }
        let mapped = match quantity_of(&name) {
            Some((q, rank)) => {
                let (unit_conv, file_conv) = mapped_definition(text, q, 3, scaling).map_err(at)?;
                Some((q, rank, unit_conv.after(file_conv)))
            }
            None => None,
        };
        channels.push(Channel { name, line, mapped });
    }
    Ok(channels)
}

/// The channel used for each quantity as `(quantity, channel index)`, the best-ranked
/// name winning; notes the ignored channels and any H-axis channel used.
fn choose_channels(channels: &[Channel], notes: &mut Vec<String>) -> Vec<(Quantity, usize)> {
    let mut used: Vec<(Quantity, usize)> = Vec::new();
    let mut ignored = Vec::new();
    for (i, ch) in channels.iter().enumerate() {
        match ch.mapped {
            Some((q, rank, _)) => match used.iter_mut().find(|(k, _)| *k == q) {
                Some(slot) => {
                    let best = channels[slot.1].mapped.map_or(usize::MAX, |m| m.1);
                    if rank < best {
                        ignored.push(channels[slot.1].name.clone());
                        slot.1 = i;
                    } else {
                        ignored.push(ch.name.clone());
                    }
                }
                None => used.push((q, i)),
            },
            None => ignored.push(ch.name.clone()),
        }
    }
    if !ignored.is_empty() {
        notes.push(format!(
            "ignored TYDEX channel(s) tire-gap does not use: {}",
            ignored.join(", ")
        ));
    }
    for (q, i) in &used {
        let name = &channels[*i].name;
        if name.len() == 3 && name.to_ascii_uppercase().ends_with('H') {
            notes.push(format!(
                "{} taken from {name} (H axes, at the wheel centre): no W-axis channel",
                q.name()
            ));
        }
    }
    used
}

/// Reads the `**MEASURDATA` rows into a table of the used channels, converted to
/// internal units; every row must hold one number per channel.
fn read_rows(
    rows: &[(usize, &str)],
    channels: &[Channel],
    used: &[(Quantity, usize)],
    source: &str,
) -> Result<Table, InputError> {
    let err = |m: String| InputError::new(source, m);
    let mut tbl = Table::default();
    let mut cols: Vec<(Quantity, usize, Conversion, Column)> = used
        .iter()
        .map(|&(q, i)| {
            let conv = channels[i].mapped.map_or(Conversion::IDENTITY, |m| m.2);
            let col = Column {
                label: channels[i].name.clone(),
                values: Vec::with_capacity(rows.len()),
            };
            (q, i, conv, col)
        })
        .collect();
    for &(line, row) in rows {
        let tokens: Vec<&str> = row.split_whitespace().collect();
        if tokens.len() != channels.len() {
            return Err(err(format!(
                "row has {} values but **MEASURCHANNELS defines {} channels",
                tokens.len(),
                channels.len()
            ))
            .at_line(line));
        }
        let mut values = Vec::with_capacity(tokens.len());
        for (token, ch) in tokens.iter().zip(channels) {
            let v =
                table::parse_number(token).map_err(|m| err(m).at_line(line).in_column(&ch.name))?;
            values.push(v);
        }
        for (_, i, conv, col) in &mut cols {
            col.values.push(conv.apply(values[*i]));
        }
        tbl.lines.push(line);
    }
    tbl.columns = cols.into_iter().map(|(q, _, _, c)| (q, c)).collect();
    Ok(tbl)
}

/// Adds a constant column for each input quantity that has no channel but a numeric
/// `**CONSTANTS` entry.
fn apply_constants(
    constants: &[(usize, &str)],
    tbl: &mut Table,
    notes: &mut Vec<String>,
    source: &str,
) -> Result<(), InputError> {
    let err = |m: String| InputError::new(source, m);
    let n = tbl.lines.len();
    for &(line, text) in constants {
        let name = text.split_whitespace().next().unwrap_or("");
        let Some((q, _)) = quantity_of(name) else {
            continue;
        };
        if !CONSTANT_INPUTS.contains(&q) || tbl.column(q).is_some() {
            continue;
        }
        let at = |m: String| err(m).at_line(line).in_column(name);
        let (conv, value) = mapped_definition(text, q, 1, |numbers| match numbers {
            [v] => Ok(*v),
            _ => Err("constant has no numeric value".to_string()),
        })
        .map_err(at)?;
        let mut v = conv.apply(value);
        if q == Quantity::Fz && v < 0.0 {
            v = -v;
            notes.push(format!(
                "constant {name} is negative (z up): negated so that load is positive"
            ));
        }
        notes.push(format!(
            "{} held at the constant {name} for every sample",
            q.name()
        ));
        tbl.columns.push((
            q,
            Column {
                label: name.to_string(),
                values: vec![v; n],
            },
        ));
    }
    Ok(())
}

/// Converts signs from ISO axes to the paper's axes (Fy and Mz negated) and makes a
/// mostly negative load positive, with notes.
fn to_paper_axes(tbl: &mut Table, notes: &mut Vec<String>) {
    let mut flipped = Vec::new();
    for q in [Quantity::Fy, Quantity::Mz] {
        if let Some(col) = tbl.column_mut(q) {
            col.values.iter_mut().for_each(|v| *v = -*v);
            flipped.push(col.label.clone());
        }
    }
    notes.push(format!(
        "TYDEX axes are ISO (x forward, y left, z up); converted to the paper's axes (y right, z down) as the FMU's isoSignConvention does: {}; slip angle, camber, slip and Fx keep their sign",
        if flipped.is_empty() {
            "no Fy or Mz channel to negate".to_string()
        } else {
            format!("{} negated", flipped.join(" and "))
        }
    ));
    if let Some(col) = tbl
        .column_mut(Quantity::Fz)
        .filter(|c| median(&c.values).is_some_and(|m| m < 0.0))
    {
        col.values.iter_mut().for_each(|v| *v = -*v);
        notes.push(format!(
            "{} is mostly negative (z up): negated so that load is positive",
            col.label
        ));
    }
}

/// The run of the file (one file is one run) and where it came from: an integer
/// `MEASID` in `**HEADER` or `**CONSTANTS`, else 1 from `"file"`.
fn run_id(sections: &Sections, source: &str) -> Result<(&'static str, i64), InputError> {
    let measid = sections
        .header
        .iter()
        .chain(&sections.constants)
        .find_map(|&(line, text)| {
            let mut tokens = text.split_whitespace();
            let key = tokens.next()?;
            key.eq_ignore_ascii_case("MEASID")
                .then(|| (line, tokens.last().unwrap_or("").to_string()))
        });
    Ok(match measid {
        Some((line, value)) => {
            let id = table::parse_run(&value).map_err(|m| {
                InputError::new(source, format!("MEASID: {m}"))
                    .at_line(line)
                    .in_column("MEASID")
            })?;
            ("MEASID", id)
        }
        None => ("file", 1),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn def(name: &str, unit: &str, numbers: &[&str]) -> Definition {
        Definition {
            name: name.into(),
            unit: unit.into(),
            numbers: numbers.iter().map(|s| s.to_string()).collect(),
        }
    }

    #[test]
    fn fixed_columns_first() {
        let line = format!(
            "{:<10}{:<30}{:<10}{}",
            "LONGSLIP", "Longitudinal slip", "", "1"
        );
        assert_eq!(readings(&line, 3)[0], def("LONGSLIP", "", &["1"]));
        let line = format!(
            "{:<10}{:<30}{:<10}{} {}",
            "INFLPRES", "Inflation pressure", "deg C", "0.1", "2"
        );
        assert_eq!(
            readings(&line, 3)[0],
            def("INFLPRES", "deg C", &["0.1", "2"])
        );
    }

    #[test]
    fn blank_separated() {
        let r = readings("SLIPANGL Slip angle deg 1 0", 3);
        assert_eq!(r[0], def("SLIPANGL", "deg", &["1", "0"]));
        assert_eq!(r[1], def("SLIPANGL", "", &["1", "0"]));
        let r = readings("TREADTMP tread temperature deg C 1", 3);
        assert_eq!(r[0], def("TREADTMP", "deg C", &["1"]));
        let r = readings("FZW N", 3);
        assert_eq!(r[0], def("FZW", "N", &[]));
        let r = readings("MZW [Nm] 2", 3);
        assert_eq!(r[0], def("MZW", "Nm", &["2"]));
    }

    #[test]
    fn scaling_rules() {
        assert_eq!(scaling(&[]), Ok(Conversion::IDENTITY));
        assert_eq!(
            scaling(&[0.1, 5.0]),
            Ok(Conversion {
                scale: 0.1,
                offset: 5.0
            })
        );
        assert_eq!(
            scaling(&[2.0, 0.0, 0.0]),
            Ok(Conversion {
                scale: 2.0,
                offset: 0.0
            })
        );
        assert!(scaling(&[2.0, 1.0, 0.0]).is_err());
        assert!(scaling(&[0.0]).is_err());
    }

    #[test]
    fn channel_names() {
        assert_eq!(quantity_of("fyw"), Some((Quantity::Fy, 0)));
        assert_eq!(quantity_of("FZH"), Some((Quantity::Fz, 2)));
        assert_eq!(quantity_of("AMBITEMP"), None);
    }
}
