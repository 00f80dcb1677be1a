//! Ply steer and conicity: offsets of the shifts at zero slip and camber (Fy, Mz).

use crate::bounds::{Row, SHIFT_SH_MAX_DEG, row};
use crate::channel::Channel;
use crate::conditions::Conditions;
use crate::error::{Num, ParamError, invalid};
use crate::extensions::effect::{Check, Effect, parameters};
use crate::formula::MagicFormula;
use crate::params::Params;
use crate::real::Real;

parameters! {
    /// Shifts at zero slip and camber: `Sh += Sh_deg` [deg], `Sv += Sv` [N or N.m] (Fy, Mz).
    PlySteerConicity { Sh_deg, Sv }
}

/// Largest ply-steer / conicity offset `|Sv|` as a share of `fz_max`: 0.1 N/N for Fy, 0.01
/// N.m/N for Mz (conicity forces are a few per cent of the load, residual aligning torques a
/// few mm times it).
pub fn ply_steer_sv_share(channel: Channel) -> f64 {
    match channel {
        Channel::Mz => 0.01,
        Channel::Fy | Channel::Fx => 0.1,
    }
}

impl Effect for PlySteerConicity {
    type Of<P: Copy> = PlySteerConicity<P>;

    fn applies_to(channel: Channel) -> bool {
        channel != Channel::Fx
    }

    /// Adds the offsets to the shifts Sh [deg] and Sv [N or N.m].
    #[inline]
    fn shift<P: Copy, T: Real + From<P>>(
        q: &PlySteerConicity<P>,
        _x: &Conditions<T>,
        mf: &mut MagicFormula<T>,
    ) {
        mf.sh += T::from(q.Sh_deg);
        mf.sv += T::from(q.Sv);
    }

    /// On the shifts: Sh with the camber shift, Sv against the load.
    fn check_with_base(&self, c: &Check, p: &Params) -> Result<(), ParamError> {
        let channel = c.channel;
        let camber_sh = match channel {
            Channel::Fy => (p.Fy.a9 * p.limits.gamma_max_deg).abs(),
            Channel::Mz => (p.Mz.a9 * p.limits.gamma_max_deg).abs(),
            Channel::Fx => 0.0,
        };
        let sh = camber_sh + self.Sh_deg.abs();
        if sh > SHIFT_SH_MAX_DEG {
            return Err(invalid(
                &c.name("Sh_deg"),
                self.Sh_deg,
                &format!(
                    "the horizontal shift |Sh| = |a9| gamma_max + |Sh_deg| reaches {sh} deg; it must \
                     be at most {} deg",
                    SHIFT_SH_MAX_DEG,
                    sh = Num(sh)
                ),
            ));
        }
        let (_, unit) = channel.per_load_meaning();
        let share = ply_steer_sv_share(channel);
        let sv_max = share * p.limits.fz_max_N;
        if self.Sv.abs() > sv_max {
            let sv_unit = if channel == Channel::Mz { "N.m" } else { "N" };
            return Err(invalid(
                &c.name("Sv"),
                self.Sv,
                &format!(
                    "the offset |Sv| must be at most {share}{unit} x fz_max = {sv_max} {sv_unit}"
                ),
            ));
        }
        Ok(())
    }

    fn bound_rows() -> Vec<Row> {
        vec![row(
            "ply_steer_conicity |Sv| / fz_max",
            format!(
                "<= {} (Fy), {} (Mz)",
                ply_steer_sv_share(Channel::Fy),
                ply_steer_sv_share(Channel::Mz)
            ),
            "1, m",
        )]
    }
}
