//! What both readers share: columns already in internal units, plus the decisions that
//! turn them into a [`Dataset`] (which measured channels are usable, how samples split into
//! runs).

use super::InputError;
use crate::data::{Dataset, Quantity};

/// One real-valued column in internal units, named as in the file.
#[derive(Debug, Clone)]
pub(crate) struct Column {
    pub label: String,
    pub values: Vec<f64>,
}

/// Samples read from one file, before the dataset-level checks.
#[derive(Debug, Clone, Default)]
pub(crate) struct Table {
    /// The file line of each sample, for error messages; its row (from 0) when the table
    /// was given in memory (`in_memory`).
    pub lines: Vec<usize>,
    pub in_memory: bool,
    /// Run ids and the name of the column they came from.
    pub run: Option<(String, Vec<i64>)>,
    pub columns: Vec<(Quantity, Column)>,
}

impl Table {
    pub fn column(&self, q: Quantity) -> Option<&Column> {
        self.columns.iter().find(|(k, _)| *k == q).map(|(_, c)| c)
    }

    pub fn column_mut(&mut self, q: Quantity) -> Option<&mut Column> {
        self.columns
            .iter_mut()
            .find(|(k, _)| *k == q)
            .map(|(_, c)| c)
    }
}

/// How a file format spells things, for messages.
pub(crate) struct Spelling {
    /// Column or channel to name when the load is missing, and the hint to show.
    pub fz_missing: (&'static str, &'static str),
    /// How to name a channel of `q` (for the "need fx with kappa" message).
    pub name: fn(Quantity) -> &'static str,
}

/// Parses one numeric cell: empty, non-numeric and non-finite cells are errors (the
/// message quotes the cell). Fortran `D` exponents (`1.5D+03`) are accepted.
pub(crate) fn parse_number(text: &str) -> Result<f64, String> {
    let t = text.trim();
    if t.is_empty() {
        return Err("empty cell: every sample needs a value".to_string());
    }
    let fortran = |t: &str| {
        let one_d = t.chars().filter(|c| c.eq_ignore_ascii_case(&'d')).count() == 1;
        let digits = t.chars().any(|c| c.is_ascii_digit());
        (one_d && digits)
            .then(|| t.replace(['D', 'd'], "E").parse::<f64>().ok())
            .flatten()
    };
    let parsed = t.parse::<f64>().ok().or_else(|| fortran(t));
    match parsed {
        Some(v) if v.is_finite() => Ok(v),
        Some(_) => Err(format!("\"{t}\" is not a finite number")),
        None if t.contains(',') && t.replace(',', ".").parse::<f64>().is_ok() => Err(format!(
            "\"{t}\" is not a number (use '.' as the decimal point)"
        )),
        None => Err(format!("\"{t}\" is not a number")),
    }
}

/// Parses a run id: an integer, or a real with no fractional part (`3.0`).
pub(crate) fn parse_run(text: &str) -> Result<i64, String> {
    let t = text.trim();
    if let Ok(r) = t.parse::<i64>() {
        return Ok(r);
    }
    run_id(parse_number(t)?).ok_or_else(|| format!("\"{t}\" is not an integer run id"))
}

/// A real as a run id: finite, without a fractional part, and exact (up to 2^53).
pub(crate) fn run_id(v: f64) -> Option<i64> {
    // Beyond 2^53 a real no longer holds every integer exactly.
    const EXACT: f64 = 9_007_199_254_740_992.0;
    (v.is_finite() && v.fract() == 0.0 && v.abs() <= EXACT).then_some(v as i64)
}

/// Turns a table into a dataset: measured channels without their slip dropped (with a
/// note), at least one usable measured channel required, runs assigned. Values a tire test
/// cannot give are judged later, row by row and channel by channel
/// (`crate::method::prepare::row_rules`).
pub(crate) fn finish(
    source: &str,
    table: Table,
    spelling: &Spelling,
    notes: &mut Vec<String>,
) -> Result<Dataset, InputError> {
    let n = table.lines.len();
    if n == 0 {
        return Err(InputError::new(source, "no data rows"));
    }
    if table.column(Quantity::Fz).is_none() {
        let (column, hint) = spelling.fz_missing;
        return Err(
            InputError::new(source, format!("missing required column: {hint}")).in_column(column),
        );
    }
    debug_assert!(table.columns.iter().all(|(_, c)| c.values.len() == n));

    let mut ds = Dataset {
        source: source.to_string(),
        ..Dataset::default()
    };
    let run = table.run.clone();
    let place = if table.in_memory { "rows" } else { "lines" };
    let time_label = table.column(Quantity::Time).map(|c| c.label.clone());
    for (q, col) in table.columns {
        if q == Quantity::Fz {
            ds.fz = col.values.into();
        } else if let Some(slot) = ds.column_slot(q) {
            *slot = Some(col.values.into());
        }
    }
    drop_unpaired(&mut ds, spelling.name, notes);
    if !has_measured(&ds) {
        let name = spelling.name;
        return Err(InputError::new(
            source,
            format!(
                "no measured force or moment with the slip it depends on: need {} with {}, or {} / {} with {}",
                name(Quantity::Fx),
                name(Quantity::Kappa),
                name(Quantity::Fy),
                name(Quantity::Mz),
                name(Quantity::Alpha),
            ),
        ));
    }

    ds.run = match run {
        Some((_, ids)) => ids,
        None => runs_from_time(
            ds.time.as_deref(),
            (&table.lines, place),
            time_label,
            n,
            notes,
        ),
    }
    .into();
    sanity_notes(&ds, notes);
    Ok(ds)
}

