//! The FMU's shared library loaded with dlopen, its 44 FMI 2.0 functions (common,
//! co-simulation, Model Exchange) and 75 FMI 3.0 functions looked up by name, and the host's
//! loggers of both standards, which keep what the instances log.

use std::ffi::{CStr, CString, c_void};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use fmi_sys::fmi2::*;
use fmi_sys::fmi3::*;

macro_rules! functions {
    ($($name:ident),+ $(,)?) => {
        /// Every exported FMI 2.0 function.
        #[allow(non_snake_case)]
        pub struct Fmi {
            $(pub $name: paste_type!($name),)+
            _handle: *mut c_void,
        }

        /// The names, in the order of the fields.
        pub const NAMES: &[&str] = &[$(stringify!($name)),+];

        impl Fmi {
            /// Loads `path` and looks up every function; the message names the missing one.
            pub fn load(path: &Path) -> Result<Fmi, String> {
                let c_path = CString::new(path.to_string_lossy().as_bytes()).unwrap();
                // SAFETY: a NUL-terminated path; the library's initialisers are the FMU's.
                let handle = unsafe { libc::dlopen(c_path.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL) };
                if handle.is_null() {
                    // SAFETY: dlerror returns NULL or a C string.
                    let why = unsafe { CStr::from_ptr(libc::dlerror()) };
                    return Err(format!("dlopen {}: {}", path.display(), why.to_string_lossy()));
                }
                Ok(Fmi {
                    $($name: {
                        let symbol = CString::new(stringify!($name)).unwrap();
                        // SAFETY: a live handle and a C string.
                        let f = unsafe { libc::dlsym(handle, symbol.as_ptr()) };
                        if f.is_null() {
                            return Err(format!("{} does not export {}", path.display(), stringify!($name)));
                        }
                        // SAFETY: the symbol is the FMI function of that name, whose C
                        // signature the standard's header (fmi-sys) gives.
                        unsafe { std::mem::transmute::<*mut c_void, paste_type!($name)>(f) }
                    },)+
                    _handle: handle,
                })
            }
        }
    };
}

