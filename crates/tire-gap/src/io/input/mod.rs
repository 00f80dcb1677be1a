//! Reading measured data: CSV with unit-suffixed column names, TYDEX .tdx files and the Tire
//! Test Consortium's run files (ASCII .dat, MATLAB .mat).
//!
//! Every reader returns a complete [`Dataset`] in internal units (see [`crate::data`])
//! plus notes for the report (ignored columns, dropped channels, sign changes, how runs
//! were found), or an [`InputError`] naming file, line and column. No reader panics on
//! any input or returns part of a file as if it were all of it. A reader only reads: every
//! row of the file is in its data set. Leaving out the rows and channels that cannot be a
//! steady tire test, and cutting a programme into its test blocks, is the method's
//! preparation, which the front ends call on each file before the files are merged
//! (`front::load`, `front::load_many`).

pub mod csv;
pub mod frame;
pub mod mat;
mod mat_layout;
mod mat_sweeps;
mod mat_text;
mod repeats;
mod table;
pub mod ttc;
pub mod tydex;

use crate::data::{Dataset, Quantity};
use serde::Serialize;
use sha2::{Digest, Sha256};
use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// A data set read from file(s), with what the report should say about how it was read.
#[derive(Debug, Clone, PartialEq)]
pub struct Loaded {
    pub dataset: Dataset,
    /// Things the reader decided or noticed, one sentence each.
    pub notes: Vec<String>,
    /// The files read, in order, with the runs each one holds.
    pub sources: Vec<SourceFile>,
}

/// One file of a data set: what it is and which runs of the data set came from it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SourceFile {
    pub file: String,
    pub format: Format,
    /// SHA-256 of the file's bytes.
    pub sha256: String,
    pub rows: usize,
    /// Its run ids in the data set (after any renumbering), in order of appearance.
    pub runs: Vec<i64>,
    /// The tire the file names (TTC files: title or `tireid`); absent from the JSON when
    /// the file names none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tire: Option<String>,
}

/// The input files' combined SHA-256: the file's own for one file; for several, the SHA-256
/// of their hex digests in order, one per line.
pub fn combined_sha256(sources: &[SourceFile]) -> String {
    match sources {
        [one] => one.sha256.clone(),
        _ => hex_sha256(
            sources
                .iter()
                .map(|s| format!("{}\n", s.sha256))
                .collect::<String>()
                .as_bytes(),
        ),
    }
}

fn hex_sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Bad input: where it is and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputError {
    /// The file, as given.
    pub file: String,
    /// 1-based line in the file, when one line is at fault.
    pub line: Option<usize>,
    /// The column (CSV) or channel (TYDEX) at fault.
    pub column: Option<String>,
    /// The rows at fault of a table given in memory (a data frame), numbered from 0.
    pub rows: Vec<usize>,
    pub message: String,
}

impl InputError {
    pub(crate) fn new(file: &str, message: impl Into<String>) -> Self {
        InputError {
            file: file.to_string(),
            line: None,
            column: None,
            rows: Vec::new(),
            message: message.into(),
        }
    }

    pub(crate) fn at_line(mut self, line: usize) -> Self {
        self.line = Some(line);
        self
    }

    pub(crate) fn in_column(mut self, column: &str) -> Self {
        self.column = Some(column.to_string());
        self
    }

    pub(crate) fn at_rows(mut self, rows: Vec<usize>) -> Self {
        self.rows = rows;
        self
    }
}

impl fmt::Display for InputError {
    /// `data.csv:17: column alpha_deg: "abc" is not a number`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if let Some(column) = &self.column {
            write!(f, ": column {column}")?;
        }
        match self.rows.as_slice() {
            [] => {}
            [one] => write!(f, ": row {one}")?,
            rows => {
                const SHOWN: usize = 10;
                let listed: Vec<String> = rows.iter().take(SHOWN).map(usize::to_string).collect();
                let more = if rows.len() > SHOWN { ", ..." } else { "" };
                write!(f, ": {} rows ({}{more})", rows.len(), listed.join(", "))?;
            }
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for InputError {}

/// A file format tire-gap reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    Csv,
    Tydex,
    /// A Tire Test Consortium ASCII run file.
    Ttc,
    /// A Tire Test Consortium MATLAB run file (MAT-file level 5).
    Mat,
    /// A table handed over in memory, columns named as in CSV ([`frame`]).
    #[serde(rename = "dataframe")]
    Frame,
}

