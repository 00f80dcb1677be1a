//! Tire Test Consortium (TTC) ASCII run files (`.dat`), one file = one run.
//!
//! Line 1 is a title (e.g. `Data from B1464run23.mat`), line 2 the channel names and line 3
//! their units, separated by blanks or tabs (`ET V N SA IA RL RE P FX FY FZ MX MZ ... TSTI TSTC
//! TSTO ... SR SL` / `s kph rpm deg deg cm cm kPa N N N N-m N-m ... degC degC degC ... none
//! none`, in any order and any subset); then one row of numbers per sample.
//!
//! **Channels used** (names ignore case; the others are listed in a note):
//!
//! | quantity    | channel | usual unit |
//! |-------------|---------|------------|
//! | time        | `ET`    | s          |
//! | speed       | `V`     | kph (mph)  |
//! | Fz          | `FZ`    | N (lb)     |
//! | alpha       | `SA`    | deg        |
//! | kappa       | `SR`, else `SL` | none |
//! | gamma       | `IA`    | deg        |
//! | pressure    | `P`     | kPa (psi)  |
//! | temperature | mean of `TSTI`, `TSTC`, `TSTO` (tread surface inside, centre, outside), else `TSTC` | degC (degF) |
//! | Fx, Fy, Mz  | `FX`, `FY`, `MZ` | N, N-m (lb, ft-lb) |
//!
//! `SR` is TTC's slip ratio from the effective rolling radius, `SL` the one from the loaded
//! radius; which one was read is noted. `AMBTMP` is the ambient temperature, never the tread's.
//!
//! **Axes.** TTC data are in SAE axes (x forward, y right, z down): a positive slip angle gives
//! a negative lateral force, and the load is a negative `FZ`. tire-gap works in the axes of
//! the 1987 paper (x forward, y right, z down, alpha > 0 giving Fy > 0): the y and z axes are
//! the same, the slip angle's sign is not. So `alpha = -SA`, `Fz = -FZ`, and camber, slip
//! ratio, Fx, Fy and Mz keep their sign (see [`sae_to_paper`]). If the median of `FZ` is
//! positive, the file already gives the load positive and it is kept (noted).
//!
//! **Run id.** The integer after `run` in the file name (`B1464run23.dat` -> 23), else in the
//! title, else 1. Several files are one data set through `load_many`.

use std::path::Path;

use super::table::{self, Column, Spelling, Table};
use super::{InputError, Loaded};
use crate::data::Quantity;
use crate::stats::median;
use crate::units;

/// TTC channel names per quantity, by preference (tread temperature is handled apart).
const CHANNELS: &[(Quantity, &[&str])] = &[
    (Quantity::Time, &["ET"]),
    (Quantity::Speed, &["V"]),
    (Quantity::Fz, &["FZ"]),
    (Quantity::Alpha, &["SA"]),
    (Quantity::Kappa, &["SR", "SL"]),
    (Quantity::Gamma, &["IA"]),
    (Quantity::Pressure, &["P"]),
    (Quantity::Fx, &["FX"]),
    (Quantity::Fy, &["FY"]),
    (Quantity::Mz, &["MZ"]),
];

/// Tread surface temperatures: inside, centre, outside.
const TREAD: [&str; 3] = ["TSTI", "TSTC", "TSTO"];

/// The preferred channel name of each quantity.
pub fn channel_name(q: Quantity) -> &'static str {
    match q {
        Quantity::Temperature => "TSTC",
        _ => CHANNELS
            .iter()
            .find(|(k, _)| *k == q)
            .map_or("run", |(_, names)| names[0]),
    }
}

const SPELLING: Spelling = Spelling {
    fz_missing: ("FZ", "channel FZ, the vertical load"),
    name: channel_name,
};

