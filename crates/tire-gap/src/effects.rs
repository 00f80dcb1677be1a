//! The candidate effects: standard physical extensions of the Magic Formula, each with few
//! parameters, in the forms of the Magic Formula literature. Each acts on one channel's
//! factors (peak D, stiffness BCD, shifts) or output, with parameters of its own per channel,
//! so every channel stays a separate least-squares problem.
//!
//! Here: what the diagnosis needs to know about each effect (the columns it needs, its
//! starting values, its form for reports). The math, the parameter names and which channels
//! an effect applies to live in [`mf87::extensions`], which the FMU runs too.

use mf87::Channel;
use mf87::extensions::{ChannelExtensions, Extension};
use serde::{Serialize, Serializer};

use crate::data::Quantity;

pub use mf87::extensions::{Conditions, Nominal};

/// A candidate effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EffectId {
    CombinedSlip,
    RelaxationLength,
    InflationPressure,
    SpeedDependence,
    PlySteerConicity,
    RollingResistance,
    Temperature,
}

impl EffectId {
    pub const ALL: [EffectId; 7] = [
        EffectId::CombinedSlip,
        EffectId::RelaxationLength,
        EffectId::InflationPressure,
        EffectId::SpeedDependence,
        EffectId::PlySteerConicity,
        EffectId::RollingResistance,
        EffectId::Temperature,
    ];

    /// The model extension this effect is.
    pub fn extension(self) -> Extension {
        match self {
            EffectId::CombinedSlip => Extension::CombinedSlip,
            EffectId::RelaxationLength => Extension::RelaxationLength,
            EffectId::InflationPressure => Extension::InflationPressure,
            EffectId::SpeedDependence => Extension::SpeedDependence,
            EffectId::PlySteerConicity => Extension::PlySteerConicity,
            EffectId::RollingResistance => Extension::RollingResistance,
            EffectId::Temperature => Extension::Temperature,
        }
    }

    pub fn id(self) -> &'static str {
        self.extension().id()
    }

    pub fn from_id(id: &str) -> Option<EffectId> {
        EffectId::ALL.into_iter().find(|e| e.id() == id)
    }

    /// The form fitted, for reports.
    pub fn form(self) -> &'static str {
        match self {
            EffectId::CombinedSlip => {
                "weighting G = cos(C atan(B s)) of Fy and Mz by slip ratio, of Fx by slip angle"
            }
            EffectId::RelaxationLength => {
                "first-order lag of the slip over travelled distance with relaxation length sigma"
            }
            EffectId::InflationPressure => {
                "stiffness (1 + k dp) and peak (1 + d dp), dp = (p - p0) / p0"
            }
            EffectId::SpeedDependence => "peak friction (1 + v dV), dV = (V - V0) / V0",
            EffectId::PlySteerConicity => "horizontal and vertical shifts at zero slip and camber",
            EffectId::RollingResistance => "Fx - (q1 + q2 V / V0) Fz",
            EffectId::Temperature => {
                "peak (1 - w ((T - Topt) / 50)^2), stiffness (1 + k (T - T0) / 50)"
            }
        }
    }

    /// Whether the effect applies to a channel at all.
    pub fn applies_to(self, channel: Channel) -> bool {
        self.extension().applies_to(channel)
    }

    /// The columns the effect needs beyond the channel's own (measurement, slip, load).
    pub fn needs(self, channel: Channel) -> &'static [Quantity] {
        match (self, channel) {
            (EffectId::CombinedSlip, Channel::Fx) => &[Quantity::Alpha],
            (EffectId::CombinedSlip, _) => &[Quantity::Kappa],
            (EffectId::RelaxationLength, _) => &[Quantity::Time, Quantity::Speed],
            (EffectId::InflationPressure, _) => &[Quantity::Pressure],
            (EffectId::SpeedDependence, _) => &[Quantity::Speed],
            (EffectId::PlySteerConicity, _) => &[],
            (EffectId::RollingResistance, _) => &[Quantity::Speed],
            (EffectId::Temperature, _) => &[Quantity::Temperature],
        }
    }

    /// Starting values of the fit, in the order of mf87's parameter names.
    fn starting_values(self) -> &'static [f64] {
        match self {
            EffectId::CombinedSlip => &[8.0, 1.0],
            EffectId::RelaxationLength => &[0.3],
            EffectId::InflationPressure => &[0.0, 0.0],
            EffectId::SpeedDependence => &[0.0],
            EffectId::PlySteerConicity => &[0.0, 0.0],
            EffectId::RollingResistance => &[0.0, 0.0],
            EffectId::Temperature => &[0.0, 0.0, 0.0],
        }
    }

    /// Parameter names (mf87's) and starting values for a channel.
    pub fn parameters(self, _channel: Channel) -> Vec<(&'static str, f64)> {
        let names = self.extension().parameter_names();
        names
            .iter()
            .copied()
            .zip(self.starting_values().iter().copied())
            .collect()
    }
}

