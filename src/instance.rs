//! One FMU instance and the FMI calls on it: the state-machine check of each call, the life
//! cycle, getting and setting variables (with the clamping warnings), stepping, and the
//! messages to the host. Its values are an `InstanceValues`; FMU states are in `fmu_states`, the
//! parameter file in `parameter_file`. Safe code: the C boundary (exports.rs, boundary.rs)
//! hands it checked slices.

use std::ffi::{CStr, CString, c_void};
use std::path::PathBuf;

use mf87::bounds::SPEED_MPS;
use mf87::extensions::LAGGED_SLIP_ABS_MAX;
use mf87::{ConditionVar, InputVar, SignConvention};

use crate::call_sequence::{Abi, FmiCall, Interface, State};
use crate::derivatives;
use crate::fmu_states::{self, NOT_A_STATE, Snapshots};
use crate::instance_values::{InstanceValues, convention_of, set_parameter};
use crate::logging::{Logger, Status};
use crate::parameter_file;
use crate::variables::{
    BooleanRole, GUID, INSTANTIATION_TOKEN, LOG_CATEGORIES, LogCategory, MODEL_IDENTIFIER,
    REAL_VARIABLES, RealRole, RealVariable, StringRole, boolean_variable, real_index,
    string_variable,
};

/// First field of every live instance, cleared on free: a best-effort check that an
/// `fmi2Component` is one of ours (another FMU's component, an FMU state or other memory
/// passed by mistake), not protection against a freed instance: once freed, its memory may be
/// reused, even by a new instance, and reading it is undefined behaviour.
const INSTANCE_MAGIC: u64 = 0x5041_4345_4a4b_4138; // "PACEJKA8"
/// Relative tolerance when comparing the master's communication point with the FMU's time.
const TIME_TOLERANCE: f64 = 1e-10;

/// One instance of the FMU.
#[repr(C)]
pub struct Instance {
    magic: u64,
    logger: Logger,
    resources: Option<PathBuf>,
    /// The FMI function being executed, for messages.
    call: &'static str,
    /// The standard the instance was instantiated through; it takes only that one's calls.
    abi: Abi,
    /// Backing store of the strings returned by fmi2GetString (valid until the next call).
    string_results: Vec<CString>,
    /// Co-simulation or Model Exchange, from fmi2Instantiate's fmuType.
    interface: Interface,
    pub model: InstanceValues,
    /// The FMU states handed out and not yet freed; freed with the instance.
    snapshots: Snapshots,
}

/// Nominal value of every continuous state (slip ratio, slip angle in rad).
const STATE_NOMINAL: f64 = 0.1;
/// Number of continuous states: each channel's relaxation state.
pub(crate) const STATES: usize = 3;
/// The continuous states in their order.
const STATE_NAMES: [&str; STATES] = ["lag_Fx", "lag_Fy", "lag_Mz"];

/// Why instantiation refused.
pub(crate) struct InstantiateError(pub(crate) String);

/// What an instantiation function was called with that the instance keeps.
pub(crate) struct Instantiation<'a> {
    pub(crate) abi: Abi,
    pub(crate) interface: Interface,
    /// FMI 2.0's fmuGUID or FMI 3.0's instantiationToken.
    pub(crate) token: Option<&'a CStr>,
    /// The FMU's resources folder, if the host gave one.
    pub(crate) resources: Option<PathBuf>,
}

impl Instantiation<'_> {
    /// The instantiation function's name.
    fn function(&self) -> String {
        match (self.abi, self.interface) {
            (Abi::Fmi2, _) => "fmi2Instantiate".into(),
            (Abi::Fmi3, Interface::CoSimulation) => "fmi3InstantiateCoSimulation".into(),
            (Abi::Fmi3, Interface::ModelExchange) => "fmi3InstantiateModelExchange".into(),
        }
    }

    /// The message instantiation refuses with, if it must.
    fn check(&self, instance_name: &str) -> Result<(), String> {
        let function = self.function();
        if instance_name.is_empty() {
            return Err(format!("{function}: instanceName must not be empty"));
        }
        let (argument, expected) = match self.abi {
            Abi::Fmi2 => ("fmuGUID", GUID),
            Abi::Fmi3 => ("instantiationToken", INSTANTIATION_TOKEN),
        };
        match self.token.map(|g| g.to_string_lossy()) {
            None => Err(format!(
                "{function}: {argument} is NULL; expected {expected}"
            )),
            Some(g) if g != expected => Err(format!(
                "{function}: {argument} {g} does not match this FMU's {expected}"
            )),
            Some(_) => Ok(()),
        }
    }
}

