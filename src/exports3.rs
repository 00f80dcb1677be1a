//! Every FMI 3.0 function: common, co-simulation and Model Exchange (scheduled execution is
//! refused at instantiation). Each body is: pointer and array checks, a call into the safe
//! [`Instance`] (through `values3` for the variables), the status back. Panics stop in
//! `boundary`. The instance type, its state machine (`Call3`), its FMU states and its
//! model are those of the FMI 2.0 functions.
//!
//! Ownership as for FMI 2.0: the instance is freed by fmi3FreeInstance, its FMU states by
//! fmi3FreeFMUState or with the instance; strings returned by fmi3GetString live until the
//! next call on the instance; the host keeps ownership of every array it passes.
#![allow(non_snake_case)]

use std::ffi::{CStr, c_char};
use std::path::PathBuf;
use std::ptr::null_mut;

use fmi_sys::fmi3::*;

use crate::boundary::{
    self, CArray, c_str, free_instance, guard, set_debug_logging, slice, slice_mut, with_instance,
};
use crate::call_sequence::{Abi, Call3, Interface};
use crate::instance::{Instance, Instantiation, STATES};
use crate::logging::{Callback, Logger, Status};
use crate::values3;
use crate::variables::LogCategory;

#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

/// Makes an instance of `interface`; NULL (with the reason logged, when there is a logger)
/// on bad arguments.
///
/// # Safety
/// Strings NULL or NUL-terminated; `logMessage` NULL or a valid callback.
unsafe fn instantiate(
    interface: Interface,
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
) -> fmi3Instance {
    crate::boundary::install_panic_hook();
    guard(null_mut(), || {
        // SAFETY: NULL or NUL-terminated by contract.
        let name = unsafe { c_str(instanceName) }
            .map(CStr::to_owned)
            .unwrap_or_default();
        let logger = Logger::new(
            Callback::Fmi3(logMessage),
            instanceEnvironment,
            name,
            loggingOn,
        );
        // SAFETY: NULL or NUL-terminated by contract.
        let (token, resources) = unsafe { (c_str(instantiationToken), c_str(resourcePath)) };
        let with = Instantiation {
            abi: Abi::Fmi3,
            interface,
            token,
            resources: resources
                .map(|r| PathBuf::from(r.to_string_lossy().into_owned()))
                .filter(|p| !p.as_os_str().is_empty()),
        };
        boundary::instantiate(logger, with)
    })
}

/// # Safety
/// Strings NULL or NUL-terminated; `logMessage` NULL or a valid callback.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
) -> fmi3Instance {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        instantiate(
            Interface::ModelExchange,
            instanceName,
            instantiationToken,
            resourcePath,
            loggingOn,
            instanceEnvironment,
            logMessage,
        )
    }
}

/// # Safety
/// Strings NULL or NUL-terminated; `logMessage` NULL or a valid callback;
/// `requiredIntermediateVariables` is not read (this FMU has no intermediate updates).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    _earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    _nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _intermediateUpdate: fmi3IntermediateUpdateCallback,
) -> fmi3Instance {
    if eventModeUsed {
        refuse(
            instanceEnvironment,
            logMessage,
            "fmi3InstantiateCoSimulation: eventModeUsed = true, but this FMU has no event mode \
             (hasEventMode = false): it has no events",
        );
        return null_mut();
    }
    // SAFETY: forwarded from this function's contract.
    unsafe {
        instantiate(
            Interface::CoSimulation,
            instanceName,
            instantiationToken,
            resourcePath,
            loggingOn,
            instanceEnvironment,
            logMessage,
        )
    }
}

/// Logs why an instantiation is refused before there is an instance.
fn refuse(
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    message: &str,
) {
    guard((), || {
        let logger = Logger::new(
            Callback::Fmi3(logMessage),
            instanceEnvironment,
            Default::default(),
            true,
        );
        logger.log(Status::Error, LogCategory::StatusError, message);
    })
}

/// Scheduled execution is not offered (the model description declares no such interface).
///
/// # Safety
/// `logMessage` NULL or a valid callback.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _clockUpdate: fmi3ClockUpdateCallback,
    _lockPreemption: fmi3LockPreemptionCallback,
    _unlockPreemption: fmi3UnlockPreemptionCallback,
) -> fmi3Instance {
    refuse(
        instanceEnvironment,
        logMessage,
        "fmi3InstantiateScheduledExecution: this FMU offers co-simulation and Model Exchange, \
         not scheduled execution",
    );
    null_mut()
}

