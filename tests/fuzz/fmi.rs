//! The FMU's shared library loaded with dlopen, its 44 FMI 2.0 functions (common,
//! co-simulation, Model Exchange) looked up by name, and a host logger that keeps what the
//! instances log.

use std::ffi::{CStr, CString, c_void};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use fmi_sys::fmi2::*;

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
