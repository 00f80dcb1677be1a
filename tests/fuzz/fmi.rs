//! The FMU's shared library loaded with dlopen, its 44 FMI 2.0 functions (common,
//! co-simulation, Model Exchange) and 75 FMI 3.0 functions looked up by name, and the host's
//! loggers of both standards, which keep what the instances log.

use std::ffi::{CStr, CString, c_void};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use fmi_sys::fmi2::*;
use fmi_sys::fmi3::*;

/// `path` opened with dlopen; the message says why not.
fn open(path: &Path) -> Result<*mut c_void, String> {
    let c_path = CString::new(path.to_string_lossy().as_bytes()).unwrap();
    // SAFETY: a NUL-terminated path; the library's initialisers are the FMU's.
    let handle = unsafe { libc::dlopen(c_path.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL) };
    if handle.is_null() {
        // SAFETY: dlerror returns NULL or a C string.
        let why = unsafe { CStr::from_ptr(libc::dlerror()) };
        return Err(format!(
            "dlopen {}: {}",
            path.display(),
            why.to_string_lossy()
        ));
    }
    Ok(handle)
}

/// The function type inside one of fmi-sys's `Option<fn>` aliases (`fmi2DoStepTYPE`,
/// `fmi3DoStepTYPE`, ...): the functions are typed by the standards' headers as fmi-sys binds
/// them.
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

/// The address of the symbol `name` of `handle` (NULL if it has none).
fn symbol(handle: *mut c_void, name: &str) -> *mut c_void {
    let symbol = CString::new(name).unwrap();
    // SAFETY: a live handle (every caller's) and a C string.
    unsafe { libc::dlsym(handle, symbol.as_ptr()) }
}

macro_rules! functions {
    ($table:ident, $names:ident, $standard:literal, $($name:ident: $ty:ident),+ $(,)?) => {
        #[doc = concat!("Every exported ", $standard, " function.")]
        #[allow(non_snake_case)]
        pub struct $table {
            $(pub $name: <$ty as Unwrapped>::F,)+
            _handle: *mut c_void,
        }

        /// The names, in the order of the fields.
        pub const $names: &[&str] = &[$(stringify!($name)),+];

        impl $table {
            /// Loads `path` (each table dlopens it: dlopen counts references) and looks up
            /// every function; the message names the missing one.
            pub fn load(path: &Path) -> Result<$table, String> {
                let handle = open(path)?;
                Ok($table {
                    $($name: {
                        let f = symbol(handle, stringify!($name));
                        // SAFETY: NULL or the FMI function of that name, whose C signature
                        // is fmi-sys's `<name>TYPE` (an Option of a function pointer, NULL
                        // being None).
                        let f = unsafe { std::mem::transmute::<*mut c_void, $ty>(f) };
                        f.get().ok_or_else(|| {
                            format!("{} does not export {}", path.display(), stringify!($name))
                        })?
                    },)+
                    _handle: handle,
                })
            }
        }
    };
}

functions!(
    Fmi,
    NAMES,
    "FMI 2.0",
    fmi2GetTypesPlatform: fmi2GetTypesPlatformTYPE,
    fmi2GetVersion: fmi2GetVersionTYPE,
    fmi2SetDebugLogging: fmi2SetDebugLoggingTYPE,
    fmi2Instantiate: fmi2InstantiateTYPE,
    fmi2FreeInstance: fmi2FreeInstanceTYPE,
    fmi2SetupExperiment: fmi2SetupExperimentTYPE,
    fmi2EnterInitializationMode: fmi2EnterInitializationModeTYPE,
    fmi2ExitInitializationMode: fmi2ExitInitializationModeTYPE,
    fmi2Terminate: fmi2TerminateTYPE,
    fmi2Reset: fmi2ResetTYPE,
    fmi2GetReal: fmi2GetRealTYPE,
    fmi2GetInteger: fmi2GetIntegerTYPE,
    fmi2GetBoolean: fmi2GetBooleanTYPE,
    fmi2GetString: fmi2GetStringTYPE,
    fmi2SetReal: fmi2SetRealTYPE,
    fmi2SetInteger: fmi2SetIntegerTYPE,
    fmi2SetBoolean: fmi2SetBooleanTYPE,
    fmi2SetString: fmi2SetStringTYPE,
    fmi2GetFMUstate: fmi2GetFMUstateTYPE,
    fmi2SetFMUstate: fmi2SetFMUstateTYPE,
    fmi2FreeFMUstate: fmi2FreeFMUstateTYPE,
    fmi2SerializedFMUstateSize: fmi2SerializedFMUstateSizeTYPE,
    fmi2SerializeFMUstate: fmi2SerializeFMUstateTYPE,
    fmi2DeSerializeFMUstate: fmi2DeSerializeFMUstateTYPE,
    fmi2GetDirectionalDerivative: fmi2GetDirectionalDerivativeTYPE,
    fmi2SetRealInputDerivatives: fmi2SetRealInputDerivativesTYPE,
    fmi2GetRealOutputDerivatives: fmi2GetRealOutputDerivativesTYPE,
    fmi2DoStep: fmi2DoStepTYPE,
    fmi2CancelStep: fmi2CancelStepTYPE,
    fmi2GetStatus: fmi2GetStatusTYPE,
    fmi2GetRealStatus: fmi2GetRealStatusTYPE,
    fmi2GetIntegerStatus: fmi2GetIntegerStatusTYPE,
    fmi2GetBooleanStatus: fmi2GetBooleanStatusTYPE,
    fmi2GetStringStatus: fmi2GetStringStatusTYPE,
    fmi2EnterEventMode: fmi2EnterEventModeTYPE,
    fmi2NewDiscreteStates: fmi2NewDiscreteStatesTYPE,
    fmi2EnterContinuousTimeMode: fmi2EnterContinuousTimeModeTYPE,
    fmi2CompletedIntegratorStep: fmi2CompletedIntegratorStepTYPE,
    fmi2SetTime: fmi2SetTimeTYPE,
    fmi2SetContinuousStates: fmi2SetContinuousStatesTYPE,
    fmi2GetContinuousStates: fmi2GetContinuousStatesTYPE,
    fmi2GetDerivatives: fmi2GetDerivativesTYPE,
    fmi2GetNominalsOfContinuousStates: fmi2GetNominalsOfContinuousStatesTYPE,
    fmi2GetEventIndicators: fmi2GetEventIndicatorsTYPE,
);