/// # Safety
/// `instance` must be NULL or from an fmi3Instantiate function; not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
    // SAFETY: forwarded from this function's contract.
    unsafe { free_instance(instance) }
}

/// # Safety
/// `instance` NULL or live; `categories` NULL or `nCategories` C strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        set_debug_logging(
            instance,
            Call3::SetDebugLogging,
            loggingOn,
            nCategories,
            categories,
        )
    }
}

/// # Safety
/// `instance` NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: fmi3Instance,
    _toleranceDefined: fmi3Boolean,
    _tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    // SAFETY: `instance` valid by contract.
    unsafe {
        with_instance(instance, Call3::EnterInitializationMode, |inst| match inst
            .setup_experiment(startTime, stopTimeDefined.then_some(stopTime))
        {
            Status::Ok => inst.enter_initialization_mode(),
            refused => refused,
        })
    }
}

/// Defines an export that takes only the instance and calls `$method` on it.
macro_rules! instance_only {
    ($(#[$doc:meta])* $name:ident, $call:ident, $body:expr) => {
        $(#[$doc])*
        /// # Safety
        /// `instance` NULL or live.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(instance: fmi3Instance) -> fmi3Status {
            // SAFETY: `instance` valid by contract.
            unsafe { with_instance(instance, Call3::$call, $body) }
        }
    };
}

instance_only!(
    fmi3ExitInitializationMode,
    ExitInitializationMode,
    Instance::exit_initialization_mode
);
instance_only!(fmi3Terminate, Terminate, Instance::terminate);
instance_only!(fmi3Reset, Reset, Instance::reset);
instance_only!(
    fmi3EnterEventMode,
    EnterEventMode,
    Instance::enter_event_mode
);
instance_only!(
    fmi3EnterContinuousTimeMode,
    EnterContinuousTimeMode,
    Instance::enter_continuous_time_mode
);
instance_only!(
    fmi3EvaluateDiscreteStates,
    EvaluateDiscreteStates,
    |_: &mut Instance| {
        // No discrete states, no clocks: nothing to evaluate.
        Status::Ok
    }
);
instance_only!(
    fmi3EnterConfigurationMode,
    EnterConfigurationMode,
    |inst: &mut Instance| { inst.unsupported("it has no structural parameters") }
);
instance_only!(
    fmi3ExitConfigurationMode,
    ExitConfigurationMode,
    |inst: &mut Instance| { inst.unsupported("it has no structural parameters") }
);
instance_only!(fmi3EnterStepMode, EnterStepMode, |inst: &mut Instance| {
    inst.unsupported("it has no event mode in co-simulation")
});

/// A get or set call: `valueReferences` and `values` as slices (NULL only when empty, else
/// [`Instance::null_array`]), then `f` on the instance, inside [`with_instance`].
///
/// # Safety
/// `instance` live or NULL; the arrays NULL or of their lengths (`values` exclusively
/// borrowed when written).
unsafe fn with_values<A: CArray>(
    instance: fmi3Instance,
    call: Call3,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: A,
    n_values: usize,
    f: impl FnOnce(&mut Instance, &[fmi3ValueReference], A::Slice<'_>) -> Status,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, call, |inst| {
            match (slice(vr, nvr), values.to_slice(n_values)) {
                (Some(vrs), Some(values)) => f(inst, vrs, values),
                (None, _) => inst.null_array("valueReferences", nvr),
                (_, None) => inst.null_array("values", n_values),
            }
        })
    }
}

/// # Safety
/// `instance` live or NULL; the arrays NULL or of their lengths.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        with_values(
            instance,
            Call3::GetFloat64,
            valueReferences,
            nValueReferences,
            values,
            nValues,
            values3::get_float64,
        )
    }
}

/// # Safety
/// `instance` live or NULL; the arrays NULL or of their lengths.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        with_values(
            instance,
            Call3::SetFloat64,
            valueReferences,
            nValueReferences,
            values,
            nValues,
            values3::set_float64,
        )
    }
}

/// # Safety
/// `instance` live or NULL; the arrays NULL or of their lengths.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetBoolean(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3Boolean,
    nValues: usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        with_values(
            instance,
            Call3::GetBoolean,
            valueReferences,
            nValueReferences,
            values,
            nValues,
            values3::get_boolean,
        )
    }
}

