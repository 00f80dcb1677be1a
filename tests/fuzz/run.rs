//! Runs one sequence against the loaded FMU as a host would and checks every call: the
//! status is one of fmi2Status (fmi3Status for FMI 3.0 calls), every Real or Float64 handed
//! out with OK or Warning is finite, a refusal of a live instance is logged (unless it has no
//! logger, which FMI 3.0 allows), a call of the other standard than the one that made the
//! instance is refused, no array is written past its end. The FMI 3.0 calls are in run3.rs;
//! the FMU-state calls, FreeInstance, SetDebugLogging and the string arguments of both
//! standards are made here. Crashes, hangs and output on stderr are seen by the parent
//! process (main.rs).

use std::ffi::{CString, c_char, c_void};
use std::path::{Path, PathBuf};
use std::ptr::{null, null_mut};

use fmi_sys::fmi2::*;
use pacejka87_tire::variables::GUID;

use crate::fmi::{self, Fmi, Fmi3, StateFunctions};
use crate::seq::{Arr, Corrupt, INSTANCES, Op, STATE_SLOTS, StateRef, Str, Time};
use crate::seq3::Vars3;

/// Parameter files of a run: good ones (the committed fits and the paper's table) first,
/// then hostile ones, in a fresh folder that is also the instances' resource folder.
pub struct Files {
    pub dir: PathBuf,
    /// Names in `dir`, or absolute paths / URIs, as passed to `parameterFile`.
    pub names: Vec<String>,
    pub good: usize,
}

impl Files {
    pub fn prepare(dir: &Path) -> Files {
        let _ = std::fs::remove_dir_all(dir);
        std::fs::create_dir_all(dir).unwrap();
        let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
        let fits = repo.join("crates/mf87/tests/data/fits");
        let mut names = Vec::new();
        let mut sources: Vec<PathBuf> = vec![repo.join("crates/mf87/data/pacejka87.json")];
        let mut fit_paths: Vec<PathBuf> = std::fs::read_dir(&fits)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "json"))
            .collect();
        fit_paths.sort();
        sources.extend(fit_paths);
        let texts: Vec<String> = sources
            .iter()
            .map(|p| std::fs::read_to_string(p).unwrap())
            .collect();
        for (i, text) in texts.iter().enumerate() {
            let name = format!("good{i}.json");
            std::fs::write(dir.join(&name), text).unwrap();
            names.push(name);
        }
        // The same files by absolute path and by file: URI.
        names.push(dir.join("good1.json").display().to_string());
        names.push(format!("file://{}", dir.join("good2.json").display()));
        let good = names.len();
        // Hostile: every number of a fit replaced in turn by extreme values, relaxation
        // lengths at the edges, broken syntax, binary, special files.
        let with_relaxation = texts
            .iter()
            .find(|t| t.contains("sigma_m"))
            .cloned()
            .unwrap_or_default();
        let mut hostile: Vec<(String, Vec<u8>)> = Vec::new();
        for sigma in ["5e-324", "-0.3", "1e308", "0.0009", "0.001", "0", "-0"] {
            hostile.push((
                format!("sigma_{sigma}.json"),
                replace_field(&with_relaxation, "sigma_m", sigma).into_bytes(),
            ));
        }
        for (field, value) in [
            ("gamma_max_deg", "-10"),
            ("gamma_max_deg", "1e-300"),
            ("fz_max_N", "-1"),
            ("fz_max_N", "1e308"),
            ("C", "1e308"),
            ("a2", "5e-324"),
            ("a13", "1e9"),
            ("pressure_kPa", "-1"),
            ("speed_mps", "0"),
            ("speed_max_mps", "1e308"),
            ("speed_min_mps", "200"),
            ("temperature_degC", "1e308"),
        ] {
            for (i, text) in texts.iter().enumerate() {
                if text.contains(&format!("\"{field}\"")) && i % 2 == 0 {
                    hostile.push((
                        format!("{field}_{value}_{i}.json"),
                        replace_field(text, field, value).into_bytes(),
                    ));
                }
            }
        }
        let half = texts[0].len() / 2;
        hostile.push((
            "truncated.json".into(),
            texts[0].as_bytes()[..half].to_vec(),
        ));
        hostile.push(("garbage.json".into(), vec![0xff, 0x00, 0xfe, b'{', 0x80]));
        hostile.push(("empty.json".into(), Vec::new()));
        hostile.push(("array.json".into(), b"[1, 2, 3]".to_vec()));
        hostile.push(("deep.json".into(), "[".repeat(100_000).into_bytes()));
        for (name, bytes) in &hostile {
            std::fs::write(dir.join(name), bytes).unwrap();
            names.push(name.clone());
        }
        // Larger than the limit (sparse), a directory, a FIFO, a device.
        let big = std::fs::File::create(dir.join("big.json")).unwrap();
        big.set_len((1 << 20) + 1).unwrap();
        names.push("big.json".into());
        std::fs::create_dir_all(dir.join("folder.json")).unwrap();
        names.push("folder.json".into());
        let fifo = CString::new(dir.join("fifo.json").display().to_string()).unwrap();
        // SAFETY: a C string path.
        unsafe { libc::mkfifo(fifo.as_ptr(), 0o600) };
        names.push("fifo.json".into());
        names.push("/dev/zero".into());
        names.push("missing.json".into());
        Files {
            dir: dir.to_path_buf(),
            names,
            good,
        }
    }
}

