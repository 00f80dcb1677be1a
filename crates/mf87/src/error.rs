//! Why a parameter set is rejected ([`ParamError`]), and how a rejection is written: the
//! parameter's name, its value ([`Num`]) and the bound it breaks.

use std::fmt;

/// Why a parameter set was rejected.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamError {
    /// The text is not a complete parameter set (syntax, missing or unknown field).
    Format(String),
    /// A value breaks the model within its validity range.
    Invalid {
        /// Which coefficient, limit or extension parameter, e.g. `Mz.a13`.
        name: String,
        value: f64,
        /// What was wrong and what range is allowed.
        reason: String,
    },
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamError::Format(msg) => write!(f, "not a valid parameter set: {msg}"),
            ParamError::Invalid {
                name,
                value,
                reason,
            } => write!(f, "parameter {name} = {}: {reason}", Num(*value)),
        }
    }
}

impl std::error::Error for ParamError {}

/// A parameter that breaks a bound: its name, value and what is allowed.
pub(crate) fn invalid(name: &str, value: f64, reason: &str) -> ParamError {
    ParamError::Invalid {
        name: name.to_string(),
        value,
        reason: reason.to_string(),
    }
}

/// A number for messages: as Rust writes it, but in exponent form when very large or very
/// small (Rust would write 1e300 with 301 digits).
#[derive(Debug, Clone, Copy)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a.is_finite() && a != 0.0 && !(1e-5..1e15).contains(&a) {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}
