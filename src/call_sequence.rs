//! The state machines of co-simulation and Model Exchange, for FMI 2.0 ([`Call`]) and FMI 3.0
//! ([`Call3`]): which function may be called in which state, one row per function. A row's
//! mask may hold states of both interfaces; a call that belongs to one interface only is
//! refused by the other. Both standards share the states; FMI 2.0's StepComplete is FMI 3.0's
//! StepMode.

use serde::{Deserialize, Serialize};

/// Instance states (co-simulation without asynchronous steps or event mode, and Model
/// Exchange).
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

    /// The state's name in the standard of `abi`.
    pub(crate) fn name(self, abi: Abi) -> &'static str {
        match self {
            State::Instantiated => "Instantiated",
            State::InitializationMode => "InitializationMode",
            State::StepComplete if abi == Abi::Fmi3 => "StepMode",
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

/// The FMI standard a call comes through.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Abi {
    Fmi2,
    Fmi3,
}

impl Abi {
    /// The prefix of its function names.
    pub(crate) fn prefix(self) -> &'static str {
        match self {
            Abi::Fmi2 => "fmi2",
            Abi::Fmi3 => "fmi3",
        }
    }
}

/// A function of one standard that takes an instance: its name, the states it is allowed in,
/// the interface it belongs to.
pub(crate) trait FmiCall: Copy {
    fn name(self) -> &'static str;
    fn abi(self) -> Abi;
    fn allowed_in(self, state: State) -> bool;
    /// The interface the call belongs to; `None`: both.
    fn interface(self) -> Option<Interface>;
}

macro_rules! calls {
    ($(#[$doc:meta])* $enum:ident, $abi:ident, $prefix:literal,
     { $($call:ident => $mask:expr,)+ }
     co_simulation: [$($cs:ident),*]
     model_exchange: [$($me:ident),*]
    ) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub(crate) enum $enum {
            $($call,)+
        }

        impl FmiCall for $enum {
            fn name(self) -> &'static str {
                match self {
                    $($enum::$call => concat!($prefix, stringify!($call)),)+
                }
            }

            fn abi(self) -> Abi {
                Abi::$abi
            }

            fn allowed_in(self, state: State) -> bool {
                let mask: u8 = match self {
                    $($enum::$call => $mask,)+
                };
                mask & state as u8 != 0
            }

            fn interface(self) -> Option<Interface> {
                match self {
                    $($enum::$cs)|* => Some(Interface::CoSimulation),
                    $($enum::$me)|* => Some(Interface::ModelExchange),
                    #[allow(unreachable_patterns)]
                    _ => None,
                }
            }
        }
    };
}

