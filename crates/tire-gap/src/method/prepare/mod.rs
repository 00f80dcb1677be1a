//! The data made ready for the fits: rows and channels that cannot be a steady tire test left
//! out ([`row_rules`], [`sanity`]), a programme cut into its test blocks ([`programme`]),
//! one channel's rows in the formula's units ([`channel_data`]), what the data can support
//! ([`adequacy`]) and the folds of the cross-validation by block ([`cv`]).

pub mod adequacy;
pub mod channel_data;
pub mod cv;
pub mod programme;
pub mod row_rules;
pub mod sanity;

pub use row_rules::Refused;

use crate::data::Dataset;

/// One file's data set made ready for merging with others: rows that are no steady test and
/// implausible channels out ([`row_rules`]), then dead channels ([`sanity`]), then, for a
/// `programme` (a TTC run file, one test programme recorded as one file), the split into its
/// test blocks, one run each ([`programme::split_into_blocks`]). What is left out is noted.
pub fn clean_file(
    ds: &mut Dataset,
    notes: &mut Vec<String>,
    programme: bool,
) -> Result<(), Refused> {
    row_rules::apply(ds, notes)?;
    sanity::apply(ds, notes).map_err(|message| Refused {
        message,
        rows: Vec::new(),
    })?;
    if programme {
        programme::split_into_blocks(ds, notes);
    }
    Ok(())
}
