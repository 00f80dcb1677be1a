//! Every FMI 2.0 function: common, co-simulation and Model Exchange. Each body is: pointer and array checks,
//! a call into the safe [`Instance`], the status back. Panics stop in `boundary`.
//!
//! Ownership: the instance (boxed here) is freed by fmi2FreeInstance; its FMU states (boxed
//! in `fmu_states`) by fmi2FreeFMUstate, or with the instance if the host did not; strings returned by fmi2GetString live until the
//! next call on the same instance; the host keeps ownership of every array it passes.
#![allow(non_snake_case)]

use std::ffi::{CStr, c_char};
use std::ptr::null_mut;

use fmi_sys::fmi2::*;

use crate::boundary::{
    CArray, c_str, free_instance, guard, instantiate, set_debug_logging, slice, slice_mut,
    with_instance,
};
use crate::call_sequence::{Abi, Call, FmiCall, Interface};
use crate::instance::{Instance, Instantiation};
use crate::logging::{Callback, Logger, Status};
use crate::resource_uri::file_uri_to_path;
use crate::variables::LogCategory;

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// # Safety
/// `functions` must be NULL or point to valid callbacks; strings NULL or NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: fmi2Type,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    crate::boundary::install_panic_hook();
    guard(null_mut(), || {
        // SAFETY: NULL or valid by contract.
        let Some(functions) = (unsafe { functions.as_ref() }) else {
            return null_mut();
        };
        // Without a logger nothing can be reported: refuse silently.
        let Some(callback) = functions.logger else {
            return null_mut();
        };
        // SAFETY: NULL or NUL-terminated by contract.
        let name = unsafe { c_str(instanceName) }
            .map(CStr::to_owned)
            .unwrap_or_default();
        let logger = Logger::new(
            Callback::Fmi2(callback),
            functions.componentEnvironment,
            name,
            loggingOn != 0,
        );
        if functions.allocateMemory.is_none() || functions.freeMemory.is_none() {
            logger.log(
                Status::Error,
                LogCategory::StatusError,
                "fmi2Instantiate: the callbacks allocateMemory and freeMemory must not be NULL",
            );
            return null_mut();
        }
        // SAFETY: NULL or NUL-terminated by contract.
        let (guid, resources) = unsafe { (c_str(fmuGUID), c_str(fmuResourceLocation)) };
        #[allow(non_upper_case_globals)]
        let interface = match fmuType {
            fmi2Type_fmi2CoSimulation => Interface::CoSimulation,
            fmi2Type_fmi2ModelExchange => Interface::ModelExchange,
            other => {
                logger.log(
                    Status::Error,
                    LogCategory::StatusError,
                    &format!(
                        "fmi2Instantiate: fmuType = {other} is neither fmi2ModelExchange (0) \
                         nor fmi2CoSimulation (1)"
                    ),
                );
                return null_mut();
            }
        };
        let with = Instantiation {
            abi: Abi::Fmi2,
            interface,
            token: guid,
            resources: resources.and_then(|r| file_uri_to_path(&r.to_string_lossy())),
        };
        instantiate(logger, with)
    })
}

/// # Safety
/// `c` must be NULL or an instance from fmi2Instantiate; it must not be used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    // SAFETY: forwarded from this function's contract.
    unsafe { free_instance(c) }
}

/// # Safety
/// `c` as for fmi2FreeInstance; `categories` NULL or `nCategories` C strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        set_debug_logging(
            c,
            Call::SetDebugLogging,
            loggingOn != 0,
            nCategories,
            categories,
        )
    }
}

/// # Safety
/// `c` must be NULL or a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe {
        with_instance(c, Call::SetupExperiment, |inst| {
            inst.setup_experiment(startTime, (stopTimeDefined != 0).then_some(stopTime))
        })
    }
}

/// # Safety
/// `c` must be NULL or a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe {
        with_instance(
            c,
            Call::EnterInitializationMode,
            Instance::enter_initialization_mode,
        )
    }
}

/// # Safety
/// `c` must be NULL or a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe {
        with_instance(
            c,
            Call::ExitInitializationMode,
            Instance::exit_initialization_mode,
        )
    }
}

