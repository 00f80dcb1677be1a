//! The FMI 3.0 calls of a sequence, made as a host would, with the checks of run.rs (status
//! within fmi3Status, no non-finite Float64 with fmi3OK or fmi3Warning, errors logged, no
//! write past an array's end, the other standard's instances refused) and FMI 3.0's own:
//! - a call whose arguments cannot fit the variables (a reference of no variable or of
//!   another type, `nValues` not the variables' element count, `nSeed` / `nSensitivity` not
//!   the knowns' and unknowns' counts, a NULL array with a length, the wrong number of
//!   continuous states or event indicators) is refused with fmi3Error;
//! - the getters and setters of Float32, the integer types, Binary and Clock, and the clock
//!   interval and shift functions refuse any value reference with fmi3Error;
//! - scheduled execution is refused: fmi3InstantiateScheduledExecution returns NULL and
//!   fmi3ActivateModelPartition fmi3Error;
//! - a function of one interface given an instance of the other is refused;
//! - an instantiation that returns NULL says why, when it has a logger;
//! - what is handed out with fmi3OK is written (booleans 0 or 1, strings readable, counts
//!   those of the model description, `lastSuccessfulTime` the end of the step);
//! - the logger is called with a status, category and environment the FMU may send, and
//!   the intermediate-update and scheduling callbacks are never called.

use std::ffi::{CStr, CString, c_char};
use std::ptr::{null, null_mut};

use fmi_sys::fmi3::*;
use pacejka87_tire::variables::{GUID, INSTANTIATION_TOKEN};

use crate::fmi;
use crate::run::{CANARY, FILL, GUARD, Host, or_null, or_null_mut};
use crate::seq::{Arr, Time};
use crate::seq3::{Absent, Interface3, Op3, Plain, StateArray, Timing, Type3};

/// `(name, status)` of the call `f.name(args)`: the function's name written once.
macro_rules! named {
    ($f:ident . $name:ident ( $($arg:expr),* $(,)? )) => {
        (stringify!($name), ($f.$name)($($arg),*))
    };
}

/// The functions of co-simulation only, and of Model Exchange only (with event mode in
/// co-simulation refused, the event-mode functions are Model Exchange's here).
pub(crate) const CO_SIMULATION_ONLY: &[&str] = &[
    "fmi3DoStep",
    "fmi3EnterStepMode",
    "fmi3GetOutputDerivatives",
];
pub(crate) const MODEL_EXCHANGE_ONLY: &[&str] = &[
    "fmi3EnterContinuousTimeMode",
    "fmi3CompletedIntegratorStep",
    "fmi3SetTime",
    "fmi3SetContinuousStates",
    "fmi3GetContinuousStateDerivatives",
    "fmi3GetEventIndicators",
    "fmi3GetContinuousStates",
    "fmi3GetNominalsOfContinuousStates",
    "fmi3GetNumberOfEventIndicators",
    "fmi3GetNumberOfContinuousStates",
    "fmi3EnterEventMode",
    "fmi3UpdateDiscreteStates",
    "fmi3EvaluateDiscreteStates",
];

const OK: fmi3Status = fmi3Status_fmi3OK;
const WARNING: fmi3Status = fmi3Status_fmi3Warning;
const ERROR: fmi3Status = fmi3Status_fmi3Error;

/// [`FILL`] as 64-bit words.
const FILL64: u64 = 0xA5A5_A5A5_A5A5_A5A5;
/// A string pointer the FMU has not written (never dereferenced).
const UNWRITTEN: usize = 0xdead_bee8;

/// The intermediate-update callback: this FMU makes no intermediate updates.
unsafe extern "C" fn intermediate_update(
    _: fmi3InstanceEnvironment,
    _: fmi3Float64,
    _: fmi3Boolean,
    _: fmi3Boolean,
    _: fmi3Boolean,
    _: fmi3Boolean,
    _: *mut fmi3Boolean,
    _: *mut fmi3Float64,
) {
    fmi::report_oddity("intermediateUpdate called by an FMU that has no intermediate updates");
}

unsafe extern "C" fn clock_update(_: fmi3InstanceEnvironment) {
    fmi::report_oddity("clockUpdate called (scheduled execution is refused)");
}

unsafe extern "C" fn lock_preemption() {
    fmi::report_oddity("lockPreemption called (scheduled execution is refused)");
}

unsafe extern "C" fn unlock_preemption() {
    fmi::report_oddity("unlockPreemption called (scheduled execution is refused)");
}

/// Why a call with these arguments must be refused, if it must: a NULL array with a length.
fn null_with_length(arr: Arr, n_first: usize, n_second: usize) -> Option<String> {
    match arr {
        Arr::Null1 if n_first > 0 => Some(format!("a NULL first array of {n_first}")),
        Arr::Null2 if n_second > 0 => Some(format!("a NULL second array of {n_second}")),
        _ => None,
    }
}

