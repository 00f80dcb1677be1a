//! Ply steer and conicity: offsets of the shifts at zero slip and camber (Fy, Mz), with
//! their load terms and the load term of the camber shift, as MF 6.1's shifts have
//! (SHy = pHy1 + pHy2 dfz with the camber shift's load dependence, SVy = Fz (pVy1 + pVy2 dfz)).

use crate::bounds::{Row, SHIFT_SH_MAX_DEG, row};
use crate::channel::Channel;
use crate::coefficients::BaseParams;
use crate::conditions::Conditions;
use crate::error::{Num, ParamError, invalid};
use crate::extensions::effect::{Check, Effect, parameters};
use crate::formula::MagicFormula;
use crate::real::Real;

parameters! {
    /// Shifts at zero slip: `Sh += Sh_deg + Sh_per_kN Fz + Sh_camber_per_kN Fz gamma` \[deg\],
    /// `Sv += Sv + Sv_per_kN Fz` [N or N.m] (Fy, Mz; Fz in kN, gamma in deg). The load terms
    /// are 0 when a parameter file leaves them out.
    PlySteerConicity { Sh_deg, Sv; Sh_per_kN, Sv_per_kN, Sh_camber_per_kN }
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
        x: &Conditions<T>,
        mf: &mut MagicFormula<T>,
    ) {
        let gamma_deg = crate::units::radians_to_degrees(x.gamma);
        mf.sh += T::from(q.Sh_deg)
            + (T::from(q.Sh_per_kN) + T::from(q.Sh_camber_per_kN) * gamma_deg) * x.fz_kn;
        mf.sv += T::from(q.Sv) + T::from(q.Sv_per_kN) * x.fz_kn;
    }

    /// On the shifts over the load and camber range: Sh with the camber shift, Sv against
    /// the load.
    fn check_with_base(&self, c: &Check, p: &BaseParams) -> Result<(), ParamError> {
        let channel = c.channel;
        let (gamma_max, fz_max) = (
            p.limits.gamma_max_deg,
            crate::units::newtons_to_kilonewtons(p.limits.fz_max_N),
        );
        let a9 = match channel {
            Channel::Fy => p.Fy.a9,
            Channel::Mz => p.Mz.a9,
            Channel::Fx => 0.0,
        };
        let sh = (a9 * gamma_max).abs()
            + self.Sh_deg.abs().max((self.Sh_deg + self.Sh_per_kN * fz_max).abs())
            + (self.Sh_camber_per_kN * fz_max * gamma_max).abs();
        if sh > SHIFT_SH_MAX_DEG {
            let with_load = self.Sh_per_kN != 0.0 || self.Sh_camber_per_kN != 0.0;
            let terms = if with_load {
                "|a9| gamma_max + |Sh_deg + Sh_per_kN Fz| + |Sh_camber_per_kN| fz_max gamma_max \
                 reaches {sh} deg over the load range"
            } else {
                "|a9| gamma_max + |Sh_deg| reaches {sh} deg"
            };
            return Err(invalid(
                &c.name("Sh_deg"),
                self.Sh_deg,
                &format!(
                    "the horizontal shift |Sh| = {}; it must be at most {} deg",
                    terms.replace("{sh}", &Num(sh).to_string()),
                    SHIFT_SH_MAX_DEG
                ),
            ));
        }
        let (_, unit) = channel.per_load_meaning();
        let share = ply_steer_sv_share(channel);
        let sv_max = share * p.limits.fz_max_N;
        let sv = self.Sv.abs().max((self.Sv + self.Sv_per_kN * fz_max).abs());
        if sv > sv_max {
            let sv_unit = if channel == Channel::Mz { "N.m" } else { "N" };
            return Err(invalid(
                &c.name("Sv"),
                self.Sv,
                &if self.Sv_per_kN == 0.0 {
                    format!(
                        "the offset |Sv| must be at most {share}{unit} x fz_max = {sv_max} {sv_unit}"
                    )
                } else {
                    format!(
                        "the offset |Sv + Sv_per_kN Fz| reaches {} {sv_unit} over the load \
                         range; it must be at most {share}{unit} x fz_max = {sv_max} {sv_unit}",
                        Num(sv)
                    )
                },
            ));
        }
        Ok(())
    }

    fn bound_rows() -> Vec<Row> {
        vec![row(
            "ply_steer_conicity |Sv + Sv_per_kN Fz| / fz_max over the load range",
            format!(
                "<= {} (Fy), {} (Mz)",
                ply_steer_sv_share(Channel::Fy),
                ply_steer_sv_share(Channel::Mz)
            ),
            "1, m",
        )]
    }
}