/// # Safety
/// `c` must be NULL or a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe { with_instance(c, Call::Terminate, Instance::terminate) }
}

/// # Safety
/// `c` must be NULL or a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe { with_instance(c, Call::Reset, Instance::reset) }
}

/// A get or set call on `nvr` variables: `vr` and `value` as slices (NULL only when empty,
/// else [`Instance::null_array`]), then `f` on the instance, inside [`with_instance`].
///
/// # Safety
/// `c` a live instance or NULL; `vr` and `value` NULL or `nvr` elements (`value` exclusively
/// borrowed when it is written).
unsafe fn with_values<A: CArray>(
    c: fmi2Component,
    call: Call,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: A,
    f: impl FnOnce(&mut Instance, &[fmi2ValueReference], A::Slice<'_>) -> Status,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, call, |inst| {
            match (slice(vr, nvr), value.to_slice(nvr)) {
                (Some(vrs), Some(values)) => f(inst, vrs, values),
                _ => inst.null_array("vr or value", nvr),
            }
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `vr` and `value` NULL or `nvr` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: forwarded from this function's contract.
    unsafe { with_values(c, Call::GetReal, vr, nvr, value, Instance::get_real) }
}

/// # Safety
/// `c` a live instance or NULL; `vr` and `value` NULL or `nvr` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        with_values(c, Call::GetInteger, vr, nvr, value, |inst, vrs, _| {
            inst.no_integer_variables(vrs)
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `vr` and `value` NULL or `nvr` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        with_values(c, Call::GetBoolean, vr, nvr, value, |inst, vrs, values| {
            inst.get_boolean(vrs, values)
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `vr` and `value` NULL or `nvr` elements. The strings
/// returned live until the next call on this instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    // SAFETY: forwarded from this function's contract.
    unsafe { with_values(c, Call::GetString, vr, nvr, value, Instance::get_string) }
}

/// # Safety
/// `c` a live instance or NULL; `vr` and `value` NULL or `nvr` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    // SAFETY: forwarded from this function's contract.
    unsafe { with_values(c, Call::SetReal, vr, nvr, value, Instance::set_real) }
}

/// # Safety
/// `c` a live instance or NULL; `vr` and `value` NULL or `nvr` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        with_values(c, Call::SetInteger, vr, nvr, value, |inst, vrs, _| {
            inst.no_integer_variables(vrs)
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `vr` and `value` NULL or `nvr` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    // SAFETY: forwarded from this function's contract.
    unsafe { with_values(c, Call::SetBoolean, vr, nvr, value, Instance::set_boolean) }
}

/// # Safety
/// `c` a live instance or NULL; `vr` and `value` NULL or `nvr` elements, each string NULL or
/// NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        with_values(c, Call::SetString, vr, nvr, value, |inst, vrs, values| {
            // SAFETY: each string NULL or NUL-terminated, by this function's contract.
            let strings: Vec<Option<&CStr>> = values.iter().map(|s| c_str(*s)).collect();
            inst.set_string(vrs, &strings)
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `FMUstate` NULL or a valid pointer to a state slot.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::GetFMUstate, |inst| {
            inst.get_state(FMUstate.as_mut())
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `FMUstate` NULL or a state from this FMU.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    // SAFETY: pointers valid by contract.
    unsafe { with_instance(c, Call::SetFMUstate, |inst| inst.set_state(FMUstate)) }
}