/// Whether `text` looks like a TTC run file: a second line naming `FZ` and a slip channel
/// (`SA`, `SR` or `SL`) and a third line with as many entries.
pub fn looks_like(text: &str) -> bool {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty()).skip(1);
    let (Some(names), Some(units)) = (lines.next(), lines.next()) else {
        return false;
    };
    let names: Vec<&str> = names.split_whitespace().collect();
    let has = |n: &str| names.iter().any(|x| x.eq_ignore_ascii_case(n));
    has("FZ")
        && ["SA", "SR", "SL"].iter().any(|n| has(n))
        && units.split_whitespace().count() == names.len()
}

/// The SAE sign convention of TTC data mapped to the paper's axes, per quantity: the factor
/// a value is multiplied by (the load's sign is decided from the data, see the module doc).
pub fn sae_to_paper(q: Quantity) -> f64 {
    match q {
        Quantity::Alpha => -1.0,
        _ => 1.0,
    }
}

/// The integer following `run` (any case) in `text`, if any.
fn run_number(text: &str) -> Option<i64> {
    let lower = text.to_ascii_lowercase();
    lower.match_indices("run").find_map(|(at, _)| {
        let digits: String = lower[at + 3..]
            .chars()
            .skip_while(|c| *c == '_' || *c == ' ')
            .take_while(char::is_ascii_digit)
            .collect();
        digits.parse().ok()
    })
}