/// # Safety
/// `instance` live or NULL; the arrays NULL or of their lengths.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetBoolean(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3Boolean,
    nValues: usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        with_values(
            instance,
            Call3::SetBoolean,
            valueReferences,
            nValueReferences,
            values,
            nValues,
            values3::set_boolean,
        )
    }
}

/// # Safety
/// `instance` live or NULL; the arrays NULL or of their lengths. The strings returned live
/// until the next call on this instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetString(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3String,
    nValues: usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        with_values(
            instance,
            Call3::GetString,
            valueReferences,
            nValueReferences,
            values,
            nValues,
            values3::get_string,
        )
    }
}

/// # Safety
/// `instance` live or NULL; the arrays NULL or of their lengths, each string NULL or
/// NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetString(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3String,
    nValues: usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        with_values(
            instance,
            Call3::SetString,
            valueReferences,
            nValueReferences,
            values,
            nValues,
            |inst, vrs, values| {
                // SAFETY: each string NULL or NUL-terminated, by this function's contract.
                let strings: Vec<Option<&CStr>> = values.iter().map(|s| c_str(*s)).collect();
                values3::set_string(inst, vrs, &strings)
            },
        )
    }
}

/// Defines the get and set functions of a type this FMU has no variable of: any value
/// reference is an error naming the variables it has; none is fine.
macro_rules! no_variables {
    ($get:ident, $get_call:ident, $set:ident, $set_call:ident, $t:ty, $type_name:literal) => {
        /// # Safety
        /// `instance` live or NULL; `valueReferences` NULL or `nValueReferences` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $get(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            _values: *mut $t,
            _nValues: usize,
        ) -> fmi3Status {
            // SAFETY: forwarded from this function's contract.
            unsafe {
                no_variables_call(
                    instance,
                    Call3::$get_call,
                    valueReferences,
                    nValueReferences,
                    $type_name,
                )
            }
        }

        /// # Safety
        /// `instance` live or NULL; `valueReferences` NULL or `nValueReferences` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $set(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            _values: *const $t,
            _nValues: usize,
        ) -> fmi3Status {
            // SAFETY: forwarded from this function's contract.
            unsafe {
                no_variables_call(
                    instance,
                    Call3::$set_call,
                    valueReferences,
                    nValueReferences,
                    $type_name,
                )
            }
        }
    };
}

/// # Safety
/// `instance` live or NULL; `vr` NULL or `nvr` elements.
unsafe fn no_variables_call(
    instance: fmi3Instance,
    call: Call3,
    vr: *const fmi3ValueReference,
    nvr: usize,
    type_name: &str,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, call, |inst| match slice(vr, nvr) {
            Some(vrs) => values3::no_variables_of_type(inst, vrs, type_name),
            None => inst.null_array("valueReferences", nvr),
        })
    }
}

no_variables!(
    fmi3GetFloat32,
    GetFloat32,
    fmi3SetFloat32,
    SetFloat32,
    fmi3Float32,
    "Float32"
);
no_variables!(fmi3GetInt8, GetInt8, fmi3SetInt8, SetInt8, fmi3Int8, "Int8");
no_variables!(
    fmi3GetUInt8,
    GetUInt8,
    fmi3SetUInt8,
    SetUInt8,
    fmi3UInt8,
    "UInt8"
);
no_variables!(
    fmi3GetInt16,
    GetInt16,
    fmi3SetInt16,
    SetInt16,
    fmi3Int16,
    "Int16"
);
no_variables!(
    fmi3GetUInt16,
    GetUInt16,
    fmi3SetUInt16,
    SetUInt16,
    fmi3UInt16,
    "UInt16"
);
no_variables!(
    fmi3GetInt32,
    GetInt32,
    fmi3SetInt32,
    SetInt32,
    fmi3Int32,
    "Int32"
);
no_variables!(
    fmi3GetUInt32,
    GetUInt32,
    fmi3SetUInt32,
    SetUInt32,
    fmi3UInt32,
    "UInt32"
);
no_variables!(
    fmi3GetInt64,
    GetInt64,
    fmi3SetInt64,
    SetInt64,
    fmi3Int64,
    "Int64"
);
no_variables!(
    fmi3GetUInt64,
    GetUInt64,
    fmi3SetUInt64,
    SetUInt64,
    fmi3UInt64,
    "UInt64"
);

/// # Safety
/// `instance` live or NULL; `valueReferences` NULL or `nValueReferences` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _valueSizes: *mut usize,
    _values: *mut fmi3Binary,
    _nValues: usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        no_variables_call(
            instance,
            Call3::GetBinary,
            valueReferences,
            nValueReferences,
            "Binary",
        )
    }
}

