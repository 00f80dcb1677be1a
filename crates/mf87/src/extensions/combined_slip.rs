//! Combined slip in the form of MF 6.1: the output weighted by a function G of the other
//! slip (Gyk of Fy by the slip ratio, Gxa of Fx by the slip angle; Mz weighted as Fy), with
//! MF 6.1's shape, curvature and horizontal shift, the narrowing of the weight with the
//! channel's own slip, its load and camber terms; for Fy the lateral force the slip ratio
//! induces (SVyk), and for Mz the moment of the longitudinal force about the laterally
//! deflected contact patch (MF 6.1's `s Fx`).

use crate::bounds::{Interval, Row, abs, row};
use crate::channel::Channel;
use crate::coefficients::BaseParams;
use crate::conditions::Conditions;
use crate::error::{Num, ParamError, invalid};
use crate::extensions::effect::{Check, Effect, parameters};
use crate::formula::MagicFormula;
use crate::real::{Real, value};

parameters! {
    /// Combined slip: the output times
    /// `G = cos(C atan(Bw x - Ew (Bw x - atan(Bw x)))) / cos(C atan(Bw Sw - Ew (Bw Sw - atan(Bw Sw))))`
    /// at `x = s + Sw`, s the other slip (slip ratio for Fy and Mz, slip angle \[rad\] for
    /// Fx), with `Bw = (B + B_camber gamma^2) cos(atan(B_slip (s_own - B_shift)))`,
    /// `Ew = min(1, E + E_per_kN Fz)`, `Sw = Sh + Sh_per_kN Fz` (s_own the channel's own slip,
    /// slip angle \[rad\] or slip ratio; gamma \[rad\]; Fz \[kN\]). Fy also gains
    /// `D (Sv + Sv_per_kN Fz + Sv_camber gamma) cos(atan(Sv_alpha alpha)) sin(Sv_shape atan(Sv_slope kappa))`
    /// (D its peak); Mz may gain the same term and
    /// `D Sm sin(atan(Sm_alpha alpha)) sin(Sv_shape atan(Sv_slope kappa))`, the moment of Fx
    /// (odd in kappa) about a contact patch deflected with Fy (odd in alpha); MF 6.1 writes
    /// both as `s Fx`, `s = R0 (ssz1 + ssz2 Fy / Fz0 + ...)`. Mz's curve may also be taken at
    /// the equivalent slip angle `sqrt(alpha_s^2 + (K_eq kappa)^2)` (MF 6.1's `alpha_t,eq`,
    /// `K_eq` its `Kxk / Kya` \[rad\]; see [`MagicFormula::eval_equivalent`]). Every parameter
    /// but B and C is 0 when a parameter file leaves it out.
    CombinedSlip {
        B, C;
        B_slip, B_shift, B_camber, E, E_per_kN, Sh, Sh_per_kN,
        Sv, Sv_per_kN, Sv_camber, Sv_alpha, Sv_shape, Sv_slope, Sm, Sm_alpha, K_eq
    }
}

/// `combined_slip.B`, `B_slip`, `Sv_alpha`, `Sv_slope` and `Sm_alpha` in magnitude [1/(slip ratio) or
/// 1/rad]: a weight may fall within 0.001 of slip at the steepest.
pub const COMBINED_SLIP_B_ABS_MAX: f64 = 1000.0;

/// `|C| atan(|B| s_max)` of `combined_slip` over the other slip's range (s_max = 1 for the
/// slip ratio, pi/2 rad for the slip angle), with B at its largest over the camber range: G
/// changes sign at most eight times. Fits of Fx by slip angle follow G ~ cos(B C s) with
/// small B and large C and reach 3 pi.
pub const COMBINED_SLIP_PHASE_MAX: f64 = 8.0 * std::f64::consts::PI;

/// The weight's horizontal shift `|Sh + Sh_per_kN Fz|` at most over the load range [slip
/// ratio, or rad]: MF 6.1 fits give a few hundredths.
pub const COMBINED_SLIP_SH_MAX: f64 = 0.2;