/// Reads a TTC run file held in memory; `source` names it (its file name gives the run id).
pub fn read_str(text: &str, source: &str) -> Result<Loaded, InputError> {
    let err = |m: String| InputError::new(source, m);
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_start_matches('\u{feff}')))
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, title) = lines
        .next()
        .ok_or_else(|| err("the file is empty".into()))?;
    let (names_line, names) = lines
        .next()
        .ok_or_else(|| err("no channel-name line (line 2 of a TTC run file)".into()))?;
    let (units_line, unit_text) = lines
        .next()
        .ok_or_else(|| err("no unit line (line 3 of a TTC run file)".into()))?;
    let names: Vec<&str> = names.split_whitespace().collect();
    let unit_of: Vec<&str> = unit_text.split_whitespace().collect();
    if unit_of.len() != names.len() {
        return Err(err(format!(
            "{} units for {} channels: the unit line must give one unit per channel",
            unit_of.len(),
            names.len()
        ))
        .at_line(units_line));
    }
    let position = |n: &str| names.iter().position(|x| x.eq_ignore_ascii_case(n));

    // The channels read: (quantity, position, conversion, column).
    let mut used = Vec::new();
    let mut notes = Vec::new();
    for (q, candidates) in CHANNELS {
        let Some((name, i)) = candidates.iter().find_map(|n| position(n).map(|i| (*n, i))) else {
            continue;
        };
        if *q == Quantity::Kappa {
            notes.push(match name {
                "SR" => "slip ratio read from SR (effective rolling radius)".to_string(),
                _ => "slip ratio read from SL (loaded radius): there is no SR channel".to_string(),
            });
        }
        used.push((*q, i, name));
    }
    let tread: Vec<Option<usize>> = TREAD.iter().map(|n| position(n)).collect();
    let tread_used: Vec<usize> = match tread.as_slice() {
        [Some(a), Some(b), Some(c)] => {
            notes.push("tread temperature: the mean of TSTI, TSTC and TSTO".to_string());
            vec![*a, *b, *c]
        }
        [_, Some(b), _] => {
            notes.push("tread temperature: TSTC (not all of TSTI, TSTC, TSTO present)".into());
            vec![*b]
        }
        _ => Vec::new(),
    };
    let conversions = used
        .iter()
        .map(|&(q, i, name)| (q, i, name))
        .chain(
            tread_used
                .iter()
                .map(|&i| (Quantity::Temperature, i, names[i])),
        )
        .map(|(q, i, name)| {
            units::conversion(q, unit_of[i]).ok_or_else(|| {
                err(format!(
                    "unit \"{}\" is not accepted for {} (accepted: {})",
                    unit_of[i],
                    q.name(),
                    units::accepted_list(q)
                ))
                .at_line(units_line)
                .in_column(name)
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let ignored: Vec<&str> = names
        .iter()
        .enumerate()
        .filter(|(i, _)| !used.iter().any(|u| u.1 == *i) && !tread_used.contains(i))
        .map(|(_, n)| *n)
        .collect();
    if !ignored.is_empty() {
        notes.push(format!("channels not used: {}", ignored.join(" ")));
    }

    let mut tbl = Table::default();
    let mut cols: Vec<Column> = used
        .iter()
        .map(|(_, _, name)| Column {
            label: name.to_string(),
            values: Vec::new(),
        })
        .collect();
    let mut temperature = Vec::new();
    let mut row = Vec::with_capacity(names.len());
    for (line, text) in lines {
        row.clear();
        for token in text.split_whitespace() {
            row.push(token);
        }
        if row.len() != names.len() {
            return Err(err(format!(
                "{} values for {} channels (line {names_line} names them)",
                row.len(),
                names.len()
            ))
            .at_line(line));
        }
        let value = |i: usize| {
            table::parse_number(row[i]).map_err(|m| err(m).at_line(line).in_column(names[i]))
        };
        for (k, &(q, i, _)) in used.iter().enumerate() {
            cols[k]
                .values
                .push(sae_to_paper(q) * conversions[k].apply(value(i)?));
        }
        if !tread_used.is_empty() {
            let mut sum = 0.0;
            for (k, &i) in tread_used.iter().enumerate() {
                sum += conversions[used.len() + k].apply(value(i)?);
            }
            temperature.push(sum / tread_used.len() as f64);
        }
        tbl.lines.push(line);
    }
    tbl.columns = used.iter().map(|u| u.0).zip(cols).collect();
    if !tread_used.is_empty() {
        tbl.columns.push((
            Quantity::Temperature,
            Column {
                label: tread_used
                    .iter()
                    .map(|&i| names[i])
                    .collect::<Vec<_>>()
                    .join("+"),
                values: temperature,
            },
        ));
    }

    // SAE to the paper's axes: the slip angle was negated above; the load is made positive.
    notes.push(
        "TTC axes are SAE (x forward, y right, z down); converted to the paper's axes: \
         alpha = -SA (a positive SAE slip angle gives a negative lateral force), Fz = -FZ; \
         camber, slip ratio, Fx, Fy and Mz keep their sign"
            .to_string(),
    );
    if let Some(col) = tbl.column_mut(Quantity::Fz) {
        if median(&col.values).is_some_and(|m| m < 0.0) {
            col.values.iter_mut().for_each(|v| *v = -*v);
        } else {
            notes.push("FZ is mostly positive: taken as the load as it is (not negated)".into());
        }
    }

    // One file is one run.
    let stem = Path::new(source)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("");
    let run = run_number(stem).or_else(|| run_number(title));
    if run.is_none() {
        notes.push("no run number in the file name or title: run 1".to_string());
    }
    tbl.run = Some(("file".to_string(), vec![run.unwrap_or(1); tbl.lines.len()]));
    let dataset = table::finish(source, tbl, &SPELLING, &mut notes)?;
    Ok(Loaded {
        dataset,
        notes,
        sources: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_numbers_come_from_the_name_or_the_title() {
        assert_eq!(run_number("B1464run23"), Some(23));
        assert_eq!(run_number("b1654_RUN_7"), Some(7));
        assert_eq!(run_number("Data from B1464run4.mat"), Some(4));
        assert_eq!(run_number("cornering"), None);
        assert_eq!(run_number("runway"), None);
    }

    #[test]
    fn detection_needs_load_slip_and_a_unit_per_channel() {
        let good = "title\nET FZ SA FY\ns N deg N\n0 -1000 1 -100\n";
        assert!(looks_like(good));
        assert!(!looks_like("title\nET FZ FY\ns N N\n"));
        assert!(!looks_like("title\nET FZ SA FY\ns N deg\n"));
        assert!(!looks_like("run,fz_N,alpha_deg\n1,2,3\n"));
    }
}