impl Host<'_> {
    /// A call that must be refused (`why`) returned something else than fmi3Error.
    fn refused(&mut self, name: &str, status: fmi3Status, why: Option<String>) {
        if let Some(why) = why
            && status != ERROR
        {
            self.find(format!("{name} returned {status} for {why}, not fmi3Error"));
        }
    }

    /// Why a get or set of `vrs` of type `ty` with `n` values must be refused, if it must.
    fn shape(&self, ty: Type3, vrs: &[u32], n: usize, arr: Arr) -> Option<String> {
        if let Some(why) = null_with_length(arr, vrs.len(), n) {
            return Some(why);
        }
        let mut total = 0;
        for vr in vrs {
            match self.v3.var(*vr) {
                Some(v) if v.ty == ty => total += v.size,
                Some(v) => return Some(format!("{} ({vr}), a {:?}", v.name, v.ty)),
                None => return Some(format!("value reference {vr}, no variable")),
            }
        }
        (total != n).then(|| format!("nValues = {n} where the variables hold {total}"))
    }

    /// A getter of `ty` (`name`, called through `call`) for `vrs` into `n` elements of `fill`
    /// and the guard: its status checked, and refused if the arguments cannot fit the
    /// variables. Returns the status and the array.
    fn get3<T: Clone>(
        &mut self,
        name: &'static str,
        (inst, vrs, n, arr): (usize, &[u32], usize, Arr),
        ty: Type3,
        fill: T,
        call: impl FnOnce(fmi3Instance, *const u32, usize, *mut T, usize) -> fmi3Status,
    ) -> (fmi3Status, Vec<T>) {
        let mut values = vec![fill; n + GUARD];
        let s = call(
            self.c(inst),
            arr.ptr(Arr::Null1, vrs.as_ptr()),
            vrs.len(),
            arr.ptr_mut(Arr::Null2, values.as_mut_ptr()),
            n,
        );
        let s = self.status(name, Some(inst), s);
        let why = self.shape(ty, vrs, n, arr);
        self.refused(name, s, why);
        (s, values)
    }

    /// A setter of `ty` (`name`, called through `call`) of `values` for `vrs`: its status
    /// checked, and refused if the arguments cannot fit the variables or set `time` (the
    /// independent variable).
    fn set3<T>(
        &mut self,
        name: &'static str,
        (inst, vrs, values, arr): (usize, &[u32], &[T], Arr),
        ty: Type3,
        call: impl FnOnce(fmi3Instance, *const u32, usize, *const T, usize) -> fmi3Status,
    ) {
        let s = call(
            self.c(inst),
            arr.ptr(Arr::Null1, vrs.as_ptr()),
            vrs.len(),
            arr.ptr(Arr::Null2, values.as_ptr()),
            values.len(),
        );
        let s = self.status(name, Some(inst), s);
        let time = self.v3.time;
        let why = self
            .shape(ty, vrs, values.len(), arr)
            .or_else(|| vrs.contains(&time).then(|| "time".to_string()));
        self.refused(name, s, why);
    }

    /// Float64s handed out: finite and written (not the canary) when OK or Warning; the
    /// guard untouched.
    fn float64s(&mut self, name: &'static str, status: fmi3Status, values: &[f64], n: usize) {
        if (status == OK || status == WARNING)
            && let Some(i) = values[..n]
                .iter()
                .position(|v| v.to_bits() == CANARY.to_bits())
        {
            self.find(format!(
                "{name} returned {status} but left value {i} of {n} unwritten"
            ));
        }
        self.reals_allowing_canary(name, status, values, n);
    }

    /// Booleans handed out with OK or Warning are 0 or 1; nothing written past `n`.
    fn booleans(&mut self, name: &'static str, status: fmi3Status, bytes: &[u8], n: usize) {
        self.past_end(name, n, "booleans", &bytes[n..], &FILL);
        if (status == OK || status == WARNING)
            && let Some(i) = bytes[..n].iter().position(|b| *b > 1)
        {
            self.find(format!(
                "{name} returned {status} with boolean {i} = {:#x}, not 0 or 1",
                bytes[i]
            ));
        }
    }

    /// The FMU's bytes of an array the FMU may write `n` elements of `size` bytes into,
    /// untouched after those.
    fn guarded(&mut self, name: &str, words: &[u64], n: usize, size: usize) {
        // SAFETY: the words' own bytes.
        let bytes = unsafe {
            std::slice::from_raw_parts(words.as_ptr().cast::<u8>(), std::mem::size_of_val(words))
        };
        self.past_end(
            name,
            n,
            "values",
            &bytes[(n * size).min(bytes.len())..],
            &FILL,
        );
    }

    /// The time to pass: the instance's own (its `time` variable) or the given value.
    fn time3(&mut self, inst: usize, t: Time) -> f64 {
        match t {
            Time::Value(v) => v,
            Time::Current => {
                let vr = self.v3.time;
                let mut now = [CANARY];
                // SAFETY: a live or NULL instance, one reference and one value.
                let s = unsafe {
                    (self.fmi3.fmi3GetFloat64)(self.c(inst), &vr, 1, now.as_mut_ptr(), 1)
                };
                let _ = fmi::take_messages();
                self.oddities();
                if s == OK && !now[0].is_finite() {
                    self.find(format!("fmi3GetFloat64(time) = {} with fmi3OK", now[0]));
                }
                if s == OK { now[0] } else { 0.0 }
            }
        }
    }

    pub(crate) fn apply3(&mut self, op: &Op3) {
        let f = self.fmi3;
        let v3 = self.v3;
        // SAFETY (all calls below): arguments are live host memory holding the counts passed
        // with them, or NULL on purpose; FMU states are NULL, ours, stale or the garbage
        // pointer on purpose (the FMU must refuse those without reading them); instances
        // are live or NULL; callbacks are functions of this file with their C signatures.
        unsafe {
            match op {
                Op3::GetVersion => {
                    let s = (f.fmi3GetVersion)();
                    self.count_ok("fmi3GetVersion", !s.is_null());
                    if s.is_null() || CStr::from_ptr(s).to_bytes() != b"3.0" {
                        self.find("fmi3GetVersion is not 3.0".into());
                    }
                }
                &Op3::Instantiate {
                    inst,
                    interface,
                    name,
                    token,
                    resources,
                    logger,
                    logging,
                    visible,
                    event_mode,
                    early_return,
                    required,
                    callbacks,
                } => {
                    // The host frees first: an instance is never lost.
                    self.free_slot(inst);
                    let guid = CString::new(GUID).unwrap();
                    let right = CString::new(INSTANTIATION_TOKEN).unwrap();
                    let mut other = INSTANTIATION_TOKEN.as_bytes().to_vec();
                    other[1] = if other[1] == b'0' { b'1' } else { b'0' };
                    let other = CString::new(other).unwrap();
                    let garbage = c"%s%n/\xff/nonexistent/";
                    let plain = self.resource_folder();
                    let name_c = self.instance_name(inst, name);
                    let token_c = match token {
                        0 => right.as_ptr(),
                        1 => guid.as_ptr(),
                        2 => null(),
                        _ => other.as_ptr(),
                    };
                    let resources_c = match resources {
                        0 => self.resource_path.as_ptr(),
                        1 => null(),
                        2 => garbage.as_ptr(),
                        3 => self.resource_uri.as_ptr(),
                        4 => c"".as_ptr(),
                        _ => plain.as_ptr(),
                    };
                    let log: fmi3LogMessageCallback =
                        if logger { Some(fmi::log_message) } else { None };
                    let env = fmi::environment(inst);
                    let required_vrs = [0u32, 4, 100, 12345];
                    let (function, c) = match interface {
                        Interface3::ModelExchange => (
                            "fmi3InstantiateModelExchange",
                            (f.fmi3InstantiateModelExchange)(
                                name_c,
                                token_c,
                                resources_c,
                                visible,
                                logging,
                                env,
                                log,
                            ),
                        ),
                        Interface3::CoSimulation => (
                            "fmi3InstantiateCoSimulation",
                            (f.fmi3InstantiateCoSimulation)(
                                name_c,
                                token_c,
                                resources_c,
                                visible,
                                logging,
                                event_mode,
                                early_return,
                                if required == 1 {
                                    required_vrs.as_ptr()
                                } else {
                                    null()
                                },
                                if required == 0 { 0 } else { required_vrs.len() },
                                env,
                                log,
                                if callbacks {
                                    Some(intermediate_update)
                                } else {
                                    None
                                },
                            ),
                        ),
                        Interface3::ScheduledExecution => (
                            "fmi3InstantiateScheduledExecution",
                            (f.fmi3InstantiateScheduledExecution)(
                                name_c,
                                token_c,
                                resources_c,
                                visible,
                                logging,
                                env,
                                log,
                                callbacks.then_some(clock_update as unsafe extern "C" fn(_)),
                                callbacks.then_some(lock_preemption as unsafe extern "C" fn()),
                                callbacks.then_some(unlock_preemption as unsafe extern "C" fn()),
                            ),
                        ),
                    };
                    let messages = fmi::take_messages();
                    self.oddities();
                    if self.verbose {
                        println!("    -> {function} = {c:?}");
                    }
                    let mut c = c;
                    if interface == Interface3::ScheduledExecution && !c.is_null() {
                        self.find(format!("{function} returned an instance, not NULL"));
                        (f.fmi3FreeInstance)(c);
                        let _ = fmi::take_messages();
                        c = null_mut();
                    }
                    if c.is_null()
                        && logger
                        && !messages
                            .iter()
                            .any(|(level, _)| *level == log::Level::Error)
                    {
                        self.find(format!("{function} returned NULL without a message"));
                    }
                    self.model_exchange[inst] = interface == Interface3::ModelExchange;
                    self.keep_instance(inst, function, c, true, !logger);
                }
                &Op3::FreeInstance { inst } => {
                    self.free_instance(inst, "fmi3FreeInstance", f.fmi3FreeInstance)
                }
                Op3::SetDebugLogging {
                    inst,
                    on,
                    categories,
                    arr,
                } => {
                    let s = self.debug_logging(
                        "fmi3SetDebugLogging",
                        *inst,
                        categories,
                        *arr,
                        |c, n, p| (f.fmi3SetDebugLogging)(c, *on, n, p),
                    );
                    let why = (*arr != Arr::Ok && !categories.is_empty())
                        .then(|| "NULL categories with a count".to_string());
                    self.refused("fmi3SetDebugLogging", s, why);
                }
                &Op3::EnterInitializationMode {
                    inst,
                    tolerance,
                    start,
                    stop,
                } => {
                    let s = (f.fmi3EnterInitializationMode)(
                        self.c(inst),
                        tolerance.is_some(),
                        tolerance.unwrap_or(0.0),
                        start,
                        stop.is_some(),
                        stop.unwrap_or(0.0),
                    );
                    let s = self.status("fmi3EnterInitializationMode", Some(inst), s);
                    let why = (!start.is_finite()).then(|| format!("startTime {start}"));
                    self.refused("fmi3EnterInitializationMode", s, why);
                }
                &Op3::Plain { inst, call } => {
                    let c = self.c(inst);
                    let (name, s) = match call {
                        Plain::ExitInitializationMode => named!(f.fmi3ExitInitializationMode(c)),
                        Plain::EnterEventMode => named!(f.fmi3EnterEventMode(c)),
                        Plain::Terminate => named!(f.fmi3Terminate(c)),
                        Plain::Reset => named!(f.fmi3Reset(c)),
                        Plain::EnterContinuousTimeMode => named!(f.fmi3EnterContinuousTimeMode(c)),
                        Plain::EvaluateDiscreteStates => named!(f.fmi3EvaluateDiscreteStates(c)),
                        Plain::EnterConfigurationMode => named!(f.fmi3EnterConfigurationMode(c)),
                        Plain::ExitConfigurationMode => named!(f.fmi3ExitConfigurationMode(c)),
                        Plain::EnterStepMode => named!(f.fmi3EnterStepMode(c)),
                    };
                    self.status(name, Some(inst), s);
                }
                Op3::GetFloat64 { inst, vrs, n, arr } => {
                    let (s, values) = self.get3(
                        "fmi3GetFloat64",
                        (*inst, vrs, *n, *arr),
                        Type3::Float64,
                        CANARY,
                        |c, vp, nvr, out, n| (f.fmi3GetFloat64)(c, vp, nvr, out, n),
                    );
                    self.float64s("fmi3GetFloat64", s, &values, *n);
                }
                Op3::SetFloat64 {
                    inst,
                    vrs,
                    values,
                    arr,
                } => {
                    self.set3(
                        "fmi3SetFloat64",
                        (*inst, vrs, values, *arr),
                        Type3::Float64,
                        |c, vp, nvr, p, n| (f.fmi3SetFloat64)(c, vp, nvr, p, n),
                    );
                }
                Op3::GetBoolean { inst, vrs, n, arr } => {
                    // Bytes, read back as bytes: a value other than 0 or 1 is seen, not
                    // undefined behaviour of the host.
                    let (s, bytes) = self.get3(
                        "fmi3GetBoolean",
                        (*inst, vrs, *n, *arr),
                        Type3::Boolean,
                        FILL,
                        |c, vp, nvr, out, n| (f.fmi3GetBoolean)(c, vp, nvr, out.cast(), n),
                    );
                    self.booleans("fmi3GetBoolean", s, &bytes, *n);
                    if s == OK && bytes[..*n].contains(&FILL) {
                        self.find(
                            "fmi3GetBoolean returned fmi3OK but left a value unwritten".into(),
                        );
                    }
                }
                Op3::SetBoolean {
                    inst,
                    vrs,
                    values,
                    arr,
                } => self.set3(
                    "fmi3SetBoolean",
                    (*inst, vrs, values, *arr),
                    Type3::Boolean,
                    |c, vp, nvr, p, n| (f.fmi3SetBoolean)(c, vp, nvr, p, n),
                ),
                Op3::GetString { inst, vrs, n, arr } => {
                    let n = *n;
                    let unwritten = UNWRITTEN as *const c_char;
                    let (s, values) = self.get3(
                        "fmi3GetString",
                        (*inst, vrs, n, *arr),
                        Type3::String,
                        unwritten,
                        |c, vp, nvr, out, n| (f.fmi3GetString)(c, vp, nvr, out, n),
                    );
                    self.past_end("fmi3GetString", n, "values", &values[n..], &unwritten);
                    if s == OK || s == WARNING {
                        // Read them: they must be valid C strings.
                        for (i, p) in values[..n].iter().enumerate() {
                            if p.is_null() || *p as usize == UNWRITTEN {
                                self.find(format!(
                                    "fmi3GetString returned {s} with value {i} NULL or unwritten"
                                ));
                            } else {
                                std::hint::black_box(CStr::from_ptr(*p).to_bytes().len());
                            }
                        }
                    }
                }
                Op3::SetString {
                    inst,
                    vrs,
                    values,
                    arr,
                } => {
                    let ptrs = self.strings(values);
                    self.set3(
                        "fmi3SetString",
                        (*inst, vrs, &ptrs.ptrs, *arr),
                        Type3::String,
                        |c, vp, nvr, p, n| (f.fmi3SetString)(c, vp, nvr, p, n),
                    );
                }
                Op3::Absent {
                    inst,
                    ty,
                    set,
                    vrs,
                    n,
                    arr,
                } => self.absent(*inst, *ty, *set, vrs, *n, *arr),
                Op3::ClockTiming {
                    inst,
                    call,
                    vrs,
                    arr,
                } => self.clock_timing(*inst, *call, vrs, *arr),
                &Op3::VariableDependencies {
                    inst,
                    list,
                    vr,
                    n,
                    null,
                } => {
                    let c = self.c(inst);
                    if list {
                        let mut words: [Vec<u64>; 4] =
                            std::array::from_fn(|_| vec![FILL64; n + GUARD]);
                        let [a, b, d, k] = &mut words;
                        let p = |w: &mut Vec<u64>| {
                            if null { null_mut() } else { w.as_mut_ptr() }
                        };
                        let s = (f.fmi3GetVariableDependencies)(
                            c,
                            vr,
                            p(a).cast(),
                            p(b).cast(),
                            p(d).cast(),
                            p(k).cast(),
                            n,
                        );
                        self.status("fmi3GetVariableDependencies", Some(inst), s);
                        for (w, size) in words.iter().zip([8, 4, 8, 4]) {
                            self.guarded("fmi3GetVariableDependencies", w, n, size);
                        }
                    } else {
                        let mut count = usize::MAX;
                        let s = (f.fmi3GetNumberOfVariableDependencies)(
                            c,
                            vr,
                            if null { null_mut() } else { &mut count },
                        );
                        self.status("fmi3GetNumberOfVariableDependencies", Some(inst), s);
                    }
                }
                &Op3::GetFMUState {
                    inst,
                    slot,
                    null_slot,
                } => self.get_state(&f.states(), inst, slot, null_slot),
                &Op3::SetFMUState { inst, state } => self.set_state(&f.states(), inst, state),
                &Op3::FreeFMUState {
                    inst,
                    state,
                    null_slot,
                } => self.free_state(&f.states(), inst, state, null_slot),
                &Op3::SerializedFMUStateSize {
                    inst,
                    state,
                    null_size,
                } => self.state_size(&f.states(), inst, state, null_size),
                &Op3::SerializeFMUState {
                    inst,
                    state,
                    buffer,
                    size_delta,
                    null,
                } => self.serialize(&f.states(), inst, state, buffer, size_delta, null),
                Op3::DeserializeFMUState {
                    inst,
                    buffer,
                    corrupt,
                    slot,
                    arr,
                } => self.deserialize(&f.states(), *inst, *buffer, corrupt, *slot, *arr),
                Op3::Derivative {
                    inst,
                    adjoint,
                    unknowns,
                    knowns,
                    seed,
                    n_sensitivity,
                    null: which_null,
                } => {
                    let n = *n_sensitivity;
                    let mut out = vec![CANARY; n + GUARD];
                    let (name, function) = if *adjoint {
                        ("fmi3GetAdjointDerivative", f.fmi3GetAdjointDerivative)
                    } else {
                        (
                            "fmi3GetDirectionalDerivative",
                            f.fmi3GetDirectionalDerivative,
                        )
                    };
                    let null = *which_null;
                    let s = function(
                        self.c(*inst),
                        or_null(null, 1, unknowns.as_ptr()),
                        unknowns.len(),
                        or_null(null, 2, knowns.as_ptr()),
                        knowns.len(),
                        or_null(null, 3, seed.as_ptr()),
                        seed.len(),
                        or_null_mut(null, 4, out.as_mut_ptr()),
                        n,
                    );
                    let s = self.status(name, Some(*inst), s);
                    let why = self.derivative_shape(
                        *adjoint,
                        unknowns,
                        knowns,
                        seed.len(),
                        n,
                        *which_null,
                    );
                    self.refused(name, s, why);
                    self.float64s(name, s, &out, n);
                }
                &Op3::UpdateDiscreteStates { inst, null } => {
                    let mut flags = [FILL; 5];
                    let mut next = CANARY;
                    let flag = |flags: &mut [u8; 5], i: usize| {
                        if null & (1 << i) != 0 {
                            null_mut()
                        } else {
                            flags.as_mut_ptr().wrapping_add(i).cast::<bool>()
                        }
                    };
                    let s = (f.fmi3UpdateDiscreteStates)(
                        self.c(inst),
                        flag(&mut flags, 0),
                        flag(&mut flags, 1),
                        flag(&mut flags, 2),
                        flag(&mut flags, 3),
                        flag(&mut flags, 4),
                        if null & 32 != 0 {
                            null_mut()
                        } else {
                            &mut next
                        },
                    );
                    let s = self.status("fmi3UpdateDiscreteStates", Some(inst), s);
                    self.flags("fmi3UpdateDiscreteStates", s, &flags, null);
                    if (s == OK || s == WARNING)
                        && null & (16 | 32) == 0
                        && flags[4] == 1
                        && !next.is_finite()
                    {
                        self.find(format!(
                            "fmi3UpdateDiscreteStates: nextEventTime {next} with status {s}"
                        ));
                    }
                }
                &Op3::CompletedIntegratorStep {
                    inst,
                    no_set_prior,
                    null,
                } => {
                    let mut flags = [FILL; 2];
                    let p = flags.as_mut_ptr().cast::<bool>();
                    let s = (f.fmi3CompletedIntegratorStep)(
                        self.c(inst),
                        no_set_prior,
                        if null & 1 != 0 { null_mut() } else { p },
                        if null & 2 != 0 {
                            null_mut()
                        } else {
                            p.wrapping_add(1)
                        },
                    );
                    let s = self.status("fmi3CompletedIntegratorStep", Some(inst), s);
                    self.flags("fmi3CompletedIntegratorStep", s, &flags, null);
                }
                &Op3::SetTime { inst, t } => {
                    let t = self.time3(inst, t);
                    let s = (f.fmi3SetTime)(self.c(inst), t);
                    let s = self.status("fmi3SetTime", Some(inst), s);
                    let why = (!t.is_finite()).then(|| format!("time {t}"));
                    self.refused("fmi3SetTime", s, why);
                }
                Op3::SetContinuousStates {
                    inst,
                    x,
                    null: null_x,
                } => {
                    let s = (f.fmi3SetContinuousStates)(
                        self.c(*inst),
                        if *null_x { null() } else { x.as_ptr() },
                        x.len(),
                    );
                    let s = self.status("fmi3SetContinuousStates", Some(*inst), s);
                    let why = if *null_x && !x.is_empty() {
                        Some("NULL states with a count".to_string())
                    } else if x.len() != v3.n_states {
                        Some(format!("{} states, not {}", x.len(), v3.n_states))
                    } else {
                        x.iter()
                            .find(|v| !v.is_finite())
                            .map(|v| format!("a state {v}"))
                    };
                    self.refused("fmi3SetContinuousStates", s, why);
                }
                &Op3::GetStateArray {
                    inst,
                    call,
                    n,
                    null,
                } => {
                    let c = self.c(inst);
                    let mut values = vec![CANARY; n + GUARD];
                    let p = if null {
                        null_mut()
                    } else {
                        values.as_mut_ptr()
                    };
                    let (name, s, expected) = match call {
                        StateArray::ContinuousStates => (
                            "fmi3GetContinuousStates",
                            (f.fmi3GetContinuousStates)(c, p, n),
                            v3.n_states,
                        ),
                        StateArray::Derivatives => (
                            "fmi3GetContinuousStateDerivatives",
                            (f.fmi3GetContinuousStateDerivatives)(c, p, n),
                            v3.n_states,
                        ),
                        StateArray::Nominals => (
                            "fmi3GetNominalsOfContinuousStates",
                            (f.fmi3GetNominalsOfContinuousStates)(c, p, n),
                            v3.n_states,
                        ),
                        StateArray::EventIndicators => (
                            "fmi3GetEventIndicators",
                            (f.fmi3GetEventIndicators)(c, p, n),
                            v3.n_indicators,
                        ),
                    };
                    let s = self.status(name, Some(inst), s);
                    let why = if null && n > 0 {
                        Some(format!("a NULL array of {n}"))
                    } else {
                        (n != expected).then(|| format!("{n} values, not {expected}"))
                    };
                    self.refused(name, s, why);
                    self.float64s(name, s, &values, n);
                }
                &Op3::GetNumberOf { inst, states, null } => {
                    let mut count = usize::MAX;
                    let p = if null { null_mut() } else { &mut count };
                    let (name, s, expected) = if states {
                        (
                            "fmi3GetNumberOfContinuousStates",
                            (f.fmi3GetNumberOfContinuousStates)(self.c(inst), p),
                            v3.n_states,
                        )
                    } else {
                        (
                            "fmi3GetNumberOfEventIndicators",
                            (f.fmi3GetNumberOfEventIndicators)(self.c(inst), p),
                            v3.n_indicators,
                        )
                    };
                    let s = self.status(name, Some(inst), s);
                    if s == OK && !null && count != expected {
                        self.find(format!(
                            "{name} = {count}; the model description has {expected}"
                        ));
                    }
                }
                Op3::GetOutputDerivatives {
                    inst,
                    vrs,
                    orders,
                    n,
                    arr,
                } => {
                    let n = *n;
                    let mut values = vec![CANARY; n + GUARD];
                    let s = (f.fmi3GetOutputDerivatives)(
                        self.c(*inst),
                        arr.ptr(Arr::Null1, vrs.as_ptr()),
                        vrs.len(),
                        orders.as_ptr(),
                        arr.ptr_mut(Arr::Null2, values.as_mut_ptr()),
                        n,
                    );
                    let s = self.status("fmi3GetOutputDerivatives", Some(*inst), s);
                    self.float64s("fmi3GetOutputDerivatives", s, &values, n);
                }
                &Op3::DoStep {
                    inst,
                    t,
                    h,
                    no_set_prior,
                    null,
                } => {
                    let t = self.time3(inst, t);
                    let mut flags = [FILL; 3];
                    let mut last = CANARY;
                    let p = flags.as_mut_ptr().cast::<bool>();
                    let flag = |i: usize| {
                        if null & (1 << i) != 0 {
                            null_mut()
                        } else {
                            p.wrapping_add(i)
                        }
                    };
                    let s = (f.fmi3DoStep)(
                        self.c(inst),
                        t,
                        h,
                        no_set_prior,
                        flag(0),
                        flag(1),
                        flag(2),
                        if null & 8 != 0 { null_mut() } else { &mut last },
                    );
                    let s = self.status("fmi3DoStep", Some(inst), s);
                    self.flags("fmi3DoStep", s, &flags, null);
                    let why = if !(h.is_finite() && h > 0.0) {
                        Some(format!("communicationStepSize {h}"))
                    } else {
                        (!t.is_finite()).then(|| format!("currentCommunicationPoint {t}"))
                    };
                    self.refused("fmi3DoStep", s, why);
                    if (s == OK || s == WARNING) && null & 8 == 0 {
                        let end = t + h;
                        if !last.is_finite() {
                            self.find(format!("fmi3DoStep: lastSuccessfulTime {last} with {s}"));
                        } else if s == OK
                            && (null & 4 != 0 || flags[2] == 0)
                            && (last - end).abs() > 1e-12 * end.abs().max(1.0)
                        {
                            self.find(format!(
                                "fmi3DoStep from {t} by {h}: lastSuccessfulTime {last}, \
                                 not {end}, without an early return"
                            ));
                        }
                    }
                }
                &Op3::ActivateModelPartition { inst, clock, t } => {
                    let s = (f.fmi3ActivateModelPartition)(self.c(inst), clock, t);
                    let s = self.status("fmi3ActivateModelPartition", Some(inst), s);
                    self.refused(
                        "fmi3ActivateModelPartition",
                        s,
                        Some("scheduled execution, which the FMU does not offer".into()),
                    );
                }
            }
        }
    }

    /// Output flags the FMU was given (bit i of `null`: the i-th was NULL): each 0 or 1 when
    /// it returned OK or Warning.
    fn flags(&mut self, name: &str, status: fmi3Status, flags: &[u8], null: u8) {
        if status != OK && status != WARNING {
            return;
        }
        for (i, b) in flags.iter().enumerate() {
            if null & (1 << i) == 0 && *b > 1 {
                self.find(format!(
                    "{name} returned {status} with output flag {i} = {b:#x}, not 0 or 1"
                ));
            }
        }
    }

    /// Why a derivative call must be refused, if it must: NULL arrays with a length, a
    /// reference of no Float64 variable, or (all references scalar Float64s) counts that do
    /// not fit.
    fn derivative_shape(
        &self,
        adjoint: bool,
        unknowns: &[u32],
        knowns: &[u32],
        n_seed: usize,
        n_sensitivity: usize,
        null: u8,
    ) -> Option<String> {
        let lengths = [unknowns.len(), knowns.len(), n_seed, n_sensitivity];
        if (1..=4).contains(&null) && lengths[null as usize - 1] > 0 {
            return Some(format!("NULL array {null} with a length"));
        }
        if let Some(vr) = unknowns
            .iter()
            .chain(knowns)
            .find(|vr| self.v3.float64(**vr).is_none())
        {
            return Some(format!("value reference {vr}, no Float64 variable"));
        }
        let scalar = unknowns
            .iter()
            .chain(knowns)
            .all(|vr| self.v3.float64(*vr).is_some_and(|v| v.size == 1));
        let (seed, sensitivity) = if adjoint {
            (unknowns.len(), knowns.len())
        } else {
            (knowns.len(), unknowns.len())
        };
        (scalar && (n_seed, n_sensitivity) != (seed, sensitivity)).then(|| {
            format!(
                "nSeed {n_seed} and nSensitivity {n_sensitivity} with {} unknowns and {} knowns",
                unknowns.len(),
                knowns.len()
            )
        })
    }

    /// A getter or setter of a type the FMU has no variable of: any reference is refused.
    ///
    /// # Safety
    /// As [`Host::apply3`].
    unsafe fn absent(
        &mut self,
        inst: usize,
        ty: Absent,
        set: bool,
        vrs: &[u32],
        n: usize,
        arr: Arr,
    ) {
        let f = self.fmi3;
        let c = self.c(inst);
        let nvr = vrs.len();
        let vp = arr.ptr(Arr::Null1, vrs.as_ptr());
        // Clock getters and setters have a value per reference and no nValues.
        let count = if ty == Absent::Clock { nvr } else { n };
        let mut words = vec![FILL64; count + GUARD];
        let mut sizes = vec![FILL64; count + GUARD];
        let bytes = [1u8, 2, 3, 4];
        let binaries = vec![bytes.as_ptr(); count];
        let set_sizes = vec![bytes.len(); count];
        let clocks = vec![false; count];
        let out = arr.ptr_mut(Arr::Null2, words.as_mut_ptr());
        let input = arr.ptr(Arr::Null2, words.as_ptr());
        macro_rules! get {
            ($name:ident, $t:ty) => {
                (
                    stringify!($name),
                    // SAFETY: `count` elements (plus the guard) of 8 bytes each.
                    unsafe { (f.$name)(c, vp, nvr, out.cast::<$t>(), n) },
                    std::mem::size_of::<$t>(),
                )
            };
        }
        macro_rules! set {
            ($name:ident, $t:ty) => {
                (
                    stringify!($name),
                    // SAFETY: as for `get`.
                    unsafe { (f.$name)(c, vp, nvr, input.cast::<$t>(), n) },
                    0,
                )
            };
        }
        let (name, s, size) = match (ty, set) {
            (Absent::Float32, false) => get!(fmi3GetFloat32, f32),
            (Absent::Int8, false) => get!(fmi3GetInt8, i8),
            (Absent::UInt8, false) => get!(fmi3GetUInt8, u8),
            (Absent::Int16, false) => get!(fmi3GetInt16, i16),
            (Absent::UInt16, false) => get!(fmi3GetUInt16, u16),
            (Absent::Int32, false) => get!(fmi3GetInt32, i32),
            (Absent::UInt32, false) => get!(fmi3GetUInt32, u32),
            (Absent::Int64, false) => get!(fmi3GetInt64, i64),
            (Absent::UInt64, false) => get!(fmi3GetUInt64, u64),
            (Absent::Float32, true) => set!(fmi3SetFloat32, f32),
            (Absent::Int8, true) => set!(fmi3SetInt8, i8),
            (Absent::UInt8, true) => set!(fmi3SetUInt8, u8),
            (Absent::Int16, true) => set!(fmi3SetInt16, i16),
            (Absent::UInt16, true) => set!(fmi3SetUInt16, u16),
            (Absent::Int32, true) => set!(fmi3SetInt32, i32),
            (Absent::UInt32, true) => set!(fmi3SetUInt32, u32),
            (Absent::Int64, true) => set!(fmi3SetInt64, i64),
            (Absent::UInt64, true) => set!(fmi3SetUInt64, u64),
            (Absent::Binary, false) => (
                "fmi3GetBinary",
                // SAFETY: `count` sizes and pointers (plus the guard).
                unsafe {
                    (f.fmi3GetBinary)(
                        c,
                        vp,
                        nvr,
                        arr.ptr_mut(Arr::Null2, sizes.as_mut_ptr()).cast(),
                        out.cast(),
                        n,
                    )
                },
                8,
            ),
            (Absent::Binary, true) => (
                "fmi3SetBinary",
                // SAFETY: `count` sizes and pointers to that many bytes.
                unsafe {
                    (f.fmi3SetBinary)(
                        c,
                        vp,
                        nvr,
                        arr.ptr(Arr::Null2, set_sizes.as_ptr()),
                        arr.ptr(Arr::Null2, binaries.as_ptr()),
                        n,
                    )
                },
                0,
            ),
            (Absent::Clock, false) => (
                "fmi3GetClock",
                // SAFETY: a value per reference (plus the guard), read back as bytes.
                unsafe { (f.fmi3GetClock)(c, vp, nvr, out.cast()) },
                1,
            ),
            (Absent::Clock, true) => (
                "fmi3SetClock",
                // SAFETY: a value per reference.
                unsafe { (f.fmi3SetClock)(c, vp, nvr, arr.ptr(Arr::Null2, clocks.as_ptr())) },
                0,
            ),
        };
        let s = self.status(name, Some(inst), s);
        let why = (nvr > 0).then(|| format!("{nvr} value references of a type it has none of"));
        self.refused(name, s, why);
        self.guarded(name, &words, count, size);
        self.guarded(name, &sizes, count, if size == 0 { 0 } else { 8 });
    }

    /// The clock interval and shift functions: there are no clocks, any reference is
    /// refused.
    ///
    /// # Safety
    /// As [`Host::apply3`].
    unsafe fn clock_timing(&mut self, inst: usize, call: Timing, vrs: &[u32], arr: Arr) {
        let f = self.fmi3;
        let c = self.c(inst);
        let nvr = vrs.len();
        let vp = arr.ptr(Arr::Null1, vrs.as_ptr());
        let mut a = vec![FILL64; nvr + GUARD];
        let mut b = vec![FILL64; nvr + GUARD];
        let mut q = vec![FILL64; nvr + GUARD];
        // What the setters pass: NaN intervals, zero resolutions.
        let nan = vec![f64::NAN; nvr];
        let zeros = vec![0u64; nvr];
        let pa = arr.ptr_mut(Arr::Null2, a.as_mut_ptr());
        let pb = arr.ptr_mut(Arr::Null2, b.as_mut_ptr());
        let pq = arr.ptr_mut(Arr::Null2, q.as_mut_ptr());
        let nan_p = arr.ptr(Arr::Null2, nan.as_ptr());
        let zeros_p = arr.ptr(Arr::Null2, zeros.as_ptr());
        // SAFETY: `nvr` elements (plus the guard) in every array.
        let (name, s) = unsafe {
            match call {
                Timing::GetIntervalDecimal => {
                    named!(f.fmi3GetIntervalDecimal(c, vp, nvr, pa.cast(), pq.cast()))
                }
                Timing::GetIntervalFraction => {
                    named!(f.fmi3GetIntervalFraction(c, vp, nvr, pa, pb, pq.cast()))
                }
                Timing::GetShiftDecimal => named!(f.fmi3GetShiftDecimal(c, vp, nvr, pa.cast())),
                Timing::GetShiftFraction => named!(f.fmi3GetShiftFraction(c, vp, nvr, pa, pb)),
                Timing::SetIntervalDecimal => named!(f.fmi3SetIntervalDecimal(c, vp, nvr, nan_p)),
                Timing::SetIntervalFraction => {
                    named!(f.fmi3SetIntervalFraction(c, vp, nvr, zeros_p, zeros_p))
                }
                Timing::SetShiftDecimal => named!(f.fmi3SetShiftDecimal(c, vp, nvr, nan_p)),
                Timing::SetShiftFraction => {
                    named!(f.fmi3SetShiftFraction(c, vp, nvr, zeros_p, zeros_p))
                }
            }
        };
        let s = self.status(name, Some(inst), s);
        let why = (nvr > 0).then(|| format!("{nvr} value references, with no clocks"));
        self.refused(name, s, why);
        self.guarded(name, &a, nvr, 8);
        self.guarded(name, &b, nvr, 8);
        self.guarded(name, &q, nvr, 4);
    }
}