/// # Safety
/// `instance` live or NULL; `valueReferences` NULL or `nValueReferences` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _valueSizes: *const usize,
    _values: *const fmi3Binary,
    _nValues: usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        no_variables_call(
            instance,
            Call3::SetBinary,
            valueReferences,
            nValueReferences,
            "Binary",
        )
    }
}

/// # Safety
/// `instance` live or NULL; `valueReferences` NULL or `nValueReferences` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetClock(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _values: *mut fmi3Clock,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        no_variables_call(
            instance,
            Call3::GetClock,
            valueReferences,
            nValueReferences,
            "Clock",
        )
    }
}

/// # Safety
/// `instance` live or NULL; `valueReferences` NULL or `nValueReferences` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetClock(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _values: *const fmi3Clock,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        no_variables_call(
            instance,
            Call3::SetClock,
            valueReferences,
            nValueReferences,
            "Clock",
        )
    }
}

/// Defines a clock interval or shift function: there are no clocks, so any value reference
/// is an error.
macro_rules! no_clocks {
    ($name:ident, $call:ident, ($($arg:ident: $t:ty),*)) => {
        /// # Safety
        /// `instance` live or NULL; `valueReferences` NULL or `nValueReferences` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            $($arg: $t),*
        ) -> fmi3Status {
            $(let _ = $arg;)*
            // SAFETY: forwarded from this function's contract.
            unsafe { no_variables_call(instance, Call3::$call, valueReferences, nValueReferences, "Clock") }
        }
    };
}

no_clocks!(fmi3GetIntervalDecimal, GetIntervalDecimal, (intervals: *mut fmi3Float64, qualifiers: *mut fmi3IntervalQualifier));
no_clocks!(fmi3GetIntervalFraction, GetIntervalFraction, (counters: *mut fmi3UInt64, resolutions: *mut fmi3UInt64, qualifiers: *mut fmi3IntervalQualifier));
no_clocks!(fmi3GetShiftDecimal, GetShiftDecimal, (shifts: *mut fmi3Float64));
no_clocks!(fmi3GetShiftFraction, GetShiftFraction, (counters: *mut fmi3UInt64, resolutions: *mut fmi3UInt64));
no_clocks!(fmi3SetIntervalDecimal, SetIntervalDecimal, (intervals: *const fmi3Float64));
no_clocks!(fmi3SetIntervalFraction, SetIntervalFraction, (counters: *const fmi3UInt64, resolutions: *const fmi3UInt64));
no_clocks!(fmi3SetShiftDecimal, SetShiftDecimal, (shifts: *const fmi3Float64));
no_clocks!(fmi3SetShiftFraction, SetShiftFraction, (counters: *const fmi3UInt64, resolutions: *const fmi3UInt64));

/// Why the variable-dependency functions are not provided.
const DEPENDENCIES: &str = "the dependencies are in the model description's ModelStructure";

/// An error for `call`, which this FMU does not support (`why`).
///
/// # Safety
/// `instance` live or NULL.
unsafe fn unsupported(instance: fmi3Instance, call: Call3, why: &str) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe { with_instance(instance, call, |inst| inst.unsupported(why)) }
}

/// # Safety
/// `instance` live or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3ActivateModelPartition(
    instance: fmi3Instance,
    _clockReference: fmi3ValueReference,
    _activationTime: fmi3Float64,
) -> fmi3Status {
    // SAFETY: `instance` valid by contract.
    unsafe {
        unsupported(
            instance,
            Call3::ActivateModelPartition,
            "scheduled execution",
        )
    }
}

/// # Safety
/// `instance` live or NULL; `nDependencies` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(
    instance: fmi3Instance,
    _valueReference: fmi3ValueReference,
    _nDependencies: *mut usize,
) -> fmi3Status {
    // SAFETY: `instance` valid by contract.
    unsafe {
        unsupported(
            instance,
            Call3::GetNumberOfVariableDependencies,
            DEPENDENCIES,
        )
    }
}

/// # Safety
/// `instance` live or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetVariableDependencies(
    instance: fmi3Instance,
    _dependent: fmi3ValueReference,
    _elementIndicesOfDependent: *mut usize,
    _independents: *mut fmi3ValueReference,
    _elementIndicesOfIndependents: *mut usize,
    _dependencyKinds: *mut fmi3DependencyKind,
    _nDependencies: usize,
) -> fmi3Status {
    // SAFETY: `instance` valid by contract.
    unsafe { unsupported(instance, Call3::GetVariableDependencies, DEPENDENCIES) }
}

