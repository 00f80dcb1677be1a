//! The FMU's C ABI called in-process with normal and hostile call sequences.
// Every unsafe block here is a host call into the C ABI with live, correctly sized arguments
// (or deliberately NULL ones): the safety argument is the same for all.
#![allow(clippy::undocumented_unsafe_blocks)]

mod support;

use std::ffi::CString;
use std::ptr::{null, null_mut};

use fmi_sys::fmi2::*;
use pacejka87_tire::exports::*;
use pacejka87_tire::variables::GUID;
use support::*;

const ISO: u32 = 0; // Boolean isoSignConvention
const PARAMETER_FILE: u32 = 0; // String parameterFile

fn repo_root() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn co_simulation_reproduces_the_reference_values() {
    let fmu = Fmu::ready("reference");
    // docs/errata.md at 4 kN: Fy(5 deg, 0) = 3389.600985 N, Mz(5 deg, 2 deg) = -29.02908832 N.m,
    // Fx(10 %) = 4234.444513 N.
    assert_eq!(
        fmu.set_many(
            &["Fz", "alpha", "kappa", "gamma"],
            &[4000.0, 5f64.to_radians(), 0.1, 0.0]
        ),
        OK
    );
    assert_eq!(fmu.step(0.0, 0.01), OK);
    let [fx, fy, _] = fmu.outputs();
    assert!(
        (fy - 3389.600985).abs() < 1e-5 && (fx - 4234.444513).abs() < 1e-5,
        "{fx} {fy}"
    );
    assert_eq!(fmu.set("gamma", 2f64.to_radians()), OK);
    assert_eq!(fmu.step(0.01, 0.01), OK);
    assert!((fmu.get("Mz") - -29.02908832).abs() < 1e-7);
    // A sweep: every step equals the pure model.
    let mut t = 0.02;
    for k in -20..=20 {
        let (alpha, kappa, gamma) = (k as f64 * 0.01, k as f64 * 0.02, k as f64 * 0.004);
        fmu.set_many(
            &["Fz", "alpha", "kappa", "gamma"],
            &[3000.0, alpha, kappa, gamma],
        );
        assert_eq!(fmu.step(t, 0.01), OK);
        t += 0.01;
        assert_eq!(fmu.outputs(), model(3000.0, alpha, kappa, gamma));
    }
}

#[test]
fn inputs_show_in_outputs_after_the_step() {
    let fmu = Fmu::ready("delay");
    let before = fmu.outputs();
    assert_eq!(
        before,
        model(4000.0, 0.0, 0.0, 0.0),
        "start values Fz = 4000 N, rest 0"
    );
    assert_eq!(fmu.set("alpha", 0.05), OK);
    assert_eq!(fmu.outputs(), before, "no change before fmi2DoStep");
    assert_eq!(fmu.step(0.0, 0.1), OK);
    assert_eq!(fmu.outputs(), model(4000.0, 0.05, 0.0, 0.0));
}

#[test]
fn non_finite_inputs_and_parameters_are_rejected_and_the_old_value_kept() {
    let fmu = Fmu::instantiate("nonfinite", None);
    assert_eq!(fmu.set("Fy_a2", f64::INFINITY), ERROR);
    assert_eq!(
        fmu.logged(&["Fy_a2 = inf", "not a finite number", "keeps its value 1011"])
            .len(),
        1
    );
    assert_eq!(fmu.setup(0.0, None), OK);
    assert_eq!(fmu.enter_init(), OK);
    assert_eq!(fmu.exit_init(), OK);
    assert_eq!(fmu.get("Fy_a2"), 1011.0);
    assert_eq!(fmu.set("alpha", 0.03), OK);
    assert_eq!(fmu.step(0.0, 0.01), OK);
    let good = fmu.outputs();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(fmu.set("alpha", bad), ERROR);
        assert_eq!(fmu.get("alpha"), 0.03);
    }
    assert_eq!(
        fmu.logged(&["alpha = NaN", "keeps its value 0.03"]).len(),
        1
    );
    // The instance is still usable and outputs stay finite and unchanged.
    assert_eq!(fmu.step(0.01, 0.01), OK);
    assert_eq!(fmu.outputs(), good);
    // In a multi-value call the valid values are kept, the bad one rejected.
    assert_eq!(
        fmu.set_many(&["Fz", "alpha", "kappa"], &[3000.0, f64::NAN, 0.05]),
        ERROR
    );
    assert_eq!(
        (fmu.get("Fz"), fmu.get("alpha"), fmu.get("kappa")),
        (3000.0, 0.03, 0.05)
    );
}

#[test]
fn out_of_range_inputs_are_clamped_with_one_warning() {
    let fmu = Fmu::ready("clamp");
    assert_eq!(fmu.set("alpha", 2.0), WARNING);
    assert_eq!(fmu.step(0.0, 0.01), OK);
    assert_eq!(
        fmu.outputs(),
        model(4000.0, std::f64::consts::FRAC_PI_2, 0.0, 0.0)
    );
    assert_eq!(fmu.set("alpha", 2.5), WARNING);
    let warnings = fmu.logged(&["alpha", "outside the valid range"]);
    assert_eq!(warnings.len(), 1, "one warning per variable: {warnings:?}");
    assert!(warnings[0].contains(
        "alpha = 2 rad is outside the valid range [-1.5707963267948966, 1.5707963267948966] rad"
    ));
    assert!(warnings[0].contains("the model uses 1.5707963267948966 rad"));
    assert_eq!(fmu.set("kappa", -1.5), WARNING);
    assert_eq!(fmu.set("gamma", 0.5), WARNING);
    assert_eq!(fmu.set("Fz", 1e6), WARNING);
    assert_eq!(fmu.step(0.01, 0.01), OK);
    let gamma_max = fmu.get("gamma_max");
    assert_eq!(
        fmu.outputs(),
        model(10_000.0, std::f64::consts::FRAC_PI_2, -1.0, gamma_max)
    );
    for name in ["kappa", "gamma", "Fz"] {
        assert_eq!(
            fmu.logged(&[name, "outside the valid range"]).len(),
            1,
            "{name}"
        );
    }
    // Lifted wheel: negative load is valid and gives no force.
    assert_eq!(fmu.set("Fz", -100.0), OK);
    assert_eq!(fmu.step(0.02, 0.01), OK);
    assert_eq!(fmu.outputs(), [0.0; 3]);
}

#[test]
fn unknown_value_references_are_errors() {
    let fmu = Fmu::ready("unknown");
    let (vr, mut x, mut b, mut i) = (9999u32, 0.0, 0, 0);
    let mut s: fmi2String = null();
    unsafe {
        assert_eq!(fmi2SetReal(fmu.c, &vr, 1, &1.0), ERROR);
        assert_eq!(fmi2GetReal(fmu.c, &vr, 1, &mut x), ERROR);
        assert_eq!(fmi2GetBoolean(fmu.c, &vr, 1, &mut b), ERROR);
        assert_eq!(fmi2GetInteger(fmu.c, &vr, 1, &mut i), ERROR);
        assert_eq!(fmi2SetInteger(fmu.c, &vr, 1, &1), ERROR);
        assert_eq!(fmi2GetString(fmu.c, &vr, 1, &mut s), ERROR);
    }
    assert_eq!(fmu.logged(&["unknown Real value reference 9999"]).len(), 2);
    assert_eq!(
        fmu.logged(&["unknown Boolean value reference 9999"]).len(),
        1
    );
    assert_eq!(
        fmu.logged(&["unknown Integer value reference 9999"]).len(),
        2
    );
    // Outputs cannot be set.
    assert_eq!(fmu.set("Fy", 1.0), ERROR);
    assert_eq!(fmu.logged(&["Fy is an output"]).len(), 1);
}

#[test]
fn null_instance_is_an_error_everywhere() {
    let c = null_mut();
    let (vr, mut x, mut b, mut i, mut st) = (0u32, 0.0, 0, 0, OK);
    let mut s: fmi2String = null();
    let mut state: fmi2FMUstate = null_mut();
    let mut size = 0usize;
    unsafe {
        let statuses = [
            fmi2SetDebugLogging(c, 1, 0, null()),
            fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
            fmi2EnterInitializationMode(c),
            fmi2ExitInitializationMode(c),
            fmi2Terminate(c),
            fmi2Reset(c),
            fmi2GetReal(c, &vr, 1, &mut x),
            fmi2GetInteger(c, &vr, 1, &mut i),
            fmi2GetBoolean(c, &vr, 1, &mut b),
            fmi2GetString(c, &vr, 1, &mut s),
            fmi2SetReal(c, &vr, 1, &x),
            fmi2SetInteger(c, &vr, 1, &i),
            fmi2SetBoolean(c, &vr, 1, &b),
            fmi2SetString(c, &vr, 1, &s),
            fmi2GetFMUstate(c, &mut state),
            fmi2SetFMUstate(c, state),
            fmi2FreeFMUstate(c, &mut state),
            fmi2SerializedFMUstateSize(c, state, &mut size),
            fmi2SerializeFMUstate(c, state, null_mut(), 0),
            fmi2DeSerializeFMUstate(c, null(), 0, &mut state),
            fmi2GetDirectionalDerivative(c, null(), 0, null(), 0, null(), null_mut()),
            fmi2SetRealInputDerivatives(c, null(), 0, null(), null()),
            fmi2GetRealOutputDerivatives(c, null(), 0, null(), null_mut()),
            fmi2DoStep(c, 0.0, 0.1, 0),
            fmi2CancelStep(c),
            fmi2GetStatus(c, fmi2StatusKind_fmi2DoStepStatus, &mut st),
            fmi2GetRealStatus(c, fmi2StatusKind_fmi2LastSuccessfulTime, &mut x),
            fmi2GetIntegerStatus(c, fmi2StatusKind_fmi2DoStepStatus, &mut i),
            fmi2GetBooleanStatus(c, fmi2StatusKind_fmi2Terminated, &mut b),
            fmi2GetStringStatus(c, fmi2StatusKind_fmi2PendingStatus, &mut s),
        ];
        assert!(statuses.iter().all(|s| *s == ERROR), "{statuses:?}");
        fmi2FreeInstance(c); // a no-op, not a crash
    }
}

