//! The FMI 2.0 state machines of co-simulation and Model Exchange: which function may be
//! called in which state, one row per function. A row's mask may hold states of both
//! interfaces; a call that belongs to one interface only is refused by the other.

use serde::{Deserialize, Serialize};

/// Instance states (FMI 2.0 co-simulation without asynchronous steps, and Model Exchange).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[repr(u8)]
pub(crate) enum State {
    Instantiated = 1,
    InitializationMode = 2,
    StepComplete = 4,
    Terminated = 8,
    /// After an internal failure: only getters, reset, state handling and free.
    Error = 16,
    /// Model Exchange: at an event instant (after initialization, fmi2EnterEventMode).
    EventMode = 32,
    /// Model Exchange: while the host integrates the continuous states.
    ContinuousTimeMode = 64,
}

impl State {
    /// Whether an instance of `interface` can be in this state.
    pub(crate) fn belongs_to(self, interface: Interface) -> bool {
        match self {
            State::StepComplete => interface == Interface::CoSimulation,
            State::EventMode | State::ContinuousTimeMode => interface == Interface::ModelExchange,
            State::Instantiated | State::InitializationMode | State::Terminated | State::Error => {
                true
            }
        }
    }

    pub(crate) fn name(self) -> &'static str {
        match self {
            State::Instantiated => "Instantiated",
            State::InitializationMode => "InitializationMode",
            State::StepComplete => "StepComplete",
            State::Terminated => "Terminated",
            State::Error => "Error",
            State::EventMode => "EventMode",
            State::ContinuousTimeMode => "ContinuousTimeMode",
        }
    }
}

const I: u8 = State::Instantiated as u8;
const N: u8 = State::InitializationMode as u8;
const S: u8 = State::StepComplete as u8;
const T: u8 = State::Terminated as u8;
const E: u8 = State::Error as u8;
const V: u8 = State::EventMode as u8;
const C: u8 = State::ContinuousTimeMode as u8;

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
    SetDebugLogging => I | N | S | T | E | V | C,
    SetupExperiment => I,
    EnterInitializationMode => I,
    ExitInitializationMode => N,
    Terminate => S | V | C,
    Reset => I | N | S | T | E | V | C,
    GetReal => N | S | T | E | V | C,
    GetInteger => N | S | T | E | V | C,
    GetBoolean => N | S | T | E | V | C,
    GetString => N | S | T | E | V | C,
    SetReal => I | N | S | V | C,
    SetInteger => I | N | S | V,
    SetBoolean => I | N | S | V,
    SetString => I | N | S | V,
    GetFMUstate => I | N | S | T | E | V | C,
    SetFMUstate => I | N | S | T | E | V | C,
    FreeFMUstate => I | N | S | T | E | V | C,
    SerializedFMUstateSize => I | N | S | T | E | V | C,
    SerializeFMUstate => I | N | S | T | E | V | C,
    DeSerializeFMUstate => I | N | S | T | E | V | C,
    GetDirectionalDerivative => N | S | T | E | V | C,
    SetRealInputDerivatives => I | N | S,
    GetRealOutputDerivatives => S | T | E,
    DoStep => S,
    CancelStep => S,
    GetStatus => S | T | E,
    GetRealStatus => S | T | E,
    GetIntegerStatus => S | T | E,
    GetBooleanStatus => S | T | E,
    GetStringStatus => S | T | E,
    EnterEventMode => V | C,
    NewDiscreteStates => V,
    EnterContinuousTimeMode => V,
    CompletedIntegratorStep => C,
    SetTime => V | C,
    SetContinuousStates => C,
    GetEventIndicators => N | V | C | T | E,
    GetContinuousStates => N | V | C | T | E,
    GetDerivatives => V | C | T | E,
    GetNominalsOfContinuousStates => I | V | C | T | E,
}

/// The interface an instance was instantiated for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Interface {
    CoSimulation,
    ModelExchange,
}

impl Interface {
    pub(crate) fn name(self) -> &'static str {
        match self {
            Interface::CoSimulation => "co-simulation",
            Interface::ModelExchange => "Model Exchange",
        }
    }
}

impl Call {
    /// The interface the call belongs to; `None`: both.
    pub(crate) fn interface(self) -> Option<Interface> {
        use Call::*;
        match self {
            SetRealInputDerivatives
            | GetRealOutputDerivatives
            | DoStep
            | CancelStep
            | GetStatus
            | GetRealStatus
            | GetIntegerStatus
            | GetBooleanStatus
            | GetStringStatus => Some(Interface::CoSimulation),
            EnterEventMode
            | NewDiscreteStates
            | EnterContinuousTimeMode
            | CompletedIntegratorStep
            | SetTime
            | SetContinuousStates
            | GetEventIndicators
            | GetContinuousStates
            | GetDerivatives
            | GetNominalsOfContinuousStates => Some(Interface::ModelExchange),
            _ => None,
        }
    }

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
