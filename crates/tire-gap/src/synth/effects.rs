//! The synthetic forms of the unmodelled effects, and the true tire they act on.
//!
//! These forms are deliberately NOT the ones the diagnosis tool fits (MF-2002 cosine
//! weighting, first-order slip lag with a constant length, linear/quadratic pressure terms,
//! friction linear in speed, constant offsets, `(q1 + q2 V/V0) Fz` rolling resistance, a
//! quadratic temperature window, a shift of the slip ratio): the tool has to recognise the
//! physics, not our formula.
//! Each effect's magnitudes are drawn from its own random stream (one ChaCha8 stream per effect).

use std::collections::BTreeMap;

use super::blocks::TrueSample;
use super::rng::{SynthRng, sign, stream, uniform};
use super::tires::{BaseTire, FZ_NOMINAL, Mods, SlideFriction};
use mf87::extensions::Extension;

/// Nominal inflation pressure (kPa): the pressure effect is 1 here.
pub const PRESSURE_NOMINAL_KPA: f64 = 240.0;
/// Reference tread temperature of the stiffness softening (degC).
pub const TEMPERATURE_REFERENCE_C: f64 = 50.0;

/// Forces and moment [N, N, N.m].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Forces {
    pub fx: f64,
    pub fy: f64,
    pub mz: f64,
}

/// Combined slip by the normalised-slip (similarity) method of Pacejka and Sharp, with
/// theoretical slips `sx = kappa / (1 + kappa)`, `sy = tan(alpha - alpha0) / (1 + kappa)`
/// (alpha0: where the pure Fy crosses zero, so camber thrust and ply steer are kept) each
/// normalised by the slip at which its pure force peaks (found numerically, in the direction
/// of the slip, times a tire-specific factor `norm`), and `s = |(sx / sx_peak, sy / sy_peak)|`:
///
/// `Fx = (|sx_n| / s) Fx0(kappa_eq)`, `Fy = (|sy_n| / s) Fy0(alpha_eq)` where the equivalent
/// pure slips have the same normalised magnitude `s`. The aligning moment is scaled the same
/// way about its value at alpha0, plus the moment of Fx about the laterally deflected contact
/// patch, `-Fx Fy / c_lat`. At kappa = 0 or alpha = alpha0 it returns the pure-slip forces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CombinedSlip {
    /// Factor on the peak slips used for normalisation (0.8..1.2).
    pub norm: f64,
    /// Lateral carcass stiffness [N/m] (250..400 kN/m).
    pub c_lat: f64,
}

/// Where a unimodal `f` peaks in |f| on [0, hi] (golden-section search).
fn peak_location(f: impl Fn(f64) -> f64, hi: f64) -> f64 {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (0.0, hi);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c).abs(), f(d).abs());
    for _ in 0..40 {
        if fc > fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c).abs();
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d).abs();
        }
    }
    (a + b) / 2.0
}

impl CombinedSlip {
    fn sample(rng: &mut SynthRng) -> Self {
        CombinedSlip {
            norm: uniform(rng, 0.8, 1.2),
            c_lat: uniform(rng, 250e3, 400e3),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[("norm", self.norm), ("c_lat_N_per_m", self.c_lat)])
    }

    /// Slip angle where the pure lateral force is zero (Newton, from the linear estimate).
    fn alpha_zero(tire: &BaseTire, fz: f64, gamma: f64, m: &Mods) -> f64 {
        let fy = |a: f64| tire.lateral(fz, a, gamma, m).0;
        let (_, k) = tire.lat_scale(fz, gamma, m);
        let mut a = (-fy(0.0) / k).clamp(-0.1, 0.1);
        for _ in 0..12 {
            let f = fy(a);
            if f.abs() < 1e-7 {
                break;
            }
            let h = 1e-6;
            let slope = (fy(a + h) - fy(a - h)) / (2.0 * h);
            if slope.abs() < 1e-9 {
                break;
            }
            a = (a - f / slope).clamp(-0.15, 0.15);
        }
        a
    }

