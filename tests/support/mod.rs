//! Calls the FMU's C ABI in-process, as a host would, and captures what it logs.
#![allow(dead_code)]

use std::ffi::{CStr, CString};
use std::ptr::{null, null_mut};
use std::sync::{Mutex, Once};

use fmi_sys::fmi2::*;
use pacejka87_tire::exports::*;
use pacejka87_tire::variables::{GUID, REAL_VARIABLES};

pub const OK: fmi2Status = fmi2Status_fmi2OK;
pub const WARNING: fmi2Status = fmi2Status_fmi2Warning;
pub const DISCARD: fmi2Status = fmi2Status_fmi2Discard;
pub const ERROR: fmi2Status = fmi2Status_fmi2Error;

/// (instance name, status, message) of every message logged through the host logger.
static LOGS: Mutex<Vec<(String, log::Level, String)>> = Mutex::new(Vec::new());

struct Capture;

impl log::Log for Capture {
    fn enabled(&self, _: &log::Metadata) -> bool {
        true
    }
    fn log(&self, record: &log::Record) {
        let entry = (
            record.target().to_string(),
            record.level(),
            record.args().to_string(),
        );
        LOGS.lock().unwrap().push(entry);
    }
    fn flush(&self) {}
}

/// Host callbacks: a real C variadic logger (fmi-sys's logger.c, which formats with
/// vsnprintf and forwards to the `log` crate, captured above) and the C allocator.
pub fn callbacks() -> fmi2CallbackFunctions {
    static INIT: Once = Once::new();
    INIT.call_once(|| {
        log::set_logger(&Capture).unwrap();
        log::set_max_level(log::LevelFilter::Trace);
    });
    fmi2CallbackFunctions {
        logger: Some(fmi_sys::fmi2::logger::callback_logger_handler),
        allocateMemory: Some(libc::calloc),
        freeMemory: Some(libc::free),
        stepFinished: None,
        componentEnvironment: null_mut(),
    }
}

/// Messages logged by the instance `name`.
pub fn messages(name: &str) -> Vec<(log::Level, String)> {
    LOGS.lock()
        .unwrap()
        .iter()
        .filter(|(n, ..)| n == name)
        .map(|(_, l, m)| (*l, m.clone()))
        .collect()
}

/// The value reference of a Real variable by name.
pub fn vr(name: &str) -> u32 {
    REAL_VARIABLES
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("no Real variable {name}"))
        .vr
}

/// An instance driven through the C ABI.
pub struct Fmu {
    pub c: fmi2Component,
    pub name: String,
    // Keeps the callbacks alive as long as the instance (the FMU copies them, but hosts often
    // keep them anyway).
    _callbacks: Box<fmi2CallbackFunctions>,
}

unsafe impl Send for Fmu {}

impl Fmu {
    pub fn instantiate(name: &str, resources: Option<&str>) -> Fmu {
        Fmu::instantiate_as(name, resources, fmi2Type_fmi2CoSimulation)
    }

    /// An instance for `fmu_type` (co-simulation or Model Exchange).
    pub fn instantiate_as(name: &str, resources: Option<&str>, fmu_type: fmi2Type) -> Fmu {
        let callbacks = Box::new(callbacks());
        let cname = CString::new(name).unwrap();
        let guid = CString::new(GUID).unwrap();
        let res = resources.map(|r| CString::new(r).unwrap());
        let c = unsafe {
            fmi2Instantiate(
                cname.as_ptr(),
                fmu_type,
                guid.as_ptr(),
                res.as_ref().map_or(null(), |r| r.as_ptr()),
                &*callbacks,
                0,
                1,
            )
        };
        assert!(!c.is_null(), "instantiation failed: {:?}", messages(name));
        Fmu {
            c,
            name: name.to_string(),
            _callbacks: callbacks,
        }
    }

    /// Instantiated, set up at t = 0 and initialized.
    pub fn ready(name: &str) -> Fmu {
        let fmu = Fmu::instantiate(name, None);
        assert_eq!(fmu.setup(0.0, None), OK);
        assert_eq!(fmu.enter_init(), OK);
        assert_eq!(fmu.exit_init(), OK);
        fmu
    }

