//! CSV with one header row and one row per sample. Column names carry their unit as a
//! suffix: `alpha_deg`, `fz_N`, `p_kPa`, `mz_Nm`, ... (`<name>_<unit>`, any unit that
//! [`crate::io::units`] accepts for that quantity). `run` and `kappa` take no suffix (`kappa_pct`
//! for percent). Names are matched ignoring case; an unknown unit on a known name is an
//! error; columns with unknown names are ignored with a note.
//!
//! Rows may contain `#` comment lines; blank lines are skipped; the delimiter is `,`
//! unless the header line uses `;` or tabs instead.

use super::table::{self, Column, Spelling, Table};
use super::{InputError, Loaded};
use crate::data::Quantity;
use crate::io::units::{self, Conversion};

/// Quantity names a column may start with (lower case).
const NAMES: &[(&str, Quantity)] = &[
    ("run", Quantity::Run),
    ("t", Quantity::Time),
    ("time", Quantity::Time),
    ("vx", Quantity::Speed),
    ("speed", Quantity::Speed),
    ("fz", Quantity::Fz),
    ("alpha", Quantity::Alpha),
    ("kappa", Quantity::Kappa),
    ("gamma", Quantity::Gamma),
    ("p", Quantity::Pressure),
    ("pressure", Quantity::Pressure),
    ("temp", Quantity::Temperature),
    ("temperature", Quantity::Temperature),
    ("fx", Quantity::Fx),
    ("fy", Quantity::Fy),
    ("mz", Quantity::Mz),
];

/// The canonical column name of each quantity (what the documentation shows).
pub fn canonical(q: Quantity) -> &'static str {
    match q {
        Quantity::Run => "run",
        Quantity::Time => "t_s",
        Quantity::Speed => "vx_mps",
        Quantity::Fz => "fz_N",
        Quantity::Alpha => "alpha_deg",
        Quantity::Kappa => "kappa",
        Quantity::Gamma => "gamma_deg",
        Quantity::Pressure => "p_kPa",
        Quantity::Temperature => "temp_C",
        Quantity::Fx => "fx_N",
        Quantity::Fy => "fy_N",
        Quantity::Mz => "mz_Nm",
    }
}

pub(super) const SPELLING: Spelling = Spelling {
    fz_missing: ("fz_N", "fz_N (or fz_kN), the vertical load"),
    name: canonical,
};

fn quantity_named(name: &str) -> Option<Quantity> {
    let lower = name.to_lowercase();
    NAMES.iter().find(|(n, _)| *n == lower).map(|(_, q)| *q)
}

/// What a header cell means.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Kind {
    Run,
    Real(Quantity, Conversion),
    Ignored,
}

/// Reads a header cell: `name`, or `name_unit` (the unit may itself contain `_`, read as
/// a space: `temp_deg_C`). Errors name what is wrong; unknown names are `Ignored`.
fn classify(header: &str) -> Result<Kind, String> {
    let (q, unit) = match quantity_named(header) {
        Some(q) => (q, ""),
        None => match header.split_once('_') {
            Some((name, unit)) => match quantity_named(name) {
                Some(q) => (q, unit),
                None => return Ok(Kind::Ignored),
            },
            None => return Ok(Kind::Ignored),
        },
    };
    let unit_spaced = unit.replace('_', " ");
    match units::conversion(q, &unit_spaced) {
        Some(_) if q == Quantity::Run => Ok(Kind::Run),
        Some(c) => Ok(Kind::Real(q, c)),
        None => {
            let stem = header.get(..header.len() - unit.len()).unwrap_or(header);
            let stem = stem.trim_end_matches('_');
            let suffixes = units::accepted_units(q)
                .iter()
                .filter(|u| **u != "1" && u.chars().all(|c| c.is_ascii_alphanumeric() || c == '%'))
                .map(|u| {
                    if u.is_empty() {
                        stem.to_string()
                    } else {
                        format!("{stem}_{u}")
                    }
                })
                .collect::<Vec<_>>()
                .join(", ");
            if unit.is_empty() {
                Err(format!(
                    "{} needs a unit suffix: write {suffixes}",
                    q.name()
                ))
            } else {
                Err(format!(
                    "unit \"{unit}\" is not accepted for {}; accepted units: {} (e.g. {suffixes}); rename the column if it holds something else",
                    q.name(),
                    units::accepted_list(q)
                ))
            }
        }
    }
}

/// Picks the delimiter from the header line: `,` unless `;` or tab is more frequent.
fn sniff_delimiter(text: &str) -> u8 {
    let header = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .unwrap_or("");
    let count = |c: char| header.matches(c).count();
    [(b',', count(',')), (b';', count(';')), (b'\t', count('\t'))]
        .into_iter()
        .fold(
            (b',', 0),
            |best, cand| if cand.1 > best.1 { cand } else { best },
        )
        .0
}