    fn forces(
        &self,
        tire: &BaseTire,
        fz: f64,
        alpha: f64,
        kappa: f64,
        gamma: f64,
        m: &Mods,
    ) -> Forces {
        let alpha0 = Self::alpha_zero(tire, fz, gamma, m);
        let sx = kappa / (1.0 + kappa);
        let sy = (alpha - alpha0).tan() / (1.0 + kappa);
        // Peak slips, as theoretical slips, on the side the slip is on.
        let dir_x = if sx < 0.0 { -1.0 } else { 1.0 };
        let kappa_peak = peak_location(|k| tire.fx0(fz, dir_x * k, m), 0.6);
        let sx_ref = self.norm * kappa_peak / (1.0 + dir_x * kappa_peak);
        let dir_y = if sy < 0.0 { -1.0 } else { 1.0 };
        let alpha_peak = peak_location(|a| tire.lateral(fz, alpha0 + dir_y * a, gamma, m).0, 0.6);
        let sy_ref = self.norm * alpha_peak.tan();
        let (sxn, syn) = (sx / sx_ref, sy / sy_ref);
        let s = sxn.hypot(syn);
        let (_, mz_at_zero) = tire.lateral(fz, alpha0, gamma, m);
        if s < 1e-12 {
            return Forces {
                fx: 0.0,
                fy: 0.0,
                mz: mz_at_zero,
            };
        }
        let sx_eq = (s * sx_ref).min(0.9).copysign(sx);
        let kappa_eq = sx_eq / (1.0 - sx_eq);
        let alpha_eq = alpha0 + (s * sy_ref).atan().copysign(sy);
        let fx = sxn.abs() / s * tire.fx0(fz, kappa_eq, m);
        let (fy_eq, mz_eq) = tire.lateral(fz, alpha_eq, gamma, m);
        let wy = syn.abs() / s;
        let fy = wy * fy_eq;
        let mz = mz_at_zero + wy * (mz_eq - mz_at_zero) - fx * fy / self.c_lat;
        Forces { fx, fy, mz }
    }
}

/// Relaxation as a lag of the FORCES (not the slip) in travelled distance, second order: two
/// first-order stages in series with lengths `L/(1+r)` and `r L/(1+r)`, so the total lag
/// length is `L`. The length grows with load, `L = L_ref (Fz / 4 kN)^e`. Fy and Mz share `L`,
/// Fx relaxes over `long_ratio * L`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Relaxation {
    /// Lateral relaxation length at 4 kN [m] (0.3..0.8).
    pub length_ref: f64,
    /// Load exponent e (0.6..0.8).
    pub load_exp: f64,
    /// Ratio r of the second stage to the first (0.15..0.35).
    pub pole_ratio: f64,
    /// Longitudinal length over lateral (0.25..0.45).
    pub long_ratio: f64,
}

/// Filter state of one block: two stages for each of Fx, Fy, Mz.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct RelaxState {
    stages: Option<[[f64; 2]; 3]>,
}

impl Relaxation {
    fn sample(rng: &mut SynthRng) -> Self {
        Relaxation {
            length_ref: uniform(rng, 0.3, 0.8),
            load_exp: uniform(rng, 0.6, 0.8),
            pole_ratio: uniform(rng, 0.15, 0.35),
            long_ratio: uniform(rng, 0.25, 0.45),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("length_at_4kN_m", self.length_ref),
            ("load_exp", self.load_exp),
            ("pole_ratio", self.pole_ratio),
            ("long_ratio", self.long_ratio),
        ])
    }

    /// Lateral relaxation length [m] at load `fz`.
    pub fn length(&self, fz: f64) -> f64 {
        self.length_ref * (fz.max(100.0) / FZ_NOMINAL).powf(self.load_exp)
    }

    /// Advance by `ds` metres towards the steady-state `target`.
    pub fn step(&self, state: &mut RelaxState, target: Forces, fz: f64, ds: f64) -> Forces {
        let inputs = [target.fx, target.fy, target.mz];
        let stages = state
            .stages
            .get_or_insert([[inputs[0]; 2], [inputs[1]; 2], [inputs[2]; 2]]);
        let l_y = self.length(fz);
        let r = self.pole_ratio;
        for (ch, (st, u)) in stages.iter_mut().zip(inputs).enumerate() {
            let l = if ch == 0 { self.long_ratio * l_y } else { l_y };
            let (l1, l2) = (l / (1.0 + r), r * l / (1.0 + r));
            let (a1, a2) = ((-ds / l1).exp(), (-ds / l2).exp());
            st[0] = a1 * st[0] + (1.0 - a1) * u;
            st[1] = a2 * st[1] + (1.0 - a2) * st[0];
        }
        Forces {
            fx: stages[0][1],
            fy: stages[1][1],
            mz: stages[2][1],
        }
    }
}

