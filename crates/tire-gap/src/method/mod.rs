//! The method: from a [`Dataset`](crate::data::Dataset) to a diagnosis. What the data can
//! support (adequacy, channel sanity, the programme's blocks, the test design), the 1987
//! model and its candidate effects as fit problems, the fits and the cross-validation by run,
//! the diagnosis itself, and the fitted model as mf87 parameters. Reads no file and writes
//! none; it imports only the shared data types ([`crate::data`]) and the progress display
//! ([`crate::progress`]).

pub mod adequacy;
pub mod channel_data;
pub mod channel_fit;
pub mod cv;
pub mod design;
pub mod diagnose;
pub mod effects;
pub mod export;
pub mod extrapolate;
pub mod fit;
pub mod model;
pub mod observer;
pub mod parallel;
pub mod programme;
pub mod reference;
pub mod regions;
pub mod row_rules;
pub mod run_order;
pub mod sanity;
pub mod splitmix;
pub mod stats;
pub mod validity;