#[test]
fn null_arrays_are_errors_unless_empty() {
    let fmu = Fmu::ready("nullarrays");
    let vr = 0u32;
    let mut x = 0.0;
    unsafe {
        assert_eq!(fmi2GetReal(fmu.c, null(), 1, &mut x), ERROR);
        assert_eq!(fmi2GetReal(fmu.c, &vr, 1, null_mut()), ERROR);
        assert_eq!(fmi2SetReal(fmu.c, &vr, 2, null()), ERROR);
        assert_eq!(fmi2SetBoolean(fmu.c, null(), 3, null()), ERROR);
        assert_eq!(fmi2SetDebugLogging(fmu.c, 1, 2, null()), ERROR);
        // nvr == 0 with NULL arrays is legal.
        assert_eq!(fmi2GetReal(fmu.c, null(), 0, null_mut()), OK);
        assert_eq!(fmi2SetReal(fmu.c, null(), 0, null()), OK);
        assert_eq!(fmi2GetBoolean(fmu.c, null(), 0, null_mut()), OK);
        assert_eq!(fmi2GetString(fmu.c, null(), 0, null_mut()), OK);
        assert_eq!(fmi2SetString(fmu.c, null(), 0, null()), OK);
        assert_eq!(fmi2GetInteger(fmu.c, null(), 0, null_mut()), OK);
        assert_eq!(
            fmi2GetRealStatus(fmu.c, fmi2StatusKind_fmi2LastSuccessfulTime, null_mut()),
            ERROR
        );
    }
    assert_eq!(
        fmu.logged(&["vr or value is NULL but 1 values were announced"])
            .len(),
        2
    );
}

#[test]
fn calls_in_the_wrong_state_are_illegal_call_sequences() {
    let fmu = Fmu::instantiate("sequence", None);
    let mut x = 0.0;
    assert_eq!(fmu.step(0.0, 0.1), ERROR);
    assert_eq!(unsafe { fmi2GetReal(fmu.c, &vr("Fy"), 1, &mut x) }, ERROR);
    assert_eq!(fmu.exit_init(), ERROR);
    assert_eq!(unsafe { fmi2Terminate(fmu.c) }, ERROR);
    let illegal = fmu.logged(&["Illegal call sequence", "state Instantiated"]);
    assert_eq!(illegal.len(), 4, "{illegal:?}");
    assert!(illegal[0].starts_with("fmi2DoStep:"));
    assert_eq!(fmu.setup(0.0, Some(1.0)), OK);
    assert_eq!(fmu.enter_init(), OK);
    assert_eq!(fmu.setup(0.0, None), ERROR);
    assert_eq!(fmu.exit_init(), OK);
    assert_eq!(fmu.enter_init(), ERROR);
    assert_eq!(unsafe { fmi2Terminate(fmu.c) }, OK);
    assert_eq!(fmu.step(0.0, 0.1), ERROR);
    assert_eq!(fmu.set("alpha", 0.1), ERROR);
    assert_eq!(
        fmu.logged(&["fmi2SetReal: Illegal call sequence", "state Terminated"])
            .len(),
        1
    );
    // Outputs may still be read after termination.
    assert_eq!(fmu.try_get("Fy").0, OK);
}

#[test]
fn fixed_parameters_cannot_change_after_initialization() {
    let fmu = Fmu::ready("fixed");
    assert_eq!(fmu.set("Fy_a1", -20.0), ERROR);
    assert_eq!(fmu.get("Fy_a1"), -22.1);
    assert_eq!(
        fmu.logged(&["Fy_a1 is a fixed parameter", "state is StepComplete"])
            .len(),
        1
    );
    assert_eq!(fmu.set_bool(ISO, true), ERROR);
    assert_eq!(fmu.set_string(PARAMETER_FILE, "x.json"), ERROR);
    assert_eq!(
        fmu.logged(&["isoSignConvention is a fixed parameter"])
            .len(),
        1
    );
    assert_eq!(fmu.logged(&["parameterFile is a fixed parameter"]).len(), 1);
    // Inputs stay settable.
    assert_eq!(fmu.set("alpha", 0.1), OK);
}

fn instantiate_raw(
    name: Option<&str>,
    kind: fmi2Type,
    guid: Option<&str>,
    functions: Option<&fmi2CallbackFunctions>,
) -> fmi2Component {
    let name = name.map(|n| CString::new(n).unwrap());
    let guid = guid.map(|g| CString::new(g).unwrap());
    unsafe {
        fmi2Instantiate(
            name.as_ref().map_or(null(), |n| n.as_ptr()),
            kind,
            guid.as_ref().map_or(null(), |g| g.as_ptr()),
            null(),
            functions.map_or(null(), |f| f as *const _),
            0,
            0,
        )
    }
}

#[test]
fn instantiation_rejects_bad_arguments_with_a_message() {
    let cb = callbacks();
    let co = fmi2Type_fmi2CoSimulation;
    assert!(
        instantiate_raw(
            Some("badguid"),
            co,
            Some("{00000000-0000-0000-0000-000000000000}"),
            Some(&cb)
        )
        .is_null()
    );
    assert_eq!(messages("badguid").len(), 1);
    assert!(
        messages("badguid")[0]
            .1
            .contains("does not match this FMU's")
    );
    assert!(instantiate_raw(Some("noguid"), co, None, Some(&cb)).is_null());
    assert!(messages("noguid")[0].1.contains("fmuGUID is NULL"));
    assert!(instantiate_raw(Some("badtype"), 7, Some(GUID), Some(&cb)).is_null());
    assert!(messages("badtype")[0].1.contains("fmuType = 7 is neither"));
    assert!(instantiate_raw(None, co, Some(GUID), Some(&cb)).is_null());
    assert!(instantiate_raw(Some(""), co, Some(GUID), Some(&cb)).is_null());
    assert!(
        messages("")
            .iter()
            .any(|(_, m)| m.contains("instanceName must not be empty"))
    );
    assert!(instantiate_raw(Some("nofunctions"), co, Some(GUID), None).is_null());
    let no_logger = fmi2CallbackFunctions { logger: None, ..cb };
    assert!(instantiate_raw(Some("nologger"), co, Some(GUID), Some(&no_logger)).is_null());
    let no_alloc = fmi2CallbackFunctions {
        allocateMemory: None,
        ..cb
    };
    assert!(instantiate_raw(Some("noalloc"), co, Some(GUID), Some(&no_alloc)).is_null());
    assert!(
        messages("noalloc")[0]
            .1
            .contains("allocateMemory and freeMemory")
    );
}

#[test]
fn communication_points_and_step_sizes_are_checked() {
    let fmu = Fmu::instantiate("steps", None);
    assert_eq!(fmu.setup(1.0, Some(2.0)), OK);
    assert_eq!(fmu.enter_init(), OK);
    assert_eq!(fmu.exit_init(), OK);
    assert_eq!(fmu.step(1.0, 0.0), ERROR);
    assert_eq!(fmu.step(1.0, -0.1), ERROR);
    assert_eq!(fmu.step(1.0, f64::NAN), ERROR);
    assert_eq!(fmu.step(0.5, 0.1), ERROR);
    assert_eq!(
        fmu.logged(&["currentCommunicationPoint = 0.5 does not match the FMU's time 1"])
            .len(),
        1
    );
    // Variable step sizes, and round-off in the master's clock, are fine.
    assert_eq!(fmu.step(1.0, 0.1), OK);
    assert_eq!(fmu.step(1.1 + 1e-13, 0.25), OK);
    assert_eq!(fmu.step(1.35, 0.65), OK);
    assert_eq!(fmu.step(2.0, 0.1), ERROR);
    assert_eq!(fmu.logged(&["passes the stop time 2"]).len(), 1);
    let (mut t, mut terminated, mut st) = (0.0, 7, OK);
    unsafe {
        assert_eq!(
            fmi2GetRealStatus(fmu.c, fmi2StatusKind_fmi2LastSuccessfulTime, &mut t),
            OK
        );
        assert_eq!(
            fmi2GetBooleanStatus(fmu.c, fmi2StatusKind_fmi2Terminated, &mut terminated),
            OK
        );
        assert_eq!(
            fmi2GetStatus(fmu.c, fmi2StatusKind_fmi2DoStepStatus, &mut st),
            DISCARD
        );
        assert_eq!(fmi2CancelStep(fmu.c), ERROR);
    }
    assert!((t - 2.0).abs() < 1e-12);
    assert_eq!(terminated, fmi2False as i32);
}