/// `|B_shift|`, the own slip at which the weight's stiffness is least narrowed, at most: within
/// the own slip's range, `|alpha| <= pi/2` rad for Fy and Mz and `|kappa| <= 1` for Fx (fits
/// to rig data move it a few tenths of a radian off zero to follow a weight that differs
/// between positive and negative slip angles); far outside it the narrowing only scales B
/// down, and B_shift and B_slip trade with B.
pub fn combined_slip_b_shift_max(channel: Channel) -> f64 {
    match channel {
        Channel::Fx => 1.0,
        Channel::Fy | Channel::Mz => std::f64::consts::FRAC_PI_2,
    }
}

/// The phase of the weight's normalisation, `|C| atan(|Bw Sw| (1 + |Ew|))`, at most \[rad\]:
/// the divisor stays at or above cos(1) = 0.54, so G is at most
/// [`COMBINED_SLIP_WEIGHT_MAX`] (fits to rig data shift the weight by a few hundredths of
/// slip at B near 20: phases up to 0.6).
pub const COMBINED_SLIP_NORM_PHASE_MAX: f64 = 1.0;

/// The largest combined-slip weight G the bounds allow, 1 / cos(1) = 1.85.
pub const COMBINED_SLIP_WEIGHT_MAX: f64 = 1.850_815_717_680_925_6;

/// The induced lateral force's size `|Sv| + |Sv_per_kN| fz_max + |Sv_camber| gamma_max`, as a
/// share of the peak D, at most (MF 6.1 fits give a few hundredths to a few tenths).
pub const COMBINED_SLIP_SV_MAX: f64 = 0.5;

/// The size of the moment of Fx about the deflected contact patch, `|Sm|`, as a share of
/// Mz's peak D, at most: an arm of a few centimetres (MF 6.1's `s`) times a braking force
/// reaches one to two times the pure moment's peak.
pub const COMBINED_SLIP_SM_MAX: f64 = 3.0;

/// The phase `|Sv_shape| atan(|Sv_slope|)` of the induced term's shape over |kappa| <= 1, at
/// most \[rad\]: the term keeps its sign on each side of kappa = 0 (MF 6.1 fits: about 2.8).
pub const COMBINED_SLIP_SV_PHASE_MAX: f64 = std::f64::consts::PI;

/// The weight's curvature `Ew = E + E_per_kN Fz` at least, over the load range: far below
/// -1 it trades with B and C and the weight's shape is no longer determined.
pub const COMBINED_SLIP_E_MIN: f64 = -5.0;

/// `K_eq`, the slip angle \[rad\] per unit slip ratio in Mz's equivalent slip (MF 6.1's
/// `Kxk / Kya`: the longitudinal over the cornering stiffness, about 0.3..1.5): within
/// `[0, 5]` (its sign does not matter, so it is not negative).
pub const COMBINED_SLIP_K_EQ: Interval = Interval::new(0.0, 5.0);

/// `cos(C atan(B x - E (B x - atan(B x))))`.
#[inline]
fn g<T: Real>(b: T, c: T, e: T, x: T) -> T {
    let bx = b * x;
    (c * (bx - e * (bx - bx.atan())).atan()).cos()
}

impl<P: Copy> CombinedSlip<P> {
    /// The weight's stiffness Bw, curvature Ew and shift Sw under `x`. A term that is an
    /// exact 0 (no value, no derivative) is not computed.
    #[inline]
    fn shape<T: Real + From<P>>(&self, x: &Conditions<T>) -> (T, T, T) {
        let b_slip = T::from(self.B_slip);
        let narrowing = if b_slip.is_exact_zero() {
            T::from(1.0)
        } else {
            (b_slip * (x.own_slip - T::from(self.B_shift))).atan().cos()
        };
        let b = (T::from(self.B) + T::from(self.B_camber) * x.gamma * x.gamma) * narrowing;
        let e = T::from(self.E) + T::from(self.E_per_kN) * x.fz_kn;
        let e = if value(e) > 1.0 { T::from(1.0) } else { e };
        let sh = T::from(self.Sh) + T::from(self.Sh_per_kN) * x.fz_kn;
        (b, e, sh)
    }
}

/// `cos(C atan(B x - E (B x - atan(B x))))`, without the curvature's terms when E is an exact
/// 0.
#[inline]
fn g_or_plain<T: Real>(b: T, c: T, e: T, x: T) -> T {
    if e.is_exact_zero() {
        (c * (b * x).atan()).cos()
    } else {
        g(b, c, e, x)
    }
}

