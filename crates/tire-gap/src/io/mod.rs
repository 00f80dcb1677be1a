//! Reading and writing: the measured-data readers and their unit conversions, output files
//! (whole-or-nothing writes, path checks), the figures, and the resource estimate said before
//! a diagnosis starts.

pub mod csv_out;
pub mod input;
pub mod output;
pub mod plots;
pub mod report;
pub mod resources;
pub mod units;
