//! Seeded, portable random streams.
//!
//! Every part of the generator (test design, base tire, each effect's magnitudes, sensor
//! noise) draws from its own ChaCha8 stream derived from the seed and a label. Switching an
//! effect on or off therefore changes nothing else: the same seed gives the same test program,
//! the same base tire and the same noise, so a dataset with an effect differs from the one
//! without it by the effect alone.
//!
//! Only `random::<f64>()` (53 random bits) and `rand_distr`'s standard normal (computed with
//! `libm`) are used; ranges, integers and shuffles are derived here, so the output does not
//! depend on `rand`'s range-sampling algorithms.

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use rand_distr::{Distribution, StandardNormal};

use crate::method::splitmix::splitmix64;

/// The generator used everywhere in `synth`.
pub(crate) type SynthRng = ChaCha8Rng;

/// FNV-1a hash of a label (stable, no dependence on std's hasher).
fn fnv1a(label: &str) -> u64 {
    label.bytes().fold(0xCBF2_9CE4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01B3)
    })
}

/// An independent stream for `label` under `seed`.
pub(crate) fn stream(seed: u64, label: &str) -> SynthRng {
    let mut state = seed ^ fnv1a(label).rotate_left(17);
    let mut key = [0u8; 32];
    for chunk in key.chunks_exact_mut(8) {
        chunk.copy_from_slice(&splitmix64(&mut state).to_le_bytes());
    }
    SynthRng::from_seed(key)
}

/// Uniform in [lo, hi).
pub(crate) fn uniform(rng: &mut SynthRng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.random::<f64>()
}

/// `nominal` times a factor uniform in [1 - rel, 1 + rel).
pub(crate) fn jitter(rng: &mut SynthRng, nominal: f64, rel: f64) -> f64 {
    nominal * uniform(rng, 1.0 - rel, 1.0 + rel)
}

/// +1 or -1 with equal odds.
pub(crate) fn sign(rng: &mut SynthRng) -> f64 {
    if rng.random::<f64>() < 0.5 { -1.0 } else { 1.0 }
}

/// A standard normal deviate.
pub(crate) fn normal(rng: &mut SynthRng) -> f64 {
    StandardNormal.sample(rng)
}

/// Uniform index in 0..n (n > 0).
pub(crate) fn index(rng: &mut SynthRng, n: usize) -> usize {
    // n is small (block counts); the product is exact enough and the min guards u -> 1.
    ((rng.random::<f64>() * n as f64) as usize).min(n - 1)
}

/// Fisher-Yates shuffle.
pub(crate) fn shuffle<T>(rng: &mut SynthRng, items: &mut [T]) {
    for i in (1..items.len()).rev() {
        let j = index(rng, i + 1);
        items.swap(i, j);
    }
}

/// Latin-hypercube sample of `n` values in [lo, hi): one per stratum, in random order.
pub(crate) fn latin(rng: &mut SynthRng, n: usize, lo: f64, hi: f64) -> Vec<f64> {
    let mut strata: Vec<usize> = (0..n).collect();
    shuffle(rng, &mut strata);
    strata
        .into_iter()
        .map(|k| lo + (hi - lo) * (k as f64 + rng.random::<f64>()) / n as f64)
        .collect()
}
