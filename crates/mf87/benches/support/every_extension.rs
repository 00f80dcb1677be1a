//! A parameter set with every extension, shared by the benchmark and the derivative tests.

use mf87::extensions::{ConditionLimits, Extension, Extensions, Nominal};
use mf87::{Channel, Params};

/// The paper's table with every extension, at small non-neutral values, on every channel it
/// applies to.
pub fn with_every_extension() -> Params {
    with_extensions(&Extension::ALL)
}

/// The paper's table with the extensions `kinds`, at the values of [`with_every_extension`],
/// on every channel each applies to.
#[allow(dead_code, reason = "the derivative tests use every extension only")]
pub fn with_extensions(kinds: &[Extension]) -> Params {
    let nominal = Nominal {
        pressure_kpa: 220.0,
        speed_mps: 15.0,
        temperature_c: 40.0,
    };
    let mut ext = Extensions::new(nominal, ConditionLimits::default());
    for channel in Channel::ALL {
        for kind in kinds.iter().filter(|k| k.applies_to(channel)) {
            let values: Vec<f64> = match kind {
                // MF 6.1's weighting with every term; the induced term on Fy and Mz, the
                // moment of Fx and the equivalent slip on Mz.
                Extension::CombinedSlip => {
                    let induced = match channel {
                        Channel::Fx => [0.0; 9],
                        Channel::Fy => [0.05, 0.01, 0.3, 2.0, 1.2, 8.0, 0.0, 0.0, 0.0],
                        Channel::Mz => [0.05, 0.01, 0.3, 2.0, 1.2, 8.0, 0.2, 3.0, 0.6],
                    };
                    [8.0, 1.0, 3.0, 0.02, 2.0, 0.1, 0.02, 0.01, 0.002]
                        .into_iter()
                        .chain(induced)
                        .collect()
                }
                Extension::RelaxationLength => vec![0.4],
                Extension::Temperature => vec![0.1, 5.0, 0.05],
                Extension::SlipRatioShift => vec![0.01, 0.002, 0.02, -0.005],
                _ => vec![0.01; kind.parameter_names().len()],
            };
            ext.channel_mut(channel).set(*kind, &values).unwrap();
        }
    }
    let mut params = Params::paper_table();
    params.extensions = Some(ext);
    params.validate().unwrap();
    params
}