/// # Safety
/// `instance` live or NULL; `FMUState` NULL or a valid pointer to a state slot.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, Call3::GetFMUState, |inst| {
            inst.get_state(FMUState.as_mut())
        })
    }
}

/// # Safety
/// `instance` live or NULL; `FMUState` NULL or a state from this FMU.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    // SAFETY: pointers valid by contract.
    unsafe {
        with_instance(instance, Call3::SetFMUState, |inst| {
            inst.set_state(FMUState)
        })
    }
}

/// # Safety
/// `instance` live or NULL; `FMUState` NULL or a slot holding NULL or a state of this FMU.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, Call3::FreeFMUState, |inst| {
            inst.free_state(FMUState.as_mut())
        })
    }
}

/// # Safety
/// `instance` live or NULL; `FMUState` a state of this FMU; `size` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, Call3::SerializedFMUStateSize, |inst| {
            inst.serialized_size(FMUState, size.as_mut())
        })
    }
}

/// # Safety
/// `instance` live or NULL; `FMUState` a state of this FMU; `serializedState` NULL or `size`
/// writable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, Call3::SerializeFMUState, |inst| {
            inst.serialize_into(FMUState, slice_mut(serializedState, size), size)
        })
    }
}

/// # Safety
/// `instance` live or NULL; `serializedState` NULL or `size` bytes; `FMUState` NULL or a
/// writable slot.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: usize,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, Call3::DeserializeFMUState, |inst| {
            inst.deserialize(slice(serializedState, size), size, FMUState.as_mut())
        })
    }
}

/// The arrays of a derivative call as slices with the lengths checked: `nSeed` must be
/// `n_seed` (the knowns' count for directional derivatives, the unknowns' for adjoint ones)
/// and `nSensitivity` `n_sensitivity`; then `f` with the FMI 2.0 references of the unknowns
/// and knowns.
///
/// # Safety
/// The arrays NULL or of their lengths; `sensitivity` exclusively borrowed.
#[allow(clippy::too_many_arguments)]
unsafe fn derivative_call(
    instance: fmi3Instance,
    call: Call3,
    unknowns: *const fmi3ValueReference,
    nUnknowns: usize,
    knowns: *const fmi3ValueReference,
    nKnowns: usize,
    seed: *const fmi3Float64,
    nSeed: usize,
    sensitivity: *mut fmi3Float64,
    nSensitivity: usize,
    adjoint: bool,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, call, |inst| {
            let (n_seed, n_sensitivity) = if adjoint {
                (nUnknowns, nKnowns)
            } else {
                (nKnowns, nUnknowns)
            };
            if nSeed != n_seed || nSensitivity != n_sensitivity {
                return inst.error(format!(
                    "nSeed = {nSeed} and nSensitivity = {nSensitivity}; with {nUnknowns} scalar \
                     unknowns and {nKnowns} scalar knowns they must be {n_seed} and {n_sensitivity}"
                ));
            }
            let (Some(u), Some(k)) = (slice(unknowns, nUnknowns), slice(knowns, nKnowns)) else {
                return inst.null_array("unknowns or knowns", nUnknowns.max(nKnowns));
            };
            let (Some(seed), Some(sensitivity)) =
                (slice(seed, nSeed), slice_mut(sensitivity, nSensitivity))
            else {
                return inst.null_array("seed or sensitivity", nSeed.max(nSensitivity));
            };
            let refs = values3::scalar_reals(inst, u, "unknowns")
                .and_then(|u| Ok((u, values3::scalar_reals(inst, k, "knowns")?)));
            match refs {
                Ok((u, k)) if adjoint => inst.get_adjoint_derivative(&u, &k, seed, sensitivity),
                Ok((u, k)) => inst.get_directional_derivative(&u, &k, seed, sensitivity),
                Err(status) => status,
            }
        })
    }
}

/// # Safety
/// `instance` live or NULL; the arrays NULL or of their lengths.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
    instance: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    nUnknowns: usize,
    knowns: *const fmi3ValueReference,
    nKnowns: usize,
    seed: *const fmi3Float64,
    nSeed: usize,
    sensitivity: *mut fmi3Float64,
    nSensitivity: usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        derivative_call(
            instance,
            Call3::GetDirectionalDerivative,
            unknowns,
            nUnknowns,
            knowns,
            nKnowns,
            seed,
            nSeed,
            sensitivity,
            nSensitivity,
            false,
        )
    }
}