#[test]
fn reset_returns_to_start_values_and_time() {
    let fmu = Fmu::instantiate("reset", None);
    assert_eq!(fmu.set("Fy_a2", 900.0), OK);
    assert_eq!(fmu.set_bool(ISO, true), OK);
    assert_eq!(fmu.setup(5.0, None), OK);
    assert_eq!(fmu.enter_init(), OK);
    assert_eq!(fmu.exit_init(), OK);
    fmu.set_many(&["Fz", "alpha", "kappa"], &[2000.0, 0.1, 0.2]);
    assert_eq!(fmu.step(5.0, 1.0), OK);
    assert_eq!(unsafe { fmi2Reset(fmu.c) }, OK);
    assert_eq!(fmu.step(6.0, 1.0), ERROR, "back in Instantiated");
    assert_eq!(fmu.setup(0.0, None), OK);
    assert_eq!(fmu.enter_init(), OK);
    assert_eq!(
        (fmu.get("Fz"), fmu.get("alpha"), fmu.get("Fy_a2")),
        (4000.0, 0.0, 1011.0)
    );
    assert_eq!(fmu.exit_init(), OK);
    assert_eq!(fmu.step(0.0, 1.0), OK, "time restarted");
    let mut iso = 1;
    assert_eq!(unsafe { fmi2GetBoolean(fmu.c, &ISO, 1, &mut iso) }, OK);
    assert_eq!(iso, 0);
}

#[test]
fn fmu_state_get_set_and_serialize_round_trip() {
    let a = Fmu::ready("state-a");
    a.set_many(
        &["Fz", "alpha", "kappa", "gamma"],
        &[5000.0, 0.08, -0.1, 0.02],
    );
    assert_eq!(a.step(0.0, 0.5), OK);
    let saved = a.outputs();
    let mut state: fmi2FMUstate = null_mut();
    assert_eq!(unsafe { fmi2GetFMUstate(a.c, &mut state) }, OK);
    assert!(!state.is_null());
    a.set_many(&["alpha", "kappa"], &[-0.2, 0.3]);
    assert_eq!(a.step(0.5, 0.5), OK);
    assert_ne!(a.outputs(), saved);
    assert_eq!(unsafe { fmi2SetFMUstate(a.c, state) }, OK);
    assert_eq!(a.outputs(), saved);
    assert_eq!(a.step(0.5, 0.5), OK, "time restored to 0.5");
    assert_eq!(a.outputs(), saved, "inputs restored too");

    // Serialize, then restore into a fresh instance.
    let mut size = 0;
    assert_eq!(
        unsafe { fmi2SerializedFMUstateSize(a.c, state, &mut size) },
        OK
    );
    let mut bytes = vec![0 as fmi2Byte; size];
    assert_eq!(
        unsafe { fmi2SerializeFMUstate(a.c, state, bytes.as_mut_ptr(), size) },
        OK
    );
    assert_eq!(
        unsafe { fmi2SerializeFMUstate(a.c, state, bytes.as_mut_ptr(), size - 1) },
        ERROR
    );
    let b = Fmu::ready("state-b");
    let mut restored: fmi2FMUstate = null_mut();
    assert_eq!(
        unsafe { fmi2DeSerializeFMUstate(b.c, bytes.as_ptr(), size, &mut restored) },
        OK
    );
    assert_eq!(unsafe { fmi2SetFMUstate(b.c, restored) }, OK);
    assert_eq!(b.outputs(), saved);
    assert_eq!(b.get("Fz"), 5000.0);

    // Corrupted bytes are rejected with a message.
    let mut bad = bytes.clone();
    let last = bad.len() - 3;
    bad[last] = b'#' as fmi2Byte;
    let mut other: fmi2FMUstate = null_mut();
    assert_eq!(
        unsafe { fmi2DeSerializeFMUstate(b.c, bad.as_ptr(), bad.len(), &mut other) },
        ERROR
    );
    assert!(other.is_null());
    assert_eq!(
        unsafe { fmi2DeSerializeFMUstate(b.c, bytes.as_ptr(), 10, &mut other) },
        ERROR
    );
    assert_eq!(b.logged(&["not a serialized state of this FMU"]).len(), 2);

    // Free: the slot is cleared; freeing a NULL slot is fine.
    for (fmu, mut s) in [(&a, state), (&b, restored)] {
        assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut s) }, OK);
        assert!(s.is_null());
        assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut s) }, OK);
    }
    assert_eq!(unsafe { fmi2SetFMUstate(a.c, null_mut()) }, ERROR);
}

#[test]
fn unsupported_functions_answer_with_an_error_message() {
    let fmu = Fmu::ready("unsupported");
    unsafe {
        assert_eq!(
            fmi2SetRealInputDerivatives(fmu.c, null(), 0, null(), null()),
            ERROR
        );
        assert_eq!(
            fmi2GetRealOutputDerivatives(fmu.c, null(), 0, null(), null_mut()),
            ERROR
        );
    }
    assert_eq!(fmu.logged(&["canInterpolateInputs = false"]).len(), 1);
    assert_eq!(fmu.logged(&["maxOutputDerivativeOrder = 0"]).len(), 1);
}

/// `J dv` through fmi2GetDirectionalDerivative.
fn directional(fmu: &Fmu, unknown: &[&str], known: &[&str], dv: &[f64]) -> (fmi2Status, Vec<f64>) {
    let u: Vec<u32> = unknown.iter().map(|n| vr(n)).collect();
    let k: Vec<u32> = known.iter().map(|n| vr(n)).collect();
    let mut out = vec![f64::NAN; u.len()];
    let status = unsafe {
        fmi2GetDirectionalDerivative(
            fmu.c,
            u.as_ptr(),
            u.len(),
            k.as_ptr(),
            k.len(),
            dv.as_ptr(),
            out.as_mut_ptr(),
        )
    };
    (status, out)
}

#[test]
fn directional_derivatives_are_central_differences_of_the_outputs() {
    let fmu = Fmu::ready("derivatives");
    let inputs = ["Fz", "alpha", "kappa", "gamma"];
    let x = [4200.0, 0.07, -0.04, 0.02];
    assert_eq!(fmu.set_many(&inputs, &x), OK);
    assert_eq!(fmu.step(0.0, 0.01), OK);
    let outputs = ["Fx", "Fy", "Mz"];
    let steps = [1e-2, 1e-7, 1e-7, 1e-7];
    let mut columns = Vec::new();
    for (k, h) in steps.iter().enumerate() {
        let (status, d) = directional(&fmu, &outputs, &[inputs[k]], &[1.0]);
        assert_eq!(status, OK);
        let (mut up, mut down) = (x, x);
        up[k] += h;
        down[k] -= h;
        let (a, b) = (
            model(up[0], up[1], up[2], up[3]),
            model(down[0], down[1], down[2], down[3]),
        );
        for i in 0..3 {
            let fd = (a[i] - b[i]) / (2.0 * h);
            assert!(
                (d[i] - fd).abs() <= 1e-5 * d[i].abs().max(1.0),
                "d{}/d{}: {} vs {fd}",
                outputs[i],
                inputs[k],
                d[i]
            );
        }
        columns.push(d);
    }
    // One call with a combined seed is the same combination of the columns, in any order of
    // the unknowns.
    let seed = [0.5, -2.0, 3.0, 0.25];
    let (status, d) = directional(&fmu, &["Mz", "Fx", "Fy"], &inputs, &seed);
    assert_eq!(status, OK);
    for (j, i) in [2, 0, 1].into_iter().enumerate() {
        let want: f64 = (0..4).map(|k| seed[k] * columns[k][i]).sum();
        assert!((d[j] - want).abs() <= 1e-9 * want.abs().max(1.0));
    }
    // Beyond the valid range an input does not move the outputs.
    assert_eq!(fmu.set("kappa", 1.5), WARNING);
    assert_eq!(fmu.step(0.01, 0.01), OK);
    assert_eq!(directional(&fmu, &outputs, &["kappa"], &[1.0]).1, [0.0; 3]);
    // Wrong roles, bad seeds and NULL arrays are errors naming them.
    assert_eq!(directional(&fmu, &["Fy"], &["Fy_C"], &[1.0]).0, ERROR);
    assert_eq!(
        fmu.logged(&["Fy_C", "is neither an input nor a state"])
            .len(),
        1
    );
    assert_eq!(directional(&fmu, &["alpha"], &["Fz"], &[1.0]).0, ERROR);
    assert_eq!(
        fmu.logged(&["alpha", "is neither an output nor a state derivative"])
            .len(),
        1
    );
    assert_eq!(directional(&fmu, &["Fy"], &["alpha"], &[f64::NAN]).0, ERROR);
    assert_eq!(
        fmu.logged(&["dvKnown for alpha", "must be finite"]).len(),
        1
    );
    let mut out = [0.0];
    let status = unsafe {
        fmi2GetDirectionalDerivative(fmu.c, &vr("Fy"), 1, null(), 1, null(), out.as_mut_ptr())
    };
    assert_eq!(status, ERROR);
    // Nothing asked, nothing done.
    assert_eq!(
        unsafe { fmi2GetDirectionalDerivative(fmu.c, null(), 0, null(), 0, null(), null_mut()) },
        OK
    );
}