impl CombinedSlip {
    /// The induced term's size and shape and the moment of Fx, over the load range up to
    /// `fz_max` \[kN\] and the camber range up to `gamma_max` \[rad\].
    fn check_induced(&self, c: &Check, fz_max: f64, gamma_max: f64) -> Result<(), ParamError> {
        let sv =
            self.Sv.abs() + self.Sv_per_kN.abs() * fz_max + self.Sv_camber.abs() * gamma_max;
        if sv > COMBINED_SLIP_SV_MAX {
            return Err(invalid(
                &c.name("Sv"),
                self.Sv,
                &format!(
                    "the induced lateral force |Sv| + |Sv_per_kN| fz_max + |Sv_camber| gamma_max \
                     reaches {} times the peak; it must be at most {COMBINED_SLIP_SV_MAX}",
                    Num(sv)
                ),
            ));
        }
        let sv_phase = self.Sv_shape.abs() * self.Sv_slope.abs().atan();
        let has_induced = [self.Sv, self.Sv_per_kN, self.Sv_camber, self.Sm]
            .iter()
            .any(|v| *v != 0.0);
        if has_induced && (sv_phase.is_nan() || sv_phase > COMBINED_SLIP_SV_PHASE_MAX) {
            return Err(invalid(
                &c.name("Sv_shape"),
                self.Sv_shape,
                &format!(
                    "the induced term's shape sin(Sv_shape atan(Sv_slope kappa)) reaches a phase \
                     of {} rad over |kappa| <= 1 (Sv_slope = {}); it must stay <= pi, so the \
                     term keeps its sign on each side of kappa = 0",
                    Num(sv_phase),
                    Num(self.Sv_slope)
                ),
            ));
        }
        if self.Sm.abs() > COMBINED_SLIP_SM_MAX {
            return Err(invalid(
                &c.name("Sm"),
                self.Sm,
                &format!(
                    "the moment of Fx |Sm| reaches {} times the peak; it must be at most \
                     {COMBINED_SLIP_SM_MAX}",
                    Num(self.Sm.abs())
                ),
            ));
        }
        Ok(())
    }
}

impl Effect for CombinedSlip {
    type Of<P: Copy> = CombinedSlip<P>;

    /// The weight G at the other slip.
    #[inline]
    fn weight<P: Copy, T: Real + From<P>>(q: &CombinedSlip<P>, x: &Conditions<T>) -> Option<T> {
        let (b, e, sh) = q.shape(x);
        let c = T::from(q.C);
        let at = g_or_plain(b, c, e, x.other_slip + sh);
        // The normalisation is 1 at an exact zero shift.
        Some(if sh.is_exact_zero() {
            at
        } else {
            at / g_or_plain(b, c, e, sh)
        })
    }

    /// Mz's equivalent slip: `K_eq kappa` in degrees (none at an exact 0, as on Fx and Fy).
    #[inline]
    fn equivalent_slip<P: Copy, T: Real + From<P>>(
        q: &CombinedSlip<P>,
        x: &Conditions<T>,
    ) -> Option<T> {
        let k = T::from(q.K_eq);
        (!k.is_exact_zero()).then(|| crate::units::radians_to_degrees(k) * x.other_slip)
    }

    /// The term the slip ratio induces (Fy and Mz) and the moment of Fx about the deflected
    /// contact patch (Mz); zero where their sizes are 0, as on Fx.
    #[inline]
    fn add<P: Copy, T: Real + From<P>>(
        q: &CombinedSlip<P>,
        x: &Conditions<T>,
        mf: &MagicFormula<T>,
    ) -> Option<T> {
        let size = T::from(q.Sv) + T::from(q.Sv_per_kN) * x.fz_kn + T::from(q.Sv_camber) * x.gamma;
        let moment = T::from(q.Sm);
        // Exact zeros (Fx, or a file without them): nothing to add.
        if size.is_exact_zero() && moment.is_exact_zero() {
            return None;
        }
        let by_alpha = |slope: P, even: bool| {
            let angle = (T::from(slope) * x.own_slip).atan();
            if even { angle.cos() } else { angle.sin() }
        };
        let by_kappa = (T::from(q.Sv_shape) * (T::from(q.Sv_slope) * x.other_slip).atan()).sin();
        let mut term = T::from(0.0);
        if !size.is_exact_zero() {
            term += size * by_alpha(q.Sv_alpha, true);
        }
        if !moment.is_exact_zero() {
            term += moment * by_alpha(q.Sm_alpha, false);
        }
        Some(mf.d * term * by_kappa)
    }

