//! The method: from a [`Dataset`](crate::data::Dataset) to a diagnosis, in stages. Reads no
//! file and writes none; it imports only the shared data types ([`crate::data`], order
//! statistics in [`crate::quantiles`]) and tells of its progress through an [`observer`].
//!
//! - [`prepare`]: a file's rows and channels that cannot be a steady tire test left out, a
//!   programme cut into its test blocks, one channel's rows in the formula's units, what the
//!   data can support and the folds of the cross-validation by block;
//! - [`fit`]: the 1987 model and its candidate effects as fit problems, least squares, and
//!   the range a fitted model holds over;
//! - [`diagnose`]: the test design (which conditions move together), the selection of effects, where the gap lies, whether an effect holds
//!   beyond its data, the MF 6.1 reference and the per-sweep floor, and the diagnosis as a
//!   whole;
//! - [`export`]: the fitted model as the FMU's parameter file.

pub mod diagnose;
pub mod export;
pub mod fit;
pub mod observer;
pub mod parallel;
pub mod prepare;
pub mod splitmix;
pub mod stats;