#[test]
fn iso_sign_convention_flips_fy_and_mz() {
    let iso = Fmu::instantiate("iso", None);
    assert_eq!(iso.set_bool(ISO, true), OK);
    assert_eq!(iso.setup(0.0, None), OK);
    assert_eq!(iso.enter_init(), OK);
    assert_eq!(iso.exit_init(), OK);
    let inputs = [4000.0, 0.06, 0.05, 0.03];
    iso.set_many(&["Fz", "alpha", "kappa", "gamma"], &inputs);
    assert_eq!(iso.step(0.0, 0.1), OK);
    let [fx, fy, mz] = model(inputs[0], inputs[1], inputs[2], inputs[3]);
    assert_eq!(iso.outputs(), [fx, -fy, -mz]);
}

#[test]
fn parameter_file_loads_with_explicit_values_taking_precedence() {
    let dir = std::env::temp_dir().join(format!("p87 test {}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut params = mf87::Params::paper_table();
    params.Fy.a2 = 1100.0;
    params.Mz.a1 = -3.0;
    std::fs::write(dir.join("tire.json"), params.to_json()).unwrap();
    // Resource location as a percent-encoded file URI (on Windows with a drive letter,
    // `file:///C:/...`); a bare name is found there.
    let uri = file_uri(&dir);
    let fmu = Fmu::instantiate("paramfile", Some(&uri));
    let resources = format!("(resources: {})", dir.display());
    assert_eq!(
        fmu.logged(&[&resources]).len(),
        1,
        "{uri}: {:?}",
        fmu.messages()
    );
    assert_eq!(fmu.set("Mz_a1", -2.5), OK);
    assert_eq!(fmu.set_string(PARAMETER_FILE, "tire.json"), OK);
    assert_eq!(fmu.get_string_after_init(), "tire.json");
    assert_eq!(fmu.get("Fy_a2"), 1100.0);
    assert_eq!(
        fmu.get("Mz_a1"),
        -2.5,
        "explicitly set value overrides the file"
    );
    assert_eq!(
        fmu.logged(&["Mz_a1 = -2.5 set explicitly overrides the parameter file"])
            .len(),
        1
    );
    assert_eq!(fmu.exit_init(), OK);

    // An invalid file: error naming the parameter; the instance stays usable.
    params.Mz.a13 = 0.2;
    std::fs::write(dir.join("bad.json"), params.to_json()).unwrap();
    let bad = Fmu::instantiate("badparamfile", None);
    let path = dir.join("bad.json").display().to_string();
    assert_eq!(bad.set_string(PARAMETER_FILE, &path), OK);
    assert_eq!(bad.setup(0.0, None), OK);
    assert_eq!(bad.enter_init(), ERROR);
    assert_eq!(
        bad.logged(&["parameter Mz.a13 = 0.2", "gamma_max_deg = 10"])
            .len(),
        1
    );
    // A missing file whose name holds printf directives: logged verbatim, no crash.
    assert_eq!(
        bad.set_string(PARAMETER_FILE, "/nonexistent/%s%n%s.json"),
        OK
    );
    assert_eq!(bad.enter_init(), ERROR);
    assert_eq!(
        bad.logged(&["/nonexistent/%s%n%s.json", "cannot read"])
            .len(),
        1
    );
    assert_eq!(bad.set_string(PARAMETER_FILE, ""), OK);
    assert_eq!(bad.enter_init(), OK);
    // A coefficient outside its own range is refused when set and keeps its value.
    assert_eq!(bad.set("Fy_C", 0.0), ERROR);
    assert_eq!(
        bad.logged(&[
            "Fy_C = 0 is outside its allowed range [0.1, 5]",
            "keeps its value 1.3"
        ])
        .len(),
        1
    );
    // Explicit coefficients are validated as a set when leaving initialization: 1 - a12
    // gamma_max = 1 - 0.2 x 10 deg < 0.
    assert_eq!(bad.set("Fy_a12", 0.2), OK);
    assert_eq!(bad.exit_init(), ERROR);
    assert_eq!(bad.logged(&["parameter Fy.a12 = 0.2"]).len(), 1);
    assert_eq!(bad.set("Fy_a12", 0.022), OK);
    assert_eq!(bad.exit_init(), OK);
    std::fs::remove_dir_all(&dir).unwrap();
}

impl Fmu {
    /// Sets up, enters initialization mode and returns the parameterFile value.
    fn get_string_after_init(&self) -> String {
        assert_eq!(self.setup(0.0, None), OK);
        assert_eq!(self.enter_init(), OK, "{:?}", self.messages());
        self.get_string(PARAMETER_FILE)
    }
}

#[test]
fn bundled_parameter_file_in_the_fmu_resources_matches_the_defaults() {
    let resources = repo_root().join("crates/mf87/data");
    let fmu = Fmu::instantiate("resources", Some(&format!("file:{}", resources.display())));
    assert_eq!(fmu.set_string(PARAMETER_FILE, "pacejka87.json"), OK);
    assert_eq!(fmu.setup(0.0, None), OK);
    assert_eq!(fmu.enter_init(), OK, "{:?}", fmu.messages());
    assert_eq!(fmu.exit_init(), OK);
    assert_eq!(fmu.outputs(), model(4000.0, 0.0, 0.0, 0.0));
}

#[test]
fn debug_logging_categories() {
    let fmu = Fmu::ready("categories");
    let unknown = CString::new("logEverything").unwrap();
    let calls = CString::new("logCalls").unwrap();
    unsafe {
        assert_eq!(fmi2SetDebugLogging(fmu.c, 1, 1, &unknown.as_ptr()), ERROR);
        assert_eq!(fmi2SetDebugLogging(fmu.c, 1, 1, &calls.as_ptr()), OK);
    }
    assert_eq!(
        fmu.logged(&["unknown log category \"logEverything\"", "logCalls"])
            .len(),
        1
    );
    fmu.step(0.0, 0.1);
    assert!(fmu.messages().iter().any(|(_, m)| m == "fmi2DoStep"));
    // Warnings are muted when logging is switched off; errors never are.
    unsafe { assert_eq!(fmi2SetDebugLogging(fmu.c, 0, 0, null()), OK) };
    let before = fmu.messages().len();
    assert_eq!(fmu.set("kappa", 3.0), WARNING);
    assert_eq!(fmu.messages().len(), before);
    assert_eq!(fmu.set("kappa", f64::NAN), ERROR);
    assert_eq!(fmu.messages().len(), before + 1);
}

#[test]
fn many_instances_on_many_threads_match_one() {
    let inputs: std::sync::Arc<Vec<[f64; 4]>> = (0..400)
        .map(|k| {
            let x = k as f64;
            [
                1000.0 + 17.0 * x,
                (x * 0.37).sin() * 0.3,
                (x * 0.11).cos() * 0.4,
                (x * 0.05).sin() * 0.1,
            ]
        })
        .collect::<Vec<_>>()
        .into();
    let run = move |name: String, offset: usize| {
        let fmu = Fmu::ready(&name);
        let mut out = Vec::new();
        for (k, x) in inputs
            .iter()
            .cycle()
            .skip(offset)
            .take(inputs.len())
            .enumerate()
        {
            fmu.set_many(&["Fz", "alpha", "kappa", "gamma"], x);
            assert_eq!(fmu.step(k as f64 * 0.01, 0.01), OK);
            out.push(fmu.outputs());
        }
        out
    };
    let expected: Vec<Vec<[f64; 3]>> = (0..8).map(|t| run(format!("serial-{t}"), t * 50)).collect();
    let handles: Vec<_> = (0..8)
        .map(|t| {
            let run = run.clone();
            std::thread::spawn(move || run(format!("thread-{t}"), t * 50))
        })
        .collect();
    for (t, h) in handles.into_iter().enumerate() {
        assert_eq!(h.join().unwrap(), expected[t]);
    }
}

fn resident_kib() -> usize {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap();
    let pages: usize = statm.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * 4
}

#[test]
fn instantiate_and_free_thousands_of_times_without_growth() {
    let cycle = |n: usize| {
        for k in 0..n {
            let fmu = Fmu::ready(&format!("cycle-{}", k % 4));
            let mut state: fmi2FMUstate = null_mut();
            unsafe {
                fmi2GetFMUstate(fmu.c, &mut state);
                fmi2FreeFMUstate(fmu.c, &mut state);
            }
        }
    };
    cycle(2_000);
    let before = resident_kib();
    cycle(20_000);
    let grown = resident_kib().saturating_sub(before);
    // The captured log lines of this test are the only thing allowed to grow.
    assert!(
        grown < 16 * 1024,
        "resident memory grew by {grown} KiB over 20000 cycles"
    );
}

/// A parameter file: the paper's table with extensions as `edit` makes them, in its own
/// temporary directory (removed when the guard drops).
struct ParameterFile {
    dir: std::path::PathBuf,
    path: String,
    params: mf87::Params,
}

impl ParameterFile {
    fn new(test: &str, edit: impl FnOnce(&mut mf87::Extensions)) -> ParameterFile {
        use mf87::extensions::{ConditionLimits, Nominal};
        let dir = std::env::temp_dir().join(format!("p87 {test} {}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let nominal = Nominal {
            pressure_kpa: 220.0,
            speed_mps: 15.0,
            temperature_c: 40.0,
        };
        let mut ext = mf87::Extensions::new(nominal, ConditionLimits::default());
        edit(&mut ext);
        let mut params = mf87::Params::paper_table();
        params.extensions = Some(ext);
        let path = dir.join("fitted.json");
        std::fs::write(&path, params.to_json()).unwrap();
        ParameterFile {
            dir,
            path: path.display().to_string(),
            params,
        }
    }

    /// An instance initialized with this file and `inputs` (name, value) set before.
    fn instance(&self, name: &str, inputs: &[(&str, f64)]) -> Fmu {
        let fmu = Fmu::instantiate(name, None);
        assert_eq!(fmu.set_string(PARAMETER_FILE, &self.path), OK);
        for (n, v) in inputs {
            assert_eq!(fmu.set(n, *v), OK);
        }
        assert_eq!(fmu.setup(0.0, None), OK);
        assert_eq!(fmu.enter_init(), OK, "{:?}", fmu.messages());
        assert_eq!(fmu.exit_init(), OK, "{:?}", fmu.messages());
        fmu
    }
}

impl Drop for ParameterFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

const INPUTS_AND_CONDITIONS: [&str; 7] = ["Fz", "alpha", "kappa", "gamma", "vx", "p", "T_tread"];

/// mf87 with extensions at inputs and conditions [Fz, alpha, kappa, gamma, vx, p, T_tread].
fn extended_model(
    params: &mf87::Params,
    x: &[f64; 7],
    lagged: Option<mf87::LaggedSlip>,
) -> [f64; 3] {
    let inputs = mf87::Inputs {
        fz: x[0],
        alpha: x[1],
        kappa: x[2],
        gamma: x[3],
    };
    let conditions = mf87::OperatingConditions {
        vx: x[4],
        p: x[5],
        t_tread: x[6],
    };
    let lagged = lagged.unwrap_or_else(|| mf87::LaggedSlip::steady(params, &inputs));
    let o = mf87::evaluate_extended(
        params,
        &inputs,
        &conditions,
        &lagged,
        mf87::SignConvention::Paper,
    );
    [o.fx, o.fy, o.mz]
}

#[test]
fn extensions_from_the_parameter_file_give_mf87_s_outputs() {
    use mf87::extensions::*;
    let file = ParameterFile::new("extensions", |e| {
        e.Fy.combined_slip = Some(CombinedSlip {
            B: 8.0,
            C: 1.0,
            ..Default::default()
        });
        e.Fy.inflation_pressure = Some(InflationPressure {
            k: 0.3,
            d: -0.1,
            ..Default::default()
        });
        e.Fy.ply_steer_conicity = Some(PlySteerConicity {
            Sh_deg: 0.2,
            Sv: 30.0,

            ..Default::default()
        });
        e.Mz.speed_dependence = Some(SpeedDependence { v: -0.05, w: 0.0 });
        e.Mz.temperature = Some(Temperature {
            w: 0.2,
            Topt_degC: 5.0,
            k: 0.1,
        });
        e.Fx.rolling_resistance = Some(RollingResistance {
            q1: 0.012,
            q2: 0.003,
        });
        e.Fx.combined_slip = Some(CombinedSlip {
            B: 6.0,
            C: 1.0,
            ..Default::default()
        });
    });
    let fmu = file.instance("extensions", &[]);
    let loaded = fmu.logged(&[
        "fmi2EnterInitializationMode: extensions loaded: Fy: combined_slip (B = 8, C = 1)",
    ]);
    assert_eq!(loaded.len(), 1, "{:?}", fmu.messages());
    assert!(
        loaded[0].contains(
            "Fx: combined_slip (B = 6, C = 1), rolling_resistance (q1 = 0.012, q2 = 0.003)"
        )
    );
    assert!(loaded[0].contains("nominal p0 = 220 kPa, V0 = 15 m/s, T0 = 40 degC"));

    let mut t = 0.0;
    for k in -6..=6 {
        let s = k as f64;
        let x = [
            4000.0 + 300.0 * s,
            0.012 * s,
            -0.015 * s,
            0.005 * s,
            15.0 + 2.0 * s,
            220_000.0 - 8000.0 * s,
            313.15 + 5.0 * s,
        ];
        assert_eq!(fmu.set_many(&INPUTS_AND_CONDITIONS, &x), OK);
        assert_eq!(fmu.step(t, 0.01), OK);
        t += 0.01;
        assert_eq!(
            fmu.outputs(),
            extended_model(&file.params, &x, None),
            "{x:?}"
        );
        if k != 0 {
            assert_ne!(
                fmu.outputs(),
                model(x[0], x[1], x[2], x[3]),
                "extensions act"
            );
        }
    }
    assert_eq!(fmu.get("vx"), 27.0);

    // A condition outside the extensions' range: one warning, the clamped value used.
    assert_eq!(fmu.set("p", 500_000.0), WARNING);
    assert_eq!(fmu.set("p", 600_000.0), WARNING);
    let warned = fmu.logged(&[
        "p = 500000 Pa: p is outside the range [100000, 400000] Pa",
        "they use 400000 Pa",
    ]);
    assert_eq!(warned.len(), 1, "{:?}", fmu.messages());
    assert_eq!(fmu.set("vx", -90.0), WARNING);
    assert_eq!(
        fmu.logged(&["vx = -90 m/s: |vx| is outside the range [0, 70] m/s"])
            .len(),
        1
    );
    assert_eq!(fmu.step(t, 0.01), OK);
    let mut x = [0.0; 7];
    for (v, n) in x.iter_mut().zip(INPUTS_AND_CONDITIONS) {
        *v = fmu.get(n);
    }
    let at_limits = [x[0], x[1], x[2], x[3], 70.0, 400_000.0, x[6]];
    assert_eq!(
        fmu.outputs(),
        extended_model(&file.params, &at_limits, None)
    );
}

#[test]
fn relaxation_lag_follows_the_first_order_step_response() {
    use mf87::extensions::RelaxationLength;
    let (sigma_fy, sigma_fx) = (0.4, 0.6);
    let file = ParameterFile::new("relaxation", |e| {
        e.Fy.relaxation_length = Some(RelaxationLength { sigma_m: sigma_fy });
        e.Fx.relaxation_length = Some(RelaxationLength { sigma_m: sigma_fx });
    });
    let vx = 12.0;
    let fmu = file.instance("relaxation", &[("vx", vx)]);
    assert_eq!(
        fmu.outputs(),
        model(4000.0, 0.0, 0.0, 0.0),
        "steady state at start"
    );
    // A slip step at t = 0; the lag follows s (1 - exp(-x / sigma)) over the distance x
    // travelled, whatever the step sizes; standing still it stops, reversing it goes on.
    let (alpha, kappa) = (3f64.to_radians(), 0.05);
    assert_eq!(fmu.set_many(&["alpha", "kappa"], &[alpha, kappa]), OK);
    let (mut t, mut x) = (0.0, 0.0);
    let steps = [0.004, 0.01, 0.002, 0.02, 0.007, 0.05, 0.1];
    for (k, h) in steps.iter().chain(&[0.1, 0.02]).enumerate() {
        let speed = match k {
            7 => 0.0,
            8 => -vx,
            _ => vx,
        };
        assert_eq!(fmu.set("vx", speed), OK);
        let before = fmu.outputs();
        assert_eq!(fmu.step(t, *h), OK);
        t += h;
        x += speed.abs() * h;
        let lag = |s: f64, sigma: f64| s * (1.0 - (-x / sigma).exp());
        let [fx, fy, mz] = fmu.outputs();
        let expected_fy = model(4000.0, lag(alpha, sigma_fy), 0.0, 0.0)[1];
        let expected_fx = model(4000.0, 0.0, lag(kappa, sigma_fx), 0.0)[0];
        assert!(
            (fy - expected_fy).abs() <= 1e-10 * expected_fy.abs(),
            "x {x}: {fy} vs {expected_fy}"
        );
        assert!(
            (fx - expected_fx).abs() <= 1e-10 * expected_fx.abs(),
            "x {x}: {fx} vs {expected_fx}"
        );
        assert_eq!(mz, model(4000.0, alpha, 0.0, 0.0)[2], "Mz has no lag");
        if speed == 0.0 {
            assert_eq!(fmu.outputs(), before, "no distance, no change");
        }
    }
    assert!(x / sigma_fy > 3.0, "the test covers most of the response");
    // One very large step (1e6 s at 12 m/s) lands on the steady state, finite.
    assert_eq!(fmu.set("vx", vx), OK);
    assert_eq!(fmu.step(t, 1e6), OK);
    assert_eq!(fmu.outputs(), model(4000.0, alpha, kappa, 0.0));
}

#[test]
fn fmu_state_keeps_the_relaxation_lag() {
    use mf87::extensions::RelaxationLength;
    let file = ParameterFile::new("lagstate", |e| {
        e.Fy.relaxation_length = Some(RelaxationLength { sigma_m: 0.5 });
    });
    let fmu = file.instance("lagstate", &[("vx", 10.0)]);
    assert_eq!(fmu.set("alpha", 0.05), OK);
    assert_eq!(fmu.step(0.0, 0.01), OK);
    let mut state: fmi2FMUstate = null_mut();
    assert_eq!(unsafe { fmi2GetFMUstate(fmu.c, &mut state) }, OK);
    let continue_from = |f: &Fmu| -> Vec<[f64; 3]> {
        (1..4)
            .map(|k| {
                assert_eq!(f.step(0.01 * k as f64, 0.01), OK);
                f.outputs()
            })
            .collect()
    };
    let first = continue_from(&fmu);
    assert_ne!(first[0], first[2], "still relaxing");
    assert_eq!(unsafe { fmi2SetFMUstate(fmu.c, state) }, OK);
    assert_eq!(continue_from(&fmu), first, "restored mid-transient");

    // Serialized into an instance that never loaded the file: the extensions and the lag
    // come with the state.
    let mut size = 0;
    assert_eq!(
        unsafe { fmi2SerializedFMUstateSize(fmu.c, state, &mut size) },
        OK
    );
    let mut bytes = vec![0 as fmi2Byte; size];
    assert_eq!(
        unsafe { fmi2SerializeFMUstate(fmu.c, state, bytes.as_mut_ptr(), size) },
        OK
    );
    let other = Fmu::ready("lagstate-other");
    let mut restored: fmi2FMUstate = null_mut();
    assert_eq!(
        unsafe { fmi2DeSerializeFMUstate(other.c, bytes.as_ptr(), size, &mut restored) },
        OK
    );
    assert_eq!(unsafe { fmi2SetFMUstate(other.c, restored) }, OK);
    assert_eq!(continue_from(&other), first);
    for (f, mut s) in [(&fmu, state), (&other, restored)] {
        assert_eq!(unsafe { fmi2FreeFMUstate(f.c, &mut s) }, OK);
    }
}

#[test]
fn bad_extensions_are_rejected_naming_the_parameter() {
    use mf87::extensions::RelaxationLength;
    let file = ParameterFile::new("badext", |e| {
        e.Fy.relaxation_length = Some(RelaxationLength { sigma_m: -0.2 });
    });
    let fmu = Fmu::instantiate("badext", None);
    assert_eq!(fmu.set_string(PARAMETER_FILE, &file.path), OK);
    assert_eq!(fmu.setup(0.0, None), OK);
    assert_eq!(fmu.enter_init(), ERROR);
    assert_eq!(
        fmu.logged(&[
            "parameter extensions.Fy.relaxation_length.sigma_m = -0.2",
            "must be 0 (no lag) or lie in [0.001, 5] m"
        ])
        .len(),
        1,
        "{:?}",
        fmu.messages()
    );
    // A misspelled parameter name is named too.
    let text = std::fs::read_to_string(&file.path)
        .unwrap()
        .replace("sigma_m", "sigma");
    std::fs::write(&file.path, text).unwrap();
    assert_eq!(fmu.enter_init(), ERROR);
    assert_eq!(
        fmu.logged(&["unknown field `sigma`"]).len(),
        1,
        "{:?}",
        fmu.messages()
    );
    // Without extensions the conditions are accepted as they are and change nothing; only
    // |vx| beyond the speed bound (150 m/s) is refused.
    let plain = Fmu::ready("noext");
    assert_eq!(plain.set("vx", -500.0), ERROR);
    assert_eq!(
        plain.set_many(&["vx", "p", "T_tread"], &[-140.0, 1.0, 5000.0]),
        OK
    );
    assert_eq!(plain.step(0.0, 0.1), OK);
    assert_eq!(plain.outputs(), model(4000.0, 0.0, 0.0, 0.0));
}

/// The state as the FMU serializes it (header and GUID lines, then JSON).
fn serialized_state(fmu: &Fmu) -> serde_json::Value {
    let mut state: fmi2FMUstate = null_mut();
    assert_eq!(unsafe { fmi2GetFMUstate(fmu.c, &mut state) }, OK);
    let mut size = 0;
    assert_eq!(
        unsafe { fmi2SerializedFMUstateSize(fmu.c, state, &mut size) },
        OK
    );
    let mut bytes = vec![0 as fmi2Byte; size];
    assert_eq!(
        unsafe { fmi2SerializeFMUstate(fmu.c, state, bytes.as_mut_ptr(), size) },
        OK
    );
    assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut state) }, OK);
    let bytes: Vec<u8> = bytes.iter().map(|b| *b as u8).collect();
    let json = bytes.splitn(3, |b| *b == b'\n').nth(2).unwrap();
    serde_json::from_slice(json).unwrap()
}

