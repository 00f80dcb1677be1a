//! Benchmark of one FMU communication step against the bare model evaluation.
//!
//! Criterion groups:
//! - `fmu/bare_evaluation`: one `mf87::evaluate` call, cycling through the same 1024 input
//!   sets as `crates/mf87/benches/evaluate.rs` (so the two are comparable within one run).
//! - `fmu/step`: what a co-simulation master does each step, through the C ABI:
//!   `fmi2SetReal` of Fz, alpha, kappa, gamma (one call, nvr = 4), `fmi2DoStep(t, h)`,
//!   `fmi2GetReal` of Fx, Fy, Mz (one call, nvr = 3). The inputs change every step, so the
//!   model is evaluated every step.
//! - `fmu_parts/*`: the three calls of a step alone, to see where the overhead is
//!   (`do_step_unchanged_inputs` is a DoStep that need not evaluate the model).
//!
//! The instance is created once, outside the timed loops, with loggingOn = 0 and the C
//! allocator and fmi-sys's variadic logger as host callbacks. The FMI functions are called
//! through opaque function pointers, as a host calls them after `dlsym`, so the optimizer
//! cannot inline the FMU into the loop (which it could, as the rlib is linked in statically).
//!
//! After the criterion groups, a plain `Instant` loop (best of 5 interleaved runs of
//! 2,000,000 iterations each) times the step and the bare evaluation in this same process and
//! prints their ratio against the target `step / bare evaluation <= 1.3`, with PASS or FAIL.
//! The bench does not fail on the target; it reports it. (It does panic if an FMI call does
//! not return fmi2OK or the FMU's outputs differ from the model: the timings would be void.)
//! It also prints the three parts alone, and for context both timings again with each
//! step's inputs chained to the previous outputs: the plain bare loop lets the CPU overlap
//! consecutive independent evaluations, which a step between them largely prevents.
//! The same loop times one `fmi2GetDirectionalDerivative` of Fx, Fy, Mz by Fz, alpha, kappa,
//! gamma (one seed vector, changing every call) against the target `<= 3` bare evaluations.
//! Under `cargo test --benches` everything runs once, briefly, and nothing is judged.
//!
//! Run with `cargo bench -p pacejka87-tire-fmu --bench step`.

use std::ffi::CString;
use std::hint::black_box;
use std::ptr::{null, null_mut};
use std::time::Instant;

use criterion::Criterion;
use fmi_sys::fmi2::*;
use mf87::{Inputs, Params, SignConvention};
use pacejka87_tire::exports::*;
use pacejka87_tire::variables::{GUID, REAL_VARIABLES};

#[path = "../crates/mf87/benches/support/input_sets.rs"]
mod input_sets;
use input_sets::{N_INPUTS, input_sets};

/// Communication step size [s].
const STEP: f64 = 1e-3;

/// The target: one FMU step may cost at most this many bare evaluations.
const TARGET_RATIO: f64 = 1.3;

/// The target: one directional derivative of the three outputs by the four inputs may cost
/// at most this many bare evaluations.
const DERIVATIVE_TARGET_RATIO: f64 = 3.0;

/// The value reference of a Real variable by name.
fn vr(name: &str) -> fmi2ValueReference {
    REAL_VARIABLES
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("no Real variable {name}"))
        .vr
}

const INPUT_NAMES: [&str; 4] = ["Fz", "alpha", "kappa", "gamma"];
const OUTPUT_NAMES: [&str; 3] = ["Fx", "Fy", "Mz"];

type SetRealFn = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *const fmi2Real,
) -> fmi2Status;
type GetRealFn = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *mut fmi2Real,
) -> fmi2Status;
type DoStepFn = unsafe extern "C" fn(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean) -> fmi2Status;
type DirectionalFn = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *const fmi2ValueReference,
    usize,
    *const fmi2Real,
    *mut fmi2Real,
) -> fmi2Status;