functions!(
    Fmi3,
    NAMES3,
    "FMI 3.0",
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

/// The FMU-state functions of a standard with their names: both standards have them with the
/// same arguments (`B`, a serialized byte: `char` in FMI 2.0, `uint8_t` in FMI 3.0).
pub struct StateFunctions<B> {
    pub get: (
        &'static str,
        unsafe extern "C" fn(fmi2Component, *mut fmi2FMUstate) -> fmi2Status,
    ),
    pub set: (
        &'static str,
        unsafe extern "C" fn(fmi2Component, fmi2FMUstate) -> fmi2Status,
    ),
    pub free: (
        &'static str,
        unsafe extern "C" fn(fmi2Component, *mut fmi2FMUstate) -> fmi2Status,
    ),
    pub size: (
        &'static str,
        unsafe extern "C" fn(fmi2Component, fmi2FMUstate, *mut usize) -> fmi2Status,
    ),
    pub serialize: (
        &'static str,
        unsafe extern "C" fn(fmi2Component, fmi2FMUstate, *mut B, usize) -> fmi2Status,
    ),
    pub deserialize: (
        &'static str,
        unsafe extern "C" fn(fmi2Component, *const B, usize, *mut fmi2FMUstate) -> fmi2Status,
    ),
}

macro_rules! state_functions {
    ($table:ident, $byte:ty: $get:ident, $set:ident, $free:ident, $size:ident, $ser:ident, $de:ident) => {
        impl $table {
            /// The FMU-state functions.
            pub fn states(&self) -> StateFunctions<$byte> {
                StateFunctions {
                    get: (stringify!($get), self.$get),
                    set: (stringify!($set), self.$set),
                    free: (stringify!($free), self.$free),
                    size: (stringify!($size), self.$size),
                    serialize: (stringify!($ser), self.$ser),
                    deserialize: (stringify!($de), self.$de),
                }
            }
        }
    };
}

state_functions!(Fmi, fmi2Byte: fmi2GetFMUstate, fmi2SetFMUstate, fmi2FreeFMUstate,
    fmi2SerializedFMUstateSize, fmi2SerializeFMUstate, fmi2DeSerializeFMUstate);
state_functions!(Fmi3, fmi3Byte: fmi3GetFMUState, fmi3SetFMUState, fmi3FreeFMUState,
    fmi3SerializedFMUStateSize, fmi3SerializeFMUState, fmi3DeserializeFMUState);

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
    let category = category.as_deref().unwrap_or("NULL");
    keep(level, format_args!("fmi3 {category}"), message);
    ODDITIES.lock().unwrap().extend(odd);
}

/// Keeps a message an instance logged (`source`: its name or category), echoed in a replay.
fn keep(level: log::Level, source: std::fmt::Arguments, message: String) {
    if ECHO.load(std::sync::atomic::Ordering::Relaxed) {
        println!("      log {level} [{source}] {message}");
    }
    LOGS.lock().unwrap().push((level, message));
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
        keep(
            record.level(),
            format_args!("{}", record.target()),
            record.args().to_string(),
        );
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