/// The function pointer type of an FMI function (fmi-sys's `<name>TYPE` without the Option).
macro_rules! paste_type {
    (fmi2GetTypesPlatform) => { unsafe extern "C" fn() -> fmi2String };
    (fmi2GetVersion) => { unsafe extern "C" fn() -> fmi2String };
    (fmi2SetDebugLogging) => { unsafe extern "C" fn(fmi2Component, fmi2Boolean, usize, *const fmi2String) -> fmi2Status };
    (fmi2Instantiate) => { unsafe extern "C" fn(fmi2String, fmi2Type, fmi2String, fmi2String, *const fmi2CallbackFunctions, fmi2Boolean, fmi2Boolean) -> fmi2Component };
    (fmi2FreeInstance) => { unsafe extern "C" fn(fmi2Component) };
    (fmi2SetupExperiment) => { unsafe extern "C" fn(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean, fmi2Real) -> fmi2Status };
    (fmi2EnterInitializationMode) => { unsafe extern "C" fn(fmi2Component) -> fmi2Status };
    (fmi2ExitInitializationMode) => { unsafe extern "C" fn(fmi2Component) -> fmi2Status };
    (fmi2Terminate) => { unsafe extern "C" fn(fmi2Component) -> fmi2Status };
    (fmi2Reset) => { unsafe extern "C" fn(fmi2Component) -> fmi2Status };
    (fmi2GetReal) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Real) -> fmi2Status };
    (fmi2GetInteger) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Integer) -> fmi2Status };
    (fmi2GetBoolean) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Boolean) -> fmi2Status };
    (fmi2GetString) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2String) -> fmi2Status };
    (fmi2SetReal) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Real) -> fmi2Status };
    (fmi2SetInteger) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Integer) -> fmi2Status };
    (fmi2SetBoolean) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Boolean) -> fmi2Status };
    (fmi2SetString) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2String) -> fmi2Status };
    (fmi2GetFMUstate) => { unsafe extern "C" fn(fmi2Component, *mut fmi2FMUstate) -> fmi2Status };
    (fmi2SetFMUstate) => { unsafe extern "C" fn(fmi2Component, fmi2FMUstate) -> fmi2Status };
    (fmi2FreeFMUstate) => { unsafe extern "C" fn(fmi2Component, *mut fmi2FMUstate) -> fmi2Status };
    (fmi2SerializedFMUstateSize) => { unsafe extern "C" fn(fmi2Component, fmi2FMUstate, *mut usize) -> fmi2Status };
    (fmi2SerializeFMUstate) => { unsafe extern "C" fn(fmi2Component, fmi2FMUstate, *mut fmi2Byte, usize) -> fmi2Status };
    (fmi2DeSerializeFMUstate) => { unsafe extern "C" fn(fmi2Component, *const fmi2Byte, usize, *mut fmi2FMUstate) -> fmi2Status };
    (fmi2GetDirectionalDerivative) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2ValueReference, usize, *const fmi2Real, *mut fmi2Real) -> fmi2Status };
    (fmi2SetRealInputDerivatives) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Integer, *const fmi2Real) -> fmi2Status };
    (fmi2GetRealOutputDerivatives) => { unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Integer, *mut fmi2Real) -> fmi2Status };
    (fmi2DoStep) => { unsafe extern "C" fn(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean) -> fmi2Status };
    (fmi2CancelStep) => { unsafe extern "C" fn(fmi2Component) -> fmi2Status };
    (fmi2GetStatus) => { unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Status) -> fmi2Status };
    (fmi2GetRealStatus) => { unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Real) -> fmi2Status };
    (fmi2GetIntegerStatus) => { unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Integer) -> fmi2Status };
    (fmi2GetBooleanStatus) => { unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Boolean) -> fmi2Status };
    (fmi2GetStringStatus) => { unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2String) -> fmi2Status };
    (fmi2EnterEventMode) => { unsafe extern "C" fn(fmi2Component) -> fmi2Status };
    (fmi2NewDiscreteStates) => { unsafe extern "C" fn(fmi2Component, *mut fmi2EventInfo) -> fmi2Status };
    (fmi2EnterContinuousTimeMode) => { unsafe extern "C" fn(fmi2Component) -> fmi2Status };
    (fmi2CompletedIntegratorStep) => { unsafe extern "C" fn(fmi2Component, fmi2Boolean, *mut fmi2Boolean, *mut fmi2Boolean) -> fmi2Status };
    (fmi2SetTime) => { unsafe extern "C" fn(fmi2Component, fmi2Real) -> fmi2Status };
    (fmi2SetContinuousStates) => { unsafe extern "C" fn(fmi2Component, *const fmi2Real, usize) -> fmi2Status };
    (fmi2GetContinuousStates) => { unsafe extern "C" fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status };
    (fmi2GetDerivatives) => { unsafe extern "C" fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status };
    (fmi2GetNominalsOfContinuousStates) => { unsafe extern "C" fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status };
    (fmi2GetEventIndicators) => { unsafe extern "C" fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status };
}

functions!(
    fmi2GetTypesPlatform,
    fmi2GetVersion,
    fmi2SetDebugLogging,
    fmi2Instantiate,
    fmi2FreeInstance,
    fmi2SetupExperiment,
    fmi2EnterInitializationMode,
    fmi2ExitInitializationMode,
    fmi2Terminate,
    fmi2Reset,
    fmi2GetReal,
    fmi2GetInteger,
    fmi2GetBoolean,
    fmi2GetString,
    fmi2SetReal,
    fmi2SetInteger,
    fmi2SetBoolean,
    fmi2SetString,
    fmi2GetFMUstate,
    fmi2SetFMUstate,
    fmi2FreeFMUstate,
    fmi2SerializedFMUstateSize,
    fmi2SerializeFMUstate,
    fmi2DeSerializeFMUstate,
    fmi2GetDirectionalDerivative,
    fmi2SetRealInputDerivatives,
    fmi2GetRealOutputDerivatives,
    fmi2DoStep,
    fmi2CancelStep,
    fmi2GetStatus,
    fmi2GetRealStatus,
    fmi2GetIntegerStatus,
    fmi2GetBooleanStatus,
    fmi2GetStringStatus,
    fmi2EnterEventMode,
    fmi2NewDiscreteStates,
    fmi2EnterContinuousTimeMode,
    fmi2CompletedIntegratorStep,
    fmi2SetTime,
    fmi2SetContinuousStates,
    fmi2GetContinuousStates,
    fmi2GetDerivatives,
    fmi2GetNominalsOfContinuousStates,
    fmi2GetEventIndicators,
);