/// Whether any measured channel is left.
pub(crate) fn has_measured(ds: &Dataset) -> bool {
    ds.fx.is_some() || ds.fy.is_some() || ds.mz.is_some()
}

/// Drops measured channels whose slip input is missing: Fx needs kappa; Fy and Mz need
/// alpha. Each drop is noted.
pub(crate) fn drop_unpaired(
    ds: &mut Dataset,
    name: fn(Quantity) -> &'static str,
    notes: &mut Vec<String>,
) {
    let pairs = [
        (Quantity::Fx, Quantity::Kappa),
        (Quantity::Fy, Quantity::Alpha),
        (Quantity::Mz, Quantity::Alpha),
    ];
    for (measured, slip) in pairs {
        if ds.has(measured) && !ds.has(slip) {
            if let Some(slot) = ds.column_slot(measured) {
                *slot = None;
            }
            notes.push(format!(
                "{} ignored: it needs the slip {} ({}), which is missing",
                name(measured),
                slip.name(),
                name(slip)
            ));
        }
    }
}

/// Run ids when the file has no run column: split where time goes backwards, else one run.
fn runs_from_time(
    time: Option<&[f64]>,
    (lines, place): (&[usize], &str),
    time_label: Option<String>,
    n: usize,
    notes: &mut Vec<String>,
) -> Vec<i64> {
    let mut ids = Vec::with_capacity(n);
    let mut resets = Vec::new();
    let mut id = 1;
    if let Some(t) = time {
        for i in 0..n {
            if i > 0 && t[i] < t[i - 1] {
                id += 1;
                resets.push(lines[i]);
            }
            ids.push(id);
        }
    } else {
        ids.resize(n, 1);
    }
    if resets.is_empty() {
        let why = match &time_label {
            Some(label) => format!("and {label} never decreases"),
            None => "and no time column".to_string(),
        };
        notes.push(format!(
            "no run column {why}: the whole file is one run, so cross-validation by run will not be possible"
        ));
    } else {
        const SHOWN: usize = 5;
        let mut at = resets
            .iter()
            .take(SHOWN)
            .map(|l| l.to_string())
            .collect::<Vec<_>>()
            .join(", ");
        if resets.len() > SHOWN {
            at.push_str(", ...");
        }
        notes.push(format!(
            "no run column: split into {} runs where {} decreases (at {place} {at})",
            resets.len() + 1,
            time_label.unwrap_or_default()
        ));
    }
    ids
}

/// Notes about values that are legal but worth a look.
fn sanity_notes(ds: &Dataset, notes: &mut Vec<String>) {
    let unloaded = ds.fz.iter().filter(|&&f| f <= 0.0).count();
    if unloaded > 0 {
        notes.push(format!(
            "{unloaded} of {} samples have Fz <= 0 (wheel off the ground or a load-cell offset)",
            ds.len()
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_number(" 1.5 "), Ok(1.5));
        assert_eq!(parse_number("-2e3"), Ok(-2000.0));
        assert_eq!(parse_number("1.5D+03"), Ok(1500.0));
        assert_eq!(parse_number("abc"), Err("\"abc\" is not a number".into()));
        assert_eq!(parse_number("D"), Err("\"D\" is not a number".into()));
        assert_eq!(
            parse_number("NaN"),
            Err("\"NaN\" is not a finite number".into())
        );
        assert_eq!(
            parse_number("-inf"),
            Err("\"-inf\" is not a finite number".into())
        );
        assert!(parse_number("").unwrap_err().starts_with("empty cell"));
        assert!(parse_number("1,5").unwrap_err().contains("decimal point"));
    }

    #[test]
    fn runs() {
        assert_eq!(parse_run("7"), Ok(7));
        assert_eq!(parse_run("-2"), Ok(-2));
        assert_eq!(parse_run("3.0"), Ok(3));
        assert_eq!(
            parse_run("1.5"),
            Err("\"1.5\" is not an integer run id".into())
        );
        assert_eq!(parse_run("x"), Err("\"x\" is not a number".into()));
    }
}
