//! The FMI 2.0 co-simulation state machine: which function may be called in which state,
//! one row per function.

use serde::{Deserialize, Serialize};

/// Instance states (FMI 2.0 co-simulation, without asynchronous steps).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[repr(u8)]
pub(crate) enum State {
    Instantiated = 1,
    InitializationMode = 2,
    StepComplete = 4,
    Terminated = 8,
    /// After an internal failure: only getters, reset, state handling and free.
    Error = 16,
}

impl State {
    pub(crate) fn name(self) -> &'static str {
        match self {
            State::Instantiated => "Instantiated",
            State::InitializationMode => "InitializationMode",
            State::StepComplete => "StepComplete",
            State::Terminated => "Terminated",
            State::Error => "Error",
        }
    }
}

const I: u8 = State::Instantiated as u8;
const N: u8 = State::InitializationMode as u8;
const S: u8 = State::StepComplete as u8;
const T: u8 = State::Terminated as u8;
const E: u8 = State::Error as u8;

macro_rules! calls {
    ($($call:ident => $mask:expr,)+) => {
        /// An FMI function that takes an instance.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub(crate) enum Call {
            $($call,)+
        }

        impl Call {
            /// The C function's name.
            pub(crate) fn name(self) -> &'static str {
                match self {
                    $(Call::$call => concat!("fmi2", stringify!($call)),)+
                }
            }

            /// The states in which the call is allowed, as a mask of [`State`] bits.
            fn allowed(self) -> u8 {
                match self {
                    $(Call::$call => $mask,)+
                }
            }
        }
    };
}

calls! {
    SetDebugLogging => I | N | S | T | E,
    SetupExperiment => I,
    EnterInitializationMode => I,
    ExitInitializationMode => N,
    Terminate => S,
    Reset => I | N | S | T | E,
    GetReal => N | S | T | E,
    GetInteger => N | S | T | E,
    GetBoolean => N | S | T | E,
    GetString => N | S | T | E,
    SetReal => I | N | S,
    SetInteger => I | N | S,
    SetBoolean => I | N | S,
    SetString => I | N | S,
    GetFMUstate => I | N | S | T | E,
    SetFMUstate => I | N | S | T | E,
    FreeFMUstate => I | N | S | T | E,
    SerializedFMUstateSize => I | N | S | T | E,
    SerializeFMUstate => I | N | S | T | E,
    DeSerializeFMUstate => I | N | S | T | E,
    GetDirectionalDerivative => N | S | T | E,
    SetRealInputDerivatives => I | N | S,
    GetRealOutputDerivatives => S | T | E,
    DoStep => S,
    CancelStep => S,
    GetStatus => S | T | E,
    GetRealStatus => S | T | E,
    GetIntegerStatus => S | T | E,
    GetBooleanStatus => S | T | E,
    GetStringStatus => S | T | E,
}

impl Call {
    pub(crate) fn allowed_in(self, state: State) -> bool {
        self.allowed() & state as u8 != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_rows_follow_the_standard() {
        assert!(Call::DoStep.allowed_in(State::StepComplete));
        assert!(!Call::DoStep.allowed_in(State::InitializationMode));
        assert!(!Call::SetupExperiment.allowed_in(State::StepComplete));
        assert!(!Call::GetReal.allowed_in(State::Instantiated));
        assert!(Call::Reset.allowed_in(State::Error));
        assert!(!Call::SetReal.allowed_in(State::Terminated));
        assert_eq!(Call::GetFMUstate.name(), "fmi2GetFMUstate");
    }
}