/// The function type inside one of fmi-sys's `Option<fn>` aliases (`fmi3DoStepTYPE`, ...):
/// the FMI 3.0 functions are typed by the standard's header as fmi-sys binds it.
pub trait Unwrapped {
    type F: Copy;
    fn get(self) -> Option<Self::F>;
}

impl<F: Copy> Unwrapped for Option<F> {
    type F = F;
    fn get(self) -> Option<F> {
        self
    }
}

macro_rules! functions3 {
    ($($name:ident: $ty:ident),+ $(,)?) => {
        /// Every exported FMI 3.0 function.
        #[allow(non_snake_case)]
        pub struct Fmi3 {
            $(pub $name: <$ty as Unwrapped>::F,)+
            _handle: *mut c_void,
        }

        /// The names, in the order of the fields.
        pub const NAMES3: &[&str] = &[$(stringify!($name)),+];

        impl Fmi3 {
            /// Loads `path` (the library [`Fmi`] loads: dlopen counts references) and looks
            /// up every function; the message names the missing one.
            pub fn load(path: &Path) -> Result<Fmi3, String> {
                let c_path = CString::new(path.to_string_lossy().as_bytes()).unwrap();
                // SAFETY: a NUL-terminated path; the library's initialisers are the FMU's.
                let handle = unsafe { libc::dlopen(c_path.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL) };
                if handle.is_null() {
                    // SAFETY: dlerror returns NULL or a C string.
                    let why = unsafe { CStr::from_ptr(libc::dlerror()) };
                    return Err(format!("dlopen {}: {}", path.display(), why.to_string_lossy()));
                }
                Ok(Fmi3 {
                    $($name: {
                        let symbol = CString::new(stringify!($name)).unwrap();
                        // SAFETY: a live handle and a C string.
                        let f = unsafe { libc::dlsym(handle, symbol.as_ptr()) };
                        // SAFETY: NULL or the FMI function of that name, whose C signature
                        // is fmi-sys's `<name>TYPE` (an Option of a function pointer, NULL
                        // being None).
                        let f = unsafe { std::mem::transmute::<*mut c_void, $ty>(f) };
                        match f.get() {
                            Some(f) => f,
                            None => return Err(format!("{} does not export {}", path.display(), stringify!($name))),
                        }
                    },)+
                    _handle: handle,
                })
            }
        }
    };
}