/// One initialized co-simulation instance, driven as a master would.
struct Fmu {
    c: fmi2Component,
    // The FMU may keep a pointer to the callbacks: they live as long as the instance.
    _callbacks: Box<fmi2CallbackFunctions>,
    set_real: SetRealFn,
    get_real: GetRealFn,
    do_step: DoStepFn,
    directional: DirectionalFn,
    input_vrs: [fmi2ValueReference; 4],
    output_vrs: [fmi2ValueReference; 3],
    /// The current communication point, advanced by `STEP` after every DoStep.
    t: f64,
    /// The OR of every status returned in the timed loops (fmi2OK is 0).
    statuses: fmi2Status,
}

impl Fmu {
    fn new() -> Fmu {
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: Some(fmi_sys::fmi2::logger::callback_logger_handler),
            allocateMemory: Some(libc::calloc),
            freeMemory: Some(libc::free),
            stepFinished: None,
            componentEnvironment: null_mut(),
        });
        let name = CString::new("bench").unwrap();
        let guid = CString::new(GUID).unwrap();
        // SAFETY: valid NUL-terminated strings, a NULL resource location (allowed: the FMU
        // then uses its built-in parameters) and callbacks that outlive the instance.
        let c = unsafe {
            fmi2Instantiate(
                name.as_ptr(),
                fmi2Type_fmi2CoSimulation,
                guid.as_ptr(),
                null(),
                &*callbacks,
                0,
                0,
            )
        };
        assert!(!c.is_null(), "fmi2Instantiate failed");
        // SAFETY: `c` is the live instance created above.
        let statuses = unsafe {
            fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0)
                | fmi2EnterInitializationMode(c)
                | fmi2ExitInitializationMode(c)
        };
        assert_eq!(statuses, fmi2Status_fmi2OK, "initialization failed");
        Fmu {
            c,
            _callbacks: callbacks,
            set_real: black_box(fmi2SetReal as SetRealFn),
            get_real: black_box(fmi2GetReal as GetRealFn),
            do_step: black_box(fmi2DoStep as DoStepFn),
            directional: black_box(fmi2GetDirectionalDerivative as DirectionalFn),
            input_vrs: INPUT_NAMES.map(vr),
            output_vrs: OUTPUT_NAMES.map(vr),
            t: 0.0,
            statuses: fmi2Status_fmi2OK,
        }
    }

    fn set_inputs(&mut self, x: &[f64; 4]) {
        // SAFETY: live instance; `input_vrs` and `x` both have 4 elements.
        self.statuses |= unsafe { (self.set_real)(self.c, self.input_vrs.as_ptr(), 4, x.as_ptr()) };
    }

    fn do_step(&mut self) {
        // SAFETY: live instance.
        self.statuses |= unsafe { (self.do_step)(self.c, self.t, STEP, 1) };
        self.t += STEP;
    }

    /// `J dv` of the outputs by the four inputs.
    fn derivative(&mut self, dv: &[f64; 4]) -> [f64; 3] {
        let mut y = [0.0; 3];
        // SAFETY: live instance; the arrays have the lengths passed.
        self.statuses |= unsafe {
            (self.directional)(
                self.c,
                self.output_vrs.as_ptr(),
                3,
                self.input_vrs.as_ptr(),
                4,
                dv.as_ptr(),
                y.as_mut_ptr(),
            )
        };
        y
    }

    fn get_outputs(&mut self) -> [f64; 3] {
        let mut y = [0.0; 3];
        // SAFETY: live instance; `output_vrs` and `y` both have 3 elements.
        self.statuses |=
            unsafe { (self.get_real)(self.c, self.output_vrs.as_ptr(), 3, y.as_mut_ptr()) };
        y
    }

    /// One communication step: set the inputs, step, get the outputs.
    fn step(&mut self, x: &[f64; 4]) -> [f64; 3] {
        self.set_inputs(x);
        self.do_step();
        self.get_outputs()
    }

    /// Panics if any call since the start failed: the timings would then be meaningless.
    fn check(&self) {
        assert_eq!(
            self.statuses, fmi2Status_fmi2OK,
            "an FMI call did not return fmi2OK: the measurement is invalid"
        );
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: the live instance, not used afterwards.
        unsafe { fmi2FreeInstance(self.c) };
    }
}