#[test]
fn a_non_finite_output_is_an_error_and_the_state_stays_finite() {
    let fmu = Fmu::ready("nonfinite-output");
    let inputs = [4000.0, 0.02, 0.01, 0.05];
    assert_eq!(
        fmu.set_many(&["Fz", "alpha", "kappa", "gamma"], &inputs),
        OK
    );
    assert_eq!(fmu.step(0.0, 0.1), OK);
    let good = fmu.outputs();
    assert_eq!(good, model(inputs[0], inputs[1], inputs[2], inputs[3]));

    // Validation keeps every loadable parameter set finite, so the test writes a value no
    // parameter file or fmi2SetReal can give straight into the live instance: the camber
    // shift Sv = (a10 Fz^2 + a11 Fz) gamma overflows.
    let instance = unsafe { pacejka87_tire::instance::Instance::from_component(fmu.c) }.unwrap();
    instance.model.params.Fy.a11 = 1e308;
    assert_eq!(fmu.set("alpha", 0.03), OK);
    assert_eq!(fmu.step(0.1, 0.1), ERROR);
    let logged = fmu.logged(&[
        "fmi2DoStep: the model gives Fy = inf (not finite)",
        "Fz = 4000 N, alpha = 0.03 rad, kappa = 0.01, gamma = 0.05 rad",
        "the outputs keep their previous values",
        "the time stays at 0.1",
    ]);
    assert_eq!(logged.len(), 1, "{:?}", fmu.messages());
    assert_eq!(fmu.outputs(), good, "the previous, finite outputs");
    let mut t = f64::NAN;
    assert_eq!(
        unsafe { fmi2GetRealStatus(fmu.c, fmi2StatusKind_fmi2LastSuccessfulTime, &mut t) },
        OK
    );
    assert_eq!(t, 0.1);
    // The state still serializes, with the finite outputs.
    let state = serialized_state(&fmu);
    assert_eq!(state["outputs"]["fy"], good[1]);
    assert_eq!(state["time"], 0.1);

    // With the parameter back, the same step succeeds.
    instance.model.params.Fy.a11 = 14.8;
    assert_eq!(fmu.step(0.1, 0.1), OK);
    assert_eq!(fmu.outputs(), model(inputs[0], 0.03, inputs[2], inputs[3]));
}

