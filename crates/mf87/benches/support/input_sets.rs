//! Input sets shared by the model and FMU benchmarks, so their timings are comparable.

use mf87::Inputs;

/// Number of precomputed input sets (a power of two, so the index wraps with a mask).
pub const N_INPUTS: usize = 1024;

/// Realistic, deterministic input sets: each input follows its own Weyl sequence
/// `frac(i * r)` with an irrational `r`, mapped onto its range.
pub fn input_sets() -> Vec<Inputs> {
    let frac = |x: f64| x - x.floor();
    (0..N_INPUTS)
        .map(|i| {
            let i = i as f64;
            let u = |r: f64| 2.0 * frac(i * r) - 1.0; // in [-1, 1)
            Inputs {
                fz: 4000.0 + 2000.0 * u(0.618_033_988_749_895),
                alpha: 8f64.to_radians() * u(0.414_213_562_373_095),
                kappa: 0.15 * u(0.732_050_807_568_877),
                gamma: 3f64.to_radians() * u(0.236_067_977_499_790),
            }
        })
        .collect()
}