    /// The induced term is 0 on Fx, the moment of Fx and the equivalent slip on Fx and Fy.
    fn check_allowed(&self, c: &Check) -> Result<(), ParamError> {
        use Channel::{Fy, Mz};
        const INDUCED: &str = "the term the slip ratio induces applies to Fy and Mz only";
        let terms: [(&str, f64, &[Channel], &str); 5] = [
            ("Sv", self.Sv, &[Fy, Mz], INDUCED),
            ("Sv_per_kN", self.Sv_per_kN, &[Fy, Mz], INDUCED),
            ("Sv_camber", self.Sv_camber, &[Fy, Mz], INDUCED),
            ("Sm", self.Sm, &[Mz], "the moment of Fx applies to Mz only"),
            ("K_eq", self.K_eq, &[Mz], "the equivalent slip applies to Mz only"),
        ];
        match terms
            .iter()
            .find(|(_, v, on, _)| *v != 0.0 && !on.contains(&c.channel))
        {
            Some((name, v, _, why)) => Err(invalid(
                &c.name(name),
                *v,
                &format!("{why}: it must be 0 on {}", c.channel),
            )),
            None => Ok(()),
        }
    }

    /// The slopes within [`COMBINED_SLIP_B_ABS_MAX`], `B_shift` within
    /// [`combined_slip_b_shift_max`], `K_eq` within [`COMBINED_SLIP_K_EQ`].
    fn check_range(&self, c: &Check) -> Result<(), ParamError> {
        let b_shift_max = combined_slip_b_shift_max(c.channel);
        if self.B_shift.is_nan() || self.B_shift.abs() > b_shift_max {
            return Err(invalid(
                &c.name("B_shift"),
                self.B_shift,
                &format!(
                    "the own slip at which the weight's stiffness is least narrowed must lie \
                     within the own slip's range, {} on {}",
                    match c.channel {
                        Channel::Fx => "+-1 (slip ratio)",
                        Channel::Fy | Channel::Mz => "+-pi/2 rad",
                    },
                    c.channel
                ),
            ));
        }
        if !COMBINED_SLIP_K_EQ.contains(self.K_eq) {
            return Err(invalid(
                &c.name("K_eq"),
                self.K_eq,
                &format!(
                    "the slip angle per unit slip ratio of the equivalent slip must lie in \
                     [{}, {}] rad",
                    COMBINED_SLIP_K_EQ.lo, COMBINED_SLIP_K_EQ.hi
                ),
            ));
        }
        for (name, v) in [
            ("B", self.B),
            ("B_slip", self.B_slip),
            ("Sv_alpha", self.Sv_alpha),
            ("Sv_slope", self.Sv_slope),
            ("Sm_alpha", self.Sm_alpha),
        ] {
            if v.abs() > COMBINED_SLIP_B_ABS_MAX {
                return Err(invalid(
                    &c.name(name),
                    v,
                    &format!("|{name}| must be <= {COMBINED_SLIP_B_ABS_MAX}"),
                ));
            }
        }
        Ok(())
    }