/// The inputs as the FMU's value array, in the order of `INPUT_NAMES`.
fn as_array(x: &Inputs) -> [f64; 4] {
    [x.fz, x.alpha, x.kappa, x.gamma]
}

fn bare(params: &Params, inputs: &[Inputs], i: usize) -> mf87::Outputs {
    mf87::evaluate(
        black_box(params),
        black_box(&inputs[i]),
        black_box(SignConvention::Paper),
    )
}

fn criterion_groups(c: &mut Criterion, fmu: &mut Fmu, params: &Params, inputs: &[Inputs]) {
    let arrays: Vec<[f64; 4]> = inputs.iter().map(as_array).collect();

    let mut group = c.benchmark_group("fmu");
    let mut i = 0;
    group.bench_function("bare_evaluation", |b| {
        b.iter(|| {
            i = (i + 1) & (N_INPUTS - 1);
            bare(params, inputs, i)
        })
    });
    group.bench_function("step", |b| {
        b.iter(|| {
            i = (i + 1) & (N_INPUTS - 1);
            fmu.step(black_box(&arrays[i]))
        })
    });
    group.finish();

    let mut group = c.benchmark_group("fmu_parts");
    group.bench_function("set_real_4", |b| {
        b.iter(|| {
            i = (i + 1) & (N_INPUTS - 1);
            fmu.set_inputs(black_box(&arrays[i]));
        })
    });
    // Make the outputs current first, so these DoSteps do not evaluate the model.
    fmu.do_step();
    group.bench_function("do_step_unchanged_inputs", |b| b.iter(|| fmu.do_step()));
    group.bench_function("get_real_3", |b| b.iter(|| fmu.get_outputs()));
    group.finish();
    fmu.check();
}

/// Time per iteration [ns] of `f` over `iters` iterations; `f` gets the input index.
fn time_loop(iters: usize, mut f: impl FnMut(usize)) -> f64 {
    let start = Instant::now();
    for k in 0..iters {
        f(k & (N_INPUTS - 1));
    }
    start.elapsed().as_secs_f64() * 1e9 / iters as f64
}

/// The own timing of the step against the bare evaluation, and its verdict.
fn ratio_check(fmu: &mut Fmu, params: &Params, inputs: &[Inputs], measuring: bool) {
    let (runs, iters) = if measuring { (5, 2_000_000) } else { (1, 1000) };
    let best = best_times(fmu, params, inputs, runs, iters);
    fmu.check();

    // The FMU really computed the model: its outputs equal the bare evaluation's.
    let last = &inputs[7];
    let y = fmu.step(&as_array(last));
    let o = mf87::evaluate(params, last, SignConvention::Paper);
    fmu.check();
    assert_eq!(y, [o.fx, o.fy, o.mz], "FMU outputs differ from the model");

    let mode = if measuring {
        format!("best of {runs} x {iters} iterations")
    } else {
        "test mode, not a measurement".to_string()
    };
    print_ratios(&best, measuring, &mode);
}