#[test]
fn the_testers_parameter_files_are_rejected_naming_parameter_value_and_bound() {
    use mf87::extensions::{PlySteerConicity, RollingResistance};
    type Edit = fn(&mut mf87::Extensions);
    const ROLLING: Option<RollingResistance> = Some(RollingResistance {
        q1: 0.01,
        q2: 0.002,
    });
    // Each gave non-finite or absurd forces with fmi2OK before the bounds.
    let cases: [(&str, Edit, &[&str]); 4] = [
        (
            "v0-denormal",
            |e| {
                e.nominal.speed_mps = 5e-324;
                e.Fx.rolling_resistance = ROLLING;
            },
            &[
                "parameter extensions.nominal.speed_mps = 5e-324",
                "must lie in [0.5, 150] m/s",
            ],
        ),
        (
            "v0-micro",
            |e| {
                e.nominal.speed_mps = 1e-6;
                e.Fx.rolling_resistance = ROLLING;
            },
            &[
                "parameter extensions.nominal.speed_mps = 1e-6",
                "must lie in [0.5, 150] m/s",
            ],
        ),
        (
            "sv-huge",
            |e| {
                e.Fy.ply_steer_conicity = Some(PlySteerConicity {
                    Sh_deg: 0.0,
                    Sv: 1e300,

                    ..Default::default()
                })
            },
            &[
                "parameter extensions.Fy.ply_steer_conicity.Sv = 1e300",
                "at most 0.1 x fz_max = 1000 N",
            ],
        ),
        (
            "q-huge",
            |e| {
                e.Fx.rolling_resistance = Some(RollingResistance {
                    q1: 1e300,
                    q2: 1e300,
                })
            },
            &[
                "parameter extensions.Fx.rolling_resistance.q1 = 1e300",
                "must lie in [-0.05, 0.3] over the speed range [0, 70] m/s",
            ],
        ),
    ];
    for (name, edit, expected) in cases {
        let file = ParameterFile::new(name, edit);
        let fmu = Fmu::instantiate(name, None);
        assert_eq!(fmu.set_string(PARAMETER_FILE, &file.path), OK);
        assert_eq!(fmu.setup(0.0, None), OK);
        assert_eq!(fmu.enter_init(), ERROR, "{name}");
        assert_eq!(
            fmu.logged(expected).len(),
            1,
            "{name}: {:?}",
            fmu.messages()
        );
        // Nothing was loaded: the instance goes on with the paper's table.
        assert_eq!(fmu.set_string(PARAMETER_FILE, ""), OK);
        assert_eq!(fmu.enter_init(), OK);
        assert_eq!(fmu.exit_init(), OK);
        assert_eq!(fmu.step(0.0, 0.1), OK);
        assert_eq!(fmu.outputs(), model(4000.0, 0.0, 0.0, 0.0));
    }
}