/// # Safety
/// `instance` live or NULL; the arrays NULL or of their lengths.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetAdjointDerivative(
    instance: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    nUnknowns: usize,
    knowns: *const fmi3ValueReference,
    nKnowns: usize,
    seed: *const fmi3Float64,
    nSeed: usize,
    sensitivity: *mut fmi3Float64,
    nSensitivity: usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        derivative_call(
            instance,
            Call3::GetAdjointDerivative,
            unknowns,
            nUnknowns,
            knowns,
            nKnowns,
            seed,
            nSeed,
            sensitivity,
            nSensitivity,
            true,
        )
    }
}

/// Writes `value` to each flag the host passed (NULL ones are skipped: the standard makes
/// them outputs, not every importer reads them).
///
/// # Safety
/// Each pointer NULL or writable.
unsafe fn set_flags(flags: &[*mut fmi3Boolean], value: bool) {
    for f in flags {
        // SAFETY: NULL or writable by contract.
        if let Some(f) = unsafe { f.as_mut() } {
            *f = value;
        }
    }
}

/// # Safety
/// `instance` live or NULL; each flag NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
    instance: fmi3Instance,
    discreteStatesNeedUpdate: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
    valuesOfContinuousStatesChanged: *mut fmi3Boolean,
    nextEventTimeDefined: *mut fmi3Boolean,
    nextEventTime: *mut fmi3Float64,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, Call3::UpdateDiscreteStates, |inst| {
            set_flags(
                &[
                    discreteStatesNeedUpdate,
                    terminateSimulation,
                    nominalsOfContinuousStatesChanged,
                    valuesOfContinuousStatesChanged,
                    nextEventTimeDefined,
                ],
                false,
            );
            if let Some(t) = nextEventTime.as_mut() {
                *t = 0.0;
            }
            inst.new_discrete_states()
        })
    }
}

/// # Safety
/// `instance` live or NULL; the two flags NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3CompletedIntegratorStep(
    instance: fmi3Instance,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    enterEventMode: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, Call3::CompletedIntegratorStep, |_| {
            // No events, no reason to stop.
            set_flags(&[enterEventMode, terminateSimulation], false);
            Status::Ok
        })
    }
}

/// # Safety
/// `instance` live or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetTime(instance: fmi3Instance, time: fmi3Float64) -> fmi3Status {
    // SAFETY: `instance` valid by contract.
    unsafe { with_instance(instance, Call3::SetTime, |inst| inst.set_time(time)) }
}

/// # Safety
/// `instance` live or NULL; `continuousStates` NULL or `nContinuousStates` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetContinuousStates(
    instance: fmi3Instance,
    continuousStates: *const fmi3Float64,
    nContinuousStates: usize,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, Call3::SetContinuousStates, |inst| {
            match slice(continuousStates, nContinuousStates) {
                Some(x) => inst.set_continuous_states(x),
                None => inst.null_array("continuousStates", nContinuousStates),
            }
        })
    }
}

/// Defines an export that fills an array of the continuous states' size.
macro_rules! state_array {
    ($name:ident, $call:ident, $arg:literal, $method:ident) => {
        /// # Safety
        /// `instance` live or NULL; the array NULL or `n` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            values: *mut fmi3Float64,
            n: usize,
        ) -> fmi3Status {
            // SAFETY: pointers valid by contract; checked for NULL.
            unsafe {
                with_instance(instance, Call3::$call, |inst| match slice_mut(values, n) {
                    Some(v) => inst.$method(v),
                    None => inst.null_array($arg, n),
                })
            }
        }
    };
}

state_array!(
    fmi3GetContinuousStates,
    GetContinuousStates,
    "continuousStates",
    get_continuous_states
);
state_array!(
    fmi3GetContinuousStateDerivatives,
    GetContinuousStateDerivatives,
    "derivatives",
    get_derivatives
);
state_array!(
    fmi3GetNominalsOfContinuousStates,
    GetNominalsOfContinuousStates,
    "nominals",
    get_nominals
);

/// # Safety
/// `instance` live or NULL; `eventIndicators` is not touched (there are none).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetEventIndicators(
    instance: fmi3Instance,
    _eventIndicators: *mut fmi3Float64,
    nEventIndicators: usize,
) -> fmi3Status {
    // SAFETY: `instance` valid by contract.
    unsafe {
        with_instance(instance, Call3::GetEventIndicators, |inst| {
            inst.get_event_indicators(nEventIndicators)
        })
    }
}