/// # Safety
/// `c` a live instance or NULL; `FMUstate` NULL or a slot holding NULL or a state of this FMU.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::FreeFMUstate, |inst| {
            inst.free_state(FMUstate.as_mut())
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `FMUstate` a state of this FMU; `size` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::SerializedFMUstateSize, |inst| {
            inst.serialized_size(FMUstate, size.as_mut())
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `FMUstate` a state of this FMU; `serializedState` NULL or
/// `size` writable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::SerializeFMUstate, |inst| {
            inst.serialize_into(FMUstate, slice_mut(serializedState as *mut u8, size), size)
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `serializedState` NULL or `size` bytes; `FMUstate` NULL or a
/// writable slot.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::DeSerializeFMUstate, |inst| {
            inst.deserialize(
                slice(serializedState as *const u8, size),
                size,
                FMUstate.as_mut(),
            )
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; the arrays NULL or of `nUnknown` and `nKnown` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    vUnknown_ref: *const fmi2ValueReference,
    nUnknown: usize,
    vKnown_ref: *const fmi2ValueReference,
    nKnown: usize,
    dvKnown: *const fmi2Real,
    dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::GetDirectionalDerivative, |inst| {
            match (
                slice(vUnknown_ref, nUnknown),
                slice(vKnown_ref, nKnown),
                slice(dvKnown, nKnown),
                slice_mut(dvUnknown, nUnknown),
            ) {
                (Some(unknown), Some(known), Some(dv_known), Some(dv_unknown)) => {
                    inst.get_directional_derivative(unknown, known, dv_known, dv_unknown)
                }
                (None, ..) | (.., None) => inst.null_array("vUnknown_ref or dvUnknown", nUnknown),
                _ => inst.null_array("vKnown_ref or dvKnown", nKnown),
            }
        })
    }
}

/// # Safety
/// `c` a live instance or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe {
        with_instance(c, Call::SetRealInputDerivatives, |inst| {
            inst.unsupported("canInterpolateInputs = false")
        })
    }
}

/// # Safety
/// `c` a live instance or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe {
        with_instance(c, Call::GetRealOutputDerivatives, |inst| {
            inst.unsupported("maxOutputDerivativeOrder = 0")
        })
    }
}

/// # Safety
/// `c` a live instance or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe {
        with_instance(c, Call::DoStep, |inst| {
            inst.do_step(currentCommunicationPoint, communicationStepSize)
        })
    }
}

/// # Safety
/// `c` a live instance or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe {
        with_instance(c, Call::CancelStep, |inst| {
            inst.unsupported("fmi2DoStep never returns fmi2Pending, so there is no step to cancel")
        })
    }
}

/// Answers a status query: `answer` gives the value for the kinds this FMU knows.
///
/// # Safety
/// `c` a live instance or NULL; `value` NULL or writable.
unsafe fn status_query<T>(
    c: fmi2Component,
    call: Call,
    value: *mut T,
    answer: impl FnOnce(&Instance) -> Option<T>,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, call, |inst| {
            let Some(value) = value.as_mut() else {
                return inst.null_array("value", 1);
            };
            match answer(inst) {
                Some(v) => {
                    *value = v;
                    Status::Ok
                }
                None => {
                    inst.log(
                        Status::Discard,
                        LogCategory::StatusWarning,
                        &format!(
                            "{}: this status kind is not available (no asynchronous steps)",
                            call.name()
                        ),
                    );
                    Status::Discard
                }
            }
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `value` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    _s: fmi2StatusKind,
    value: *mut fmi2Status,
) -> fmi2Status {
    // SAFETY: forwarded.
    unsafe { status_query(c, Call::GetStatus, value, |_| None) }
}

/// # Safety
/// `c` a live instance or NULL; `value` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: forwarded.
    unsafe {
        status_query(c, Call::GetRealStatus, value, |inst| {
            (s == fmi2StatusKind_fmi2LastSuccessfulTime).then(|| inst.last_successful_time())
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `value` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    _s: fmi2StatusKind,
    value: *mut fmi2Integer,
) -> fmi2Status {
    // SAFETY: forwarded.
    unsafe { status_query(c, Call::GetIntegerStatus, value, |_| None) }
}

/// # Safety
/// `c` a live instance or NULL; `value` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    // The FMU never asks to end the simulation: fmi2Terminated is always false.
    // SAFETY: forwarded.
    unsafe {
        status_query(c, Call::GetBooleanStatus, value, |_| {
            (s == fmi2StatusKind_fmi2Terminated).then_some(fmi2False as fmi2Boolean)
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `value` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    _s: fmi2StatusKind,
    value: *mut fmi2String,
) -> fmi2Status {
    // SAFETY: forwarded.
    unsafe { status_query(c, Call::GetStringStatus, value, |_| None) }
}

// The exports have exactly the signatures of the standard's headers.
// ---- Model Exchange ------------------------------------------------------------------------

/// # Safety
/// `c` a live instance or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterEventMode(c: fmi2Component) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe { with_instance(c, Call::EnterEventMode, |inst| inst.enter_event_mode()) }
}

/// # Safety
/// `c` a live instance or NULL; `eventInfo` NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2NewDiscreteStates(
    c: fmi2Component,
    eventInfo: *mut fmi2EventInfo,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::NewDiscreteStates, |inst| {
            let Some(info) = eventInfo.as_mut() else {
                return inst.null_array("eventInfo", 1);
            };
            *info = fmi2EventInfo {
                newDiscreteStatesNeeded: 0,
                terminateSimulation: 0,
                nominalsOfContinuousStatesChanged: 0,
                valuesOfContinuousStatesChanged: 0,
                nextEventTimeDefined: 0,
                nextEventTime: 0.0,
            };
            inst.new_discrete_states()
        })
    }
}

/// # Safety
/// `c` a live instance or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: fmi2Component) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe {
        with_instance(c, Call::EnterContinuousTimeMode, |inst| {
            inst.enter_continuous_time_mode()
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; the two flags NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
    c: fmi2Component,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
    enterEventMode: *mut fmi2Boolean,
    terminateSimulation: *mut fmi2Boolean,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::CompletedIntegratorStep, |inst| {
            match (enterEventMode.as_mut(), terminateSimulation.as_mut()) {
                (Some(event), Some(terminate)) => {
                    // No events, no reason to stop.
                    *event = 0;
                    *terminate = 0;
                    Status::Ok
                }
                _ => inst.null_array("enterEventMode or terminateSimulation", 1),
            }
        })
    }
}

