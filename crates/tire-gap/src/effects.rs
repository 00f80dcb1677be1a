//! The candidate effects: standard physical extensions of the Magic Formula, each with few
//! parameters, in the forms of the Magic Formula literature. Each acts on one channel's
//! factors (peak D, stiffness BCD, shifts) or output, with parameters of its own per channel,
//! so every channel stays a separate least-squares problem.

use mf87::{Channel, MagicFormula};
use serde::Serialize;

use crate::data::Quantity;

/// Scale of temperature differences in the temperature window [degC].
const TEMPERATURE_SCALE: f64 = 50.0;

/// A candidate effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
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

    pub fn id(self) -> &'static str {
        match self {
            EffectId::CombinedSlip => "combined_slip",
            EffectId::RelaxationLength => "relaxation_length",
            EffectId::InflationPressure => "inflation_pressure",
            EffectId::SpeedDependence => "speed_dependence",
            EffectId::PlySteerConicity => "ply_steer_conicity",
            EffectId::RollingResistance => "rolling_resistance",
            EffectId::Temperature => "temperature",
        }
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
        match self {
            EffectId::PlySteerConicity => channel != Channel::Fx,
            EffectId::RollingResistance => channel == Channel::Fx,
            _ => true,
        }
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

    /// Parameter names and starting values for a channel.
    pub fn parameters(self, channel: Channel) -> &'static [(&'static str, f64)] {
        match (self, channel) {
            (EffectId::CombinedSlip, _) => &[("B", 8.0), ("C", 1.0)],
            (EffectId::RelaxationLength, _) => &[("sigma_m", 0.3)],
            (EffectId::InflationPressure, _) => &[("k", 0.0), ("d", 0.0)],
            (EffectId::SpeedDependence, _) => &[("v", 0.0)],
            (EffectId::PlySteerConicity, _) => &[("Sh_deg", 0.0), ("Sv", 0.0)],
            (EffectId::RollingResistance, _) => &[("q1", 0.0), ("q2", 0.0)],
            (EffectId::Temperature, _) => &[("w", 0.0), ("Topt_degC", 0.0), ("k", 0.0)],
        }
    }
}

impl std::fmt::Display for EffectId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.id())
    }
}

/// Reference conditions the effects are expressed around (medians of the fitting data).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Nominal {
    /// Pressure p0 [kPa].
    pub pressure_kpa: f64,
    /// Speed V0 [m/s].
    pub speed_mps: f64,
    /// Temperature T0 [degC].
    pub temperature_c: f64,
}

/// The operating conditions of one row that effects may use.
#[derive(Debug, Clone, Copy, Default)]
pub struct Conditions {
    pub fz_kn: f64,
    /// The other slip: slip ratio for Fy and Mz, slip angle [rad] for Fx.
    pub other_slip: f64,
    pub speed: f64,
    pub pressure: f64,
    pub temperature: f64,
}

/// Applies the factor-level part of `effect` with parameters `q` to `mf`.
pub fn apply_to_factors(
    effect: EffectId,
    q: &[f64],
    nominal: &Nominal,
    x: &Conditions,
    mf: &mut MagicFormula,
) {
    // Scaling the peak D by s_d and the stiffness BCD by s_k: B = BCD / (C D) scales by s_k / s_d.
    let mut scale = |s_k: f64, s_d: f64| {
        mf.d *= s_d;
        mf.b *= s_k / s_d;
    };
    match effect {
        EffectId::InflationPressure => {
            let dp = (x.pressure - nominal.pressure_kpa) / nominal.pressure_kpa;
            scale(1.0 + q[0] * dp, 1.0 + q[1] * dp);
        }
        EffectId::SpeedDependence => {
            let dv = (x.speed - nominal.speed_mps) / nominal.speed_mps;
            scale(1.0, 1.0 + q[0] * dv);
        }
        EffectId::Temperature => {
            let window = (x.temperature - (nominal.temperature_c + q[1])) / TEMPERATURE_SCALE;
            let dt = (x.temperature - nominal.temperature_c) / TEMPERATURE_SCALE;
            scale(1.0 + q[2] * dt, 1.0 - q[0] * window * window);
        }
        EffectId::PlySteerConicity => {
            mf.sh += q[0];
            mf.sv += q[1];
        }
        EffectId::CombinedSlip | EffectId::RelaxationLength | EffectId::RollingResistance => {}
    }
}

/// Applies the output-level part of `effect` (weighting, additive terms) to `y`.
pub fn apply_to_output(
    effect: EffectId,
    q: &[f64],
    nominal: &Nominal,
    x: &Conditions,
    y: f64,
) -> f64 {
    match effect {
        EffectId::CombinedSlip => y * (q[1] * (q[0] * x.other_slip).atan()).cos(),
        EffectId::RollingResistance => {
            y - (q[0] + q[1] * x.speed / nominal.speed_mps)
                * mf87::units::kilonewtons_to_newtons(x.fz_kn)
        }
        _ => y,
    }
}

/// The relaxation length [m] of a parameter (kept non-negative).
pub fn relaxation_length(q: &[f64]) -> f64 {
    q[0].abs()
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
        for e in [
            EffectId::InflationPressure,
            EffectId::SpeedDependence,
            EffectId::Temperature,
            EffectId::PlySteerConicity,
        ] {
            let q: Vec<f64> = e.parameters(Channel::Fy).iter().map(|p| p.1).collect();
            let mut m = mf;
            apply_to_factors(e, &q, &nominal, &x, &mut m);
            assert_eq!(m, mf, "{}", e.id());
        }
        // Peak scaling keeps the cornering stiffness BCD.
        let mut m = mf;
        apply_to_factors(EffectId::SpeedDependence, &[-0.1], &nominal, &x, &mut m);
        assert!((m.b * m.c * m.d - mf.b * mf.c * mf.d).abs() < 1e-9);
        assert!(m.d < mf.d);
        // Combined slip weight is 1 at zero other slip and falls with it.
        assert_eq!(
            apply_to_output(EffectId::CombinedSlip, &[8.0, 1.0], &nominal, &x, 100.0),
            100.0
        );
        let x2 = Conditions {
            other_slip: 0.1,
            ..x
        };
        assert!(apply_to_output(EffectId::CombinedSlip, &[8.0, 1.0], &nominal, &x2, 100.0) < 80.0);
        // Rolling resistance opposes forward rolling.
        let fx = apply_to_output(EffectId::RollingResistance, &[0.01, 0.0], &nominal, &x, 0.0);
        assert!((fx + 40.0).abs() < 1e-9);
    }
}
