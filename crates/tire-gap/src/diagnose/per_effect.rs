//! What the diagnosis knows of each candidate effect beyond `crate::effects`: the rows where
//! it must show (its home, where its paired test is run), and the experiment that separates
//! two effects the data cannot tell apart.

use mf87::Channel;

use crate::effects::EffectId;
use crate::model::ChannelData;

/// The rows where an effect, if present, must show (its "home"): the paired test is run there,
/// so a candidate that merely soaks up a misfit of the base formula elsewhere is not claimed.
/// `None`: every row.
pub(super) fn home_rows(effect: EffectId, data: &ChannelData) -> Option<Vec<bool>> {
    match effect {
        // Offsets at zero slip: the linear range, |alpha| < 2 deg.
        EffectId::PlySteerConicity => Some(data.slip.iter().map(|a| a.abs() < 2.0).collect()),
        // Force against rolling at zero slip: |sigma| < 1 %.
        EffectId::RollingResistance => Some(data.slip.iter().map(|s| s.abs() < 1.0).collect()),
        // Combined slip: rows where the other slip is not small.
        EffectId::CombinedSlip => {
            let threshold = if data.channel == Channel::Fx {
                1f64.to_radians()
            } else {
                0.02
            };
            data.other_slip
                .as_ref()
                .map(|o| o.iter().map(|x| x.abs() > threshold).collect())
        }
        // Effects on stiffness, peak or the slip's history act on the force the slip makes:
        // they cannot show where the channel's own slip is near zero (Fx in pure cornering).
        // |alpha| >= 1 deg for Fy and Mz, |sigma| >= 1 % for Fx.
        EffectId::RelaxationLength
        | EffectId::InflationPressure
        | EffectId::SpeedDependence
        | EffectId::Temperature => Some(data.slip.iter().map(|s| s.abs() >= 1.0).collect()),
    }
}

/// The separating experiment for a pair of effects the data cannot tell apart.
pub(super) fn separating_test(a: EffectId, b: EffectId) -> String {
    use EffectId::*;
    let (a, b) = if a <= b { (a, b) } else { (b, a) };
    match (a, b) {
        (SpeedDependence, Temperature) => {
            "repeat sweeps at two speeds with the tread held at one temperature (pre-conditioned), \
             and at one speed at two tread temperatures"
                .into()
        }
        (RelaxationLength, SpeedDependence) => {
            "steady-state slip sweeps (slow enough for the lag to vanish) at several speeds, and \
             sinusoidal slip at one speed and several frequencies"
                .into()
        }
        (CombinedSlip, RelaxationLength) => {
            "quasi-static combined-slip sweeps, and transient pure-slip steps".into()
        }
        (InflationPressure, Temperature) => {
            "sweeps at two pressures with the tread at one temperature (cold pressure set, \
             temperature logged)"
                .into()
        }
        (SpeedDependence, RollingResistance) | (RollingResistance, Temperature) => {
            "free-rolling runs (zero slip) at several speeds and temperatures".into()
        }
        _ => format!(
            "runs that vary the input of {} while holding the input of {} constant, and the reverse",
            a.id(),
            b.id()
        ),
    }
}