/// Writes `n` to `*out`.
///
/// # Safety
/// `instance` live or NULL; `out` NULL or writable.
unsafe fn count_query(
    instance: fmi3Instance,
    call: Call3,
    out: *mut usize,
    n: usize,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, call, |inst| match out.as_mut() {
            Some(out) => {
                *out = n;
                Status::Ok
            }
            None => inst.null_array("the count", 1),
        })
    }
}

/// # Safety
/// `instance` live or NULL; `nEventIndicators` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(
    instance: fmi3Instance,
    nEventIndicators: *mut usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        count_query(
            instance,
            Call3::GetNumberOfEventIndicators,
            nEventIndicators,
            0,
        )
    }
}

/// # Safety
/// `instance` live or NULL; `nContinuousStates` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(
    instance: fmi3Instance,
    nContinuousStates: *mut usize,
) -> fmi3Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        count_query(
            instance,
            Call3::GetNumberOfContinuousStates,
            nContinuousStates,
            STATES,
        )
    }
}

/// # Safety
/// `instance` live or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetOutputDerivatives(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _orders: *const fmi3Int32,
    _values: *mut fmi3Float64,
    _nValues: usize,
) -> fmi3Status {
    // SAFETY: `instance` valid by contract.
    unsafe {
        unsupported(
            instance,
            Call3::GetOutputDerivatives,
            "maxOutputDerivativeOrder = 0",
        )
    }
}

/// # Safety
/// `instance` live or NULL; each output flag and `lastSuccessfulTime` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DoStep(
    instance: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(instance, Call3::DoStep, |inst| {
            let status = inst.do_step(currentCommunicationPoint, communicationStepSize);
            set_flags(
                &[eventHandlingNeeded, terminateSimulation, earlyReturn],
                false,
            );
            if let Some(t) = lastSuccessfulTime.as_mut() {
                *t = inst.model.time;
            }
            status
        })
    }
}