    pub fn setup(&self, start: f64, stop: Option<f64>) -> fmi2Status {
        unsafe {
            fmi2SetupExperiment(
                self.c,
                0,
                0.0,
                start,
                stop.is_some() as i32,
                stop.unwrap_or(0.0),
            )
        }
    }
    pub fn enter_init(&self) -> fmi2Status {
        unsafe { fmi2EnterInitializationMode(self.c) }
    }
    pub fn exit_init(&self) -> fmi2Status {
        unsafe { fmi2ExitInitializationMode(self.c) }
    }
    pub fn set(&self, name: &str, value: f64) -> fmi2Status {
        unsafe { fmi2SetReal(self.c, &vr(name), 1, &value) }
    }
    pub fn set_many(&self, names: &[&str], values: &[f64]) -> fmi2Status {
        let vrs: Vec<u32> = names.iter().map(|n| vr(n)).collect();
        unsafe { fmi2SetReal(self.c, vrs.as_ptr(), vrs.len(), values.as_ptr()) }
    }
    pub fn get(&self, name: &str) -> f64 {
        let mut v = f64::NAN;
        let status = unsafe { fmi2GetReal(self.c, &vr(name), 1, &mut v) };
        assert_eq!(status, OK, "get {name}: {:?}", messages(&self.name));
        v
    }
    pub fn try_get(&self, name: &str) -> (fmi2Status, f64) {
        let mut v = f64::NAN;
        let status = unsafe { fmi2GetReal(self.c, &vr(name), 1, &mut v) };
        (status, v)
    }
    pub fn step(&self, t: f64, h: f64) -> fmi2Status {
        unsafe { fmi2DoStep(self.c, t, h, 1) }
    }
    pub fn set_bool(&self, vr: u32, value: bool) -> fmi2Status {
        let v = value as fmi2Boolean;
        unsafe { fmi2SetBoolean(self.c, &vr, 1, &v) }
    }
    pub fn set_string(&self, vr: u32, value: &str) -> fmi2Status {
        let s = CString::new(value).unwrap();
        let p = s.as_ptr();
        unsafe { fmi2SetString(self.c, &vr, 1, &p) }
    }
    pub fn get_string(&self, vr: u32) -> String {
        let mut p: fmi2String = null();
        assert_eq!(unsafe { fmi2GetString(self.c, &vr, 1, &mut p) }, OK);
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
    pub fn outputs(&self) -> [f64; 3] {
        [self.get("Fx"), self.get("Fy"), self.get("Mz")]
    }
    pub fn messages(&self) -> Vec<(log::Level, String)> {
        messages(&self.name)
    }
    /// The messages containing every one of `words`.
    pub fn logged(&self, words: &[&str]) -> Vec<String> {
        self.messages()
            .into_iter()
            .map(|(_, m)| m)
            .filter(|m| words.iter().all(|w| m.contains(w)))
            .collect()
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        unsafe { fmi2FreeInstance(self.c) };
    }
}

/// The pure model's outputs (the crate is checked against the reference CSV).
pub fn model(fz: f64, alpha: f64, kappa: f64, gamma: f64) -> [f64; 3] {
    let o = mf87::evaluate(
        &mf87::Params::paper_table(),
        &mf87::Inputs {
            fz,
            alpha,
            kappa,
            gamma,
        },
        mf87::SignConvention::Paper,
    );
    [o.fx, o.fy, o.mz]
}

/// A `file:` URI for an absolute path of this system, percent-encoded as an importer writes
/// it: `file:///tmp/my%20fmu` on POSIX systems, `file:///C:/my%20fmu` on Windows.
pub fn file_uri(path: &std::path::Path) -> String {
    let text = path.to_str().expect("a UTF-8 path");
    let slashed = if cfg!(windows) {
        format!("/{}", text.replace('\\', "/"))
    } else {
        text.to_string()
    };
    let mut uri = String::from("file://");
    for byte in slashed.bytes() {
        match byte {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'.' | b'_' | b'~' | b':' => {
                uri.push(char::from(byte))
            }
            _ => uri.push_str(&format!("%{byte:02X}")),
        }
    }
    uri
}