    /// Over the load and camber range: the phase of G, its shift and normalisation, the
    /// induced force's size.
    fn check_with_base(&self, c: &Check, base: &BaseParams) -> Result<(), ParamError> {
        let gamma_max = base.limits.gamma_max_deg.to_radians();
        let fz_max = crate::units::newtons_to_kilonewtons(base.limits.fz_max_N);
        let b_max = self.B.abs() + self.B_camber.abs() * gamma_max * gamma_max;
        let (s_max, s_name) = match c.channel {
            Channel::Fx => (std::f64::consts::FRAC_PI_2, "|alpha| <= pi/2 rad"),
            Channel::Fy | Channel::Mz => (1.0, "|kappa| <= 1"),
        };
        let phase = self.C.abs() * (b_max * s_max).atan();
        if phase.is_nan() || phase > COMBINED_SLIP_PHASE_MAX {
            return Err(invalid(
                &c.name("C"),
                self.C,
                &format!(
                    "the phase |C| atan(|B| s) of the weight G reaches {phase} rad over {s_name} \
                     (B = {}, with B_camber at gamma_max {}); it must stay <= 8 pi = {} rad",
                    Num(self.B),
                    Num(b_max),
                    COMBINED_SLIP_PHASE_MAX,
                    phase = Num(phase)
                ),
            ));
        }
        let sh_max = self.Sh.abs().max((self.Sh + self.Sh_per_kN * fz_max).abs());
        if sh_max > COMBINED_SLIP_SH_MAX {
            return Err(invalid(
                &c.name("Sh"),
                self.Sh,
                &format!(
                    "the weight's shift |Sh + Sh_per_kN Fz| reaches {} over the load range; it \
                     must be at most {COMBINED_SLIP_SH_MAX}",
                    Num(sh_max)
                ),
            ));
        }
        let e_low = self.E.min(self.E + self.E_per_kN * fz_max);
        if e_low.is_nan() || e_low < COMBINED_SLIP_E_MIN {
            return Err(invalid(
                &c.name("E"),
                self.E,
                &format!(
                    "the weight's curvature E + E_per_kN Fz falls to {} over the load range; it \
                     must stay >= {COMBINED_SLIP_E_MIN}",
                    Num(e_low)
                ),
            ));
        }
        let e_max = self.E.abs().max((self.E + self.E_per_kN * fz_max).abs());
        let norm = self.C.abs() * (b_max * sh_max * (1.0 + e_max)).atan();
        if norm > COMBINED_SLIP_NORM_PHASE_MAX {
            return Err(invalid(
                &c.name("Sh"),
                self.Sh,
                &format!(
                    "the weight's normalisation cos(C atan(Bw Sw - Ew (Bw Sw - atan(Bw Sw)))) \
                     may fall to cos({}) over the load and camber range (|Bw| up to {}, \
                     |Sw| {}, |Ew| {}); its phase must stay <= {COMBINED_SLIP_NORM_PHASE_MAX} rad",
                    Num(norm),
                    Num(b_max),
                    Num(sh_max),
                    Num(e_max)
                ),
            ));
        }
        self.check_induced(c, fz_max, gamma_max)
    }

    fn bound_rows() -> Vec<Row> {
        vec![
            row(
                "combined_slip |B|, |B_slip|, |Sv_alpha|, |Sv_slope|, |Sm_alpha|",
                abs(COMBINED_SLIP_B_ABS_MAX),
                "1, 1/rad",
            ),
            row(
                "combined_slip |C| atan((|B| + |B_camber| gamma_max^2) s_max)",
                format!("<= 8 pi ({COMBINED_SLIP_PHASE_MAX:.2})"),
                "rad",
            ),
            row(
                "combined_slip |B_shift|",
                "<= 1 (Fx), pi/2 (Fy, Mz)".to_string(),
                "1, rad",
            ),
            row(
                "combined_slip |Sh + Sh_per_kN Fz| over the load range",
                format!("<= {COMBINED_SLIP_SH_MAX}"),
                "1, rad",
            ),
            row(
                "combined_slip normalisation phase |C| atan(|Bw Sw| (1 + |Ew|))",
                format!("<= {COMBINED_SLIP_NORM_PHASE_MAX}"),
                "rad",
            ),
            row(
                "combined_slip |Sv| + |Sv_per_kN| fz_max + |Sv_camber| gamma_max (Fy, Mz)",
                format!("<= {COMBINED_SLIP_SV_MAX}"),
                "1 (of the peak D)",
            ),
            row(
                "combined_slip E + E_per_kN Fz over the load range",
                format!(">= {COMBINED_SLIP_E_MIN}"),
                "1",
            ),
            row(
                "combined_slip |Sv_shape| atan(|Sv_slope|) (with an induced term)",
                "<= pi (3.1416)".to_string(),
                "rad",
            ),
            row(
                "combined_slip K_eq (Mz)",
                format!("[{}, {}]", COMBINED_SLIP_K_EQ.lo, COMBINED_SLIP_K_EQ.hi),
                "rad",
            ),
            row(
                "combined_slip |Sm| (Mz)",
                format!("<= {COMBINED_SLIP_SM_MAX}"),
                "1 (of the peak D)",
            ),
        ]
    }
}