/// # Safety
/// `c` a live instance or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetTime(c: fmi2Component, time: fmi2Real) -> fmi2Status {
    // SAFETY: `c` valid by contract.
    unsafe { with_instance(c, Call::SetTime, |inst| inst.set_time(time)) }
}

/// # Safety
/// `c` a live instance or NULL; `x` NULL or `nx` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetContinuousStates(
    c: fmi2Component,
    x: *const fmi2Real,
    nx: usize,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::SetContinuousStates, |inst| match slice(x, nx) {
            Some(x) => inst.set_continuous_states(x),
            None => inst.null_array("x", nx),
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `x` NULL or `nx` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetContinuousStates(
    c: fmi2Component,
    x: *mut fmi2Real,
    nx: usize,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::GetContinuousStates, |inst| {
            match slice_mut(x, nx) {
                Some(x) => inst.get_continuous_states(x),
                None => inst.null_array("x", nx),
            }
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `derivatives` NULL or `nx` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDerivatives(
    c: fmi2Component,
    derivatives: *mut fmi2Real,
    nx: usize,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(c, Call::GetDerivatives, |inst| {
            match slice_mut(derivatives, nx) {
                Some(dx) => inst.get_derivatives(dx),
                None => inst.null_array("derivatives", nx),
            }
        })
    }
}

/// # Safety
/// `c` a live instance or NULL; `x_nominal` NULL or `nx` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(
    c: fmi2Component,
    x_nominal: *mut fmi2Real,
    nx: usize,
) -> fmi2Status {
    // SAFETY: pointers valid by contract; checked for NULL.
    unsafe {
        with_instance(
            c,
            Call::GetNominalsOfContinuousStates,
            |inst| match slice_mut(x_nominal, nx) {
                Some(n) => inst.get_nominals(n),
                None => inst.null_array("x_nominal", nx),
            },
        )
    }
}

/// # Safety
/// `c` a live instance or NULL; `eventIndicators` NULL or `ni` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetEventIndicators(
    c: fmi2Component,
    _eventIndicators: *mut fmi2Real,
    ni: usize,
) -> fmi2Status {
    // SAFETY: `c` valid by contract; the array is not touched (there are no indicators).
    unsafe {
        with_instance(c, Call::GetEventIndicators, |inst| {
            inst.get_event_indicators(ni)
        })
    }
}