/// Inflation pressure as power laws of `p / p0` (p0 = 240 kPa): friction `(p/p0)^-eta`,
/// cornering stiffness `(p/p0)^ey` evaluated at the load `Fz (p0/p)^beta` (higher pressure
/// moves the load of peak cornering stiffness up, so the net change depends on load),
/// longitudinal stiffness `(p/p0)^ex`, pneumatic trail `(p/p0)^-tau` (shorter contact patch).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pressure {
    pub mu_exp: f64,
    pub ky_exp: f64,
    pub load_shift_exp: f64,
    pub kx_exp: f64,
    pub trail_exp: f64,
}

impl Pressure {
    fn sample(rng: &mut SynthRng) -> Self {
        Pressure {
            mu_exp: uniform(rng, 0.1, 0.2),
            ky_exp: uniform(rng, 0.35, 0.55),
            load_shift_exp: uniform(rng, 0.3, 0.6),
            kx_exp: uniform(rng, 0.1, 0.3),
            trail_exp: uniform(rng, 0.2, 0.4),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("p0_kPa", PRESSURE_NOMINAL_KPA),
            ("mu_exp", -self.mu_exp),
            ("ky_exp", self.ky_exp),
            ("stiffness_load_shift_exp", -self.load_shift_exp),
            ("kx_exp", self.kx_exp),
            ("trail_exp", -self.trail_exp),
        ])
    }

    fn apply(&self, m: &mut Mods, p: f64) {
        let r = (p / PRESSURE_NOMINAL_KPA).max(0.1);
        let mu = r.powf(-self.mu_exp);
        m.mu_x *= mu;
        m.mu_y *= mu;
        m.k_y *= r.powf(self.ky_exp);
        m.fz_stiff *= r.powf(-self.load_shift_exp);
        m.k_x *= r.powf(self.kx_exp);
        m.trail *= r.powf(-self.trail_exp);
    }
}

/// Speed dependence of friction, two parts: a saturating exponential in rolling speed,
/// `1 - A (1 - exp(-V / Vc))` (most of the loss at low speed; A set so that friction falls by
/// `drop` between 5 and 30 m/s), and a fall with the sliding speed `Vs = V |slip|`,
/// `1 - d (1 - exp(-Vs / vs))`, which also bends the force curve beyond its peak more at high
/// speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Speed {
    /// Friction loss from rolling speed between 5 and 30 m/s (0.06..0.10).
    pub drop: f64,
    /// Characteristic speed Vc [m/s] (6..14).
    pub v_char: f64,
    /// Sliding-speed friction loss d (0.03..0.06) and speed vs [m/s] (1.5..3).
    pub slide: SlideFriction,
}

impl Speed {
    fn sample(rng: &mut SynthRng) -> Self {
        Speed {
            drop: uniform(rng, 0.06, 0.1),
            v_char: uniform(rng, 6.0, 14.0),
            slide: SlideFriction {
                drop: uniform(rng, 0.03, 0.06),
                v_char: uniform(rng, 1.5, 3.0),
            },
        }
    }

    fn amplitude(&self) -> f64 {
        self.drop / ((-5.0 / self.v_char).exp() - (-30.0 / self.v_char).exp())
    }

    /// Rolling-speed friction factor.
    pub fn factor(&self, v: f64) -> f64 {
        1.0 - self.amplitude() * (1.0 - (-v.max(0.0) / self.v_char).exp())
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("drop_5_to_30_mps", self.drop),
            ("amplitude", self.amplitude()),
            ("v_char_mps", self.v_char),
            ("slide_drop", self.slide.drop),
            ("slide_v_char_mps", self.slide.v_char),
        ])
    }

    fn apply(&self, m: &mut Mods, v: f64) {
        let g = self.factor(v);
        m.mu_x *= g;
        m.mu_y *= g;
        m.slide = Some(self.slide);
    }
}