#[test]
fn a_slip_ratio_shift_moves_fx_along_kappa_and_a_shift_past_its_bound_is_refused() {
    use mf87::extensions::SlipRatioShift;
    // Sh = 0.012, Sh_per_kN = 0.002: at 4 kN Fx is read at kappa + 0.02.
    let file = ParameterFile::new("slip-ratio-shift", |e| {
        e.Fx.slip_ratio_shift = Some(SlipRatioShift {
            Sh: 0.012,
            Sh_per_kN: 0.002,
            ..Default::default()
        })
    });
    let fmu = file.instance("slip-ratio-shift", &[]);
    let loaded =
        fmu.logged(&["extensions loaded: Fx: slip_ratio_shift (Sh = 0.012, Sh_per_kN = 0.002)"]);
    assert_eq!(loaded.len(), 1, "{:?}", fmu.messages());
    let mut t = 0.0;
    for (kappa, read_at) in [(-0.02, 0.0), (0.0, 0.02), (0.08, 0.1), (-0.12, -0.1)] {
        let (alpha, gamma) = (0.03, 0.01);
        assert_eq!(
            fmu.set_many(
                &["Fz", "alpha", "kappa", "gamma"],
                &[4000.0, alpha, kappa, gamma]
            ),
            OK
        );
        assert_eq!(fmu.step(t, 0.01), OK);
        t += 0.01;
        let out = fmu.outputs();
        let x = [4000.0, alpha, kappa, gamma, 0.0, 220e3, 313.15];
        assert_eq!(
            out,
            extended_model(&file.params, &x, None),
            "kappa = {kappa}"
        );
        // The paper's Fx at the shifted slip ratio; Fy and Mz as without the shift.
        let at = model(4000.0, alpha, read_at, gamma);
        assert!(
            (out[0] - at[0]).abs() <= 1e-9 * at[0].abs().max(1.0),
            "kappa = {kappa}: {} vs {}",
            out[0],
            at[0]
        );
        assert_eq!([out[1], out[2]], [at[1], at[2]]);
        if read_at == 0.0 {
            assert!(
                out[0].abs() < 1e-9,
                "free rolling reads as slip -0.02: {}",
                out[0]
            );
        }
    }
    // fz_max = 10 kN: 0.01 + 0.0045 x 10 = 0.055 at the top of the load range.
    let file = ParameterFile::new("slip-ratio-shift-past", |e| {
        e.Fx.slip_ratio_shift = Some(SlipRatioShift {
            Sh: 0.01,
            Sh_per_kN: 0.0045,
            ..Default::default()
        })
    });
    let (status, fmu) = load_parameter_file("slip-ratio-shift-past", &file.path);
    assert_eq!(status, ERROR);
    let logged = fmu.logged(&[
        "parameter extensions.Fx.slip_ratio_shift.Sh_per_kN = 0.0045",
        "at Fz = 10000 N; it must be at most 0.05 over the load range",
    ]);
    assert_eq!(logged.len(), 1, "{:?}", fmu.messages());
}

/// An instance that tries to load `path` as its parameter file; the status of
/// fmi2EnterInitializationMode and the instance.
fn load_parameter_file(name: &str, path: &str) -> (fmi2Status, Fmu) {
    let fmu = Fmu::instantiate(name, None);
    assert_eq!(fmu.set_string(PARAMETER_FILE, path), OK);
    assert_eq!(fmu.setup(0.0, None), OK);
    (fmu.enter_init(), fmu)
}

#[test]
fn parameter_files_that_are_not_regular_files_are_refused() {
    let dir = std::env::temp_dir().join(format!("p87 special {}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let dir_path = dir.display().to_string();
    let (status, fmu) = load_parameter_file("param-dir", &dir_path);
    assert_eq!(status, ERROR);
    assert_eq!(
        fmu.logged(&[
            "parameterFile",
            &dir_path,
            "a directory, not a regular file"
        ])
        .len(),
        1,
        "{:?}",
        fmu.messages()
    );

    // Larger than the limit: refused from its size, without reading it (a sparse file).
    let big = dir.join("big.json");
    let file = std::fs::File::create(&big).unwrap();
    file.set_len(pacejka87_tire::parameter_file::MAX_BYTES + 1)
        .unwrap();
    let (status, fmu) = load_parameter_file("param-big", &big.display().to_string());
    assert_eq!(status, ERROR);
    assert_eq!(
        fmu.logged(&["big.json", "it has 1048577 bytes", "at most 1048576 bytes"])
            .len(),
        1,
        "{:?}",
        fmu.messages()
    );
    // At the limit it is read (and rejected as JSON: it is all zero bytes).
    file.set_len(pacejka87_tire::parameter_file::MAX_BYTES)
        .unwrap();
    let (status, fmu) = load_parameter_file("param-at-limit", &big.display().to_string());
    assert_eq!(status, ERROR);
    assert_eq!(
        fmu.logged(&["big.json", "not a valid parameter set"]).len(),
        1,
        "{:?}",
        fmu.messages()
    );
    drop(file); // Windows removes no open file
    std::fs::remove_dir_all(&dir).unwrap();
}

/// [`load_parameter_file`] on another thread, so that a blocking open or an endless read
/// fails the test within `seconds` instead of hanging it (or filling memory for long); then
/// `unblock` runs. The status and the messages logged.
#[cfg(unix)]
fn load_parameter_file_within(
    name: &str,
    path: &str,
    seconds: u64,
    unblock: impl FnOnce(),
) -> (fmi2Status, Vec<String>) {
    let (name, file) = (name.to_string(), path.to_string());
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let (status, fmu) = load_parameter_file(&name, &file);
        let messages = fmu.messages().into_iter().map(|(_, m)| m).collect();
        let _ = tx.send((status, messages));
    });
    match rx.recv_timeout(std::time::Duration::from_secs(seconds)) {
        Ok(outcome) => outcome,
        Err(_) => {
            unblock();
            panic!("loading {path:?} as parameterFile did not return within {seconds} s");
        }
    }
}

