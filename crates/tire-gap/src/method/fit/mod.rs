//! The fit problems and their solution: the 1987 model with its candidate effects as one
//! parameter vector, least squares, and the range a fitted model holds over.

pub mod channel_fit;
pub mod effects;
pub mod least_squares;
pub mod model;
pub mod validity;