/// Reads CSV text; `source` names the file in messages and in the dataset.
pub fn read_str(text: &str, source: &str) -> Result<Loaded, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(InputError::new(source, "the file is empty"));
    }
    // Cells are trimmed where they are read (names here, numbers as they are parsed), not by
    // the reader, which would build a second record per row.
    let mut reader = ::csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .delimiter(sniff_delimiter(text))
        .from_reader(text.as_bytes());
    let lines = Lines::new(text);
    let csv_err = |e: ::csv::Error| lines.csv_error(source, e);

    let mut header = ::csv::StringRecord::new();
    if !reader.read_record(&mut header).map_err(csv_err)? {
        return Err(InputError::new(source, "the file is empty"));
    }
    let header_line = header.position().map_or(1, |p| lines.line_of(p));
    let names: Vec<String> = header.iter().map(|c| c.trim().to_string()).collect();
    let mut notes = Vec::new();
    let hint = if text.contains("**MEASURCHANNELS") {
        " (this looks like a TYDEX file: give it the .tdx extension)"
    } else {
        ""
    };
    let kinds = header_kinds(&names, Some(header_line), hint, source, &mut notes)?;
    let tbl = read_rows(&mut reader, &names, &kinds, &lines, source)?;
    let dataset = table::finish(source, tbl, &SPELLING, &mut notes)?;
    Ok(Loaded {
        dataset,
        notes,
        sources: Vec::new(),
    })
}

/// The line breaks in `text`.
fn line_breaks(text: &str) -> usize {
    text.bytes().filter(|&b| b == b'\n').count()
}

/// The lines of the text, to find a record's own line from its byte offset.
struct Lines<'a> {
    text: &'a str,
    /// Byte offset of each line's start.
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    /// The lines of `text` and where each starts.
    fn new(text: &'a str) -> Self {
        let mut starts = Vec::with_capacity(line_breaks(text) + 1);
        starts.push(0);
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        Lines { text, starts }
    }

    /// The text of the 1-based line `line`, if the text has it.
    fn line(&self, line: usize) -> Option<&'a str> {
        let start = *self.starts.get(line.checked_sub(1)?)?;
        let end = self
            .starts
            .get(line)
            .map_or(self.text.len(), |next| next - 1);
        Some(&self.text[start..end])
    }

    /// The 1-based line of a record. Its position is where the reader stood before it,
    /// ahead of any comment or blank lines it skipped: those are stepped over.
    fn line_of(&self, p: &::csv::Position) -> usize {
        let byte = usize::try_from(p.byte()).unwrap_or(usize::MAX);
        let mut line = self.starts.partition_point(|&start| start <= byte).max(1);
        while let Some(l) = self.line(line) {
            if l.trim_end_matches('\r').is_empty() || l.starts_with('#') {
                line += 1;
            } else {
                break;
            }
        }
        line.min(self.starts.len())
    }

    /// A CSV syntax error, at its line when known.
    fn csv_error(&self, source: &str, e: ::csv::Error) -> InputError {
        let line = e.position().map(|p| self.line_of(p));
        let mut err = InputError::new(source, format!("malformed CSV: {e}"));
        err.line = line;
        err
    }
}

/// Classifies the header cells (on `header_line` of a file): no two may give the same
/// quantity, at least one must be read (else the error ends with `hint`); notes the ignored
/// ones.
pub(super) fn header_kinds(
    names: &[String],
    header_line: Option<usize>,
    hint: &str,
    source: &str,
    notes: &mut Vec<String>,
) -> Result<Vec<Kind>, InputError> {
    let at = |e: InputError| InputError {
        line: header_line,
        ..e
    };
    let mut kinds = Vec::with_capacity(names.len());
    let mut ignored = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let kind = classify(name).map_err(|m| at(InputError::new(source, m).in_column(name)))?;
        let clash = |k: &Kind| match (k, &kind) {
            (Kind::Run, Kind::Run) => true,
            (Kind::Real(a, _), Kind::Real(b, _)) => a == b,
            _ => false,
        };
        if let Some(j) = kinds.iter().position(clash) {
            let what = match kind {
                Kind::Real(q, _) => q.name(),
                _ => "run",
            };
            return Err(at(InputError::new(
                source,
                format!("duplicate column: {} and {name} both give {what}", names[j]),
            )
            .in_column(name)));
        }
        if kind == Kind::Ignored {
            ignored.push(if name.is_empty() {
                format!("(unnamed column {})", i + 1)
            } else {
                name.clone()
            });
        }
        kinds.push(kind);
    }
    if kinds.iter().all(|k| *k == Kind::Ignored) {
        return Err(at(InputError::new(
            source,
            format!(
                "the header names no column tire-gap reads (expected e.g. run, fz_N, alpha_deg, kappa, fx_N, fy_N, mz_Nm){hint}"
            ),
        )));
    }
    if !ignored.is_empty() {
        notes.push(format!(
            "ignored column(s) tire-gap does not use: {}",
            ignored.join(", ")
        ));
    }
    Ok(kinds)
}