impl Instance {
    /// Checks the arguments of an instantiation function and makes an instance.
    pub(crate) fn new(
        logger: Logger,
        with: Instantiation,
    ) -> Result<Box<Instance>, (Logger, InstantiateError)> {
        if let Err(message) = with.check(logger.instance_name()) {
            return Err((logger, InstantiateError(message)));
        }
        let function = with.function();
        let instance = Box::new(Instance {
            magic: INSTANCE_MAGIC,
            logger,
            resources: with.resources,
            call: "",
            abi: with.abi,
            string_results: Vec::new(),
            interface: with.interface,
            model: InstanceValues::initial(),
            snapshots: Snapshots::default(),
        });
        instance.log(
            Status::Ok,
            LogCategory::Events,
            &format!(
                "{function}: {} instance of {MODEL_IDENTIFIER} created (resources: {})",
                with.interface.name(),
                instance
                    .resources
                    .as_deref()
                    .map(|p| p.display().to_string())
                    .unwrap_or_else(|| "none".into())
            ),
        );
        Ok(instance)
    }

    /// The instance behind an `fmi2Component`: `None` for NULL or when the first field is not
    /// `INSTANCE_MAGIC` (a best-effort check against a wrong pointer, see there).
    ///
    /// # Safety
    /// `c` must be NULL or a pointer from fmi2Instantiate not yet freed; the magic number does
    /// not make a freed pointer safe.
    pub unsafe fn from_component<'a>(c: *mut c_void) -> Option<&'a mut Instance> {
        let instance = c as *mut Instance;
        // SAFETY: by contract, a non-NULL `c` points to an Instance we allocated.
        unsafe { instance.as_mut() }.filter(|i| i.magic == INSTANCE_MAGIC)
    }

    /// Marks the instance freed before its memory is released.
    pub(crate) fn mark_freed(&mut self) {
        self.log(
            Status::Ok,
            LogCategory::Events,
            &format!("{}FreeInstance: instance freed", self.abi.prefix()),
        );
        self.magic = 0;
    }

    pub(crate) fn log(&self, status: Status, category: LogCategory, message: &str) {
        self.logger.log(status, category, message);
    }

    /// Logs `message` as an error of the current call and returns fmi2Error.
    #[cold]
    #[inline(never)]
    pub(crate) fn error(&self, message: impl AsRef<str>) -> Status {
        self.log(
            Status::Error,
            LogCategory::StatusError,
            &format!("{}: {}", self.call, message.as_ref()),
        );
        Status::Error
    }

    #[cold]
    #[inline(never)]
    fn warning(&self, message: impl AsRef<str>) -> Status {
        self.log(
            Status::Warning,
            LogCategory::StatusWarning,
            &format!("{}: {}", self.call, message.as_ref()),
        );
        Status::Warning
    }

    /// Logs `message` as an event of the current call, if events are enabled.
    fn event(&self, message: impl AsRef<str>) {
        if self.logger.is_enabled(LogCategory::Events) {
            self.log(
                Status::Ok,
                LogCategory::Events,
                &format!("{}: {}", self.call, message.as_ref()),
            );
        }
    }

    /// Starts an FMI call: records it and checks the state machine.
    #[inline]
    pub(crate) fn begin_call(&mut self, call: impl FmiCall) -> bool {
        self.call = call.name();
        if self.logger.is_enabled(LogCategory::Calls) {
            self.log(Status::Ok, LogCategory::Calls, call.name());
        }
        if call.abi() != self.abi {
            self.error(format!(
                "this instance was made by {}Instantiate...: it takes only {} functions",
                self.abi.prefix(),
                self.abi.prefix()
            ));
            return false;
        }
        if call.interface().is_some_and(|only| only != self.interface) {
            self.error(format!(
                "not a function of {} (this instance was instantiated for it)",
                self.interface.name()
            ));
            return false;
        }
        if call.allowed_in(self.model.state) {
            return true;
        }
        self.error(format!(
            "Illegal call sequence: not allowed in state {}",
            self.model.state.name(self.abi)
        ));
        false
    }

    /// After a panic inside a call: log it and refuse further stepping until reset.
    pub(crate) fn fail_internally(&mut self, call: impl FmiCall, message: &str) {
        self.call = call.name();
        self.model.state = State::Error;
        let p = self.abi.prefix();
        self.error(format!(
            "internal error ({message}); the instance is in the Error state: call {p}Reset or {p}FreeInstance"
        ));
    }