/// Ply steer and conicity as a slip-angle shift whose force grows faster than the load,
/// `dFy(Fz) = F_ref (Fz / 4 kN)^n` (n 1.2..1.4; the shift is `dFy / Ky`, so the offset fades
/// once the tire saturates and also moves Mz through the trail), plus a residual aligning
/// torque `M_ref (Fz / 4 kN)^m` (m 1.3..1.7). F_ref is 60..150 N with a random sign; M_ref is
/// 1.5..3.5 N.m in the direction of the trail's share `-t dFy`, so the aligning-moment offset
/// at 4 kN totals about 3..8 N.m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PlySteer {
    pub fy_ref: f64,
    pub fy_load_exp: f64,
    pub mz_ref: f64,
    pub mz_load_exp: f64,
}

impl PlySteer {
    fn sample(rng: &mut SynthRng) -> Self {
        let fy_ref = sign(rng) * uniform(rng, 60.0, 150.0);
        PlySteer {
            fy_ref,
            fy_load_exp: uniform(rng, 1.2, 1.4),
            // Same direction as the trail's share (-t dFy), so they add up.
            mz_ref: -fy_ref.signum() * uniform(rng, 1.5, 3.5),
            mz_load_exp: uniform(rng, 1.3, 1.7),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("fy_at_4kN_N", self.fy_ref),
            ("fy_load_exp", self.fy_load_exp),
            ("mz_at_4kN_Nm", self.mz_ref),
            ("mz_load_exp", self.mz_load_exp),
        ])
    }

    /// Lateral force offset at small slip [N].
    pub fn fy(&self, fz: f64) -> f64 {
        self.fy_ref * (fz.max(0.0) / FZ_NOMINAL).powf(self.fy_load_exp)
    }

    /// Residual aligning torque [N.m].
    pub fn mz(&self, fz: f64) -> f64 {
        self.mz_ref * (fz.max(0.0) / FZ_NOMINAL).powf(self.mz_load_exp)
    }
}

/// Rolling resistance in the SAE J2452 style,
/// `Fr = c Fz0 (Fz / Fz0)^b (p / p0)^a (1 + k (V / 30 m/s)^2)`, acting against rolling
/// (Fx decreases by Fr for forward speed), at every slip. c is 0.008..0.012, b 0.85..0.95,
/// a -0.45..-0.3, k 0.15..0.35.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rolling {
    pub coef: f64,
    pub load_exp: f64,
    pub pressure_exp: f64,
    pub speed_frac: f64,
}

impl Rolling {
    fn sample(rng: &mut SynthRng) -> Self {
        Rolling {
            coef: uniform(rng, 0.008, 0.012),
            load_exp: uniform(rng, 0.85, 0.95),
            pressure_exp: -uniform(rng, 0.3, 0.45),
            speed_frac: uniform(rng, 0.15, 0.35),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("coef", self.coef),
            ("load_exp", self.load_exp),
            ("pressure_exp", self.pressure_exp),
            ("speed_frac_at_30_mps", self.speed_frac),
        ])
    }

    /// Rolling resistance force [N] (positive; subtracted from Fx).
    pub fn force(&self, fz: f64, v: f64, p: f64) -> f64 {
        if fz <= 0.0 {
            return 0.0;
        }
        self.coef
            * FZ_NOMINAL
            * (fz / FZ_NOMINAL).powf(self.load_exp)
            * (p / PRESSURE_NOMINAL_KPA).max(0.1).powf(self.pressure_exp)
            * (1.0 + self.speed_frac * (v / 30.0).powi(2))
            * v.signum()
    }
}

/// Tread temperature: an asymmetric Gaussian window on friction,
/// `1 - A (1 - exp(-((T - Topt) / w)^2))` with `w` wider on the cold side than on the hot
/// side (Topt 45..70 degC, A 0.15..0.22, w 30..40 cold / 18..28 hot), and a linear softening
/// of both slip stiffnesses, `1 - s (T - 50 degC)` (s 0.0012..0.0025 per degC).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Temperature {
    pub t_opt: f64,
    pub loss: f64,
    pub width_cold: f64,
    pub width_hot: f64,
    pub stiff_slope: f64,
}

