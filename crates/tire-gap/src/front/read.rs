//! Reading data sets as every front end reads them: each file read as it is
//! ([`crate::io::input`]), its rows and channels made ready by the method's preparation
//! ([`crate::method::prepare::clean_file`]) before the files are merged, so that what one
//! file's rules leave out is counted in that file's notes.

use std::path::{Path, PathBuf};

use crate::io::input::frame::{self, FrameColumn};
use crate::io::input::{self, Format, InputError, Loaded, expand, merge};
use crate::method::prepare::clean_file;

/// One file's data set, as read, made ready: see [`clean_file`]. Its record (rows, runs) is
/// of what is kept. A refusal names the file, and for a table in memory the rows at fault.
pub fn prepared(mut loaded: Loaded) -> Result<Loaded, InputError> {
    let (source, format) = loaded
        .sources
        .first()
        .map(|s| (s.file.clone(), s.format))
        .unwrap_or_else(|| (loaded.dataset.source.clone(), Format::Csv));
    let programme = matches!(format, Format::Ttc | Format::Mat);
    // A TYDEX file is one measurement; the test plan is the set of them.
    let plan = format != Format::Tydex;
    clean_file(&mut loaded.dataset, &mut loaded.notes, programme, plan).map_err(|r| {
        let e = InputError::new(&source, r.message);
        // Rows are named for a table in memory; a file's message names its first row.
        match format {
            Format::Frame => e.at_rows(r.rows),
            _ => e,
        }
    })?;
    for s in &mut loaded.sources {
        s.rows = loaded.dataset.len();
        s.runs = loaded.dataset.runs();
    }
    Ok(loaded)
}

/// Text already in memory read as `format` and made ready; `source` names it.
pub fn read_str(text: &str, source: &str, format: Format) -> Result<Loaded, InputError> {
    prepared(input::read_str(text, source, format)?)
}

/// One file read (see [`input::load`]) and made ready.
pub fn load(path: &Path) -> Result<Loaded, InputError> {
    prepared(input::load(path)?)
}

/// A file's contents, already in memory, read as [`load`] does.
pub fn load_bytes(path: &Path, bytes: Vec<u8>) -> Result<Loaded, InputError> {
    prepared(input::load_bytes(path, bytes)?)
}

/// Several files, each read and made ready, merged into one data set (see [`merge`]).
pub fn load_many<P: AsRef<Path> + Sync>(paths: &[P]) -> Result<Loaded, InputError> {
    match paths {
        [] => Err(InputError::new("", "no input files")),
        [one] => load(one.as_ref()),
        // The files read side by side; the first refusal in file order is the error.
        _ => merge(
            crate::method::parallel::parallel_map(paths, |p| load(p.as_ref()))
                .into_iter()
                .collect::<Result<Vec<_>, _>>()?,
        ),
    }
}

/// Files and directories (see [`expand`]) as one data set ([`load_many`]).
pub fn load_paths(paths: &[PathBuf]) -> Result<Loaded, InputError> {
    let (files, mut notes) = expand(paths)?;
    let mut loaded = load_many(&files)?;
    notes.append(&mut loaded.notes);
    loaded.notes = notes;
    Ok(loaded)
}

/// A table in memory (see [`frame::read`]) made ready; a refusal for rows of the load names
/// the load's column.
pub fn read_frame(columns: Vec<FrameColumn>, source: &str) -> Result<Loaded, InputError> {
    let read = frame::read(columns, source)?;
    let column = read.load_column;
    prepared(read.loaded).map_err(|e| {
        match column.filter(|_| !e.rows.is_empty() && e.column.is_none()) {
            Some(column) => e.in_column(&column),
            None => e,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn column(name: &str, values: &[f64]) -> FrameColumn {
        FrameColumn {
            name: name.into(),
            values: values.to_vec(),
            not_numbers: Vec::new(),
        }
    }

    /// A lateral sweep of 21 rows at 4 kN, but row 7 (line 8 of the file) at 400 kN.
    fn sweep_with_one_load_no_tire_carries() -> String {
        let mut text = String::from("run,fz_kN,alpha_deg,fy_N\n");
        for i in 0..21 {
            let alpha = -5.0 + 0.5 * i as f64;
            let fz = if i == 7 { 400.0 } else { 4.0 };
            text += &format!("1,{fz},{alpha},{}\n", 900.0 * alpha);
        }
        text
    }

    #[test]
    fn the_reader_keeps_every_row_and_the_preparation_leaves_out_the_doubtful_ones() {
        let text = sweep_with_one_load_no_tire_carries();
        let raw = input::read_str(&text, "s.csv", Format::Csv).unwrap();
        assert_eq!(raw.dataset.len(), 21);
        assert_eq!(raw.sources[0].rows, 21);
        assert!(!raw.notes.iter().any(|n| n.contains("left out")));

        let ready = read_str(&text, "s.csv", Format::Csv).unwrap();
        assert_eq!(ready.dataset.len(), 20);
        assert_eq!(ready.sources[0].rows, 20);
        assert!(!ready.dataset.fz.contains(&400_000.0));
        assert!(
            ready
                .notes
                .iter()
                .any(|n| n.starts_with("1 of 21 rows left out: Fz outside")),
            "{:?}",
            ready.notes
        );
    }

    /// A slip-ratio sweep of 40 rows at 11 m/s from -0.1 up to `top`, after 5 rows at
    /// standstill whose slip ratio reads 30 (a rig's slip ratio with the wheel not turning).
    fn sweep_after_standstill(top: f64) -> String {
        let mut text = String::from("run,fz_N,kappa,fx_N,vx_mps\n");
        for _ in 0..5 {
            text += "1,3000,30,0,0\n";
        }
        for i in 0..40 {
            let kappa = -0.1 + (top + 0.1) * i as f64 / 39.0;
            text += &format!("1,3000,{kappa},{},11\n", 2700.0 * (10.0 * kappa).tanh());
        }
        text
    }

    #[test]
    fn a_slip_ratio_above_one_is_noted_only_on_the_rows_kept() {
        let notes = |text: &str| {
            read_str(text, "k.csv", Format::Csv)
                .unwrap()
                .notes
                .into_iter()
                .filter(|n| n.starts_with("|kappa| reaches"))
                .collect::<Vec<_>>()
        };
        assert_eq!(notes(&sweep_after_standstill(0.3)), Vec::<String>::new());
        let noted = notes(&sweep_after_standstill(1.5));
        assert!(
            noted.len() == 1 && noted[0].starts_with("|kappa| reaches 1.5 on"),
            "{noted:?}"
        );
    }

    #[test]
    fn a_tables_load_refused_on_half_its_rows_names_its_column_and_rows() {
        // A load no tire carries on half the rows: the load is required, so this is an
        // error (a few such rows would be left out, see `method::prepare::row_rules`).
        let cols = vec![
            column("run", &[1.0, 1.0, 2.0, 2.0]),
            column("fz_kN", &[4.0, 400.0, 5.0, 500.0]),
            column("alpha_deg", &[-2.0, 2.0, -4.0, 4.0]),
            column("fy_N", &[-800.0, 800.0, -1500.0, 1500.0]),
        ];
        assert!(frame::read(cols.clone(), "DataFrame").is_ok());
        let e = read_frame(cols, "DataFrame").unwrap_err();
        assert!(
            e.message
                .starts_with("the load is implausible on 2 of 4 rows (first at row 2 of the file"),
            "{e}"
        );
        assert_eq!(
            (e.column.as_deref(), e.rows.as_slice()),
            (Some("fz_kN"), &[1, 3][..])
        );
    }
}