#[cfg(unix)]
#[test]
fn devices_and_fifos_are_refused_without_blocking() {
    let (status, messages) = load_parameter_file_within("param-devzero", "/dev/zero", 10, || {});
    assert_eq!(status, ERROR);
    let found = |words: &[&str]| {
        messages
            .iter()
            .filter(|m| words.iter().all(|w| m.contains(w)))
            .count()
    };
    assert_eq!(
        found(&["/dev/zero", "a character device, not a regular file"]),
        1,
        "{messages:?}"
    );

    let dir = std::env::temp_dir().join(format!("p87 fifo {}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("params.fifo");
    let c_path = CString::new(fifo.display().to_string()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0);
    let (status, messages) =
        load_parameter_file_within("param-fifo", &fifo.display().to_string(), 10, || {
            // A writer lets a blocked open return, so the process can end.
            let _ = std::fs::OpenOptions::new().write(true).open(&fifo);
        });
    assert_eq!(status, ERROR);
    let found = messages
        .iter()
        .filter(|m| {
            m.contains("params.fifo") && m.contains("a FIFO (named pipe), not a regular file")
        })
        .count();
    assert_eq!(found, 1, "{messages:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn parameter_files_with_a_bom_load_and_array_forms_are_refused() {
    let dir = std::env::temp_dir().join(format!("p87 forms {}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut params = mf87::Params::paper_table();
    params.Fy.a2 = 1050.0;
    let bom = dir.join("bom.json");
    std::fs::write(&bom, format!("\u{feff}{}", params.to_json())).unwrap();
    let (status, fmu) = load_parameter_file("param-bom", &bom.display().to_string());
    assert_eq!(status, OK, "{:?}", fmu.messages());
    assert_eq!(fmu.get("Fy_a2"), 1050.0);

    // The whole set, or one channel, as a positional array (serde would accept both).
    let table: serde_json::Value = serde_json::from_str(&params.to_json()).unwrap();
    let positional = |channel: &str| -> serde_json::Value {
        let names = mf87::Params::coefficient_names(mf87::Channel::from_name(channel).unwrap());
        names.iter().map(|n| table[channel][*n].clone()).collect()
    };
    let mut one_channel = table.clone();
    one_channel["Fx"] = positional("Fx");
    let whole = serde_json::json!([
        positional("Fy"),
        positional("Mz"),
        positional("Fx"),
        [10000.0, 10.0]
    ]);
    for (name, value, expected) in [
        ("array-fx", one_channel, "`Fx` is a JSON array"),
        (
            "array-all",
            whole,
            "must be a JSON object with named fields, not an array",
        ),
    ] {
        let path = dir.join(format!("{name}.json"));
        std::fs::write(&path, value.to_string()).unwrap();
        let (status, fmu) = load_parameter_file(name, &path.display().to_string());
        assert_eq!(status, ERROR, "{name}");
        assert_eq!(
            fmu.logged(&["not a valid parameter set", expected]).len(),
            1,
            "{name}: {:?}",
            fmu.messages()
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn model_exchange_runs_the_standard_s_state_machine() {
    let fmu = Fmu::instantiate_as("me-run", None, fmi2Type_fmi2ModelExchange);
    let c = fmu.c;
    assert_eq!(
        fmu.set_many(&["Fz", "alpha", "kappa"], &[4000.0, 0.05, 0.1]),
        OK
    );
    assert_eq!(fmu.setup(0.0, None), OK);
    assert_eq!(fmu.enter_init(), OK);
    let mut x = [f64::NAN; 3];
    assert_eq!(unsafe { fmi2GetContinuousStates(c, x.as_mut_ptr(), 3) }, OK);
    assert_eq!(x, [0.1, 0.05, 0.05], "steady states follow kappa and alpha");
    assert_eq!(fmu.exit_init(), OK);
    // Event mode: no discrete states, no next event.
    let mut info = fmi2EventInfo {
        newDiscreteStatesNeeded: 1,
        terminateSimulation: 1,
        nominalsOfContinuousStatesChanged: 1,
        valuesOfContinuousStatesChanged: 1,
        nextEventTimeDefined: 1,
        nextEventTime: 5.0,
    };
    assert_eq!(unsafe { fmi2NewDiscreteStates(c, &mut info) }, OK);
    assert_eq!(
        (
            info.newDiscreteStatesNeeded,
            info.terminateSimulation,
            info.nextEventTimeDefined
        ),
        (0, 0, 0)
    );
    // Co-simulation calls are refused by a Model Exchange instance, and the reverse.
    assert_eq!(fmu.step(0.0, 0.01), ERROR);
    assert_eq!(fmu.logged(&["not a function of Model Exchange"]).len(), 1);
    assert_eq!(unsafe { fmi2EnterContinuousTimeMode(c) }, OK);
    assert_eq!(unsafe { fmi2SetTime(c, 0.5) }, OK);
    // Without a relaxation length the states do not move and the outputs are the model's.
    let mut dx = [f64::NAN; 3];
    assert_eq!(unsafe { fmi2GetDerivatives(c, dx.as_mut_ptr(), 3) }, OK);
    assert_eq!(dx, [0.0; 3]);
    assert_eq!(fmu.outputs(), model(4000.0, 0.05, 0.1, 0.0));
    assert_eq!(fmu.set("alpha", -0.02), OK);
    assert_eq!(fmu.outputs(), model(4000.0, -0.02, 0.1, 0.0));
    let mut nominal = [0.0; 3];
    assert_eq!(
        unsafe { fmi2GetNominalsOfContinuousStates(c, nominal.as_mut_ptr(), 3) },
        OK
    );
    assert!(nominal.iter().all(|n| *n > 0.0));
    assert_eq!(unsafe { fmi2GetEventIndicators(c, null_mut(), 0) }, OK);
    // Wrong counts and values are errors naming them.
    assert_eq!(unsafe { fmi2GetDerivatives(c, dx.as_mut_ptr(), 2) }, ERROR);
    assert_eq!(fmu.logged(&["nx = 2", "3 continuous states"]).len(), 1);
    let bad = [0.0, f64::NAN, 0.0];
    assert_eq!(
        unsafe { fmi2SetContinuousStates(c, bad.as_ptr(), 3) },
        ERROR
    );
    let (mut enter, mut stop) = (1, 1);
    assert_eq!(
        unsafe { fmi2CompletedIntegratorStep(c, 1, &mut enter, &mut stop) },
        OK
    );
    assert_eq!((enter, stop), (0, 0));
    assert_eq!(unsafe { fmi2EnterEventMode(c) }, OK);
    assert_eq!(unsafe { fmi2Terminate(c) }, OK);
}

#[test]
fn a_co_simulation_state_is_refused_by_a_model_exchange_instance() {
    let cs = Fmu::ready("state-cs");
    assert_eq!(cs.step(0.0, 0.01), OK);
    let mut state = null_mut();
    assert_eq!(unsafe { fmi2GetFMUstate(cs.c, &mut state) }, OK);
    let me = Fmu::instantiate_as("state-me", None, fmi2Type_fmi2ModelExchange);
    // A state belongs to the instance that made it: another instance refuses it unread.
    assert_eq!(unsafe { fmi2SetFMUstate(me.c, state) }, ERROR);
    assert_eq!(me.logged(&["not a state of this instance"]).len(), 1);
    // Serialized, it moves between instances, and the interface is checked.
    let bytes = serialized_bytes(&cs, state);
    let mut moved = null_mut();
    assert_eq!(
        unsafe { fmi2DeSerializeFMUstate(me.c, bytes.as_ptr().cast(), bytes.len(), &mut moved) },
        OK
    );
    assert_eq!(unsafe { fmi2SetFMUstate(me.c, moved) }, ERROR);
    assert_eq!(
        me.logged(&["StepComplete", "Model Exchange instance"])
            .len(),
        1
    );
    // An Instantiated-state snapshot belongs to both.
    let mut fresh = null_mut();
    assert_eq!(unsafe { fmi2GetFMUstate(me.c, &mut fresh) }, OK);
    let bytes = serialized_bytes(&me, fresh);
    let mut fresh_cs = null_mut();
    assert_eq!(
        unsafe { fmi2DeSerializeFMUstate(cs.c, bytes.as_ptr().cast(), bytes.len(), &mut fresh_cs) },
        OK
    );
    assert_eq!(unsafe { fmi2SetFMUstate(cs.c, fresh_cs) }, OK);
    // Freeing through the wrong instance is refused; through the right one it works once.
    let mut wrong = state;
    assert_eq!(unsafe { fmi2FreeFMUstate(me.c, &mut wrong) }, ERROR);
    assert_eq!(wrong, state, "a refused state is left in the slot");
    for (fmu, mut s) in [(&cs, state), (&me, fresh), (&me, moved), (&cs, fresh_cs)] {
        assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut s) }, OK);
        assert!(s.is_null());
    }
    let mut again = state;
    assert_eq!(unsafe { fmi2FreeFMUstate(cs.c, &mut again) }, ERROR);
}

#[test]
fn free_instance_frees_the_states_the_host_kept() {
    let fmu = Fmu::ready("state-owner");
    let mut kept = [null_mut(); 3];
    for s in &mut kept[..2] {
        assert_eq!(unsafe { fmi2GetFMUstate(fmu.c, s) }, OK);
    }
    let bytes = serialized_bytes(&fmu, kept[0]);
    assert_eq!(
        unsafe { fmi2DeSerializeFMUstate(fmu.c, bytes.as_ptr().cast(), bytes.len(), &mut kept[2]) },
        OK
    );
    // SAFETY of the count: a live instance of this library.
    let instance = unsafe { pacejka87_tire::instance::Instance::from_component(fmu.c) }.unwrap();
    assert_eq!(instance.allocated_states(), 3);
    let mut one = kept[1];
    assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut one) }, OK);
    assert_eq!(instance.allocated_states(), 2);
    // A garbage pointer is refused without being read.
    let mut garbage = 0xdead_bee0usize as fmi2FMUstate;
    assert_eq!(unsafe { fmi2SetFMUstate(fmu.c, garbage) }, ERROR);
    assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut garbage) }, ERROR);
    // The other two are freed with the instance (valgrind in the fuzz test checks no leak).
}

/// The serialized form of `state` of `fmu`.
fn serialized_bytes(fmu: &Fmu, state: fmi2FMUstate) -> Vec<u8> {
    let mut size = 0;
    assert_eq!(
        unsafe { fmi2SerializedFMUstateSize(fmu.c, state, &mut size) },
        OK
    );
    let mut bytes = vec![0u8; size];
    assert_eq!(
        unsafe { fmi2SerializeFMUstate(fmu.c, state, bytes.as_mut_ptr().cast(), size) },
        OK
    );
    bytes
}

#[test]
fn parameters_outside_their_own_range_are_refused_when_set() {
    let fmu = Fmu::instantiate("ranges", None);
    for (name, value, range) in [
        (
            "gamma_max",
            -0.1,
            "[0.0017453292519943296, 1.5533430342749532] rad",
        ),
        ("gamma_max", f64::NAN, "not a finite number"),
        ("Fz_max", 5.0, "[10, 100000] N"),
        ("Mz_a3", 2e9, "[-1000000000, 1000000000]"),
    ] {
        assert_eq!(fmu.set(name, value), ERROR, "{name} = {value}");
        assert_eq!(
            fmu.logged(&[&format!("{name} = {value}"), range]).len(),
            1,
            "{:?}",
            fmu.messages()
        );
    }
    // The limits kept their values: the camber range is not inverted, gamma clamps as usual.
    assert_eq!(fmu.set("gamma", 0.0), OK);
    assert_eq!(fmu.set("gamma", 1.0), WARNING);
    assert_eq!(fmu.setup(0.0, None), OK);
    assert_eq!(fmu.enter_init(), OK);
    assert_eq!(fmu.exit_init(), OK);
    assert!(fmu.outputs().iter().all(|v| v.is_finite()));
}

#[test]
fn speeds_and_relaxation_states_beyond_their_bounds_are_refused() {
    let fmu = Fmu::ready("vx-bound");
    assert_eq!(fmu.set("vx", -1.7e308), ERROR);
    assert_eq!(fmu.set("vx", 150.5), ERROR);
    assert_eq!(fmu.logged(&["vx = 150.5 m/s", "[0, 150] m/s"]).len(), 1);
    assert_eq!(fmu.set("vx", -150.0), OK);
    let me = Fmu::instantiate_as("state-bound", None, fmi2Type_fmi2ModelExchange);
    assert_eq!(me.setup(0.0, None), OK);
    assert_eq!(me.enter_init(), OK);
    assert_eq!(me.exit_init(), OK);
    assert_eq!(unsafe { fmi2EnterContinuousTimeMode(me.c) }, OK);
    let huge = [1.7e308, 0.0, 0.0];
    assert_eq!(
        unsafe { fmi2SetContinuousStates(me.c, huge.as_ptr(), 3) },
        ERROR
    );
    assert_eq!(me.logged(&["lag_Fx", "within +-100"]).len(), 1);
    let fine = [100.0, -100.0, 0.5];
    assert_eq!(
        unsafe { fmi2SetContinuousStates(me.c, fine.as_ptr(), 3) },
        OK
    );
    let mut dx = [f64::NAN; 3];
    assert_eq!(unsafe { fmi2GetDerivatives(me.c, dx.as_mut_ptr(), 3) }, OK);
    assert!(dx.iter().all(|v| v.is_finite()));
}