calls! {
    /// An FMI 2.0 function that takes an instance.
    Call, Fmi2, "fmi2",
    {
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
    co_simulation: [
        SetRealInputDerivatives, GetRealOutputDerivatives, DoStep, CancelStep, GetStatus,
        GetRealStatus, GetIntegerStatus, GetBooleanStatus, GetStringStatus
    ]
    model_exchange: [
        EnterEventMode, NewDiscreteStates, EnterContinuousTimeMode, CompletedIntegratorStep,
        SetTime, SetContinuousStates, GetEventIndicators, GetContinuousStates, GetDerivatives,
        GetNominalsOfContinuousStates
    ]
}

calls! {
    /// An FMI 3.0 function that takes an instance (this FMU has no clocks, no structural
    /// parameters, no event mode in co-simulation and no scheduled execution). The rows
    /// follow the standard's state machine as the Modelica Association's Reference FMUs read
    /// it: variables may be read from instantiation on and set until termination.
    Call3, Fmi3, "fmi3",
    {
        SetDebugLogging => I | N | S | T | E | V | C,
        EnterInitializationMode => I,
        ExitInitializationMode => N,
        Terminate => S | V | C,
        Reset => I | N | S | T | E | V | C,
        GetFloat64 => I | N | S | T | E | V | C,
        SetFloat64 => I | N | S | T | V | C,
        GetBoolean => I | N | S | T | E | V | C,
        SetBoolean => I | N | S | T | V,
        GetString => I | N | S | T | E | V | C,
        SetString => I | N | S | T | V,
        GetFloat32 => I | N | S | T | E | V | C,
        GetInt8 => I | N | S | T | E | V | C,
        GetUInt8 => I | N | S | T | E | V | C,
        GetInt16 => I | N | S | T | E | V | C,
        GetUInt16 => I | N | S | T | E | V | C,
        GetInt32 => I | N | S | T | E | V | C,
        GetUInt32 => I | N | S | T | E | V | C,
        GetInt64 => I | N | S | T | E | V | C,
        GetUInt64 => I | N | S | T | E | V | C,
        GetBinary => I | N | S | T | E | V | C,
        GetClock => I | N | S | T | E | V | C,
        SetFloat32 => I | N | S | T | V | C,
        SetInt8 => I | N | S | T | V | C,
        SetUInt8 => I | N | S | T | V | C,
        SetInt16 => I | N | S | T | V | C,
        SetUInt16 => I | N | S | T | V | C,
        SetInt32 => I | N | S | T | V | C,
        SetUInt32 => I | N | S | T | V | C,
        SetInt64 => I | N | S | T | V | C,
        SetUInt64 => I | N | S | T | V | C,
        SetBinary => I | N | S | T | V | C,
        SetClock => I | N | S | T | V | C,
        GetNumberOfVariableDependencies => I | N | S | T | E | V | C,
        GetVariableDependencies => I | N | S | T | E | V | C,
        GetFMUState => I | N | S | T | E | V | C,
        SetFMUState => I | N | S | T | E | V | C,
        FreeFMUState => I | N | S | T | E | V | C,
        SerializedFMUStateSize => I | N | S | T | E | V | C,
        SerializeFMUState => I | N | S | T | E | V | C,
        DeserializeFMUState => I | N | S | T | E | V | C,
        GetDirectionalDerivative => N | S | T | E | V | C,
        GetAdjointDerivative => N | S | T | E | V | C,
        EnterConfigurationMode => I | S | V,
        ExitConfigurationMode => 0,
        GetIntervalDecimal => I | N | S | T | E | V | C,
        GetIntervalFraction => I | N | S | T | E | V | C,
        GetShiftDecimal => I | N | S | T | E | V | C,
        GetShiftFraction => I | N | S | T | E | V | C,
        SetIntervalDecimal => I | N | S | T | E | V | C,
        SetIntervalFraction => I | N | S | T | E | V | C,
        SetShiftDecimal => I | N | S | T | E | V | C,
        SetShiftFraction => I | N | S | T | E | V | C,
        EvaluateDiscreteStates => V,
        UpdateDiscreteStates => V,
        EnterEventMode => C,
        EnterContinuousTimeMode => V,
        CompletedIntegratorStep => C,
        SetTime => V | C,
        SetContinuousStates => C,
        GetContinuousStateDerivatives => N | V | C | T | E,
        GetEventIndicators => N | V | C | T | E,
        GetContinuousStates => N | V | C | T | E,
        GetNominalsOfContinuousStates => I | N | V | C | T | E,
        GetNumberOfEventIndicators => I | N | S | T | E | V | C,
        GetNumberOfContinuousStates => I | N | S | T | E | V | C,
        EnterStepMode => V,
        GetOutputDerivatives => S | T | E,
        DoStep => S,
        ActivateModelPartition => 0,
    }
    co_simulation: [EnterStepMode, GetOutputDerivatives, DoStep]
    model_exchange: [
        EnterContinuousTimeMode, CompletedIntegratorStep, SetTime, SetContinuousStates,
        GetContinuousStateDerivatives, GetEventIndicators, GetContinuousStates,
        GetNominalsOfContinuousStates, GetNumberOfEventIndicators, GetNumberOfContinuousStates,
        EnterEventMode
    ]
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
        assert_eq!(Call::DoStep.interface(), Some(Interface::CoSimulation));
        assert_eq!(Call::GetReal.interface(), None);
        assert_eq!(Call3::GetFMUState.name(), "fmi3GetFMUState");
        assert!(Call3::DoStep.allowed_in(State::StepComplete));
        assert!(!Call3::ExitConfigurationMode.allowed_in(State::Instantiated));
        assert_eq!(Call3::UpdateDiscreteStates.interface(), None);
        assert_eq!(State::StepComplete.name(Abi::Fmi3), "StepMode");
    }
}