functions3!(
    fmi3GetVersion: fmi3GetVersionTYPE,
    fmi3SetDebugLogging: fmi3SetDebugLoggingTYPE,
    fmi3InstantiateModelExchange: fmi3InstantiateModelExchangeTYPE,
    fmi3InstantiateCoSimulation: fmi3InstantiateCoSimulationTYPE,
    fmi3InstantiateScheduledExecution: fmi3InstantiateScheduledExecutionTYPE,
    fmi3FreeInstance: fmi3FreeInstanceTYPE,
    fmi3EnterInitializationMode: fmi3EnterInitializationModeTYPE,
    fmi3ExitInitializationMode: fmi3ExitInitializationModeTYPE,
    fmi3EnterEventMode: fmi3EnterEventModeTYPE,
    fmi3Terminate: fmi3TerminateTYPE,
    fmi3Reset: fmi3ResetTYPE,
    fmi3GetFloat32: fmi3GetFloat32TYPE,
    fmi3GetFloat64: fmi3GetFloat64TYPE,
    fmi3GetInt8: fmi3GetInt8TYPE,
    fmi3GetUInt8: fmi3GetUInt8TYPE,
    fmi3GetInt16: fmi3GetInt16TYPE,
    fmi3GetUInt16: fmi3GetUInt16TYPE,
    fmi3GetInt32: fmi3GetInt32TYPE,
    fmi3GetUInt32: fmi3GetUInt32TYPE,
    fmi3GetInt64: fmi3GetInt64TYPE,
    fmi3GetUInt64: fmi3GetUInt64TYPE,
    fmi3GetBoolean: fmi3GetBooleanTYPE,
    fmi3GetString: fmi3GetStringTYPE,
    fmi3GetBinary: fmi3GetBinaryTYPE,
    fmi3GetClock: fmi3GetClockTYPE,
    fmi3SetFloat32: fmi3SetFloat32TYPE,
    fmi3SetFloat64: fmi3SetFloat64TYPE,
    fmi3SetInt8: fmi3SetInt8TYPE,
    fmi3SetUInt8: fmi3SetUInt8TYPE,
    fmi3SetInt16: fmi3SetInt16TYPE,
    fmi3SetUInt16: fmi3SetUInt16TYPE,
    fmi3SetInt32: fmi3SetInt32TYPE,
    fmi3SetUInt32: fmi3SetUInt32TYPE,
    fmi3SetInt64: fmi3SetInt64TYPE,
    fmi3SetUInt64: fmi3SetUInt64TYPE,
    fmi3SetBoolean: fmi3SetBooleanTYPE,
    fmi3SetString: fmi3SetStringTYPE,
    fmi3SetBinary: fmi3SetBinaryTYPE,
    fmi3SetClock: fmi3SetClockTYPE,
    fmi3GetNumberOfVariableDependencies: fmi3GetNumberOfVariableDependenciesTYPE,
    fmi3GetVariableDependencies: fmi3GetVariableDependenciesTYPE,
    fmi3GetFMUState: fmi3GetFMUStateTYPE,
    fmi3SetFMUState: fmi3SetFMUStateTYPE,
    fmi3FreeFMUState: fmi3FreeFMUStateTYPE,
    fmi3SerializedFMUStateSize: fmi3SerializedFMUStateSizeTYPE,
    fmi3SerializeFMUState: fmi3SerializeFMUStateTYPE,
    fmi3DeserializeFMUState: fmi3DeserializeFMUStateTYPE,
    fmi3GetDirectionalDerivative: fmi3GetDirectionalDerivativeTYPE,
    fmi3GetAdjointDerivative: fmi3GetAdjointDerivativeTYPE,
    fmi3EnterConfigurationMode: fmi3EnterConfigurationModeTYPE,
    fmi3ExitConfigurationMode: fmi3ExitConfigurationModeTYPE,
    fmi3GetIntervalDecimal: fmi3GetIntervalDecimalTYPE,
    fmi3GetIntervalFraction: fmi3GetIntervalFractionTYPE,
    fmi3GetShiftDecimal: fmi3GetShiftDecimalTYPE,
    fmi3GetShiftFraction: fmi3GetShiftFractionTYPE,
    fmi3SetIntervalDecimal: fmi3SetIntervalDecimalTYPE,
    fmi3SetIntervalFraction: fmi3SetIntervalFractionTYPE,
    fmi3SetShiftDecimal: fmi3SetShiftDecimalTYPE,
    fmi3SetShiftFraction: fmi3SetShiftFractionTYPE,
    fmi3EvaluateDiscreteStates: fmi3EvaluateDiscreteStatesTYPE,
    fmi3UpdateDiscreteStates: fmi3UpdateDiscreteStatesTYPE,
    fmi3EnterContinuousTimeMode: fmi3EnterContinuousTimeModeTYPE,
    fmi3CompletedIntegratorStep: fmi3CompletedIntegratorStepTYPE,
    fmi3SetTime: fmi3SetTimeTYPE,
    fmi3SetContinuousStates: fmi3SetContinuousStatesTYPE,
    fmi3GetContinuousStateDerivatives: fmi3GetContinuousStateDerivativesTYPE,
    fmi3GetEventIndicators: fmi3GetEventIndicatorsTYPE,
    fmi3GetContinuousStates: fmi3GetContinuousStatesTYPE,
    fmi3GetNominalsOfContinuousStates: fmi3GetNominalsOfContinuousStatesTYPE,
    fmi3GetNumberOfEventIndicators: fmi3GetNumberOfEventIndicatorsTYPE,
    fmi3GetNumberOfContinuousStates: fmi3GetNumberOfContinuousStatesTYPE,
    fmi3EnterStepMode: fmi3EnterStepModeTYPE,
    fmi3GetOutputDerivatives: fmi3GetOutputDerivativesTYPE,
    fmi3DoStep: fmi3DoStepTYPE,
    fmi3ActivateModelPartition: fmi3ActivateModelPartitionTYPE,
);