    /// An error for a NULL array passed with a non-zero length.
    #[cold]
    #[inline(never)]
    pub(crate) fn null_array(&self, what: &str, n: usize) -> Status {
        self.error(format!("{what} is NULL but {n} values were announced"))
    }

    // ---- logging ----------------------------------------------------------------------

    pub(crate) fn set_debug_logging(&mut self, on: bool, categories: &[&CStr]) -> Status {
        if categories.is_empty() {
            self.logger.set_all(on);
            return Status::Ok;
        }
        let mut status = Status::Ok;
        for name in categories {
            match LogCategory::from_name(&name.to_string_lossy()) {
                Some(c) => self.logger.set_enabled(c, on),
                None => status = status.max(self.unknown_log_category(name)),
            }
        }
        status
    }

    #[cold]
    #[inline(never)]
    fn unknown_log_category(&self, name: &CStr) -> Status {
        let known: Vec<&str> = LOG_CATEGORIES.iter().map(|(n, _)| *n).collect();
        self.error(format!(
            "unknown log category {:?}; known: {}",
            name.to_string_lossy(),
            known.join(", ")
        ))
    }

    // ---- life cycle -------------------------------------------------------------------

    pub(crate) fn setup_experiment(&mut self, start_time: f64, stop_time: Option<f64>) -> Status {
        if !start_time.is_finite() {
            return self.error(format!("startTime = {start_time} is not a finite number"));
        }
        if let Some(stop) = stop_time
            && !(stop.is_finite() && stop >= start_time)
        {
            return self.error(format!(
                "stopTime = {stop} must be finite and >= startTime = {start_time}"
            ));
        }
        self.model.time = start_time;
        self.model.stop_time = stop_time;
        Status::Ok
    }

    pub(crate) fn enter_initialization_mode(&mut self) -> Status {
        if !self.model.parameter_file.is_empty()
            && let Err(status) = self.load_parameter_file()
        {
            return status;
        }
        self.model.state = State::InitializationMode;
        self.model.outputs_stale = true;
        Status::Ok
    }

    /// Replaces the parameters with those of `parameterFile`, except the ones set explicitly
    /// before, which take precedence over the file.
    fn load_parameter_file(&mut self) -> Result<(), Status> {
        let (path, mut loaded) =
            parameter_file::load(&self.model.parameter_file, self.resources.as_deref())
                .map_err(|message| self.error(message))?;
        for (var, value) in self.model.explicitly_set_parameters() {
            set_parameter(&mut loaded, var.role, value);
            self.event(format!(
                "{} = {value} set explicitly overrides the parameter file",
                var.name
            ));
        }
        self.model.params = loaded;
        self.event(format!("parameters loaded from {}", path.display()));
        match &self.model.params.extensions {
            Some(ext) => self.event(format!("extensions loaded: {ext}")),
            None => self.event("no extensions in the parameter file: the 1987 model alone"),
        }
        Ok(())
    }

    pub(crate) fn exit_initialization_mode(&mut self) -> Status {
        if let Err(e) = self.model.params.validate() {
            return self.error(format!("{e}; the parameter set is rejected"));
        }
        if let Err(e) = self.model.compute_initial_outputs() {
            return self.error(format!("{e}; still in initialization mode"));
        }
        self.model.state = match self.interface {
            Interface::CoSimulation => State::StepComplete,
            Interface::ModelExchange => State::EventMode,
        };
        Status::Ok
    }

    pub(crate) fn terminate(&mut self) -> Status {
        self.model.state = State::Terminated;
        Status::Ok
    }

    pub(crate) fn reset(&mut self) -> Status {
        self.model = InstanceValues::initial();
        self.event("reset to start values");
        Status::Ok
    }

    // ---- variables --------------------------------------------------------------------

    #[inline]
    pub(crate) fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Status {
        let mut status = Status::Ok;
        if self.model.outputs_stale
            && self.interface == Interface::ModelExchange
            && matches!(
                self.model.state,
                State::EventMode | State::ContinuousTimeMode
            )
            && let Err(e) = self.model.compute_outputs()
        {
            status = self.error(e);
        }
        if self.model.outputs_stale && self.model.state == State::InitializationMode {
            if let Err(e) = self.model.params.validate() {
                return self.error(format!("cannot compute outputs: {e}"));
            }
            if let Err(e) = self.model.compute_initial_outputs() {
                status = self.error(e);
            }
        }
        for (vr, value) in vrs.iter().zip(values.iter_mut()) {
            match real_index(*vr) {
                Some(i) => {
                    *value = self.model.real(&REAL_VARIABLES[i]);
                    if !value.is_finite() {
                        status = status.max(self.not_finite(REAL_VARIABLES[i].name, *value));
                    }
                }
                None => status = status.max(self.unknown_reference("Real", *vr)),
            }
        }
        status
    }