const _: fmi3GetVersionTYPE = Some(fmi3GetVersion);
const _: fmi3SetDebugLoggingTYPE = Some(fmi3SetDebugLogging);
const _: fmi3InstantiateModelExchangeTYPE = Some(fmi3InstantiateModelExchange);
const _: fmi3InstantiateCoSimulationTYPE = Some(fmi3InstantiateCoSimulation);
const _: fmi3InstantiateScheduledExecutionTYPE = Some(fmi3InstantiateScheduledExecution);
const _: fmi3FreeInstanceTYPE = Some(fmi3FreeInstance);
const _: fmi3EnterInitializationModeTYPE = Some(fmi3EnterInitializationMode);
const _: fmi3ExitInitializationModeTYPE = Some(fmi3ExitInitializationMode);
const _: fmi3EnterEventModeTYPE = Some(fmi3EnterEventMode);
const _: fmi3TerminateTYPE = Some(fmi3Terminate);
const _: fmi3ResetTYPE = Some(fmi3Reset);
const _: fmi3GetFloat32TYPE = Some(fmi3GetFloat32);
const _: fmi3GetFloat64TYPE = Some(fmi3GetFloat64);
const _: fmi3GetInt8TYPE = Some(fmi3GetInt8);
const _: fmi3GetUInt8TYPE = Some(fmi3GetUInt8);
const _: fmi3GetInt16TYPE = Some(fmi3GetInt16);
const _: fmi3GetUInt16TYPE = Some(fmi3GetUInt16);
const _: fmi3GetInt32TYPE = Some(fmi3GetInt32);
const _: fmi3GetUInt32TYPE = Some(fmi3GetUInt32);
const _: fmi3GetInt64TYPE = Some(fmi3GetInt64);
const _: fmi3GetUInt64TYPE = Some(fmi3GetUInt64);
const _: fmi3GetBooleanTYPE = Some(fmi3GetBoolean);
const _: fmi3GetStringTYPE = Some(fmi3GetString);
const _: fmi3GetBinaryTYPE = Some(fmi3GetBinary);
const _: fmi3GetClockTYPE = Some(fmi3GetClock);
const _: fmi3SetFloat32TYPE = Some(fmi3SetFloat32);
const _: fmi3SetFloat64TYPE = Some(fmi3SetFloat64);
const _: fmi3SetInt8TYPE = Some(fmi3SetInt8);
const _: fmi3SetUInt8TYPE = Some(fmi3SetUInt8);
const _: fmi3SetInt16TYPE = Some(fmi3SetInt16);
const _: fmi3SetUInt16TYPE = Some(fmi3SetUInt16);
const _: fmi3SetInt32TYPE = Some(fmi3SetInt32);
const _: fmi3SetUInt32TYPE = Some(fmi3SetUInt32);
const _: fmi3SetInt64TYPE = Some(fmi3SetInt64);
const _: fmi3SetUInt64TYPE = Some(fmi3SetUInt64);
const _: fmi3SetBooleanTYPE = Some(fmi3SetBoolean);
const _: fmi3SetStringTYPE = Some(fmi3SetString);
const _: fmi3SetBinaryTYPE = Some(fmi3SetBinary);
const _: fmi3SetClockTYPE = Some(fmi3SetClock);
const _: fmi3GetNumberOfVariableDependenciesTYPE = Some(fmi3GetNumberOfVariableDependencies);
const _: fmi3GetVariableDependenciesTYPE = Some(fmi3GetVariableDependencies);
const _: fmi3GetFMUStateTYPE = Some(fmi3GetFMUState);
const _: fmi3SetFMUStateTYPE = Some(fmi3SetFMUState);
const _: fmi3FreeFMUStateTYPE = Some(fmi3FreeFMUState);
const _: fmi3SerializedFMUStateSizeTYPE = Some(fmi3SerializedFMUStateSize);
const _: fmi3SerializeFMUStateTYPE = Some(fmi3SerializeFMUState);
const _: fmi3DeserializeFMUStateTYPE = Some(fmi3DeserializeFMUState);
const _: fmi3GetDirectionalDerivativeTYPE = Some(fmi3GetDirectionalDerivative);
const _: fmi3GetAdjointDerivativeTYPE = Some(fmi3GetAdjointDerivative);
const _: fmi3EnterConfigurationModeTYPE = Some(fmi3EnterConfigurationMode);
const _: fmi3ExitConfigurationModeTYPE = Some(fmi3ExitConfigurationMode);
const _: fmi3GetIntervalDecimalTYPE = Some(fmi3GetIntervalDecimal);
const _: fmi3GetIntervalFractionTYPE = Some(fmi3GetIntervalFraction);
const _: fmi3GetShiftDecimalTYPE = Some(fmi3GetShiftDecimal);
const _: fmi3GetShiftFractionTYPE = Some(fmi3GetShiftFraction);
const _: fmi3SetIntervalDecimalTYPE = Some(fmi3SetIntervalDecimal);
const _: fmi3SetIntervalFractionTYPE = Some(fmi3SetIntervalFraction);
const _: fmi3SetShiftDecimalTYPE = Some(fmi3SetShiftDecimal);
const _: fmi3SetShiftFractionTYPE = Some(fmi3SetShiftFraction);
const _: fmi3EvaluateDiscreteStatesTYPE = Some(fmi3EvaluateDiscreteStates);
const _: fmi3UpdateDiscreteStatesTYPE = Some(fmi3UpdateDiscreteStates);
const _: fmi3EnterContinuousTimeModeTYPE = Some(fmi3EnterContinuousTimeMode);
const _: fmi3CompletedIntegratorStepTYPE = Some(fmi3CompletedIntegratorStep);
const _: fmi3SetTimeTYPE = Some(fmi3SetTime);
const _: fmi3SetContinuousStatesTYPE = Some(fmi3SetContinuousStates);
const _: fmi3GetContinuousStateDerivativesTYPE = Some(fmi3GetContinuousStateDerivatives);
const _: fmi3GetEventIndicatorsTYPE = Some(fmi3GetEventIndicators);
const _: fmi3GetContinuousStatesTYPE = Some(fmi3GetContinuousStates);
const _: fmi3GetNominalsOfContinuousStatesTYPE = Some(fmi3GetNominalsOfContinuousStates);
const _: fmi3GetNumberOfEventIndicatorsTYPE = Some(fmi3GetNumberOfEventIndicators);
const _: fmi3GetNumberOfContinuousStatesTYPE = Some(fmi3GetNumberOfContinuousStates);
const _: fmi3EnterStepModeTYPE = Some(fmi3EnterStepMode);
const _: fmi3GetOutputDerivativesTYPE = Some(fmi3GetOutputDerivatives);
const _: fmi3DoStepTYPE = Some(fmi3DoStep);
const _: fmi3ActivateModelPartitionTYPE = Some(fmi3ActivateModelPartition);
