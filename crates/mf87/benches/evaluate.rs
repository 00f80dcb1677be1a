//! Benchmarks of the pure model.
//!
//! - `mf87/evaluate`: one [`mf87::evaluate`] call (Fx, Fy, Mz, with input clamping and unit
//!   conversion) with the paper's coefficients.
//! - `mf87/channel/{Fy,Mz,Fx}`: for context, one channel alone,
//!   `channel_factors(..).eval(x)`, in the paper's units (kN, deg, percent).
//! - `mf87/evaluate_extended`: [`mf87::evaluate_extended`] with every extension on every
//!   channel it applies to (relaxation lag given), for the cost of the extensions.
//! - `mf87/evaluate_extended/temperature`: the same with one extension (temperature), as a
//!   parameter file a diagnosis exports carries: the absent extensions must cost nothing.
//!
//! Every iteration takes the next of 1024 precomputed, realistic input sets (Fz 2..6 kN,
//! alpha +-8 deg, kappa +-0.15, gamma +-3 deg, spread by a Weyl sequence), so nothing can be
//! constant-folded and the branch predictor sees varying data. `benches/step.rs` of the FMU
//! package uses the same input sets, so its `bare evaluation` is comparable with this one.
//!
//! Run with `cargo bench -p mf87 --bench evaluate`.

use std::hint::black_box;

use criterion::Criterion;
use mf87::{Channel, LaggedSlip, OperatingConditions, Params, SignConvention};

#[path = "support/every_extension.rs"]
mod every_extension;
#[path = "support/input_sets.rs"]
mod input_sets;
use every_extension::{with_every_extension, with_extensions};
use input_sets::{N_INPUTS, input_sets};

fn bench_evaluate(c: &mut Criterion) {
    let params = Params::paper_table();
    let inputs = input_sets();
    let mut group = c.benchmark_group("mf87");

    let mut i = 0;
    group.bench_function("evaluate", |b| {
        b.iter(|| {
            i = (i + 1) & (N_INPUTS - 1);
            mf87::evaluate(
                black_box(&params),
                black_box(&inputs[i]),
                black_box(SignConvention::Paper),
            )
        })
    });

    for channel in Channel::ALL {
        // (load [kN], camber [deg], slip [deg or percent]) in the paper's units.
        let args: Vec<(f64, f64, f64)> = inputs
            .iter()
            .map(|x| {
                let fz_kn = mf87::units::newtons_to_kilonewtons(x.fz);
                match channel {
                    Channel::Fx => (fz_kn, 0.0, mf87::units::slip_ratio_to_percent(x.kappa)),
                    Channel::Fy | Channel::Mz => (
                        fz_kn,
                        mf87::units::radians_to_degrees(x.gamma),
                        mf87::units::radians_to_degrees(x.alpha),
                    ),
                }
            })
            .collect();
        let mut i = 0;
        group.bench_function(format!("channel/{channel}"), |b| {
            b.iter(|| {
                i = (i + 1) & (N_INPUTS - 1);
                let (fz_kn, gamma_deg, x) = black_box(args[i]);
                mf87::channel_factors(black_box(&params), channel, fz_kn, gamma_deg).eval(x)
            })
        });
    }
    let conditions = OperatingConditions {
        vx: 22.0,
        p: 235_000.0,
        t_tread: 330.0,
    };
    for (name, extended) in [
        ("evaluate_extended", with_every_extension()),
        (
            "evaluate_extended/temperature",
            with_extensions(&[mf87::extensions::Extension::Temperature]),
        ),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                i = (i + 1) & (N_INPUTS - 1);
                let x = &inputs[i];
                let lagged = LaggedSlip {
                    fx: 0.9 * x.kappa,
                    fy: 0.9 * x.alpha,
                    mz: 0.9 * x.alpha,
                };
                mf87::evaluate_extended(
                    black_box(&extended),
                    black_box(x),
                    black_box(&conditions),
                    black_box(&lagged),
                    black_box(SignConvention::Paper),
                )
            })
        });
    }
    group.finish();
}

criterion::criterion_group!(benches, bench_evaluate);
criterion::criterion_main!(benches);
