//! A table handed over in memory, such as a pandas DataFrame: columns named as in CSV
//! (`run`, `fz_N`, `alpha_deg`, `kappa`, ...; see [`super::csv`]), each a column of 64-bit
//! floats, rows numbered from 0 (pandas' `iloc`). It is read as the CSV reader reads a file,
//! with the same names, units, checks and notes; an error names the column and every row at
//! fault rather than the first.

use sha2::{Digest, Sha256};

use super::csv::{Kind, SPELLING, header_kinds};
use super::table::{self, Column, Table};
use super::{Format, InputError, Loaded};
use crate::data::Quantity;

/// One column as handed over.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameColumn {
    pub name: String,
    pub values: Vec<f64>,
    /// Rows whose cell was not a number at all (text, an object); their `values` are NaN.
    pub not_numbers: Vec<usize>,
}

/// Rows of `values` where `bad` holds, with those already known to be bad.
fn rows_where(values: &[f64], known: &[usize], bad: impl Fn(f64) -> bool) -> Vec<usize> {
    let mut rows: Vec<usize> = values
        .iter()
        .enumerate()
        .filter(|(_, v)| bad(**v))
        .map(|(i, _)| i)
        .chain(known.iter().copied())
        .collect();
    rows.sort_unstable();
    rows.dedup();
    rows
}

/// A table read: the data set, and the name of its load's column (messages about rows of the
/// load name it).
#[derive(Debug)]
pub struct Frame {
    pub loaded: Loaded,
    pub load_column: Option<String>,
}

/// Reads the columns as one data set; `source` names it in messages and in the report.
pub fn read(columns: Vec<FrameColumn>, source: &str) -> Result<Frame, InputError> {
    let n = columns.first().map_or(0, |c| c.values.len());
    if let Some(c) = columns.iter().find(|c| c.values.len() != n) {
        return Err(InputError::new(
            source,
            format!(
                "the columns differ in length: {} has {} rows, {} has {n}",
                c.name,
                c.values.len(),
                columns[0].name
            ),
        )
        .in_column(&c.name));
    }
    let names: Vec<String> = columns.iter().map(|c| c.name.clone()).collect();
    let mut notes = Vec::new();
    let kinds = header_kinds(&names, None, "", source, &mut notes)?;
    if n == 0 {
        return Err(InputError::new(source, "no data rows: the table is empty"));
    }
    let sha256 = content_sha256(&columns);
    let load_column = names
        .iter()
        .zip(&kinds)
        .find(|(_, k)| matches!(k, Kind::Real(Quantity::Fz, _)))
        .map(|(n, _)| n.clone());
    let mut tbl = Table {
        lines: (0..n).collect(),
        in_memory: true,
        ..Table::default()
    };
    for (col, kind) in columns.into_iter().zip(kinds) {
        add_column(&mut tbl, col, kind, source)?;
    }
    let dataset = table::finish(source, tbl, &SPELLING, &mut notes)?;
    let loaded = Loaded {
        dataset,
        notes,
        sources: Vec::new(),
    };
    let mut loaded = super::sourced(loaded, None, source, Format::Frame, &[]);
    for s in &mut loaded.sources {
        s.sha256.clone_from(&sha256);
    }
    Ok(Frame {
        loaded,
        load_column,
    })
}

/// Checks one column and adds it to the table: numbers, finite, run ids whole.
fn add_column(
    tbl: &mut Table,
    col: FrameColumn,
    kind: Kind,
    source: &str,
) -> Result<(), InputError> {
    let fault = |rows: Vec<usize>, m: String| {
        InputError::new(source, m)
            .in_column(&col.name)
            .at_rows(rows)
    };
    match kind {
        Kind::Ignored => {}
        Kind::Run => {
            let bad = rows_where(&col.values, &col.not_numbers, |v| {
                table::run_id(v).is_none()
            });
            if !bad.is_empty() {
                return Err(fault(bad, "run ids must be integers".to_string()));
            }
            let ids = col
                .values
                .iter()
                .filter_map(|v| table::run_id(*v))
                .collect();
            tbl.run = Some((col.name, ids));
        }
        Kind::Real(q, conversion) => {
            let bad = rows_where(&col.values, &col.not_numbers, |v| !v.is_finite());
            if !bad.is_empty() {
                let what = if col.not_numbers.is_empty() {
                    "missing or not finite (NaN or infinite): every sample needs a value"
                } else {
                    "not numbers, missing or not finite: every sample needs a number"
                };
                return Err(fault(bad, what.to_string()));
            }
            let values: Vec<f64> = col.values.iter().map(|v| conversion.apply(*v)).collect();
            tbl.columns.push((
                q,
                Column {
                    label: col.name,
                    values,
                },
            ));
        }
    }
    Ok(())
}

