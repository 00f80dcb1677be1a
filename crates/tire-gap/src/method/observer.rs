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

/// Passes every call on to `inner`, calling `before_stage` with each stage's name first: a
/// front end's additions to an observer (a clock per stage, memory given back).
pub struct OnStage<'a, F> {
    pub inner: &'a dyn Observer,
    pub before_stage: F,
}

impl<F: Fn(&str) + Sync> Observer for OnStage<'_, F> {
    fn stage(&self, msg: &str, steps: u64) {
        (self.before_stage)(msg);
        self.inner.stage(msg, steps);
    }

    fn step(&self) {
        self.inner.step();
    }

    fn note(&self, msg: &str) {
        self.inner.note(msg);
    }

    fn cancelled(&self) -> bool {
        self.inner.cancelled()
    }
}