/// The FMU library next to this test binary (target/<profile>/), or `FUZZ_FMU_LIB`.
pub fn library_path() -> PathBuf {
    if let Some(p) = std::env::var_os("FUZZ_FMU_LIB") {
        return PathBuf::from(p);
    }
    let exe = std::env::current_exe().unwrap();
    // target/<profile>/deps/fuzz-<hash>
    let profile_dir = exe.parent().and_then(Path::parent).unwrap();
    profile_dir.join(format!(
        "{}pacejka87_tire{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    ))
}

/// (status, message) of every message logged since the last [`take_messages`].
static LOGS: Mutex<Vec<(log::Level, String)>> = Mutex::new(Vec::new());
/// Whether messages are echoed as they come (replay).
static ECHO: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// What the FMI 3.0 logger saw that no FMU may send (a status outside fmi3Status, a NULL
/// or unknown category, a NULL message, an instanceEnvironment the host never gave).
static ODDITIES: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// The instanceEnvironment the host gives the FMI 3.0 instance of slot `inst` (never
/// dereferenced: the logger checks that messages come back with one of these).
pub fn environment(inst: usize) -> fmi3InstanceEnvironment {
    (ENVIRONMENT_BASE + inst) as fmi3InstanceEnvironment
}

const ENVIRONMENT_BASE: usize = 0x7e57_0000;

/// The log categories of the model description.
const CATEGORIES: &[&str] = &[
    "logStatusError",
    "logStatusWarning",
    "logEvents",
    "logCalls",
];

/// The host's FMI 3.0 `logMessage`: keeps the message as the FMI 2.0 logger does.
///
/// # Safety
/// `category` and `message` NULL or NUL-terminated (what is checked).
pub unsafe extern "C" fn log_message(
    environment: fmi3InstanceEnvironment,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
) {
    let mut odd = Vec::new();
    // fmi3OK, fmi3Warning, fmi3Discard, fmi3Error, fmi3Fatal.
    let level = match status {
        0 => log::Level::Info,
        1 => log::Level::Warn,
        2 => log::Level::Trace,
        3 | 4 => log::Level::Error,
        other => {
            odd.push(format!("logMessage got status {other}, not an fmi3Status"));
            log::Level::Error
        }
    };
    let text = |s: fmi3String| {
        // SAFETY: NUL-terminated if not NULL, by this function's contract.
        (!s.is_null()).then(|| unsafe { CStr::from_ptr(s) }.to_string_lossy().into_owned())
    };
    let category = text(category);
    match &category {
        None => odd.push("logMessage got category NULL".into()),
        Some(c) if !CATEGORIES.contains(&c.as_str()) => odd.push(format!(
            "logMessage got category {c:?}, not one of the model description's"
        )),
        Some(_) => {}
    }
    let message = text(message).unwrap_or_else(|| {
        odd.push("logMessage got message NULL".into());
        String::new()
    });
    let env = environment as usize;
    if !(ENVIRONMENT_BASE..ENVIRONMENT_BASE + crate::seq::INSTANCES).contains(&env) {
        odd.push(format!(
            "logMessage got instanceEnvironment {env:#x}, not one the host gave"
        ));
    }
    if ECHO.load(std::sync::atomic::Ordering::Relaxed) {
        println!(
            "      log {level} [fmi3 {}] {message}",
            category.as_deref().unwrap_or("NULL")
        );
    }
    LOGS.lock().unwrap().push((level, message));
    ODDITIES.lock().unwrap().extend(odd);
}

/// Records a callback the FMU should not have made.
pub fn report_oddity(what: &str) {
    ODDITIES.lock().unwrap().push(what.to_string());
}

/// What the FMI 3.0 logger found wrong since the last call.
pub fn take_oddities() -> Vec<String> {
    std::mem::take(&mut *ODDITIES.lock().unwrap())
}

struct Capture;

impl log::Log for Capture {
    fn enabled(&self, _: &log::Metadata) -> bool {
        true
    }
    fn log(&self, record: &log::Record) {
        let message = record.args().to_string();
        if ECHO.load(std::sync::atomic::Ordering::Relaxed) {
            println!(
                "      log {} [{}] {}",
                record.level(),
                record.target(),
                message
            );
        }
        LOGS.lock().unwrap().push((record.level(), message));
    }
    fn flush(&self) {}
}

/// Installs the capturing logger; `echo` prints each message too.
pub fn capture_logs(echo: bool) {
    ECHO.store(echo, std::sync::atomic::Ordering::Relaxed);
    let _ = log::set_logger(&Capture);
    log::set_max_level(log::LevelFilter::Trace);
}

pub fn take_messages() -> Vec<(log::Level, String)> {
    std::mem::take(&mut *LOGS.lock().unwrap())
}
