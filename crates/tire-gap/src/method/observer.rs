//! What the method tells of its progress, and how it is asked to stop: an observer the front
//! end hands it (the command line's terminal bar, the Python package's cancel flag, or
//! [`Unobserved`]).

/// Told of each stage and step of the work, from any of its threads; asked whether to go on.
pub trait Observer: Sync {
    /// A new stage of `steps` steps (0: unknown).
    fn stage(&self, _msg: &str, _steps: u64) {}

    /// One step of the current stage done.
    fn step(&self) {}

    /// A note about the input (also in the report).
    fn note(&self, _msg: &str) {}

    /// Whether the work should stop: each job not yet started is skipped, and the diagnosis
    /// ends with [`Stopped::Cancelled`](crate::method::diagnose::Stopped::Cancelled) at the
    /// end of the stage.
    fn cancelled(&self) -> bool {
        false
    }
}

/// An observer that is told nothing and never stops the work.
pub struct Unobserved;

impl Observer for Unobserved {}