impl Temperature {
    fn sample(rng: &mut SynthRng) -> Self {
        Temperature {
            t_opt: uniform(rng, 45.0, 70.0),
            loss: uniform(rng, 0.15, 0.22),
            width_cold: uniform(rng, 30.0, 40.0),
            width_hot: uniform(rng, 18.0, 28.0),
            stiff_slope: uniform(rng, 0.0012, 0.0025),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("t_opt_C", self.t_opt),
            ("friction_loss", self.loss),
            ("width_cold_C", self.width_cold),
            ("width_hot_C", self.width_hot),
            ("stiffness_slope_per_C", -self.stiff_slope),
            ("stiffness_ref_C", TEMPERATURE_REFERENCE_C),
        ])
    }

    /// Friction factor at temperature `t`.
    pub fn friction(&self, t: f64) -> f64 {
        let w = if t < self.t_opt {
            self.width_cold
        } else {
            self.width_hot
        };
        1.0 - self.loss * (1.0 - (-((t - self.t_opt) / w).powi(2)).exp())
    }

    /// Stiffness factor at temperature `t`.
    pub fn stiffness(&self, t: f64) -> f64 {
        (1.0 - self.stiff_slope * (t - TEMPERATURE_REFERENCE_C)).max(0.5)
    }

    fn apply(&self, m: &mut Mods, t: f64) {
        let (f, k) = (self.friction(t), self.stiffness(t));
        m.mu_x *= f;
        m.mu_y *= f;
        m.k_x *= k;
        m.k_y *= k;
    }
}

/// The rig's own offsets of the longitudinal curve: its slip ratio computed with a rolling
/// radius `R` off the tire's effective rolling radius `Re` by a fraction, so that it reads
/// `kappa_m = (1 + kappa) Re / R - 1` (free rolling reads as slip `Re / R - 1`, and every
/// slip is stretched by `Re / R`), and its Fx load cell's crosstalk from the load,
/// `Fx_m = Fx + c Fz`. `Re / R - 1` is 0.004..0.012 and `c` 0.002..0.006 in magnitude, each
/// with a random sign.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RigOffsets {
    /// `Re / R`.
    pub radius_ratio: f64,
    /// `c` [N/N].
    pub crosstalk: f64,
}

impl RigOffsets {
    fn sample(rng: &mut SynthRng) -> Self {
        let radius_error = sign(rng) * uniform(rng, 0.004, 0.012);
        RigOffsets {
            radius_ratio: 1.0 + radius_error,
            crosstalk: sign(rng) * uniform(rng, 0.002, 0.006),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("radius_ratio_Re_over_R", self.radius_ratio),
            ("fx_crosstalk_per_fz", self.crosstalk),
        ])
    }

    /// The slip ratio the rig reports for the true slip ratio `kappa`.
    pub fn measured_kappa(&self, kappa: f64) -> f64 {
        (1.0 + kappa) * self.radius_ratio - 1.0
    }

    /// What the load cell adds to Fx at load `fz` [N].
    pub fn fx_offset(&self, fz: f64) -> f64 {
        self.crosstalk * fz
    }
}

fn named(pairs: &[(&str, f64)]) -> BTreeMap<String, f64> {
    pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

/// The effects switched on, with their magnitudes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct EffectSet {
    pub combined: Option<CombinedSlip>,
    pub relaxation: Option<Relaxation>,
    pub pressure: Option<Pressure>,
    pub speed: Option<Speed>,
    pub ply: Option<PlySteer>,
    pub rolling: Option<Rolling>,
    pub temperature: Option<Temperature>,
    pub rig: Option<RigOffsets>,
}