/// `text` with the value of every field `field` replaced by `value`.
fn replace_field(text: &str, field: &str, value: &str) -> String {
    let key = format!("\"{field}\":");
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(&key) {
        out.push_str(&rest[..i + key.len()]);
        rest = &rest[i + key.len()..];
        let end = rest.find([',', '\n', '}']).unwrap_or(rest.len());
        out.push(' ');
        out.push_str(value);
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// Something wrong a sequence showed (crashes, hangs and stderr are found by the parent).
#[derive(Debug, Clone)]
pub struct Finding {
    pub call: usize,
    pub what: String,
}

/// Guard elements after every array the FMU writes: they must stay untouched.
pub(crate) const GUARD: usize = 4;
pub(crate) const CANARY: f64 = -1.234_567_890_123e-77;
/// Bytes the FMU must not write (after an array's end, or values it did not set).
pub(crate) const FILL: u8 = 0xA5;

/// The host: instances, FMU-state slots, serialized buffers, what it checks.
pub struct Host<'a> {
    pub(crate) fmi: &'a Fmi,
    pub(crate) fmi3: &'a Fmi3,
    pub(crate) v3: &'static Vars3,
    pub(crate) files: &'a Files,
    pub(crate) verbose: bool,
    /// Instances of either standard (the same pointer type, `void *`).
    pub(crate) instances: [fmi2Component; INSTANCES],
    /// Whether the instance in a slot was made by an fmi3Instantiate function.
    pub(crate) made_by_fmi3: [bool; INSTANCES],
    /// Whether it was made without a logger (FMI 3.0's NULL `logMessage`): it cannot report.
    pub(crate) logless: [bool; INSTANCES],
    /// Whether it was made by fmi3InstantiateModelExchange (else co-simulation).
    pub(crate) model_exchange: [bool; INSTANCES],
    pub(crate) states: [fmi2FMUstate; STATE_SLOTS],
    pub(crate) stale: [fmi2FMUstate; STATE_SLOTS],
    pub(crate) buffers: Vec<Vec<u8>>,
    callbacks: Box<[fmi2CallbackFunctions; 4]>,
    pub(crate) names: Vec<CString>,
    pub(crate) resource_uri: CString,
    /// The resource folder as FMI 3.0 passes it: a path ending in a slash.
    pub(crate) resource_path: CString,
    pub findings: Vec<Finding>,
    call: usize,
    /// Per function: (calls returning OK, calls).
    counts: std::collections::BTreeMap<&'static str, (u64, u64)>,
}

/// C strings (or NULLs) and the array of their pointers that a call is given.
pub(crate) struct CStrings {
    _owned: Vec<Option<CString>>,
    pub ptrs: Vec<*const c_char>,
}

impl CStrings {
    pub(crate) fn new(owned: impl Iterator<Item = Option<CString>>) -> CStrings {
        let owned: Vec<Option<CString>> = owned.collect();
        // The strings' bytes stay where they are when `owned` moves.
        let ptrs = owned
            .iter()
            .map(|c| c.as_ref().map_or(null(), |c| c.as_ptr()))
            .collect();
        CStrings {
            _owned: owned,
            ptrs,
        }
    }
}

/// `p`, or NULL where `nulled` (the argument a call makes NULL, 0 for none) is `which`.
pub(crate) fn or_null<T>(nulled: u8, which: u8, p: *const T) -> *const T {
    if nulled == which { null() } else { p }
}

pub(crate) fn or_null_mut<T>(nulled: u8, which: u8, p: *mut T) -> *mut T {
    if nulled == which { null_mut() } else { p }
}

/// The garbage FMU state pointer: not NULL, not allocated by anyone.
pub(crate) const GARBAGE_STATE: usize = 0xdead_bee0;

impl<'a> Host<'a> {
    pub fn new(fmi: &'a Fmi, fmi3: &'a Fmi3, files: &'a Files, verbose: bool) -> Host<'a> {
        let good = fmi2CallbackFunctions {
            logger: Some(fmi_sys::fmi2::logger::callback_logger_handler),
            allocateMemory: Some(libc::calloc),
            freeMemory: Some(libc::free),
            stepFinished: None,
            componentEnvironment: null_mut(),
        };
        let callbacks = Box::new([
            good,
            fmi2CallbackFunctions {
                logger: None,
                ..good
            },
            fmi2CallbackFunctions {
                allocateMemory: None,
                ..good
            },
            good,
        ]);
        Host {
            fmi,
            fmi3,
            v3: Vars3::get(),
            files,
            verbose,
            instances: [null_mut(); INSTANCES],
            made_by_fmi3: [false; INSTANCES],
            logless: [false; INSTANCES],
            model_exchange: [false; INSTANCES],
            states: [null_mut(); STATE_SLOTS],
            stale: [null_mut(); STATE_SLOTS],
            buffers: vec![Vec::new(); STATE_SLOTS],
            callbacks,
            names: (0..INSTANCES)
                .map(|i| CString::new(format!("fuzz{i}")).unwrap())
                .collect(),
            resource_uri: CString::new(format!("file://{}/", files.dir.display())).unwrap(),
            resource_path: CString::new(format!("{}/", files.dir.display())).unwrap(),
            findings: Vec::new(),
            call: 0,
            counts: Default::default(),
        }
    }

    pub(crate) fn find(&mut self, what: String) {
        if self.verbose {
            println!("  FINDING: {what}");
        }
        self.findings.push(Finding {
            call: self.call,
            what,
        });
    }

    /// Runs the sequence, then frees every instance (the states it holds go with them).
    pub fn run(&mut self, ops: &[Op]) {
        for (i, op) in ops.iter().enumerate() {
            self.call = i;
            if self.verbose {
                println!("[{i}] {op:?}");
            }
            self.apply(op);
        }
        self.call = ops.len();
        for inst in 0..INSTANCES {
            self.free_slot(inst);
        }
        let _ = fmi::take_messages();
        self.oddities();
    }

    /// Frees the instance in slot `inst`, if any, with the FreeInstance of the standard that
    /// made it.
    pub(crate) fn free_slot(&mut self, inst: usize) {
        let c = std::mem::replace(&mut self.instances[inst], null_mut());
        if !c.is_null() {
            // SAFETY: a live instance of ours, freed once.
            unsafe {
                if self.made_by_fmi3[inst] {
                    (self.fmi3.fmi3FreeInstance)(c)
                } else {
                    (self.fmi.fmi2FreeInstance)(c)
                }
            };
        }
    }

    /// FreeInstance of either standard (`name`). It frees an instance of the other standard
    /// too (it has no status to refuse with): the slot is empty after it.
    ///
    /// # Safety
    /// `free` is the FMU's function of that name.
    pub(crate) unsafe fn free_instance(
        &mut self,
        inst: usize,
        name: &'static str,
        free: unsafe extern "C" fn(fmi2Component),
    ) {
        self.count_ok(name, !self.c(inst).is_null());
        // SAFETY: a live or NULL instance.
        unsafe { free(self.c(inst)) };
        self.instances[inst] = null_mut();
        let _ = fmi::take_messages();
        self.oddities();
    }

    /// The instance name an instantiation passes: 0 the slot's, 1 empty, 2 NULL.
    pub(crate) fn instance_name(&self, inst: usize, name: u8) -> *const c_char {
        match name {
            0 => self.names[inst].as_ptr(),
            1 => c"".as_ptr(),
            _ => null(),
        }
    }

    /// The resource folder as a plain path without the trailing slash.
    pub(crate) fn resource_folder(&self) -> CString {
        CString::new(self.files.dir.display().to_string()).unwrap()
    }

    /// Keeps what the instantiation `function` returned in slot `inst`.
    pub(crate) fn keep_instance(
        &mut self,
        inst: usize,
        function: &'static str,
        c: fmi2Component,
        fmi3: bool,
        logless: bool,
    ) {
        self.instances[inst] = c;
        self.made_by_fmi3[inst] = fmi3;
        self.logless[inst] = logless;
        self.count_ok(function, !c.is_null());
    }

    /// SetDebugLogging of either standard (`name`, called through `call` with the instance and
    /// the categories' count and array): its status.
    pub(crate) fn debug_logging(
        &mut self,
        name: &'static str,
        inst: usize,
        categories: &[Option<&str>],
        arr: Arr,
        call: impl FnOnce(fmi2Component, usize, *const *const c_char) -> fmi2Status,
    ) -> fmi2Status {
        let owned = categories
            .iter()
            .map(|c| c.map(|c| CString::new(c).unwrap()));
        let strings = CStrings::new(owned);
        let p = if arr == Arr::Ok {
            strings.ptrs.as_ptr()
        } else {
            null()
        };
        let s = call(self.c(inst), strings.ptrs.len(), p);
        self.status(name, Some(inst), s)
    }

    /// The strings a SetString of either standard passes.
    pub(crate) fn strings(&self, values: &[Str]) -> CStrings {
        let names = &self.files.names;
        CStrings::new(values.iter().map(|v| match v {
            Str::Null => None,
            Str::File(i) => Some(CString::new(names[i % names.len()].clone()).unwrap()),
            Str::Text(t) => Some(CString::new(t.clone()).unwrap()),
            Str::NotUtf8 => Some(CString::new(vec![0xc3, 0x28, b'a']).unwrap()),
        }))
    }

    /// What the FMI 3.0 logger was sent that it should not have been.
    pub(crate) fn oddities(&mut self) {
        for odd in fmi::take_oddities() {
            self.find(odd);
        }
    }

    /// Checks a status of either standard (by the function's name): within the enum; an
    /// error of a live instance was logged (errors are logged whatever loggingOn says;
    /// warnings and discards follow it), unless the instance has no logger; a call given an
    /// instance of the other standard is an error.
    pub(crate) fn status(
        &mut self,
        name: &'static str,
        inst: Option<usize>,
        status: fmi2Status,
    ) -> fmi2Status {
        let messages = fmi::take_messages();
        self.oddities();
        let count = self.counts.entry(name).or_default();
        count.0 += u64::from(status == fmi2Status_fmi2OK);
        count.1 += 1;
        if self.verbose {
            println!("    -> {name} = {status}");
        }
        let fmi3 = name.starts_with("fmi3");
        let (last, standard) = if fmi3 {
            (4, "fmi3Status")
        } else {
            (5, "fmi2Status")
        };
        if !(0..=last).contains(&status) {
            self.find(format!("{name} returned {status}, not an {standard}"));
        }
        let live = inst.filter(|i| !self.instances[*i].is_null());
        if let Some(i) = live
            && status == fmi2Status_fmi2Error
            && !self.logless[i]
            && !messages
                .iter()
                .any(|(level, _)| *level == log::Level::Error)
        {
            self.find(format!("{name} returned {status} without a message"));
        }
        if let Some(i) = live
            && self.made_by_fmi3[i] != fmi3
            && status != fmi2Status_fmi2Error
        {
            let made = if self.made_by_fmi3[i] { "3.0" } else { "2.0" };
            self.find(format!(
                "{name} given an FMI {made} instance returned {status}, not an error"
            ));
        }
        if let Some(i) = live
            && fmi3
            && self.made_by_fmi3[i]
            && status != fmi2Status_fmi2Error
        {
            let me = self.model_exchange[i];
            let wrong = if me {
                crate::run3::CO_SIMULATION_ONLY.contains(&name)
            } else {
                crate::run3::MODEL_EXCHANGE_ONLY.contains(&name)
            };
            if wrong {
                let interface = if me {
                    "Model Exchange"
                } else {
                    "co-simulation"
                };
                self.find(format!(
                    "{name} given a {interface} instance returned {status}, not an error"
                ));
            }
        }
        status
    }

    /// Reals handed out: finite unless the call refused; the guard untouched.
    pub(crate) fn reals(
        &mut self,
        name: &'static str,
        status: fmi2Status,
        values: &[f64],
        n: usize,
    ) {
        self.past_end(name, n, "values", &values[n..], &CANARY);
        if status == fmi2Status_fmi2OK || status == fmi2Status_fmi2Warning {
            for (i, v) in values[..n].iter().enumerate() {
                // Untouched entries (the canary) are allowed: e.g. unknown references.
                if !v.is_finite() {
                    self.find(format!(
                        "{name} returned {v} at index {i} with status {status}"
                    ));
                }
            }
        }
    }

    pub(crate) fn c(&self, inst: usize) -> fmi2Component {
        self.instances[inst]
    }

    pub(crate) fn state(&self, r: StateRef) -> fmi2FMUstate {
        match r {
            StateRef::Slot(s) => self.states[s],
            StateRef::Stale(s) => self.stale[s],
            StateRef::Garbage => GARBAGE_STATE as fmi2FMUstate,
        }
    }

    fn apply(&mut self, op: &Op) {
        let f = self.fmi;
        // SAFETY (all calls below): arguments are live, correctly sized host memory, or NULL
        // on purpose; FMU states are NULL, ours, stale or the garbage pointer on purpose
        // (the FMU must refuse those without reading them); instances are live or NULL.
        unsafe {
            match op {
                Op::GetTypesPlatform => {
                    let s = (f.fmi2GetTypesPlatform)();
                    self.count_ok("fmi2GetTypesPlatform", !s.is_null());
                    if s.is_null() {
                        self.find("fmi2GetTypesPlatform returned NULL".into());
                    }
                }
                Op::GetVersion => {
                    let s = (f.fmi2GetVersion)();
                    self.count_ok("fmi2GetVersion", !s.is_null());
                    if s.is_null() || std::ffi::CStr::from_ptr(s).to_bytes() != b"2.0" {
                        self.find("fmi2GetVersion is not 2.0".into());
                    }
                }
                &Op::Instantiate {
                    inst,
                    fmu_type,
                    name,
                    guid,
                    resources,
                    callbacks,
                    logging,
                } => {
                    // The host frees first: an instance is never lost.
                    self.free_slot(inst);
                    let wrong = c"{00000000-0000-0000-0000-000000000000}";
                    let guid_c = CString::new(GUID).unwrap();
                    let garbage_uri = c"file://%s%n/\xff/nonexistent";
                    let plain = self.resource_folder();
                    let c = (f.fmi2Instantiate)(
                        self.instance_name(inst, name),
                        fmu_type as fmi2Type,
                        match guid {
                            0 => guid_c.as_ptr(),
                            1 => wrong.as_ptr(),
                            _ => null(),
                        },
                        match resources {
                            0 => self.resource_uri.as_ptr(),
                            1 => null(),
                            2 => garbage_uri.as_ptr(),
                            _ => plain.as_ptr(),
                        },
                        if callbacks == 3 {
                            null()
                        } else {
                            &self.callbacks[callbacks as usize]
                        },
                        0,
                        logging as fmi2Boolean,
                    );
                    let _ = fmi::take_messages();
                    if self.verbose {
                        println!("    -> fmi2Instantiate = {c:?}");
                    }
                    self.keep_instance(inst, "fmi2Instantiate", c, false, false);
                }
                &Op::FreeInstance { inst } => {
                    self.free_instance(inst, "fmi2FreeInstance", f.fmi2FreeInstance)
                }
                Op::SetDebugLogging {
                    inst,
                    on,
                    categories,
                    arr,
                } => {
                    self.debug_logging(
                        "fmi2SetDebugLogging",
                        *inst,
                        categories,
                        *arr,
                        |c, n, p| (f.fmi2SetDebugLogging)(c, *on as fmi2Boolean, n, p),
                    );
                }
                &Op::SetupExperiment {
                    inst,
                    tolerance,
                    start,
                    stop,
                } => {
                    let s = (f.fmi2SetupExperiment)(
                        self.c(inst),
                        tolerance.is_some() as fmi2Boolean,
                        tolerance.unwrap_or(0.0),
                        start,
                        stop.is_some() as fmi2Boolean,
                        stop.unwrap_or(0.0),
                    );
                    self.status("fmi2SetupExperiment", Some(inst), s);
                }
                &Op::EnterInitializationMode { inst } => {
                    let s = (f.fmi2EnterInitializationMode)(self.c(inst));
                    self.status("fmi2EnterInitializationMode", Some(inst), s);
                }
                &Op::ExitInitializationMode { inst } => {
                    let s = (f.fmi2ExitInitializationMode)(self.c(inst));
                    self.status("fmi2ExitInitializationMode", Some(inst), s);
                }
                &Op::Terminate { inst } => {
                    let s = (f.fmi2Terminate)(self.c(inst));
                    self.status("fmi2Terminate", Some(inst), s);
                }
                &Op::Reset { inst } => {
                    let s = (f.fmi2Reset)(self.c(inst));
                    self.status("fmi2Reset", Some(inst), s);
                }
                Op::GetReal { inst, vrs, arr } => {
                    let n = vrs.len();
                    let mut values = vec![CANARY; n + GUARD];
                    let s = (f.fmi2GetReal)(
                        self.c(*inst),
                        arr.ptr(Arr::Null1, vrs.as_ptr()),
                        n,
                        arr.ptr_mut(Arr::Null2, values.as_mut_ptr()),
                    );
                    let s = self.status("fmi2GetReal", Some(*inst), s);
                    self.reals_allowing_canary("fmi2GetReal", s, &values, n);
                }
                Op::GetInteger { inst, vrs, arr } => {
                    let mut values = vec![0i32; vrs.len()];
                    let s = (f.fmi2GetInteger)(
                        self.c(*inst),
                        arr.ptr(Arr::Null1, vrs.as_ptr()),
                        vrs.len(),
                        arr.ptr_mut(Arr::Null2, values.as_mut_ptr()),
                    );
                    self.status("fmi2GetInteger", Some(*inst), s);
                }
                Op::GetBoolean { inst, vrs, arr } => {
                    let mut values = vec![7i32; vrs.len()];
                    let s = (f.fmi2GetBoolean)(
                        self.c(*inst),
                        arr.ptr(Arr::Null1, vrs.as_ptr()),
                        vrs.len(),
                        arr.ptr_mut(Arr::Null2, values.as_mut_ptr()),
                    );
                    self.status("fmi2GetBoolean", Some(*inst), s);
                }
                Op::GetString { inst, vrs, arr } => {
                    let mut values = vec![null::<c_char>(); vrs.len()];
                    let s = (f.fmi2GetString)(
                        self.c(*inst),
                        arr.ptr(Arr::Null1, vrs.as_ptr()),
                        vrs.len(),
                        arr.ptr_mut(Arr::Null2, values.as_mut_ptr()),
                    );
                    let s = self.status("fmi2GetString", Some(*inst), s);
                    if s == fmi2Status_fmi2OK {
                        // Read them: they must be valid C strings.
                        let total: usize = values
                            .iter()
                            .filter(|p| !p.is_null())
                            .map(|p| std::ffi::CStr::from_ptr(*p).to_bytes().len())
                            .sum();
                        std::hint::black_box(total);
                    }
                }
                Op::SetReal {
                    inst,
                    vrs,
                    values,
                    arr,
                } => {
                    let s = (f.fmi2SetReal)(
                        self.c(*inst),
                        arr.ptr(Arr::Null1, vrs.as_ptr()),
                        vrs.len(),
                        arr.ptr(Arr::Null2, values.as_ptr()),
                    );
                    self.status("fmi2SetReal", Some(*inst), s);
                }
                Op::SetInteger {
                    inst,
                    vrs,
                    values,
                    arr,
                } => {
                    let s = (f.fmi2SetInteger)(
                        self.c(*inst),
                        arr.ptr(Arr::Null1, vrs.as_ptr()),
                        vrs.len(),
                        arr.ptr(Arr::Null2, values.as_ptr()),
                    );
                    self.status("fmi2SetInteger", Some(*inst), s);
                }
                Op::SetBoolean {
                    inst,
                    vrs,
                    values,
                    arr,
                } => {
                    let s = (f.fmi2SetBoolean)(
                        self.c(*inst),
                        arr.ptr(Arr::Null1, vrs.as_ptr()),
                        vrs.len(),
                        arr.ptr(Arr::Null2, values.as_ptr()),
                    );
                    self.status("fmi2SetBoolean", Some(*inst), s);
                }
                Op::SetString {
                    inst,
                    vrs,
                    values,
                    arr,
                } => {
                    let ptrs = self.strings(values);
                    let ptrs = &ptrs.ptrs;
                    let s = (f.fmi2SetString)(
                        self.c(*inst),
                        arr.ptr(Arr::Null1, vrs.as_ptr()),
                        vrs.len(),
                        arr.ptr(Arr::Null2, ptrs.as_ptr()),
                    );
                    self.status("fmi2SetString", Some(*inst), s);
                }
                &Op::GetFMUstate {
                    inst,
                    slot,
                    null_slot,
                } => self.get_state(&f.states(), inst, slot, null_slot),
                &Op::SetFMUstate { inst, state } => self.set_state(&f.states(), inst, state),
                &Op::FreeFMUstate {
                    inst,
                    state,
                    null_slot,
                } => self.free_state(&f.states(), inst, state, null_slot),
                &Op::SerializedFMUstateSize {
                    inst,
                    state,
                    null_size,
                } => self.state_size(&f.states(), inst, state, null_size),
                &Op::SerializeFMUstate {
                    inst,
                    state,
                    buffer,
                    size_delta,
                    null,
                } => self.serialize(&f.states(), inst, state, buffer, size_delta, null),
                Op::DeSerializeFMUstate {
                    inst,
                    buffer,
                    corrupt,
                    slot,
                    arr,
                } => self.deserialize(&f.states(), *inst, *buffer, corrupt, *slot, *arr),
                Op::GetDirectionalDerivative {
                    inst,
                    unknown,
                    known,
                    dv,
                    null: which_null,
                } => {
                    let n = unknown.len();
                    let mut out = vec![CANARY; n + GUARD];
                    let null = *which_null;
                    let s = (f.fmi2GetDirectionalDerivative)(
                        self.c(*inst),
                        or_null(null, 1, unknown.as_ptr()),
                        n,
                        or_null(null, 2, known.as_ptr()),
                        known.len(),
                        or_null(null, 3, dv.as_ptr()),
                        or_null_mut(null, 4, out.as_mut_ptr()),
                    );
                    let s = self.status("fmi2GetDirectionalDerivative", Some(*inst), s);
                    self.reals_allowing_canary("fmi2GetDirectionalDerivative", s, &out, n);
                }
                &Op::SetRealInputDerivatives { inst } => {
                    let (vr, order, value) = (0u32, 1i32, 1.0f64);
                    let s = (f.fmi2SetRealInputDerivatives)(self.c(inst), &vr, 1, &order, &value);
                    self.status("fmi2SetRealInputDerivatives", Some(inst), s);
                }
                &Op::GetRealOutputDerivatives { inst } => {
                    let (vr, order) = (4u32, 1i32);
                    let mut value = [CANARY; 1 + GUARD];
                    let s = (f.fmi2GetRealOutputDerivatives)(
                        self.c(inst),
                        &vr,
                        1,
                        &order,
                        value.as_mut_ptr(),
                    );
                    let s = self.status("fmi2GetRealOutputDerivatives", Some(inst), s);
                    self.reals("fmi2GetRealOutputDerivatives", s, &value, 1);
                }
                &Op::DoStep { inst, t, h } => {
                    let t = self.time(inst, t);
                    let s = (f.fmi2DoStep)(self.c(inst), t, h, 0);
                    self.status("fmi2DoStep", Some(inst), s);
                }
                &Op::CancelStep { inst } => {
                    let s = (f.fmi2CancelStep)(self.c(inst));
                    self.status("fmi2CancelStep", Some(inst), s);
                }
                &Op::GetStatus {
                    inst,
                    which,
                    kind,
                    null: null_value,
                } => {
                    let c = self.c(inst);
                    let mut real = [CANARY; 1 + GUARD];
                    let mut int = 0i32;
                    let mut string: fmi2String = null();
                    let mut status: fmi2Status = 0;
                    let (name, s) = match which {
                        0 => (
                            "fmi2GetStatus",
                            (f.fmi2GetStatus)(
                                c,
                                kind as u32,
                                if null_value { null_mut() } else { &mut status },
                            ),
                        ),
                        1 => (
                            "fmi2GetRealStatus",
                            (f.fmi2GetRealStatus)(
                                c,
                                kind as u32,
                                if null_value {
                                    null_mut()
                                } else {
                                    real.as_mut_ptr()
                                },
                            ),
                        ),
                        2 => (
                            "fmi2GetIntegerStatus",
                            (f.fmi2GetIntegerStatus)(
                                c,
                                kind as u32,
                                if null_value { null_mut() } else { &mut int },
                            ),
                        ),
                        3 => (
                            "fmi2GetBooleanStatus",
                            (f.fmi2GetBooleanStatus)(
                                c,
                                kind as u32,
                                if null_value { null_mut() } else { &mut int },
                            ),
                        ),
                        _ => (
                            "fmi2GetStringStatus",
                            (f.fmi2GetStringStatus)(
                                c,
                                kind as u32,
                                if null_value { null_mut() } else { &mut string },
                            ),
                        ),
                    };
                    let s = self.status(name, Some(inst), s);
                    if which == 1 && !null_value {
                        self.reals_allowing_canary(name, s, &real, 1);
                    }
                }
                &Op::EnterEventMode { inst } => {
                    let s = (f.fmi2EnterEventMode)(self.c(inst));
                    self.status("fmi2EnterEventMode", Some(inst), s);
                }
                &Op::NewDiscreteStates { inst, null } => {
                    let mut info = fmi2EventInfo {
                        nextEventTime: CANARY,
                        ..Default::default()
                    };
                    let s = (f.fmi2NewDiscreteStates)(
                        self.c(inst),
                        if null { null_mut() } else { &mut info },
                    );
                    let s = self.status("fmi2NewDiscreteStates", Some(inst), s);
                    if s == fmi2Status_fmi2OK
                        && info.nextEventTimeDefined != 0
                        && !info.nextEventTime.is_finite()
                    {
                        self.find("fmi2NewDiscreteStates: nextEventTime not finite".into());
                    }
                }
                &Op::EnterContinuousTimeMode { inst } => {
                    let s = (f.fmi2EnterContinuousTimeMode)(self.c(inst));
                    self.status("fmi2EnterContinuousTimeMode", Some(inst), s);
                }
                &Op::CompletedIntegratorStep { inst, null } => {
                    let (mut a, mut b) = (0, 0);
                    let s = (f.fmi2CompletedIntegratorStep)(
                        self.c(inst),
                        1,
                        if null { null_mut() } else { &mut a },
                        &mut b,
                    );
                    self.status("fmi2CompletedIntegratorStep", Some(inst), s);
                }
                &Op::SetTime { inst, t } => {
                    let t = self.time(inst, t);
                    let s = (f.fmi2SetTime)(self.c(inst), t);
                    self.status("fmi2SetTime", Some(inst), s);
                }
                Op::SetContinuousStates {
                    inst,
                    x,
                    null: null_x,
                } => {
                    let s = (f.fmi2SetContinuousStates)(
                        self.c(*inst),
                        if *null_x { null() } else { x.as_ptr() },
                        x.len(),
                    );
                    self.status("fmi2SetContinuousStates", Some(*inst), s);
                }
                &Op::GetContinuousStates { inst, n, null } => self.get_array(
                    inst,
                    n,
                    null,
                    "fmi2GetContinuousStates",
                    f.fmi2GetContinuousStates,
                ),
                &Op::GetDerivatives { inst, n, null } => {
                    self.get_array(inst, n, null, "fmi2GetDerivatives", f.fmi2GetDerivatives)
                }
                &Op::GetNominalsOfContinuousStates { inst, n, null } => self.get_array(
                    inst,
                    n,
                    null,
                    "fmi2GetNominalsOfContinuousStates",
                    f.fmi2GetNominalsOfContinuousStates,
                ),
                &Op::GetEventIndicators { inst, n, null } => self.get_array(
                    inst,
                    n,
                    null,
                    "fmi2GetEventIndicators",
                    f.fmi2GetEventIndicators,
                ),
                Op::Fmi3(op) => self.apply3(op),
            }
        }
    }

    /// GetFMUstate of either standard into slot `slot` (or a NULL slot).
    ///
    /// # Safety
    /// As [`Host::apply`] (for these six FMU-state calls); `f` the FMU's functions.
    pub(crate) unsafe fn get_state<B>(
        &mut self,
        f: &StateFunctions<B>,
        inst: usize,
        slot: usize,
        null_slot: bool,
    ) {
        let (name, get) = f.get;
        let p = if null_slot {
            null_mut()
        } else {
            &mut self.states[slot]
        };
        // SAFETY: the caller's.
        let s = unsafe { get(self.c(inst), p) };
        self.status(name, Some(inst), s);
    }

    pub(crate) unsafe fn set_state<B>(&mut self, f: &StateFunctions<B>, inst: usize, r: StateRef) {
        let (name, set) = f.set;
        // SAFETY: the caller's.
        let s = unsafe { set(self.c(inst), self.state(r)) };
        self.status(name, Some(inst), s);
    }

    /// FreeFMUstate; a state it freed is forgotten in every slot and remembered as stale.
    pub(crate) unsafe fn free_state<B>(
        &mut self,
        f: &StateFunctions<B>,
        inst: usize,
        r: StateRef,
        null_slot: bool,
    ) {
        let (name, free) = f.free;
        let mut ptr = self.state(r);
        let before = ptr;
        let p = if null_slot { null_mut() } else { &mut ptr };
        // SAFETY: the caller's.
        let s = unsafe { free(self.c(inst), p) };
        let s = self.status(name, Some(inst), s);
        if s == fmi2Status_fmi2OK && !before.is_null() && !null_slot {
            if !ptr.is_null() {
                self.find(format!("{name} left the slot non-NULL"));
            }
            for i in 0..STATE_SLOTS {
                if self.states[i] == before {
                    self.states[i] = null_mut();
                    self.stale[i] = before;
                }
            }
        }
    }

    pub(crate) unsafe fn state_size<B>(
        &mut self,
        f: &StateFunctions<B>,
        inst: usize,
        r: StateRef,
        null_size: bool,
    ) {
        let (name, size_of) = f.size;
        let mut size = usize::MAX;
        let p = if null_size { null_mut() } else { &mut size };
        // SAFETY: the caller's.
        let s = unsafe { size_of(self.c(inst), self.state(r), p) };
        self.status(name, Some(inst), s);
    }

    /// SerializeFMUstate into a buffer of the size the FMU gives, off by `size_delta`; kept
    /// in buffer `buffer` when OK. Nothing written past the size.
    pub(crate) unsafe fn serialize<B>(
        &mut self,
        f: &StateFunctions<B>,
        inst: usize,
        r: StateRef,
        buffer: usize,
        size_delta: i8,
        null: bool,
    ) {
        let ((size_name, size_of), (name, serialize)) = (f.size, f.serialize);
        let c = self.c(inst);
        let ptr = self.state(r);
        let mut size = 0usize;
        // SAFETY: the caller's.
        let s = unsafe { size_of(c, ptr, &mut size) };
        self.status(size_name, Some(inst), s);
        let size = size.saturating_add_signed(size_delta as isize).min(1 << 24);
        let mut bytes = vec![FILL; size + 16];
        let p = if null { null_mut() } else { bytes.as_mut_ptr() };
        // SAFETY: the caller's; `size` bytes and more.
        let s = unsafe { serialize(c, ptr, p.cast(), size) };
        let s = self.status(name, Some(inst), s);
        self.past_end(name, size, "bytes", &bytes[size..], &FILL);
        if s == fmi2Status_fmi2OK {
            bytes.truncate(size);
            self.buffers[buffer] = bytes;
        }
    }

    /// DeSerializeFMUstate of buffer `buffer`, damaged as `corrupt` says, into slot `slot`.
    pub(crate) unsafe fn deserialize<B>(
        &mut self,
        f: &StateFunctions<B>,
        inst: usize,
        buffer: usize,
        corrupt: &Corrupt,
        slot: usize,
        arr: Arr,
    ) {
        let (name, deserialize) = f.deserialize;
        let bytes = corrupted(&self.buffers[buffer], corrupt);
        let c = self.c(inst);
        let (p, n) = (arr.ptr(Arr::Null1, bytes.as_ptr()), bytes.len());
        let state = arr.ptr_mut(Arr::Null2, &mut self.states[slot]);
        // SAFETY: the caller's.
        let s = unsafe { deserialize(c, p.cast(), n, state) };
        self.status(name, Some(inst), s);
    }

    /// A write past the `n` elements (`what`) a call was given: what follows them (`past`)
    /// is still `fill`.
    pub(crate) fn past_end<'v, T: PartialEq + 'v>(
        &mut self,
        name: &str,
        n: usize,
        what: &str,
        past: impl IntoIterator<Item = &'v T>,
        fill: &T,
    ) {
        if past.into_iter().any(|v| v != fill) {
            self.find(format!("{name} wrote past the {n} {what} it was given"));
        }
    }

    /// As [`Host::reals`], but an entry the FMU did not write (still the canary) is fine.
    pub(crate) fn reals_allowing_canary(
        &mut self,
        name: &'static str,
        status: fmi2Status,
        values: &[f64],
        n: usize,
    ) {
        let mut seen: Vec<f64> = values.to_vec();
        for v in &mut seen[..n] {
            if v.to_bits() == CANARY.to_bits() {
                *v = 0.0;
            }
        }
        self.reals(name, status, &seen, n);
    }

    /// # Safety
    /// `function` is the FMU's function of that name.
    unsafe fn get_array(
        &mut self,
        inst: usize,
        n: usize,
        null: bool,
        name: &'static str,
        function: unsafe extern "C" fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status,
    ) {
        let mut values = vec![CANARY; n + GUARD];
        // SAFETY: `n` values plus the guard, or NULL on purpose.
        let s = unsafe {
            function(
                self.c(inst),
                if null {
                    null_mut()
                } else {
                    values.as_mut_ptr()
                },
                n,
            )
        };
        let s = self.status(name, Some(inst), s);
        self.reals_allowing_canary(name, s, &values, n);
    }

    /// The time to pass: the instance's own (as it reports it) or the given value.
    fn time(&mut self, inst: usize, t: Time) -> f64 {
        match t {
            Time::Value(v) => v,
            Time::Current => {
                let mut now = 0.0;
                // SAFETY: a live or NULL instance, a writable value.
                let s = unsafe {
                    (self.fmi.fmi2GetRealStatus)(
                        self.c(inst),
                        fmi2StatusKind_fmi2LastSuccessfulTime,
                        &mut now,
                    )
                };
                let _ = fmi::take_messages();
                if s == fmi2Status_fmi2OK && !now.is_finite() {
                    self.find(format!(
                        "fmi2GetRealStatus(LastSuccessfulTime) = {now} with fmi2OK"
                    ));
                }
                if s == fmi2Status_fmi2OK { now } else { 0.0 }
            }
        }
    }

    /// Calls per FMI function: (returned fmi2OK, all).
    pub fn call_counts(&self) -> &std::collections::BTreeMap<&'static str, (u64, u64)> {
        &self.counts
    }

    pub(crate) fn count_ok(&mut self, name: &'static str, ok: bool) {
        let count = self.counts.entry(name).or_default();
        count.0 += u64::from(ok);
        count.1 += 1;
    }
}

/// `bytes` damaged as `how` says.
pub(crate) fn corrupted(bytes: &[u8], how: &Corrupt) -> Vec<u8> {
    let at = |permille: u16| bytes.len() * permille as usize / 1000;
    match how {
        Corrupt::None => bytes.to_vec(),
        Corrupt::Truncate(p) => bytes[..at(*p)].to_vec(),
        Corrupt::Flip { at: p, mask } => {
            let mut b = bytes.to_vec();
            if !b.is_empty() {
                let i = at(*p).min(b.len() - 1);
                b[i] ^= mask;
            }
            b
        }
        Corrupt::Number { nth, with } => replace_nth(bytes, *nth, with, |c| {
            c.is_ascii_digit() || c == b'-' || c == b'.' || c == b'e' || c == b'E' || c == b'+'
        }),
        Corrupt::Word { nth, with } => {
            let text = String::from_utf8_lossy(bytes);
            let quoted: Vec<(usize, usize)> = text
                .match_indices('"')
                .map(|(i, _)| i)
                .collect::<Vec<_>>()
                .chunks(2)
                .filter(|c| c.len() == 2)
                .map(|c| (c[0], c[1] + 1))
                .collect();
            match quoted.get(*nth as usize % quoted.len().max(1)) {
                Some(&(a, b)) => {
                    let mut out = text[..a].to_string();
                    out.push_str(with);
                    out.push_str(&text[b..]);
                    out.into_bytes()
                }
                None => bytes.to_vec(),
            }
        }
        Corrupt::Append(tail) => {
            let mut b = bytes.to_vec();
            b.extend(tail.as_bytes());
            b
        }
        Corrupt::Empty => Vec::new(),
    }
}

/// Replaces the `nth` run of bytes matching `part` (after the header lines) with `with`.
fn replace_nth(bytes: &[u8], nth: u16, with: &str, part: impl Fn(u8) -> bool) -> Vec<u8> {
    let start = bytes
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .nth(1)
        .map_or(0, |(i, _)| i + 1);
    let mut runs = Vec::new();
    let mut i = start;
    while i < bytes.len() {
        if part(bytes[i]) && (bytes[i].is_ascii_digit() || bytes[i] == b'-') {
            let a = i;
            while i < bytes.len() && part(bytes[i]) {
                i += 1;
            }
            runs.push((a, i));
        } else {
            i += 1;
        }
    }
    if runs.is_empty() {
        return bytes.to_vec();
    }
    let (a, b) = runs[nth as usize % runs.len()];
    let mut out = bytes[..a].to_vec();
    out.extend(with.as_bytes());
    out.extend(&bytes[b..]);
    out
}

#[allow(dead_code)]
fn _unused(_: *mut c_void) {}