/// Best time per iteration [ns] over `runs` runs of: the bare evaluation, the FMU step,
/// fmi2SetReal, fmi2DoStep without evaluation, fmi2GetReal, the bare evaluation and the FMU
/// step with inputs chained to the previous outputs, and the directional derivative.
fn best_times(
    fmu: &mut Fmu,
    params: &Params,
    inputs: &[Inputs],
    runs: usize,
    iters: usize,
) -> [f64; 8] {
    let arrays: Vec<[f64; 4]> = inputs.iter().map(as_array).collect();
    // Feeds the previous outputs into the next inputs (`+ 0.0 * prev` changes no value but
    // cannot be optimized away), so that consecutive evaluations cannot overlap in the CPU.
    let mut prev = 0.0;
    let mut best = [f64::INFINITY; 8];
    let seeds: Vec<[f64; 4]> = inputs
        .iter()
        .map(|x| as_array(x).map(|v| v.sin()))
        .collect();
    for _ in 0..runs {
        // Interleaved, so a burst of load on the machine hits all alike.
        let times = [
            time_loop(iters, |i| {
                black_box(bare(params, inputs, i));
            }),
            time_loop(iters, |i| {
                black_box(fmu.step(black_box(&arrays[i])));
            }),
            time_loop(iters, |i| fmu.set_inputs(black_box(&arrays[i]))),
            {
                // The outputs are current after this step, so the timed ones do not evaluate.
                fmu.do_step();
                time_loop(iters, |_| fmu.do_step())
            },
            time_loop(iters, |_| {
                black_box(fmu.get_outputs());
            }),
            time_loop(iters, |i| {
                let mut x = inputs[i];
                x.fz += 0.0 * prev;
                let o = bare(params, std::slice::from_ref(&x), 0);
                prev = o.fx + o.fy + o.mz;
            }),
            time_loop(iters, |i| {
                let mut x = arrays[i];
                x[0] += 0.0 * prev;
                let y = fmu.step(black_box(&x));
                prev = y[0] + y[1] + y[2];
            }),
            time_loop(iters, |i| {
                black_box(fmu.derivative(black_box(&seeds[i])));
            }),
        ];
        for (b, t) in best.iter_mut().zip(times) {
            *b = b.min(t);
        }
    }
    best
}

/// The verdict of a ratio against its target: judged only when measuring.
fn verdict(measuring: bool, ratio: f64, target: f64) -> &'static str {
    match (measuring, ratio <= target) {
        (false, _) => "not judged",
        (true, true) => "PASS",
        (true, false) => "FAIL",
    }
}

/// Prints the times of [`best_times`] and the verdicts on the step and derivative ratios.
fn print_ratios(best: &[f64; 8], measuring: bool, mode: &str) {
    let [
        bare_ns,
        step_ns,
        set_ns,
        do_step_ns,
        get_ns,
        bare_chained,
        step_chained,
        derivative_ns,
    ] = *best;
    let ratio = step_ns / bare_ns;
    let step_verdict = verdict(measuring, ratio, TARGET_RATIO);
    println!();
    println!("step / bare evaluation ({mode}):");
    println!(
        "  FMU step: {step_ns:.1} ns, bare evaluation: {bare_ns:.1} ns, ratio {ratio:.2} \
         (target <= {TARGET_RATIO}): {step_verdict}"
    );
    println!(
        "  parts: fmi2SetReal(nvr=4) {set_ns:.1} ns, fmi2DoStep without evaluation \
         {do_step_ns:.1} ns, fmi2GetReal(nvr=3) {get_ns:.1} ns"
    );
    println!(
        "  context, inputs chained to the previous outputs (no overlap between evaluations): \
         FMU step {step_chained:.1} ns, bare evaluation {bare_chained:.1} ns, ratio {:.2}",
        step_chained / bare_chained
    );
    let derivative_ratio = derivative_ns / bare_ns;
    let derivative_verdict = verdict(measuring, derivative_ratio, DERIVATIVE_TARGET_RATIO);
    println!(
        "  fmi2GetDirectionalDerivative (Fx, Fy, Mz by Fz, alpha, kappa, gamma): \
         {derivative_ns:.1} ns, {derivative_ratio:.2} bare evaluations \
         (target <= {DERIVATIVE_TARGET_RATIO}): {derivative_verdict}"
    );
}

fn main() {
    let mut criterion = Criterion::default().configure_from_args();
    // As criterion decides: without --bench (cargo test --benches) or with --test, it only
    // checks that the benchmarks run.
    let args: Vec<String> = std::env::args().collect();
    let has = |flag: &str| args.iter().any(|a| a.split('=').next() == Some(flag));
    let measuring = has("--bench") && !has("--test") && !has("--list");
    // Under a profiler (--profile-time) only the selected criterion benchmark should run.
    let profiling = has("--profile-time");

    let params = Params::paper_table();
    let inputs = input_sets();
    let mut fmu = Fmu::new();
    criterion_groups(&mut criterion, &mut fmu, &params, &inputs);
    criterion.final_summary();
    if !has("--list") && !profiling {
        ratio_check(&mut fmu, &params, &inputs, measuring);
    }
}
