//! The FMI 3.0 C ABI called in-process: every call in every state (allowed, or an error the
//! FMU logs, never a crash), the reference model in both interfaces, the coefficient arrays,
//! exact directional and adjoint derivatives, FMU states, calls across the two standards.
// Every unsafe block here is a host call into the C ABI with live, correctly sized arguments
// (or deliberately NULL ones): the safety argument is the same for all.
#![allow(clippy::undocumented_unsafe_blocks)]

mod support;

use std::ffi::{CStr, CString, c_void};
use std::ptr::{null, null_mut};
use std::sync::Mutex;

use fmi_sys::fmi3::*;
use pacejka87_tire::exports3::*;
use pacejka87_tire::variables::{INSTANTIATION_TOKEN, VARIABLES_3};
use support::model;

const OK: fmi3Status = fmi3Status_fmi3OK;
const ERROR: fmi3Status = fmi3Status_fmi3Error;

/// The messages one instance logged: (status, message).
type Log = Mutex<Vec<(fmi3Status, String)>>;

unsafe extern "C" fn log_message(
    env: fmi3InstanceEnvironment,
    status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    let log = unsafe { &*(env as *const Log) };
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    log.lock().unwrap().push((status, text));
}

fn vr(name: &str) -> u32 {
    VARIABLES_3
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .vr
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Interface {
    CoSimulation,
    ModelExchange,
}

/// An FMI 3.0 instance with its own log.
struct Fmu {
    i: fmi3Instance,
    log: Box<Log>,
    time: f64,
}

impl Fmu {
    fn new(interface: Interface) -> Fmu {
        let log: Box<Log> = Box::default();
        let env = &*log as *const Log as *mut c_void;
        let name = c"fmi3-test";
        let token = CString::new(INSTANTIATION_TOKEN).unwrap();
        let i = unsafe {
            match interface {
                Interface::CoSimulation => fmi3InstantiateCoSimulation(
                    name.as_ptr(),
                    token.as_ptr(),
                    null(),
                    false,
                    true,
                    false,
                    false,
                    null(),
                    0,
                    env,
                    Some(log_message),
                    None,
                ),
                Interface::ModelExchange => fmi3InstantiateModelExchange(
                    name.as_ptr(),
                    token.as_ptr(),
                    null(),
                    false,
                    true,
                    env,
                    Some(log_message),
                ),
            }
        };
        assert!(!i.is_null());
        Fmu { i, log, time: 0.0 }
    }

    fn initialize(&self) -> fmi3Status {
        let s = unsafe { fmi3EnterInitializationMode(self.i, false, 0.0, 0.0, false, 0.0) };
        if s != OK {
            return s;
        }
        unsafe { fmi3ExitInitializationMode(self.i) }
    }

    fn set(&self, names: &[&str], values: &[f64]) -> fmi3Status {
        let vrs: Vec<u32> = names.iter().map(|n| vr(n)).collect();
        unsafe {
            fmi3SetFloat64(
                self.i,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        }
    }

    fn get(&self, names: &[&str]) -> (fmi3Status, Vec<f64>) {
        let vrs: Vec<u32> = names.iter().map(|n| vr(n)).collect();
        let mut values = vec![f64::NAN; names.len()];
        let s = unsafe {
            fmi3GetFloat64(
                self.i,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        };
        (s, values)
    }

    fn step(&mut self, h: f64) -> fmi3Status {
        let (mut event, mut terminate, mut early, mut last) = (true, true, true, f64::NAN);
        let s = unsafe {
            fmi3DoStep(
                self.i,
                self.time,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        };
        if s == OK {
            assert!(!event && !terminate && !early);
            self.time += h;
            assert_eq!(last, self.time);
        }
        s
    }

    fn messages(&self) -> Vec<(fmi3Status, String)> {
        self.log.lock().unwrap().clone()
    }

    fn derivatives(
        &self,
        adjoint: bool,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
    ) -> (fmi3Status, Vec<f64>) {
        let n = if adjoint {
            knowns.len()
        } else {
            unknowns.len()
        };
        let mut out = vec![f64::NAN; n];
        let f = if adjoint {
            fmi3GetAdjointDerivative
        } else {
            fmi3GetDirectionalDerivative
        };
        let s = unsafe {
            f(
                self.i,
                unknowns.as_ptr(),
                unknowns.len(),
                knowns.as_ptr(),
                knowns.len(),
                seed.as_ptr(),
                seed.len(),
                out.as_mut_ptr(),
                out.len(),
            )
        };
        (s, out)
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        unsafe { fmi3FreeInstance(self.i) };
    }
}

/// A small deterministic generator of uniform numbers in [lo, hi).
struct Lcg(u64);

impl Lcg {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

const INPUTS: [&str; 4] = ["Fz", "alpha", "kappa", "gamma"];
const OUTPUTS: [&str; 3] = ["Fx", "Fy", "Mz"];

#[test]
fn both_interfaces_reproduce_the_model() {
    let mut rng = Lcg(1);
    let mut cs = Fmu::new(Interface::CoSimulation);
    let me = Fmu::new(Interface::ModelExchange);
    assert_eq!(cs.initialize(), OK);
    assert_eq!(me.initialize(), OK);
    assert_eq!(unsafe { fmi3EnterContinuousTimeMode(me.i) }, OK);
    for _ in 0..500 {
        let x = [
            rng.uniform(300.0, 9000.0),
            rng.uniform(-1.5, 1.5),
            rng.uniform(-0.95, 0.95),
            rng.uniform(-0.17, 0.17),
        ];
        let expected = model(x[0], x[1], x[2], x[3]);
        assert_eq!(cs.set(&INPUTS, &x), OK);
        assert_eq!(cs.step(0.01), OK);
        assert_eq!(cs.get(&OUTPUTS), (OK, expected.to_vec()));
        assert_eq!(me.set(&INPUTS, &x), OK);
        assert_eq!(me.get(&OUTPUTS), (OK, expected.to_vec()));
    }
}

#[test]
fn coefficient_arrays_are_the_coefficient_tables() {
    let fmu = Fmu::new(Interface::CoSimulation);
    let params = mf87::Params::paper_table();
    for (name, channel) in [
        ("Fy_coefficients", mf87::Channel::Fy),
        ("Mz_coefficients", mf87::Channel::Mz),
        ("Fx_coefficients", mf87::Channel::Fx),
    ] {
        let n = mf87::Params::coefficient_names(channel).len();
        let table: Vec<f64> = (0..n)
            .map(|i| params.coefficient(channel, i).unwrap())
            .collect();
        let mut values = vec![0.0; n];
        let s = unsafe { fmi3GetFloat64(fmu.i, &vr(name), 1, values.as_mut_ptr(), n) };
        assert_eq!((s, values), (OK, table), "{name}");
        // One value short of the array is an error naming both counts.
        let mut short = vec![0.0; n - 1];
        let s = unsafe { fmi3GetFloat64(fmu.i, &vr(name), 1, short.as_mut_ptr(), n - 1) };
        assert_eq!(s, ERROR);
    }
    assert!(fmu.messages().iter().any(|(s, m)| *s == ERROR
        && m.contains("nValues = 8, but the variables asked for hold 9 values")));
    // A changed table changes the forces as the model says.
    let mut changed = params.clone();
    *changed.coefficient_mut(mf87::Channel::Fx, 0).unwrap() = 1.5;
    *changed.coefficient_mut(mf87::Channel::Fx, 3).unwrap() = 60.0;
    let fx: Vec<f64> = (0..9)
        .map(|i| changed.coefficient(mf87::Channel::Fx, i).unwrap())
        .collect();
    let s = unsafe { fmi3SetFloat64(fmu.i, &vr("Fx_coefficients"), 1, fx.as_ptr(), 9) };
    assert_eq!(s, OK);
    assert_eq!(fmu.initialize(), OK);
    assert_eq!(fmu.set(&["Fz", "kappa"], &[3500.0, 0.05]), OK);
    let mut fmu = fmu;
    assert_eq!(fmu.step(0.01), OK);
    let expected = mf87::evaluate(
        &changed,
        &mf87::Inputs {
            fz: 3500.0,
            alpha: 0.0,
            kappa: 0.05,
            gamma: 0.0,
        },
        mf87::SignConvention::Paper,
    );
    assert_eq!(fmu.get(&["Fx"]), (OK, vec![expected.fx]));
    // Fixed after initialization: refused, the value kept.
    let s = unsafe { fmi3SetFloat64(fmu.i, &vr("Fx_coefficients"), 1, fx.as_ptr(), 9) };
    assert_eq!(s, ERROR);
}

#[test]
fn adjoint_is_the_transposed_directional_derivative() {
    // Knowns: the inputs and the relaxation states; unknowns: the outputs and state rates.
    let fmu = Fmu::new(Interface::ModelExchange);
    assert_eq!(fmu.initialize(), OK);
    assert_eq!(unsafe { fmi3EnterContinuousTimeMode(fmu.i) }, OK);
    let knowns: Vec<u32> = [
        "Fz", "alpha", "kappa", "gamma", "vx", "p", "T_tread", "lag_Fx", "lag_Fy", "lag_Mz",
    ]
    .iter()
    .map(|n| vr(n))
    .collect();
    let unknowns: Vec<u32> = [
        "Fx",
        "Fy",
        "Mz",
        "der(lag_Fx)",
        "der(lag_Fy)",
        "der(lag_Mz)",
    ]
    .iter()
    .map(|n| vr(n))
    .collect();
    let mut rng = Lcg(7);
    for _ in 0..1000 {
        let x = [
            rng.uniform(300.0, 9000.0),
            rng.uniform(-1.5, 1.5),
            rng.uniform(-0.95, 0.95),
            rng.uniform(-0.17, 0.17),
        ];
        assert_eq!(fmu.set(&INPUTS, &x), OK);
        // The Jacobian by columns (directional, unit seeds) and by rows (adjoint).
        let columns: Vec<Vec<f64>> = (0..knowns.len())
            .map(|j| {
                let mut seed = vec![0.0; knowns.len()];
                seed[j] = 1.0;
                let (s, c) = fmu.derivatives(false, &unknowns, &knowns, &seed);
                assert_eq!(s, OK);
                c
            })
            .collect();
        for i in 0..unknowns.len() {
            let mut seed = vec![0.0; unknowns.len()];
            seed[i] = 1.0;
            let (s, row) = fmu.derivatives(true, &unknowns, &knowns, &seed);
            assert_eq!(s, OK);
            for j in 0..knowns.len() {
                assert_eq!(
                    row[j], columns[j][i],
                    "d unknown {i} / d known {j} at {x:?}"
                );
            }
        }
        // vᵀ (J u) = (vᵀ J) u for random seeds.
        let u: Vec<f64> = (0..knowns.len()).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let v: Vec<f64> = (0..unknowns.len())
            .map(|_| rng.uniform(-1.0, 1.0))
            .collect();
        let (_, ju) = fmu.derivatives(false, &unknowns, &knowns, &u);
        let (_, vj) = fmu.derivatives(true, &unknowns, &knowns, &v);
        let lhs: f64 = v.iter().zip(&ju).map(|(a, b)| a * b).sum();
        let rhs: f64 = vj.iter().zip(&u).map(|(a, b)| a * b).sum();
        let scale: f64 = v.iter().zip(&ju).map(|(a, b)| (a * b).abs()).sum::<f64>() + 1e-12;
        assert!((lhs - rhs).abs() <= 1e-13 * scale, "{lhs} {rhs}");
    }
    // Mismatched counts and non-scalar knowns are errors.
    let (s, _) = fmu.derivatives(true, &unknowns, &knowns, &[1.0; 3]);
    assert_eq!(s, ERROR);
    let (s, _) = fmu.derivatives(false, &unknowns[..1], &[vr("Fy_coefficients")], &[1.0]);
    assert_eq!(s, ERROR);
    // Messages in FMI 3.0's words: a non-finite seed, an input as an unknown.
    let (s, _) = fmu.derivatives(false, &unknowns[..1], &knowns[..1], &[f64::NAN]);
    assert_eq!(s, ERROR);
    let (s, _) = fmu.derivatives(false, &knowns[..1], &knowns[..1], &[1.0]);
    assert_eq!(s, ERROR);
    let messages = fmu.messages();
    assert!(
        messages
            .iter()
            .any(|(_, m)| m.contains("nSeed = 3 and nSensitivity = 10")),
        "{messages:?}"
    );
    assert!(
        messages
            .iter()
            .any(|(_, m)| m.contains("knowns[0] = 100 (Fy_coefficients) is not a scalar")),
        "{messages:?}"
    );
    assert!(
        messages
            .iter()
            .any(|(_, m)| m.contains("fmi3GetDirectionalDerivative: seed for Fz is NaN")),
        "{messages:?}"
    );
    assert!(
        messages
            .iter()
            .any(|(_, m)| m.contains("unknowns 0 (Fz) is neither an output nor a state derivative")),
        "{messages:?}"
    );
}

/// Drives a fresh instance of `interface` into the state `state` names.
fn instance_in(interface: Interface, state: &str) -> Fmu {
    let mut fmu = Fmu::new(interface);
    let ok = |s: fmi3Status| assert_eq!(s, OK, "reaching {state}");
    match state {
        "Instantiated" => {}
        "InitializationMode" => {
            ok(unsafe { fmi3EnterInitializationMode(fmu.i, false, 0.0, 0.0, false, 0.0) })
        }
        "StepMode" | "EventMode" => ok(fmu.initialize()),
        "ContinuousTimeMode" => {
            ok(fmu.initialize());
            ok(unsafe { fmi3EnterContinuousTimeMode(fmu.i) });
        }
        "Terminated" => {
            ok(fmu.initialize());
            if interface == Interface::CoSimulation {
                ok(fmu.step(0.01));
            }
            ok(unsafe { fmi3Terminate(fmu.i) });
        }
        other => panic!("{other}"),
    }
    fmu.time = 0.0;
    fmu
}

/// Every fmi3 function that takes an instance, called once with well-formed arguments; its
/// name and status.
fn call_everything(fmu: &Fmu, which: usize) -> (&'static str, fmi3Status) {
    let i = fmu.i;
    let (fz, fy, lag, coeffs) = (vr("Fz"), vr("Fy"), vr("lag_Fy"), vr("Fy_coefficients"));
    let iso = vr("isoSignConvention");
    let file = vr("parameterFile");
    // Output buffers as raw pointers to heap memory the calls may write.
    let x: *mut f64 = Box::leak(Box::new([0.0f64; 14])).as_mut_ptr();
    let b: *mut bool = Box::leak(Box::new(false));
    let s: *mut fmi3String = Box::leak(Box::new(null()));
    let n: *mut usize = Box::leak(Box::new(0usize));
    let flag: *mut bool = Box::leak(Box::new(false));
    let t: *mut f64 = Box::leak(Box::new(0.0f64));
    let slot: *mut fmi3FMUState = Box::leak(Box::new(null_mut()));
    let empty = c"";
    let category = [c"logEvents".as_ptr()];
    unsafe {
        let calls: [(&'static str, &dyn Fn() -> fmi3Status); 40] = [
            ("SetDebugLogging", &|| {
                fmi3SetDebugLogging(i, true, 1, category.as_ptr())
            }),
            ("EnterInitializationMode", &|| {
                fmi3EnterInitializationMode(i, false, 0.0, 0.0, false, 0.0)
            }),
            ("ExitInitializationMode", &|| fmi3ExitInitializationMode(i)),
            ("GetFloat64 input", &|| fmi3GetFloat64(i, &fz, 1, x, 1)),
            ("GetFloat64 output", &|| fmi3GetFloat64(i, &fy, 1, x, 1)),
            ("GetFloat64 array", &|| fmi3GetFloat64(i, &coeffs, 1, x, 14)),
            ("SetFloat64 input", &|| {
                fmi3SetFloat64(i, &fz, 1, [4100.0].as_ptr(), 1)
            }),
            ("SetFloat64 array", &|| fmi3SetFloat64(i, &coeffs, 1, x, 14)),
            ("GetBoolean", &|| fmi3GetBoolean(i, &iso, 1, b, 1)),
            ("SetBoolean", &|| {
                fmi3SetBoolean(i, &iso, 1, [false].as_ptr(), 1)
            }),
            ("GetString", &|| fmi3GetString(i, &file, 1, s, 1)),
            ("SetString", &|| {
                fmi3SetString(i, &file, 1, [empty.as_ptr()].as_ptr(), 1)
            }),
            ("GetInt32 none", &|| {
                fmi3GetInt32(i, null(), 0, null_mut(), 0)
            }),
            ("GetFMUState", &|| {
                let r = fmi3GetFMUState(i, slot);
                if r == OK {
                    fmi3FreeFMUState(i, slot);
                }
                r
            }),
            ("GetDirectionalDerivative", &|| {
                fmi3GetDirectionalDerivative(i, &fy, 1, &fz, 1, [1.0].as_ptr(), 1, x, 1)
            }),
            ("GetAdjointDerivative", &|| {
                fmi3GetAdjointDerivative(i, &fy, 1, &fz, 1, [1.0].as_ptr(), 1, x, 1)
            }),
            ("EnterConfigurationMode", &|| fmi3EnterConfigurationMode(i)),
            ("ExitConfigurationMode", &|| fmi3ExitConfigurationMode(i)),
            ("GetClock none", &|| fmi3GetClock(i, null(), 0, null_mut())),
            ("GetIntervalDecimal none", &|| {
                fmi3GetIntervalDecimal(i, null(), 0, null_mut(), null_mut())
            }),
            ("EvaluateDiscreteStates", &|| fmi3EvaluateDiscreteStates(i)),
            ("UpdateDiscreteStates", &|| {
                fmi3UpdateDiscreteStates(i, flag, flag, flag, flag, flag, t)
            }),
            ("EnterEventMode", &|| fmi3EnterEventMode(i)),
            ("EnterContinuousTimeMode", &|| {
                fmi3EnterContinuousTimeMode(i)
            }),
            ("CompletedIntegratorStep", &|| {
                fmi3CompletedIntegratorStep(i, true, flag, flag)
            }),
            ("SetTime", &|| fmi3SetTime(i, 0.0)),
            ("SetContinuousStates", &|| {
                fmi3SetContinuousStates(i, [0.0; 3].as_ptr(), 3)
            }),
            ("GetContinuousStateDerivatives", &|| {
                fmi3GetContinuousStateDerivatives(i, x, 3)
            }),
            ("GetEventIndicators", &|| {
                fmi3GetEventIndicators(i, null_mut(), 0)
            }),
            ("GetContinuousStates", &|| fmi3GetContinuousStates(i, x, 3)),
            ("GetNominalsOfContinuousStates", &|| {
                fmi3GetNominalsOfContinuousStates(i, x, 3)
            }),
            ("GetNumberOfEventIndicators", &|| {
                fmi3GetNumberOfEventIndicators(i, n)
            }),
            ("GetNumberOfContinuousStates", &|| {
                fmi3GetNumberOfContinuousStates(i, n)
            }),
            ("EnterStepMode", &|| fmi3EnterStepMode(i)),
            ("GetOutputDerivatives", &|| {
                fmi3GetOutputDerivatives(i, &fy, 1, [1].as_ptr(), x, 1)
            }),
            ("DoStep", &|| {
                fmi3DoStep(i, 0.0, 0.01, true, flag, flag, flag, t)
            }),
            ("ActivateModelPartition", &|| {
                fmi3ActivateModelPartition(i, 0, 0.0)
            }),
            ("GetFloat64 state", &|| fmi3GetFloat64(i, &lag, 1, x, 1)),
            ("Terminate", &|| fmi3Terminate(i)),
            ("Reset", &|| fmi3Reset(i)),
        ];
        let (name, f) = calls[which];
        (name, f())
    }
}

/// What the standard (as the Modelica Association's Reference FMUs implement its state
/// machine) allows, for the calls whose answer does not depend on arguments: `None` when
/// only the FMU's own rules decide (e.g. an output is calculated, a parameter fixed).
fn allowed(name: &str, interface: Interface, state: &str) -> Option<bool> {
    let cs = interface == Interface::CoSimulation;
    let me = !cs;
    Some(match name {
        "SetDebugLogging" => true,
        "GetNumberOfEventIndicators" | "GetNumberOfContinuousStates" => me,
        "EnterInitializationMode" => state == "Instantiated",
        "ExitInitializationMode" => state == "InitializationMode",
        "GetFloat64 input" | "GetBoolean" | "GetString" | "GetFloat64 array" => true,
        "GetInt32 none" | "GetClock none" | "GetIntervalDecimal none" => true,
        "SetFloat64 input" => true,
        "GetDirectionalDerivative" | "GetAdjointDerivative" => state != "Instantiated",
        "ExitConfigurationMode" | "ActivateModelPartition" | "EnterStepMode" => false,
        "EnterContinuousTimeMode" => me && state == "EventMode",
        "CompletedIntegratorStep" | "SetContinuousStates" => me && state == "ContinuousTimeMode",
        "SetTime" => me && matches!(state, "EventMode" | "ContinuousTimeMode"),
        "EnterEventMode" => me && state == "ContinuousTimeMode",
        "UpdateDiscreteStates" | "EvaluateDiscreteStates" => state == "EventMode",
        "GetContinuousStateDerivatives" | "GetEventIndicators" | "GetContinuousStates" => {
            me && matches!(
                state,
                "InitializationMode" | "EventMode" | "ContinuousTimeMode" | "Terminated"
            )
        }
        "DoStep" => cs && state == "StepMode",
        "GetOutputDerivatives" => false,
        "Terminate" => matches!(state, "StepMode" | "EventMode" | "ContinuousTimeMode"),
        "Reset" | "GetFMUState" => true,
        _ => return None,
    })
}

#[test]
fn every_call_in_every_state_is_allowed_or_a_logged_error() {
    let states: [(Interface, &[&str]); 2] = [
        (
            Interface::CoSimulation,
            &[
                "Instantiated",
                "InitializationMode",
                "StepMode",
                "Terminated",
            ],
        ),
        (
            Interface::ModelExchange,
            &[
                "Instantiated",
                "InitializationMode",
                "EventMode",
                "ContinuousTimeMode",
                "Terminated",
            ],
        ),
    ];
    let mut checked = 0;
    for (interface, names) in states {
        for state in names {
            for which in 0..40 {
                let fmu = instance_in(interface, state);
                let before = fmu.messages().len();
                let (name, status) = call_everything(&fmu, which);
                assert!(
                    status == OK || status == ERROR,
                    "{name} in {interface:?} {state}: status {status}"
                );
                let errors: Vec<String> = fmu.messages()[before..]
                    .iter()
                    .filter(|(s, _)| *s == ERROR)
                    .map(|(_, m)| m.clone())
                    .collect();
                let function = format!("fmi3{}", name.split(' ').next().unwrap());
                if status == ERROR {
                    assert!(
                        errors.iter().any(|m| m.starts_with(&function)),
                        "{name} in {interface:?} {state}: an error without a message naming \
                         {function}: {errors:?}"
                    );
                } else {
                    assert!(errors.is_empty(), "{name}: OK but logged {errors:?}");
                }
                if let Some(expected) = allowed(name, interface, state) {
                    assert_eq!(
                        status == OK,
                        expected,
                        "{name} in {interface:?} {state}: status {status}, {errors:?}"
                    );
                }
                // Whatever happened, the instance resets and runs again.
                let mut fmu = fmu;
                assert_eq!(unsafe { fmi3Reset(fmu.i) }, OK);
                fmu.time = 0.0;
                assert_eq!(
                    fmu.initialize(),
                    OK,
                    "{name} in {state}: {:?}",
                    fmu.messages()
                );
                if interface == Interface::CoSimulation {
                    assert_eq!(fmu.step(0.01), OK);
                }
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 9 * 40);
}

#[test]
fn calls_across_the_standards_and_null_instances_are_errors() {
    let fmu = Fmu::new(Interface::CoSimulation);
    assert_eq!(fmu.initialize(), OK);
    let vr = [vr("Fy")];
    let mut value = [0.0];
    let s =
        unsafe { pacejka87_tire::exports::fmi2GetReal(fmu.i, vr.as_ptr(), 1, value.as_mut_ptr()) };
    assert_eq!(s, ERROR);
    assert!(fmu.messages().iter().any(|(_, m)| m.contains(
        "fmi2GetReal: this instance was made by fmi3Instantiate...: it takes only fmi3 functions"
    )));
    unsafe {
        assert_eq!(
            fmi3DoStep(
                null_mut(),
                0.0,
                0.1,
                true,
                null_mut(),
                null_mut(),
                null_mut(),
                null_mut()
            ),
            ERROR
        );
        assert_eq!(
            fmi3GetFloat64(null_mut(), vr.as_ptr(), 1, value.as_mut_ptr(), 1),
            ERROR
        );
        assert_eq!(fmi3Terminate(null_mut()), ERROR);
        fmi3FreeInstance(null_mut());
    }
    // The flags of fmi3DoStep may be NULL: the step is taken.
    let s = unsafe {
        fmi3DoStep(
            fmu.i,
            0.0,
            0.1,
            true,
            null_mut(),
            null_mut(),
            null_mut(),
            null_mut(),
        )
    };
    assert_eq!(s, OK);
}

#[test]
fn states_round_trip_through_serialization() {
    let mut a = Fmu::new(Interface::CoSimulation);
    assert_eq!(a.initialize(), OK);
    assert_eq!(a.set(&INPUTS, &[4500.0, 0.1, 0.05, 0.01]), OK);
    assert_eq!(a.step(0.01), OK);
    let saved = a.get(&OUTPUTS);
    let mut state: fmi3FMUState = null_mut();
    assert_eq!(unsafe { fmi3GetFMUState(a.i, &mut state) }, OK);
    let mut size = 0;
    assert_eq!(
        unsafe { fmi3SerializedFMUStateSize(a.i, state, &mut size) },
        OK
    );
    let mut bytes = vec![0u8; size];
    assert_eq!(
        unsafe { fmi3SerializeFMUState(a.i, state, bytes.as_mut_ptr(), size) },
        OK
    );
    let b = Fmu::new(Interface::CoSimulation);
    let mut restored: fmi3FMUState = null_mut();
    assert_eq!(
        unsafe { fmi3DeserializeFMUState(b.i, bytes.as_ptr(), size, &mut restored) },
        OK
    );
    assert_eq!(unsafe { fmi3SetFMUState(b.i, restored) }, OK);
    assert_eq!(b.get(&OUTPUTS), saved);
    assert_eq!(b.get(&["time"]), (OK, vec![0.01]));
    // A state of another instance is refused without being read.
    assert_eq!(unsafe { fmi3SetFMUState(b.i, state) }, ERROR);
    let mut garbage = 0xdead_bee0usize as fmi3FMUState;
    assert_eq!(unsafe { fmi3FreeFMUState(b.i, &mut garbage) }, ERROR);
    assert_eq!(unsafe { fmi3FreeFMUState(a.i, &mut state) }, OK);
    assert_eq!(unsafe { fmi3FreeFMUState(b.i, &mut restored) }, OK);
    assert!(state.is_null() && restored.is_null());
}