impl Format {
    /// The format a file name's extension names, if any (`.csv`, `.tdx`, `.dat`, `.mat`, any
    /// case).
    pub fn of_extension(path: &Path) -> Option<Format> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("csv") => Some(Format::Csv),
            Some("tdx") => Some(Format::Tydex),
            Some("dat") => Some(Format::Ttc),
            Some("mat") => Some(Format::Mat),
            _ => None,
        }
    }

    /// By extension (`.csv`, `.tdx`, `.mat`, any case; `.dat` is TTC unless its content is
    /// TYDEX); otherwise by content: a MAT-file if it starts with MATLAB's header text
    /// (`MATLAB 5.0 MAT-file`), TYDEX if the first line that is neither blank nor a `!`
    /// comment starts with `**`, TTC if its second and third lines name channels with the
    /// load and a slip and one unit each, else CSV.
    pub fn detect(path: &Path, text: &str) -> Format {
        let tydex = || {
            text.lines()
                .map(|l| l.trim().trim_start_matches('\u{feff}'))
                .find(|l| !l.is_empty() && !l.starts_with('!'))
                .is_some_and(|l| l.starts_with("**"))
        };
        match Format::of_extension(path) {
            Some(Format::Ttc) if tydex() => Format::Tydex,
            Some(f) => f,
            None if mat::looks_like(text.as_bytes()) => Format::Mat,
            None if tydex() => Format::Tydex,
            None if ttc::looks_like(text) => Format::Ttc,
            None => Format::Csv,
        }
    }
}

/// Reads text already in memory; `source` names it in messages and in the dataset.
pub fn read_str(text: &str, source: &str, format: Format) -> Result<Loaded, InputError> {
    let (loaded, tire) = match format {
        Format::Csv => (csv::read_str(text, source)?, None),
        Format::Tydex => (tydex::read_str(text, source)?, None),
        Format::Ttc => ttc::read_run(text, source)?,
        Format::Mat => mat::read_run(text.as_bytes(), source)?,
        Format::Frame => {
            return Err(InputError::new(
                source,
                "a data frame is read from its columns (input::frame), not from text",
            ));
        }
    };
    Ok(sourced(loaded, tire, source, format, text.as_bytes()))
}

/// `loaded` as read from the one file `source`, with the file's record (its rows and runs as
/// read).
pub(crate) fn sourced(
    mut loaded: Loaded,
    tire: Option<String>,
    source: &str,
    format: Format,
    bytes: &[u8],
) -> Loaded {
    loaded.sources = vec![SourceFile {
        file: source.to_string(),
        format,
        sha256: hex_sha256(bytes),
        rows: loaded.dataset.len(),
        runs: loaded.dataset.runs(),
        tire,
    }];
    loaded
}

/// Reads one regular file (not a pipe or device, which could block or never end), choosing
/// the reader with [`Format::detect`].
pub fn load(path: &Path) -> Result<Loaded, InputError> {
    let name = path.display().to_string();
    let cannot = |e: std::io::Error| InputError::new(&name, format!("cannot read the file: {e}"));
    let meta = std::fs::metadata(path).map_err(cannot)?;
    if !meta.is_file() {
        return Err(InputError::new(
            &name,
            "not a regular file (a directory, pipe or device): give a data file or a directory of them",
        ));
    }
    let bytes = std::fs::read(path).map_err(cannot)?;
    load_bytes(path, bytes)
}

/// Reads the contents of the file at `path`, already in memory, as [`load`] does.
pub fn load_bytes(path: &Path, bytes: Vec<u8>) -> Result<Loaded, InputError> {
    let source = path.display().to_string();
    // MAT-files are binary: by extension or by their header text.
    if Format::of_extension(path) == Some(Format::Mat) || mat::looks_like(&bytes) {
        let (loaded, tire) = mat::read_run(&bytes, &source)?;
        return Ok(sourced(loaded, tire, &source, Format::Mat, &bytes));
    }
    let sha256 = hex_sha256(&bytes);
    let mut notes = Vec::new();
    let text = match String::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => {
            notes.push("the file is not UTF-8: read as Latin-1 (ISO 8859-1)".to_string());
            // Every byte is a Latin-1 character with the same code point.
            e.into_bytes().into_iter().map(char::from).collect()
        }
    };
    let mut loaded = read_str(&text, &source, Format::detect(path, &text))?;
    notes.append(&mut loaded.notes);
    loaded.notes = notes;
    for s in &mut loaded.sources {
        s.sha256.clone_from(&sha256);
    }
    Ok(loaded)
}

