//! The data made ready for the fits: rows and channels that cannot be a steady tire test left
//! out ([`row_rules`], [`sanity`]), a programme cut into its test blocks ([`programme`]),
//! one channel's rows in the formula's units ([`channel_data`]), what the data can support
//! ([`adequacy`]) and the folds of the cross-validation by block ([`cv`]).

pub mod adequacy;
pub mod channel_data;
pub mod cv;
pub mod free_rolling;
pub mod programme;
pub mod row_rules;
pub mod sanity;

pub use row_rules::Refused;

use crate::data::Dataset;

/// One file's data set made ready for merging with others: rows that are no steady test and
/// implausible channels out ([`row_rules`]), then dead channels ([`sanity`]), then, for a
/// `programme` (a TTC run file, one test programme recorded as one file), the split into its
/// test blocks, one run each ([`programme::split_into_blocks`]), and, for a file that holds a
/// `plan` (a programme or a table of runs, not one measurement of a TYDEX file), a slip ratio
/// the blocks never move taken as free rolling ([`free_rolling`]). What is left out is noted.
pub fn clean_file(
    ds: &mut Dataset,
    notes: &mut Vec<String>,
    programme: bool,
    plan: bool,
) -> Result<(), Refused> {
    row_rules::apply(ds, notes)?;
    sanity::apply(ds, notes).map_err(|message| Refused {
        message,
        rows: Vec::new(),
    })?;
    slip_ratio_note(ds, notes);
    if programme {
        programme::split_into_blocks(ds, notes);
    }
    if plan {
        free_rolling::apply(ds, notes);
    }
    Ok(())
}

/// A note when the slip ratio of the rows kept exceeds 1 in magnitude (legal, but what a
/// slip given in percent under a plain-ratio name looks like). Judged after the rules, so a
/// wheel at standstill, where a rig's slip ratio is meaningless, does not raise it.
fn slip_ratio_note(ds: &Dataset, notes: &mut Vec<String>) {
    let Some(kappa) = &ds.kappa else {
        return;
    };
    let max = kappa.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if max > 1.0 {
        notes.push(format!(
            "|kappa| reaches {max} on the rows kept (slip ratio): if the file gives slip in \
             percent, mark the unit (kappa_pct, or % in TYDEX)"
        ));
    }
}