impl EffectSet {
    /// Magnitudes for `seed`; each effect from its own stream, so they do not depend on which
    /// other effects are on.
    pub fn sample(seed: u64, on: &[Extension]) -> EffectSet {
        let mut set = EffectSet::default();
        for e in Extension::ALL {
            if !on.contains(&e) {
                continue;
            }
            let rng = &mut stream(seed, &format!("effect:{}", e.name()));
            match e {
                Extension::CombinedSlip => set.combined = Some(CombinedSlip::sample(rng)),
                Extension::RelaxationLength => set.relaxation = Some(Relaxation::sample(rng)),
                Extension::InflationPressure => set.pressure = Some(Pressure::sample(rng)),
                Extension::SpeedDependence => set.speed = Some(Speed::sample(rng)),
                Extension::PlySteerConicity => set.ply = Some(PlySteer::sample(rng)),
                Extension::RollingResistance => set.rolling = Some(Rolling::sample(rng)),
                Extension::Temperature => set.temperature = Some(Temperature::sample(rng)),
                Extension::SlipRatioShift => set.rig = Some(RigOffsets::sample(rng)),
            }
        }
        set
    }

    /// The parameters of each effect that is on.
    pub fn params(&self) -> Vec<(Extension, BTreeMap<String, f64>)> {
        let mut out = Vec::new();
        let mut add = |e: Extension, p: Option<BTreeMap<String, f64>>| {
            if let Some(p) = p {
                out.push((e, p));
            }
        };
        add(Extension::CombinedSlip, self.combined.map(|x| x.params()));
        add(
            Extension::RelaxationLength,
            self.relaxation.map(|x| x.params()),
        );
        add(
            Extension::InflationPressure,
            self.pressure.map(|x| x.params()),
        );
        add(Extension::SpeedDependence, self.speed.map(|x| x.params()));
        add(Extension::PlySteerConicity, self.ply.map(|x| x.params()));
        add(
            Extension::RollingResistance,
            self.rolling.map(|x| x.params()),
        );
        add(Extension::Temperature, self.temperature.map(|x| x.params()));
        add(Extension::SlipRatioShift, self.rig.map(|x| x.params()));
        out
    }

    /// Modifiers of the base tire at one instant.
    fn mods(&self, x: &TrueSample) -> Mods {
        let mut m = Mods {
            speed: x.speed,
            ..Mods::default()
        };
        if let Some(p) = &self.pressure {
            p.apply(&mut m, x.pressure);
        }
        if let Some(s) = &self.speed {
            s.apply(&mut m, x.speed);
        }
        if let Some(t) = &self.temperature {
            t.apply(&mut m, x.temp);
        }
        m
    }
}

/// The tire on the rig: a base tire with effects.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TrueTire {
    pub base: BaseTire,
    pub effects: EffectSet,
}

impl TrueTire {
    /// Steady-state forces (before relaxation and rolling resistance).
    pub fn steady(&self, x: &TrueSample) -> Forces {
        let m = self.effects.mods(x);
        let mut alpha = x.alpha;
        if let Some(ply) = &self.effects.ply {
            let (_, ky) = self.base.lat_scale(x.fz, 0.0, &m);
            alpha += ply.fy(x.fz) / ky;
        }
        let mut f = match &self.effects.combined {
            Some(c) => c.forces(&self.base, x.fz, alpha, x.kappa, x.gamma, &m),
            None => {
                let (fy, mz) = self.base.lateral(x.fz, alpha, x.gamma, &m);
                Forces {
                    fx: self.base.fx0(x.fz, x.kappa, &m),
                    fy,
                    mz,
                }
            }
        };
        if let Some(ply) = &self.effects.ply {
            f.mz += ply.mz(x.fz);
        }
        f
    }

    /// Rolling resistance to subtract from Fx [N] (0 when the effect is off).
    pub fn rolling_resistance(&self, x: &TrueSample) -> f64 {
        self.effects
            .rolling
            .map_or(0.0, |r| r.force(x.fz, x.speed, x.pressure))
    }

    /// The slip ratio the rig reports (the true one when its offsets are off).
    pub fn measured_kappa(&self, x: &TrueSample) -> f64 {
        self.effects
            .rig
            .map_or(x.kappa, |r| r.measured_kappa(x.kappa))
    }

    /// What the rig's load cell adds to Fx [N] (0 when its offsets are off).
    pub fn fx_offset(&self, x: &TrueSample) -> f64 {
        self.effects.rig.map_or(0.0, |r| r.fx_offset(x.fz))
    }
}