/// The data files named on a command line: files as given, directories replaced by their
/// `.csv`, `.tdx`, `.dat` and `.mat` files (not recursive, sorted by name), with notes on what
/// a directory held besides. A TTC run shipped in both formats (`X.dat` and `X.mat` side by
/// side in a directory) is read once, from the `.mat` (noted). A file named twice (or a run
/// as both files), a directory without data files, or a path that is neither a file nor a
/// directory is an error.
pub fn expand(paths: &[PathBuf]) -> Result<(Vec<PathBuf>, Vec<String>), InputError> {
    let mut files: Vec<PathBuf> = Vec::new();
    let mut notes = Vec::new();
    for path in paths {
        let name = path.display().to_string();
        let meta = std::fs::metadata(path)
            .map_err(|e| InputError::new(&name, format!("cannot read: {e}")))?;
        if !meta.is_dir() {
            files.push(path.clone());
            continue;
        }
        files.extend(directory_files(path, &name, &mut notes)?);
    }
    no_file_twice(&files)?;
    Ok((files, notes))
}

/// The data files of a directory, sorted by name, a TTC run in both formats read from the
/// `.mat` only; notes those twins and any other entries ignored.
fn directory_files(
    path: &Path,
    name: &str,
    notes: &mut Vec<String>,
) -> Result<Vec<PathBuf>, InputError> {
    let entries = std::fs::read_dir(path)
        .and_then(|d| {
            d.map(|e| e.map(|e| e.path()))
                .collect::<Result<Vec<_>, _>>()
        })
        .map_err(|e| InputError::new(name, format!("cannot list the directory: {e}")))?;
    let (mut data, other): (Vec<PathBuf>, Vec<PathBuf>) = entries
        .into_iter()
        .partition(|p| Format::of_extension(p).is_some() && p.is_file());
    if data.is_empty() {
        return Err(InputError::new(
            name,
            "the directory holds no .csv, .tdx or .dat file (nor a .mat run file)",
        ));
    }
    data.sort();
    let twins: Vec<PathBuf> = data
        .iter()
        .filter(|p| Format::of_extension(p) == Some(Format::Ttc))
        .filter(|p| data.iter().any(|q| mat_twin(p, q)))
        .cloned()
        .collect();
    if !twins.is_empty() {
        data.retain(|p| !twins.contains(p));
        notes.push(format!(
            "{name}: {} run(s) are there as both .dat and .mat; read from the .mat only: {}",
            twins.len(),
            twins
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    if !other.is_empty() {
        notes.push(format!(
            "{name}: read its {} .csv/.tdx/.dat/.mat file(s); {} other entr{} ignored",
            data.len(),
            other.len(),
            if other.len() == 1 { "y" } else { "ies" }
        ));
    }
    Ok(data)
}

/// Refuses a file given twice (by its canonical path) and a TTC run given as both its
/// `.dat` and `.mat` files: their runs would count twice.
fn no_file_twice(files: &[PathBuf]) -> Result<(), InputError> {
    let mut seen: Vec<(PathBuf, &PathBuf)> = Vec::new();
    for f in files {
        let id = std::fs::canonicalize(f).unwrap_or_else(|_| f.clone());
        if let Some((_, first)) = seen.iter().find(|(k, _)| *k == id) {
            return Err(InputError::new(
                &f.display().to_string(),
                format!(
                    "the same file is given twice (also as {}): its runs would count twice",
                    first.display()
                ),
            ));
        }
        seen.push((id, f));
    }
    for f in files
        .iter()
        .filter(|f| Format::of_extension(f) == Some(Format::Ttc))
    {
        if let Some(twin) = files.iter().find(|g| mat_twin(f, g)) {
            return Err(InputError::new(
                &f.display().to_string(),
                format!(
                    "{} holds the same TTC run in MATLAB form: its runs would count twice; \
                     give one of the two",
                    twin.display()
                ),
            ));
        }
    }
    Ok(())
}

/// Whether `mat` is the MATLAB form of the TTC run file `dat`: same path but the extension.
fn mat_twin(dat: &Path, mat: &Path) -> bool {
    Format::of_extension(mat) == Some(Format::Mat)
        && dat.with_extension("") == mat.with_extension("")
}

/// The files' notes, each note once, with the files it concerns (a programme of many files
/// repeats the same notes in every file).
fn grouped_notes(parts: &[Loaded]) -> Vec<String> {
    let mut groups: Vec<(&str, Vec<&str>)> = Vec::new();
    for p in parts {
        for n in &p.notes {
            match groups.iter_mut().find(|(note, _)| note == n) {
                Some((_, files)) => files.push(&p.dataset.source),
                None => groups.push((n, vec![&p.dataset.source])),
            }
        }
    }
    groups
        .into_iter()
        .map(|(note, files)| match files.as_slice() {
            [one] => format!("{one}: {note}"),
            _ if files.len() == parts.len() => format!("every file ({}): {note}", files.len()),
            [a, b] => format!("{a}, {b}: {note}"),
            [a, .., z] => format!("{} files ({a} .. {z}): {note}", files.len()),
            [] => note.to_string(),
        })
        .collect()
}

/// Refuses files of two or more tires; notes files without a tire name beside named ones.
fn one_tire(parts: &[Loaded], notes: &mut Vec<String>) -> Result<(), InputError> {
    let mut tires: Vec<(String, &str, Vec<&str>)> = Vec::new();
    let mut unnamed = Vec::new();
    for s in parts.iter().flat_map(|p| &p.sources) {
        let Some(tire) = &s.tire else {
            unnamed.push(s.file.as_str());
            continue;
        };
        let key = ttc::tire_key(tire);
        match tires.iter_mut().find(|(k, _, _)| *k == key) {
            Some((_, _, files)) => files.push(&s.file),
            None => tires.push((key, tire, vec![&s.file])),
        }
    }
    if let [_, (_, _, second), ..] = tires.as_slice() {
        // Each tire's files: all of them up to five, else the first three and a count.
        let list: Vec<String> = tires
            .iter()
            .map(|(_, tire, files)| match files.len() {
                ..=5 => format!("\"{tire}\" ({})", files.join(", ")),
                n => format!("\"{tire}\" ({} and {} more)", files[..3].join(", "), n - 3),
            })
            .collect();
        return Err(InputError::new(
            second[0],
            format!(
                "the files are of {} different tires: {}. One diagnosis is of one tire: \
                 diagnose each tire's files separately",
                tires.len(),
                list.join("; ")
            ),
        ));
    }
    if let (Some((_, tire, _)), false) = (tires.first(), unnamed.is_empty()) {
        notes.push(format!(
            "no tire name in {}: taken as the same tire as the other files ({tire})",
            unnamed.join(", ")
        ));
    }
    let run_files = parts
        .iter()
        .flat_map(|p| &p.sources)
        .filter(|s| matches!(s.format, Format::Ttc | Format::Mat))
        .count();
    if tires.is_empty() && run_files > 1 {
        notes.push(format!(
            "none of the {run_files} TTC run files names its tire (their titles give the test \
             programme only): they are taken as one tire; a diagnosis of several tires' files \
             is of none of them"
        ));
    }
    Ok(())
}

/// Concatenates data sets from several files (of one tire: files of several are refused). A
/// file that holds the same rows as an earlier one (one run saved twice) is left out (noted).
/// Run ids stay as read unless two files share one; then all runs are numbered 1, 2, ... in
/// file order (noted), so each TYDEX file is its own run. A column missing from some files is
/// dropped (noted).
pub fn merge(parts: Vec<Loaded>) -> Result<Loaded, InputError> {
    let mut notes = grouped_notes(&parts);
    let mut parts = repeats::without_repeats(parts, &mut notes);
    let sources: Vec<String> = parts.iter().map(|p| p.dataset.source.clone()).collect();
    one_tire(&parts, &mut notes)?;
    let mut ds = Dataset {
        source: sources.join(", "),
        ..Dataset::default()
    };
    let (run, fz, sources) = merged_runs(&parts, &mut notes);
    (ds.run, ds.fz) = (run.into(), fz.into());
    merge_optional_columns(&mut parts, &mut ds, &mut notes);
    table::drop_unpaired(&mut ds, Quantity::name, &mut notes);
    if !table::has_measured(&ds) {
        return Err(InputError::new(
            &ds.source,
            "no measured force or moment, with the slip it depends on, is present in every file",
        ));
    }
    Ok(Loaded {
        dataset: ds,
        notes,
        sources,
    })
}

/// The run ids and loads of all files in file order, and their sources with the runs of
/// each. Run ids are kept unless two files share one; then all runs are numbered 1, 2, ...
/// in file order (noted).
fn merged_runs(parts: &[Loaded], notes: &mut Vec<String>) -> (Vec<i64>, Vec<f64>, Vec<SourceFile>) {
    let run_sets: Vec<Vec<i64>> = parts.iter().map(|p| p.dataset.runs()).collect();
    let clash = run_sets.iter().enumerate().any(|(i, a)| {
        run_sets[i + 1..]
            .iter()
            .any(|b| a.iter().any(|r| b.contains(r)))
    });
    let mut next = 1;
    let mut renumbered = Vec::new();
    let mut sources = Vec::new();
    let rows: usize = parts.iter().map(|p| p.dataset.run.len()).sum();
    let (mut run, mut fz): (Vec<i64>, Vec<f64>) =
        (Vec::with_capacity(rows), Vec::with_capacity(rows));
    for (part, runs) in parts.iter().zip(&run_sets) {
        let first_row = run.len();
        if clash {
            let first = next;
            // Each run's position among the file's runs, looked up once a stretch of rows.
            let mut position: HashMap<i64, i64> = HashMap::with_capacity(runs.len());
            for (k, &r) in runs.iter().enumerate() {
                position.entry(r).or_insert(k as i64);
            }
            let mut at: Option<(i64, i64)> = None;
            for &r in part.dataset.run.iter() {
                let k = match at {
                    Some((id, k)) if id == r => k,
                    _ => position.get(&r).copied().unwrap_or(0),
                };
                at = Some((r, k));
                run.push(first + k);
            }
            next += runs.len() as i64;
            renumbered.push(format!(
                "{} -> {}",
                part.dataset.source,
                if runs.len() == 1 {
                    first.to_string()
                } else {
                    format!("{first}..{}", next - 1)
                }
            ));
        } else {
            run.extend_from_slice(&part.dataset.run);
        }
        fz.extend_from_slice(&part.dataset.fz);
        let own = crate::data::runs_of(&run[first_row..]);
        sources.extend(part.sources.iter().map(|s| SourceFile {
            runs: own.clone(),
            ..s.clone()
        }));
    }
    if clash {
        notes.push(format!(
            "run ids repeat across files: runs renumbered in file order ({})",
            renumbered.join(", ")
        ));
    }
    (run, fz, sources)
}

/// Joins the optional columns into `ds`, each kept only when every file has it (a column
/// some files lack is dropped, noted). Each file's column is released once joined, so the
/// files' columns and the joined ones are not all held at once.
fn merge_optional_columns(parts: &mut [Loaded], ds: &mut Dataset, notes: &mut Vec<String>) {
    for q in Quantity::ALL {
        if matches!(q, Quantity::Run | Quantity::Fz) {
            continue;
        }
        let missing: Vec<&str> = parts
            .iter()
            .filter(|p| p.dataset.column(q).is_none())
            .map(|p| p.dataset.source.as_str())
            .collect();
        if missing.len() == parts.len() {
            continue;
        }
        if !missing.is_empty() {
            notes.push(format!(
                "{} dropped: missing in {}",
                q.name(),
                missing.join(", ")
            ));
            continue;
        }
        let mut joined = Vec::with_capacity(parts.iter().map(|p| p.dataset.len()).sum());
        for part in parts.iter_mut() {
            if let Some(column) = part.dataset.column_slot(q).and_then(Option::take) {
                joined.extend_from_slice(&column);
            }
        }
        if let Some(slot) = ds.column_slot(q) {
            *slot = Some(joined.into());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display() {
        let e = InputError::new("data.csv", "\"abc\" is not a number")
            .at_line(17)
            .in_column("alpha_deg");
        assert_eq!(
            e.to_string(),
            "data.csv:17: column alpha_deg: \"abc\" is not a number"
        );
        assert_eq!(
            InputError::new("x.tdx", "no data rows").to_string(),
            "x.tdx: no data rows"
        );
    }

    #[test]
    fn detect() {
        let p = Path::new;
        assert_eq!(Format::detect(p("a.CSV"), "**HEADER"), Format::Csv);
        assert_eq!(Format::detect(p("a.Tdx"), "run,fz_N"), Format::Tydex);
        assert_eq!(
            Format::detect(p("a.dat"), "\n! comment\n  **HEADER\n"),
            Format::Tydex
        );
        assert_eq!(Format::detect(p("a"), "run,fz_N\n"), Format::Csv);
        assert_eq!(Format::detect(p("a.DAT"), "t\nFZ SA\nN deg\n"), Format::Ttc);
        assert_eq!(Format::detect(p("a.log"), "t\nFZ SA\nN deg\n"), Format::Ttc);
        assert_eq!(Format::detect(p("a.txt"), ""), Format::Csv);
        assert_eq!(Format::detect(p("a.MAT"), "x"), Format::Mat);
        assert_eq!(
            Format::detect(p("a.bin"), "MATLAB 5.0 MAT-file, Platform: GLNXA64"),
            Format::Mat
        );
        assert!(mat_twin(p("d/B1run2.dat"), p("d/B1run2.MAT")));
        assert!(!mat_twin(p("d/B1run2.dat"), p("e/B1run2.mat")));
        assert!(!mat_twin(p("d/B1run2.dat"), p("d/B1run2.dat")));
    }
}
