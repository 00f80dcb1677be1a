//! [`Channel`]: the model's three outputs, each with its own coefficient row in a parameter
//! set and its own set of extensions.

use std::fmt;

use serde::Serialize;

/// An output channel of the model, each with its own coefficient row. Serialized as its
/// [`name`](Channel::name).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Channel {
    /// Lateral force.
    Fy,
    /// Aligning moment.
    Mz,
    /// Longitudinal force.
    Fx,
}

impl Channel {
    pub const ALL: [Channel; 3] = [Channel::Fy, Channel::Mz, Channel::Fx];

    /// The channel's name as in the paper and in parameter files.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Fy => "Fy",
            Channel::Mz => "Mz",
            Channel::Fx => "Fx",
        }
    }

    pub fn from_name(name: &str) -> Option<Channel> {
        Channel::ALL.into_iter().find(|c| c.name() == name)
    }

    /// What the channel's value per N of load is, and its unit suffix (for messages).
    pub(crate) fn per_load_meaning(self) -> (&'static str, &'static str) {
        match self {
            Channel::Fx | Channel::Fy => ("friction coefficient", ""),
            Channel::Mz => ("lever arm", " m"),
        }
    }
}

impl fmt::Display for Channel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}