const _: fmi2GetTypesPlatformTYPE = Some(fmi2GetTypesPlatform);
const _: fmi2GetVersionTYPE = Some(fmi2GetVersion);
const _: fmi2SetDebugLoggingTYPE = Some(fmi2SetDebugLogging);
const _: fmi2InstantiateTYPE = Some(fmi2Instantiate);
const _: fmi2FreeInstanceTYPE = Some(fmi2FreeInstance);
const _: fmi2SetupExperimentTYPE = Some(fmi2SetupExperiment);
const _: fmi2EnterInitializationModeTYPE = Some(fmi2EnterInitializationMode);
const _: fmi2ExitInitializationModeTYPE = Some(fmi2ExitInitializationMode);
const _: fmi2TerminateTYPE = Some(fmi2Terminate);
const _: fmi2ResetTYPE = Some(fmi2Reset);
const _: fmi2GetRealTYPE = Some(fmi2GetReal);
const _: fmi2GetIntegerTYPE = Some(fmi2GetInteger);
const _: fmi2GetBooleanTYPE = Some(fmi2GetBoolean);
const _: fmi2GetStringTYPE = Some(fmi2GetString);
const _: fmi2SetRealTYPE = Some(fmi2SetReal);
const _: fmi2SetIntegerTYPE = Some(fmi2SetInteger);
const _: fmi2SetBooleanTYPE = Some(fmi2SetBoolean);
const _: fmi2SetStringTYPE = Some(fmi2SetString);
const _: fmi2GetFMUstateTYPE = Some(fmi2GetFMUstate);
const _: fmi2SetFMUstateTYPE = Some(fmi2SetFMUstate);
const _: fmi2FreeFMUstateTYPE = Some(fmi2FreeFMUstate);
const _: fmi2SerializedFMUstateSizeTYPE = Some(fmi2SerializedFMUstateSize);
const _: fmi2SerializeFMUstateTYPE = Some(fmi2SerializeFMUstate);
const _: fmi2DeSerializeFMUstateTYPE = Some(fmi2DeSerializeFMUstate);
const _: fmi2GetDirectionalDerivativeTYPE = Some(fmi2GetDirectionalDerivative);
const _: fmi2SetRealInputDerivativesTYPE = Some(fmi2SetRealInputDerivatives);
const _: fmi2GetRealOutputDerivativesTYPE = Some(fmi2GetRealOutputDerivatives);
const _: fmi2DoStepTYPE = Some(fmi2DoStep);
const _: fmi2CancelStepTYPE = Some(fmi2CancelStep);
const _: fmi2GetStatusTYPE = Some(fmi2GetStatus);
const _: fmi2GetRealStatusTYPE = Some(fmi2GetRealStatus);
const _: fmi2GetIntegerStatusTYPE = Some(fmi2GetIntegerStatus);
const _: fmi2GetBooleanStatusTYPE = Some(fmi2GetBooleanStatus);
const _: fmi2GetStringStatusTYPE = Some(fmi2GetStringStatus);
const _: fmi2EnterEventModeTYPE = Some(fmi2EnterEventMode);
const _: fmi2NewDiscreteStatesTYPE = Some(fmi2NewDiscreteStates);
const _: fmi2EnterContinuousTimeModeTYPE = Some(fmi2EnterContinuousTimeMode);
const _: fmi2CompletedIntegratorStepTYPE = Some(fmi2CompletedIntegratorStep);
const _: fmi2SetTimeTYPE = Some(fmi2SetTime);
const _: fmi2SetContinuousStatesTYPE = Some(fmi2SetContinuousStates);
const _: fmi2GetContinuousStatesTYPE = Some(fmi2GetContinuousStates);
const _: fmi2GetDerivativesTYPE = Some(fmi2GetDerivatives);
const _: fmi2GetNominalsOfContinuousStatesTYPE = Some(fmi2GetNominalsOfContinuousStates);
const _: fmi2GetEventIndicatorsTYPE = Some(fmi2GetEventIndicators);