impl std::fmt::Display for EffectId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.id())
    }
}

impl Serialize for EffectId {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.id())
    }
}

/// The relaxation length [m] of a fitted parameter: the fit is unconstrained, the model uses
/// its magnitude.
pub fn relaxation_length(q: &[f64]) -> f64 {
    q[0].abs()
}

/// A channel's effects, with fitted parameters `q` in the order of
/// [`EffectId::parameters`], as mf87 extensions (the relaxation length as the model uses it).
pub fn channel_extensions<'a>(
    effects: impl IntoIterator<Item = (EffectId, &'a [f64])>,
) -> ChannelExtensions {
    let mut ext = ChannelExtensions::default();
    for (effect, q) in effects {
        let relaxation = [relaxation_length(q)];
        let values = match effect {
            EffectId::RelaxationLength => &relaxation[..],
            _ => q,
        };
        // The vectors are built from mf87's names (`parameters`): the lengths agree.
        ext.set(effect.extension(), values)
            .expect("effect parameters follow mf87's parameter names");
    }
    ext
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_round_trip_and_are_the_issue_s() {
        let ids: Vec<&str> = EffectId::ALL.iter().map(|e| e.id()).collect();
        assert_eq!(
            ids,
            [
                "combined_slip",
                "relaxation_length",
                "inflation_pressure",
                "speed_dependence",
                "ply_steer_conicity",
                "rolling_resistance",
                "temperature"
            ]
        );
        for e in EffectId::ALL {
            assert_eq!(EffectId::from_id(e.id()), Some(e));
            assert_eq!(
                serde_json::to_string(&e).unwrap(),
                format!("\"{}\"", e.id())
            );
        }
    }

    #[test]
    fn starting_values_are_neutral_where_the_form_allows() {
        use mf87::MagicFormula;
        let nominal = Nominal {
            pressure_kpa: 220.0,
            speed_mps: 15.0,
            temperature_c: 50.0,
        };
        let x = Conditions {
            fz_kn: 4.0,
            other_slip: 0.0,
            speed: 25.0,
            pressure: 260.0,
            temperature: 80.0,
        };
        let mf = MagicFormula {
            b: 0.2,
            c: 1.3,
            d: 4000.0,
            e: -0.5,
            sh: 0.0,
            sv: 0.0,
        };
        let start =
            |e: EffectId| -> Vec<f64> { e.parameters(Channel::Fy).iter().map(|p| p.1).collect() };
        for e in [
            EffectId::InflationPressure,
            EffectId::SpeedDependence,
            EffectId::Temperature,
            EffectId::PlySteerConicity,
        ] {
            let q = start(e);
            let mut m = mf;
            channel_extensions([(e, &q[..])]).apply_to_factors(&nominal, &x, &mut m);
            assert_eq!(m, mf, "{}", e.id());
        }
        // Peak scaling keeps the cornering stiffness BCD.
        let mut m = mf;
        channel_extensions([(EffectId::SpeedDependence, &[-0.1][..])])
            .apply_to_factors(&nominal, &x, &mut m);
        assert!((m.b * m.c * m.d - mf.b * mf.c * mf.d).abs() < 1e-9);
        assert!(m.d < mf.d);
        // Combined slip weight is 1 at zero other slip and falls with it.
        let combined =
            channel_extensions([(EffectId::CombinedSlip, &start(EffectId::CombinedSlip)[..])]);
        assert_eq!(combined.apply_to_output(&nominal, &x, 100.0), 100.0);
        let x2 = Conditions {
            other_slip: 0.1,
            ..x
        };
        assert!(combined.apply_to_output(&nominal, &x2, 100.0) < 80.0);
        // Rolling resistance opposes forward rolling.
        let rolling = channel_extensions([(EffectId::RollingResistance, &[0.01, 0.0][..])]);
        assert!((rolling.apply_to_output(&nominal, &x, 0.0) + 40.0).abs() < 1e-9);
        // The fit's relaxation parameter may go negative; the model uses its magnitude.
        let relax = channel_extensions([(EffectId::RelaxationLength, &[-0.4][..])]);
        assert_eq!(relax.relaxation_length_m(), Some(0.4));
    }

    #[test]
    fn every_effect_is_an_mf87_extension_with_matching_parameters() {
        for e in EffectId::ALL {
            let names = e.extension().parameter_names();
            assert_eq!(e.starting_values().len(), names.len(), "{e}");
            for c in Channel::ALL {
                assert_eq!(e.applies_to(c), e.extension().applies_to(c));
            }
        }
        let kinds: std::collections::BTreeSet<_> =
            EffectId::ALL.iter().map(|e| e.extension()).collect();
        assert_eq!(kinds.len(), mf87::extensions::Extension::ALL.len());
    }
}