/// An empty column, made `rows` long at once, for each real-valued header cell.
fn real_columns(
    names: &[String],
    kinds: &[Kind],
    rows: usize,
) -> Vec<(Quantity, Conversion, Column)> {
    kinds
        .iter()
        .zip(names)
        .filter_map(|(k, name)| match k {
            Kind::Real(q, c) => Some((
                *q,
                *c,
                Column {
                    label: name.clone(),
                    values: Vec::with_capacity(rows),
                },
            )),
            _ => None,
        })
        .collect()
}

/// Reads the data rows into a table, values converted to internal units; rows of only
/// delimiters are skipped, and at least one row is needed.
fn read_rows(
    reader: &mut ::csv::Reader<&[u8]>,
    names: &[String],
    kinds: &[Kind],
    lines: &Lines,
    source: &str,
) -> Result<Table, InputError> {
    // At most one row a line after the header: the columns are made that long at once, not
    // grown (a growing column can hold twice its rows).
    let rows = lines.starts.len().saturating_sub(1);
    let mut tbl = Table {
        lines: Vec::with_capacity(rows),
        ..Table::default()
    };
    let mut run_ids = Vec::new();
    if kinds.contains(&Kind::Run) {
        run_ids.reserve_exact(rows);
    }
    let mut cols = real_columns(names, kinds, rows);
    let mut record = ::csv::StringRecord::new();
    while reader
        .read_record(&mut record)
        .map_err(|e| lines.csv_error(source, e))?
    {
        let line = record.position().map_or(0, |p| lines.line_of(p));
        // A line of only delimiters (and blanks) is a blank row: skip it like a blank line.
        if record.iter().all(|c| c.trim().is_empty()) {
            continue;
        }
        if record.len() != names.len() {
            return Err(InputError::new(
                source,
                format!(
                    "row has {} fields but the header has {}",
                    record.len(),
                    names.len()
                ),
            )
            .at_line(line));
        }
        let mut real = cols.iter_mut();
        for ((cell, kind), name) in record.iter().zip(kinds).zip(names) {
            let at = |m: String| InputError::new(source, m).at_line(line).in_column(name);
            match kind {
                Kind::Run => run_ids.push(table::parse_run(cell).map_err(at)?),
                Kind::Real(..) => {
                    let v = table::parse_number(cell).map_err(at)?;
                    if let Some((_, conv, col)) = real.next() {
                        col.values.push(conv.apply(v));
                    }
                }
                Kind::Ignored => {}
            }
        }
        tbl.lines.push(line);
    }
    if tbl.lines.is_empty() {
        return Err(InputError::new(
            source,
            "no data rows: the file has only a header",
        ));
    }
    if let Some(j) = kinds.iter().position(|k| *k == Kind::Run) {
        tbl.run = Some((names[j].clone(), run_ids));
    }
    tbl.columns = cols.into_iter().map(|(q, _, c)| (q, c)).collect();
    Ok(tbl)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn real(q: Quantity, unit: &str) -> Kind {
        Kind::Real(q, units::conversion(q, unit).unwrap())
    }

    #[test]
    fn header_names() {
        assert_eq!(classify("alpha_deg"), Ok(real(Quantity::Alpha, "deg")));
        assert_eq!(classify("ALPHA_rad"), Ok(real(Quantity::Alpha, "rad")));
        assert_eq!(classify("kappa"), Ok(real(Quantity::Kappa, "")));
        assert_eq!(classify("kappa_pct"), Ok(real(Quantity::Kappa, "%")));
        assert_eq!(
            classify("temp_deg_C"),
            Ok(real(Quantity::Temperature, "degC"))
        );
        assert_eq!(classify("vx_km/h"), Ok(real(Quantity::Speed, "kph")));
        assert_eq!(classify("run"), Ok(Kind::Run));
        assert_eq!(classify("comment"), Ok(Kind::Ignored));
        assert_eq!(classify("wheel_speed"), Ok(Kind::Ignored));
        assert_eq!(
            classify("alpha_grad"),
            Err("unit \"grad\" is not accepted for alpha; accepted units: deg, degree, degrees, °, rad (e.g. alpha_deg, alpha_degree, alpha_degrees, alpha_rad); rename the column if it holds something else".into())
        );
        assert_eq!(
            classify("fz"),
            Err("Fz needs a unit suffix: write fz_N, fz_kN, fz_lbf, fz_lb".into())
        );
        assert!(classify("run_s").is_err());
    }

    #[test]
    fn delimiters() {
        assert_eq!(sniff_delimiter("a,b,c\n1,2,3"), b',');
        assert_eq!(sniff_delimiter("# c, d, e, f\na;b;c\n"), b';');
        assert_eq!(sniff_delimiter("a\tb\n"), b'\t');
    }
}