/// SHA-256 of the table as handed over: per column, its name, a newline, then its values as
/// little-endian 64-bit floats.
fn content_sha256(columns: &[FrameColumn]) -> String {
    let mut h = Sha256::new();
    for c in columns {
        h.update(c.name.as_bytes());
        h.update(b"\n");
        for v in &c.values {
            h.update(v.to_le_bytes());
        }
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Quantity;

    fn col(name: &str, values: &[f64]) -> FrameColumn {
        FrameColumn {
            name: name.to_string(),
            values: values.to_vec(),
            not_numbers: Vec::new(),
        }
    }

    fn sweep() -> Vec<FrameColumn> {
        vec![
            col("run", &[1.0, 1.0, 2.0, 2.0]),
            col("fz_kN", &[4.0, 4.0, 5.0, 5.0]),
            col("alpha_deg", &[-2.0, 2.0, -4.0, 4.0]),
            col("fy_N", &[-800.0, 800.0, -1500.0, 1500.0]),
            col("comment", &[0.0; 4]),
        ]
    }

    #[test]
    fn reads_as_the_csv_reader_reads_the_same_table() {
        let frame = read(sweep(), "DataFrame").unwrap().loaded;
        let text = "run,fz_kN,alpha_deg,fy_N,comment\n1,4,-2,-800,0\n1,4,2,800,0\n2,5,-4,-1500,0\n2,5,4,1500,0\n";
        let file = super::super::read_str(text, "t.csv", Format::Csv).unwrap();
        assert_eq!(frame.dataset.fz, file.dataset.fz);
        assert_eq!(frame.dataset.alpha, file.dataset.alpha);
        assert_eq!(frame.dataset.fy, file.dataset.fy);
        assert_eq!(frame.dataset.run, file.dataset.run);
        assert_eq!(frame.dataset.column(Quantity::Fz).unwrap()[2], 5000.0);
        assert_eq!(frame.notes, file.notes);
        assert_eq!(frame.sources[0].format, Format::Frame);
        assert_eq!(frame.sources[0].rows, 4);
        assert_eq!(frame.sources[0].sha256.len(), 64);
    }

    #[test]
    fn errors_name_the_column_and_every_row_at_fault() {
        let mut cols = sweep();
        cols[1].values[1] = f64::NAN;
        cols[1].values[3] = f64::INFINITY;
        let e = read(cols, "DataFrame").unwrap_err();
        assert_eq!(e.column.as_deref(), Some("fz_kN"));
        assert_eq!(e.rows, vec![1, 3]);
        assert_eq!(
            e.to_string(),
            "DataFrame: column fz_kN: 2 rows (1, 3): missing or not finite (NaN or infinite): every sample needs a value"
        );

        let mut cols = sweep();
        cols[2].values[0] = f64::NAN;
        cols[2].not_numbers = vec![0];
        let e = read(cols, "DataFrame").unwrap_err();
        assert_eq!(
            (e.column.as_deref(), e.rows.as_slice()),
            (Some("alpha_deg"), &[0][..])
        );
        assert!(e.message.starts_with("not numbers"));

        let mut cols = sweep();
        cols[0].values[2] = 1.5;
        let e = read(cols, "DataFrame").unwrap_err();
        assert_eq!(
            (e.column.as_deref(), e.rows.as_slice()),
            (Some("run"), &[2][..])
        );
    }

    #[test]
    fn names_and_shapes_are_checked_as_in_a_csv_header() {
        let mut cols = sweep();
        cols[2].name = "alpha_grad".into();
        let e = read(cols, "DataFrame").unwrap_err();
        assert_eq!(e.column.as_deref(), Some("alpha_grad"));
        assert!(e.message.contains("not accepted for alpha"), "{e}");

        let cols: Vec<FrameColumn> = sweep().into_iter().filter(|c| c.name != "fz_kN").collect();
        let e = read(cols, "DataFrame").unwrap_err();
        assert!(e.message.starts_with("missing required column"), "{e}");

        let mut cols = sweep();
        cols[3].values.pop();
        assert!(
            read(cols, "DataFrame")
                .unwrap_err()
                .message
                .contains("differ in length")
        );

        let empty: Vec<FrameColumn> = sweep().into_iter().map(|c| col(&c.name, &[])).collect();
        assert!(
            read(empty, "DataFrame")
                .unwrap_err()
                .message
                .contains("empty")
        );
    }
}
