//! The fit problems and their solution: the 1987 model with its candidate effects as one
//! parameter vector, least squares, the range a fitted model holds over, and how many rows
//! the model was evaluated on.

pub mod channel_fit;
pub mod effects;
pub mod evaluations;
pub mod least_squares;
pub mod model;
pub mod validity;