    /// A value the FMU would hand out is not finite: never with fmi2OK.
    #[cold]
    #[inline(never)]
    pub(crate) fn not_finite(&self, what: &str, value: f64) -> Status {
        self.error(format!(
            "{what} = {value} is not finite (inputs Fz = {}, alpha = {}, kappa = {}, gamma = {}, \
             vx = {}; states {:?}); the value returned is not usable",
            self.model.inputs.fz,
            self.model.inputs.alpha,
            self.model.inputs.kappa,
            self.model.inputs.gamma,
            self.model.conditions.vx,
            [
                self.model.lagged.fx,
                self.model.lagged.fy,
                self.model.lagged.mz
            ],
        ))
    }

    /// fmi2Error naming the first non-finite value of `values` (the `i`-th named by
    /// `name(i)`), else fmi2OK.
    fn all_finite(&self, values: &[f64], name: impl Fn(usize) -> String) -> Status {
        match values.iter().position(|v| !v.is_finite()) {
            Some(i) => self.not_finite(&name(i), values[i]),
            None => Status::Ok,
        }
    }

    #[inline]
    pub(crate) fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        let mut status = Status::Ok;
        for (vr, value) in vrs.iter().zip(values) {
            let one = match real_index(*vr) {
                Some(i) => self.set_real_variable(i, *value),
                None => self.unknown_reference("Real", *vr),
            };
            status = status.max(one);
        }
        status
    }

    #[inline]
    fn set_real_variable(&mut self, index: usize, value: f64) -> Status {
        let var = &REAL_VARIABLES[index];
        if !value.is_finite() {
            return self.non_finite_value(var, value);
        }
        match var.role {
            RealRole::Output(_) => {
                self.error(format!("{} is an output and cannot be set", var.name))
            }
            RealRole::State(_) | RealRole::Derivative(_) => self.error(format!(
                "{} is calculated and cannot be set (a state is set with \
                 {}SetContinuousStates in Model Exchange)",
                var.name,
                self.abi.prefix()
            )),
            RealRole::Input(input) => self.set_input(var, input, value),
            RealRole::Condition(condition) => self.set_condition(var, condition, value),
            RealRole::Coefficient(..) | RealRole::Limit(_) => {
                if let Err(s) = self.check_fixed_parameter(var.name, &self.model.real(var)) {
                    return s;
                }
                if let Err(s) = self.check_parameter_range(var, value) {
                    return s;
                }
                set_parameter(&mut self.model.params, var.role, value);
                self.model.explicitly_set |= 1 << index;
                self.model.outputs_stale = true;
                Status::Ok
            }
        }
    }

    /// A parameter's own range (the bounds table); what it gives together with the others
    /// is checked when initialization ends. Refused, it keeps its value.
    fn check_parameter_range(&self, var: &RealVariable, value: f64) -> Result<(), Status> {
        let allowed = match var.role {
            RealRole::Coefficient(_, index) => mf87::coefficient_allowed(index),
            RealRole::Limit(limit) => mf87::limit_allowed(limit),
            _ => return Ok(()),
        };
        if allowed.contains(value) {
            return Ok(());
        }
        let unit = if var.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", var.unit)
        };
        Err(self.error(format!(
            "{} = {value}{unit} is outside its allowed range {allowed}{unit}; it keeps its value {}",
            var.name,
            self.model.real(var)
        )))
    }

    #[inline]
    fn set_input(&mut self, var: &RealVariable, input: InputVar, value: f64) -> Status {
        self.model.inputs.set(input, value);
        self.model.outputs_stale = true;
        let (lo, hi) = input.valid_range(&self.model.params.limits);
        if (lo..=hi).contains(&value) {
            return Status::Ok;
        }
        self.clamped_input(var, value, lo, hi)
    }

    #[cold]
    #[inline(never)]
    fn non_finite_value(&self, var: &RealVariable, value: f64) -> Status {
        self.error(format!(
            "{} = {value} is not a finite number; {} keeps its value {}",
            var.name,
            var.name,
            self.model.real(var)
        ))
    }

    /// An input outside its valid range: warn once per variable.
    #[cold]
    #[inline(never)]
    fn clamped_input(&mut self, var: &RealVariable, value: f64, lo: f64, hi: f64) -> Status {
        if !self.model.first_clamping(var.role) {
            return Status::Warning;
        }
        let clamped = value.clamp(lo, hi);
        self.warning(format!(
            "{} = {value} {unit} is outside the valid range [{lo}, {hi}] {unit}; the model uses {clamped} {unit} \
             (further clamping of {} is not logged again)",
            var.name,
            var.name,
            unit = var.unit
        ))
    }

    /// Sets a condition; with extensions loaded that use it, warns once if it is outside
    /// their range (they use the clamped value). Kept out of line: the loop of fmi2SetReal
    /// stays as small as before for the four model inputs.
    #[inline(never)]
    fn set_condition(&mut self, var: &RealVariable, condition: ConditionVar, value: f64) -> Status {
        if condition == ConditionVar::Speed && !SPEED_MPS.contains(value.abs()) {
            return self.error(format!(
                "{} = {value} m/s: |{}| must lie in {SPEED_MPS} m/s; it keeps its value {}",
                var.name,
                var.name,
                self.model.real(var)
            ));
        }
        self.model.conditions.set(condition, value);
        let Some(ext) = &self.model.params.extensions else {
            return Status::Ok;
        };
        self.model.outputs_stale = true;
        if !ext.uses(condition) || condition.in_range(value, &ext.limits) {
            return Status::Ok;
        }
        let limits = ext.limits;
        self.clamped_condition(var, condition, value, &limits)
    }

    #[cold]
    #[inline(never)]
    fn clamped_condition(
        &mut self,
        var: &RealVariable,
        condition: ConditionVar,
        value: f64,
        limits: &mf87::extensions::ConditionLimits,
    ) -> Status {
        if !self.model.first_clamping(var.role) {
            return Status::Warning;
        }
        let (lo, hi) = condition.valid_range(limits);
        let used = condition.used_value(value, limits);
        let what = match condition {
            ConditionVar::Speed => "|vx|",
            ConditionVar::Pressure | ConditionVar::Temperature => var.name,
        };
        self.warning(format!(
            "{} = {value} {unit}: {what} is outside the range [{lo}, {hi}] {unit} of the loaded extensions; \
             they use {used} {unit} (further clamping of {} is not logged again)",
            var.name,
            var.name,
            unit = var.unit
        ))
    }

    #[cold]
    #[inline(never)]
    fn unknown_reference(&self, kind: &str, vr: u32) -> Status {
        self.error(format!("unknown {kind} value reference {vr}"))
    }

    /// fmi2GetInteger / fmi2SetInteger: this FMU has no Integer variables.
    pub(crate) fn no_integer_variables(&self, vrs: &[u32]) -> Status {
        match vrs.first() {
            Some(vr) => self.unknown_reference("Integer", *vr),
            None => Status::Ok,
        }
    }

    pub(crate) fn get_boolean(&self, vrs: &[u32], values: &mut [i32]) -> Status {
        let mut status = Status::Ok;
        for (vr, value) in vrs.iter().zip(values.iter_mut()) {
            match boolean_variable(*vr) {
                Some(v) => match v.role {
                    BooleanRole::IsoSignConvention => {
                        *value = i32::from(self.model.convention == SignConvention::Iso);
                    }
                },
                None => status = status.max(self.unknown_reference("Boolean", *vr)),
            }
        }
        status
    }

    /// Fixed parameters may be set only before ExitInitializationMode.
    fn check_fixed_parameter(
        &self,
        name: &str,
        current: &dyn std::fmt::Debug,
    ) -> Result<(), Status> {
        match self.model.state {
            State::Instantiated | State::InitializationMode => Ok(()),
            state => Err(self.error(format!(
                "{name} is a fixed parameter: it can only be set before {}ExitInitializationMode \
                 (state is {}); it keeps its value {current:?}",
                self.abi.prefix(),
                state.name(self.abi)
            ))),
        }
    }

    pub(crate) fn set_boolean(&mut self, vrs: &[u32], values: &[i32]) -> Status {
        let mut status = Status::Ok;
        for (vr, value) in vrs.iter().zip(values) {
            let Some(v) = boolean_variable(*vr) else {
                status = status.max(self.unknown_reference("Boolean", *vr));
                continue;
            };
            let current = self.model.convention == SignConvention::Iso;
            if let Err(s) = self.check_fixed_parameter(v.name, &current) {
                status = status.max(s);
                continue;
            }
            match v.role {
                BooleanRole::IsoSignConvention => {
                    self.model.convention = convention_of(*value != 0)
                }
            }
            self.model.outputs_stale = true;
        }
        status
    }

    /// Fills `values` with pointers valid until the next call on this instance.
    pub(crate) fn get_string(
        &mut self,
        vrs: &[u32],
        values: &mut [*const std::ffi::c_char],
    ) -> Status {
        self.string_results.clear();
        let mut status = Status::Ok;
        for (vr, value) in vrs.iter().zip(values.iter_mut()) {
            match string_variable(*vr) {
                Some(v) => {
                    let text = match v.role {
                        StringRole::ParameterFile => &self.model.parameter_file,
                    };
                    self.string_results
                        .push(CString::new(text.as_str()).unwrap_or_default());
                    *value = self
                        .string_results
                        .last()
                        .map_or(std::ptr::null(), |s| s.as_ptr());
                }
                None => status = status.max(self.unknown_reference("String", *vr)),
            }
        }
        status
    }

    pub(crate) fn set_string(&mut self, vrs: &[u32], values: &[Option<&CStr>]) -> Status {
        let mut status = Status::Ok;
        for (vr, value) in vrs.iter().zip(values) {
            let Some(v) = string_variable(*vr) else {
                status = status.max(self.unknown_reference("String", *vr));
                continue;
            };
            if let Err(s) = self.check_fixed_parameter(v.name, &self.model.parameter_file) {
                status = status.max(s);
                continue;
            }
            let Some(text) = value.map(|s| s.to_str()) else {
                status = status.max(self.error(format!("{} = NULL; pass \"\" for none", v.name)));
                continue;
            };
            let Ok(text) = text else {
                status = status.max(self.error(format!("{} is not valid UTF-8", v.name)));
                continue;
            };
            match v.role {
                StringRole::ParameterFile => self.model.parameter_file = text.to_string(),
            }
        }
        status
    }

    // ---- stepping ---------------------------------------------------------------------

    #[inline]
    pub(crate) fn do_step(&mut self, t: f64, h: f64) -> Status {
        if !(h.is_finite() && h > 0.0) {
            return self.error(format!(
                "communicationStepSize = {h} must be a finite number > 0"
            ));
        }
        let time = self.model.time;
        let tolerance = TIME_TOLERANCE * time.abs().max(h).max(1.0);
        if !(t.is_finite() && (t - time).abs() <= tolerance) {
            return self.error(format!(
                "currentCommunicationPoint = {t} does not match the FMU's time {time}"
            ));
        }
        if !(t + h).is_finite() {
            return self.error(format!(
                "a step from {t} by {h} ends at {}: the time must stay finite",
                t + h
            ));
        }
        if let Some(stop) = self.model.stop_time
            && t + h > stop + tolerance
        {
            return self.error(format!(
                "a step from {t} by {h} passes the stop time {stop}"
            ));
        }
        let lag_before = self.model.lagged;
        if self.model.params.extensions.is_some() {
            self.model.advance_lag(h);
        }
        if self.model.outputs_stale
            && let Err(e) = self.model.compute_outputs()
        {
            // The step did not happen: time and relaxation lag stay where they were.
            self.model.lagged = lag_before;
            return self.error(format!("{e}; the time stays at {time}"));
        }
        self.model.time = t + h;
        Status::Ok
    }

    /// `dv_unknown = J dv_known`: exact partial derivatives of the outputs `unknown` with
    /// respect to the inputs `known`, at the current inputs and state.
    pub(crate) fn get_directional_derivative(
        &mut self,
        unknown: &[u32],
        known: &[u32],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> Status {
        if let Err(s) = self.prepare_derivatives() {
            return s;
        }
        let arguments = derivatives::Arguments::of(self.abi);
        match derivatives::directional(
            &arguments,
            &self.model,
            unknown,
            known,
            dv_known,
            dv_unknown,
        ) {
            Ok(()) => {
                let argument = match self.abi {
                    Abi::Fmi2 => "dvUnknown",
                    Abi::Fmi3 => "sensitivity",
                };
                self.all_finite(dv_unknown, |i| {
                    format!("{argument}[{i}] (vr {})", unknown[i])
                })
            }
            Err(e) => self.error(e),
        }
    }

    /// `sensitivity = seedᵀ J`: the adjoint (vector-Jacobian) product of the outputs and
    /// state derivatives `unknown` with respect to the inputs and states `known`, exact: one
    /// directional derivative per known, each seeded with 1.
    pub(crate) fn get_adjoint_derivative(
        &mut self,
        unknown: &[u32],
        known: &[u32],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Status {
        if let Err(s) = self.prepare_derivatives() {
            return s;
        }
        if let Some(i) = seed.iter().position(|v| !v.is_finite()) {
            return self.error(format!(
                "seed[{i}] (for vr {}) is {}: it must be finite",
                unknown[i], seed[i]
            ));
        }
        let arguments = derivatives::Arguments::of(self.abi);
        let mut column = vec![0.0; unknown.len()];
        for (j, vr) in known.iter().enumerate() {
            if let Err(e) = derivatives::directional(
                &arguments,
                &self.model,
                unknown,
                &[*vr],
                &[1.0],
                &mut column,
            ) {
                return self.error(e);
            }
            sensitivity[j] = column.iter().zip(seed).map(|(d, s)| d * s).sum();
        }
        self.all_finite(sensitivity, |j| {
            format!("sensitivity[{j}] (vr {})", known[j])
        })
    }

    /// Before derivatives in initialization mode: the parameters validated and the
    /// relaxation lag in its steady state, as for the outputs.
    fn prepare_derivatives(&mut self) -> Result<(), Status> {
        if self.model.outputs_stale && self.model.state == State::InitializationMode {
            if let Err(e) = self.model.params.validate() {
                return Err(self.error(format!("cannot compute derivatives: {e}")));
            }
            if let Err(e) = self.model.compute_initial_outputs() {
                return Err(self.error(e));
            }
        }
        Ok(())
    }

    // ---- Model Exchange ---------------------------------------------------------------

    pub(crate) fn enter_event_mode(&mut self) -> Status {
        self.model.state = State::EventMode;
        Status::Ok
    }

    /// The model has no discrete states and no events: nothing to iterate, no next event.
    pub(crate) fn new_discrete_states(&mut self) -> Status {
        Status::Ok
    }

    pub(crate) fn enter_continuous_time_mode(&mut self) -> Status {
        self.model.state = State::ContinuousTimeMode;
        Status::Ok
    }

    pub(crate) fn set_time(&mut self, time: f64) -> Status {
        if !time.is_finite() {
            return self.error(format!("time = {time} must be finite"));
        }
        self.model.time = time;
        Status::Ok
    }

    /// The number of states the host passes must be [`STATES`].
    fn check_state_count(&self, nx: usize) -> Result<(), Status> {
        if nx == STATES {
            Ok(())
        } else {
            Err(self.error(format!(
                "nx = {nx}, but this FMU has {STATES} continuous states (lag_Fx, lag_Fy, lag_Mz)"
            )))
        }
    }

    pub(crate) fn set_continuous_states(&mut self, x: &[f64]) -> Status {
        if let Err(s) = self.check_state_count(x.len()) {
            return s;
        }
        if let Some(bad) = x
            .iter()
            .position(|v| !v.is_finite() || v.abs() > LAGGED_SLIP_ABS_MAX)
        {
            return self.error(format!(
                "continuous state {bad} ({}) is {}: it must lie within +-{LAGGED_SLIP_ABS_MAX}; \
                 the states keep their values",
                STATE_NAMES[bad], x[bad]
            ));
        }
        self.model.lagged = mf87::LaggedSlip {
            fx: x[0],
            fy: x[1],
            mz: x[2],
        };
        self.model.outputs_stale = true;
        Status::Ok
    }

    pub(crate) fn get_continuous_states(&mut self, x: &mut [f64]) -> Status {
        if let Err(s) = self.check_state_count(x.len()) {
            return s;
        }
        if self.model.state == State::InitializationMode && self.model.outputs_stale {
            // The states are steady after initialization: computed with the outputs.
            if let Err(e) = self.model.compute_initial_outputs() {
                return self.error(e);
            }
        }
        let l = self.model.lagged;
        x.copy_from_slice(&[l.fx, l.fy, l.mz]);
        self.all_finite(x, |i| STATE_NAMES[i].to_string())
    }

    pub(crate) fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
        if let Err(s) = self.check_state_count(dx.len()) {
            return s;
        }
        let r = self.model.state_rates();
        dx.copy_from_slice(&[r.fx, r.fy, r.mz]);
        self.all_finite(dx, |i| format!("der({})", STATE_NAMES[i]))
    }

    pub(crate) fn get_nominals(&mut self, nominals: &mut [f64]) -> Status {
        if let Err(s) = self.check_state_count(nominals.len()) {
            return s;
        }
        nominals.fill(STATE_NOMINAL);
        Status::Ok
    }

    /// The model has no event indicators.
    pub(crate) fn get_event_indicators(&mut self, n: usize) -> Status {
        if n == 0 {
            Status::Ok
        } else {
            self.error(format!("ni = {n}, but this FMU has no event indicators"))
        }
    }

    pub(crate) fn last_successful_time(&self) -> f64 {
        self.model.time
    }

    /// Errors for what this FMU does not provide, naming the capability flag.
    pub(crate) fn unsupported(&self, what: &str) -> Status {
        self.error(format!("not supported by this FMU ({what})"))
    }

    // ---- FMU state --------------------------------------------------------------------

    /// The FMU state argument's name in this instance's standard.
    fn state_argument(&self) -> &'static str {
        match self.abi {
            Abi::Fmi2 => "FMUstate",
            Abi::Fmi3 => "FMUState",
        }
    }

    /// Copies the state into `*slot` (`None`: the host passed NULL).
    pub(crate) fn get_state(&mut self, slot: Option<&mut *mut c_void>) -> Status {
        match slot {
            Some(slot) => self.store_snapshot(slot, self.model.clone()),
            None => self.null_array(self.state_argument(), 1),
        }
    }

    fn store_snapshot(&mut self, slot: &mut *mut c_void, model: InstanceValues) -> Status {
        match self.snapshots.store(slot, model) {
            Ok(()) => Status::Ok,
            Err(why) => self.error(why),
        }
    }

    /// FreeFMUState: frees `*slot` if it is a state of this instance and sets it NULL.
    pub(crate) fn free_state(&mut self, slot: Option<&mut *mut c_void>) -> Status {
        let Some(slot) = slot else {
            return self.null_array(self.state_argument(), 1);
        };
        if slot.is_null() {
            return Status::Ok;
        }
        if self.snapshots.free(*slot) {
            *slot = std::ptr::null_mut();
            Status::Ok
        } else {
            self.error(NOT_A_STATE)
        }
    }

    /// How many FMU states of this instance are allocated.
    pub fn allocated_states(&self) -> usize {
        self.snapshots.len()
    }

    pub(crate) fn set_state(&mut self, state: *mut c_void) -> Status {
        let snapshot = self.snapshots.get(state);
        match snapshot {
            Some(s) if !s.model().state.belongs_to(self.interface) => self.error(format!(
                "the state was taken in {}, which this {} instance does not have",
                s.model().state.name(self.abi),
                self.interface.name()
            )),
            Some(s) => {
                let model = s.model().clone();
                self.model = model;
                self.event(format!("state restored (time {})", self.model.time));
                Status::Ok
            }
            None => self.error(NOT_A_STATE),
        }
    }

    fn serialize(&self, state: *mut c_void) -> Result<Vec<u8>, Status> {
        let Some(s) = self.snapshots.get(state) else {
            return Err(self.error(NOT_A_STATE));
        };
        fmu_states::serialize(s.model()).map_err(|e| self.error(format!("cannot serialize: {e}")))
    }

    /// SerializedFMUStateSize: the size of `state` serialized into `*size`.
    pub(crate) fn serialized_size(&self, state: *mut c_void, size: Option<&mut usize>) -> Status {
        let Some(size) = size else {
            return self.null_array("size", 1);
        };
        match self.serialize(state) {
            Ok(bytes) => {
                *size = bytes.len();
                Status::Ok
            }
            Err(status) => status,
        }
    }

    /// SerializeFMUState: `state` serialized into `buffer` (`None`: NULL with `size` bytes
    /// announced), which must be large enough.
    pub(crate) fn serialize_into(
        &self,
        state: *mut c_void,
        buffer: Option<&mut [u8]>,
        size: usize,
    ) -> Status {
        let Some(buffer) = buffer else {
            return self.null_array("serializedState", size);
        };
        match self.serialize(state) {
            Ok(bytes) if bytes.len() <= buffer.len() => {
                buffer[..bytes.len()].copy_from_slice(&bytes);
                Status::Ok
            }
            Ok(bytes) => self.error(format!(
                "serializedState has {size} bytes, the state needs {}: ask {}Serialized{}Size",
                bytes.len(),
                self.abi.prefix(),
                self.state_argument()
            )),
            Err(status) => status,
        }
    }

    /// DeserializeFMUState: a new state of this instance from `bytes`, into `*slot`.
    pub(crate) fn deserialize(
        &mut self,
        bytes: Option<&[u8]>,
        size: usize,
        slot: Option<&mut *mut c_void>,
    ) -> Status {
        let (Some(bytes), Some(slot)) = (bytes, slot) else {
            let what = format!("serializedState or {}", self.state_argument());
            return self.null_array(&what, size);
        };
        let model = match fmu_states::deserialize(bytes) {
            Ok(m) => m,
            Err(e) => return self.error(format!("not a serialized state of this FMU: {e}")),
        };
        self.store_snapshot(slot, model)
    }
}
