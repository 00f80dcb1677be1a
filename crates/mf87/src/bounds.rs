//! The bounds every parameter set must keep: the general ones here, each effect's own in its
//! file under `extensions` (`extensions::<name>`).
//!
//! They keep the outputs finite and of a physical size everywhere in the validity range:
//! loads in (0, fz_max], cambers within +-gamma_max, every slip, and the extensions' range of
//! speed, pressure and temperature. [`crate::Params::validate`] checks them and names the
//! parameter, its value and the bound it breaks; [`crate::bounds_table`] lists them, with
//! the effects' own, for docs/parameters.md.
//!
//! With them, each output is at most, per N of load, the peak bound plus the camber-shift
//! bound (plus the rolling-resistance bound for Fx), and the ply-steer offset on top: the
//! combined-slip weighting G = cos(C atan(B s)) never exceeds 1 in magnitude. Shape factors
//! (B, C, E) change where the force peaks, not how large it is; their bounds keep every step
//! of the formula finite and are far beyond fitted values. Units as in the paper: load in kN
//! inside the formula, angles in deg, slip in percent.

use std::fmt;

use crate::channel::Channel;
pub use crate::error::Num;

/// A closed interval `[lo, hi]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    pub lo: f64,
    pub hi: f64,
}

impl Interval {
    pub const fn new(lo: f64, hi: f64) -> Interval {
        Interval { lo, hi }
    }

    /// Whether `x` lies in the interval (never for NaN).
    pub fn contains(self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }
}

impl fmt::Display for Interval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}, {}]", self.lo, self.hi)
    }
}

/// `limits.fz_max_N` \[N\]: from a small wheel to the heaviest truck and bus tires (tens of kN)
/// with margin; the formula's polynomials in kN are fitted to road tires.
pub const FZ_MAX_N: Interval = Interval::new(10.0, 100_000.0);

/// `limits.gamma_max_deg` \[deg\]: up to the lean of a motorcycle with margin; 90 deg would be
/// the wheel lying flat.
pub const GAMMA_MAX_DEG: Interval = Interval::new(0.1, 89.0);

/// Every coefficient of the 1987 table in magnitude, in its units (load in kN): the paper's are
/// below 1200, but within the other bounds the load polynomials of a tire with fz_max = 10 N
/// reach 1e7.
/// Most coefficients are held far tighter through what they set (below); this cap also holds
/// the few that could otherwise grow without changing the outputs (e.g. a13 < 0).
pub const COEFFICIENT_ABS_MAX: f64 = 1e9;

/// Shape factor `C`: the paper has 1.3 (Fy), 1.65 (Fx), 2.4 (Mz); below 0.1 the curve never
/// gets near its peak, above 5 it turns over more than twice.
pub const SHAPE_C: Interval = Interval::new(0.1, 5.0);

/// Largest peak per load `|D| / Fz` over the load range, with the extensions' peak scales at
/// their largest: the friction coefficient of Fx and Fy (racing slicks reach about 2) and the
/// lever arm of Mz \[m\] (pneumatic trails are centimetres).
pub fn peak_per_load_max(channel: Channel) -> f64 {
    match channel {
        Channel::Fx | Channel::Fy => FRICTION_MAX,
        Channel::Mz => LEVER_ARM_MAX_M,
    }
}

/// See [`peak_per_load_max`].
pub const FRICTION_MAX: f64 = 5.0;
/// See [`peak_per_load_max`].
pub const LEVER_ARM_MAX_M: f64 = 0.5;

/// Stiffness factor `B = BCD / (C D)` over loads and cambers, with the extensions' scales at
/// their extremes [1/deg for Fy and Mz, 1/percent for Fx]. Positive: the slope at zero slip
/// points the way of the peak. The paper spans 0.07..0.5, fits reach 0.003 at vanishing load.
pub const STIFFNESS_B: Interval = Interval::new(1e-5, 1e3);

/// Curvature factor `E` over loads and cambers. The curve stays within +-D for any E; the
/// paper reaches -15.4 at the camber limit, fits reach 2.3, and -1047 where a fitted a13 sits
/// just below 1 / gamma_max (E / (1 - a13 |gamma|) is singular there). The bound keeps E / B
/// finite.
pub const CURVATURE_E: Interval = Interval::new(-1e6, 1e6);

/// `|a4 atan(a5 Fz)|` of Fy's stiffness `a3 sin(a4 atan(a5 Fz))` stays below pi over the
/// load range: the cornering stiffness does not vanish or reverse with load.
pub const FY_STIFFNESS_PHASE_MAX: f64 = std::f64::consts::PI;

/// `|a5| fz_max` [kN/kN] of the stiffness `(a3 Fz^2 + a4 Fz) e^(-a5 Fz)` of Mz and Fx: the
/// exponential changes the stiffness by at most e^10 over the load range (paper: 1.1).
pub const EXPONENT_A5_FZ_MAX: f64 = 10.0;

/// Largest horizontal shift `|Sh|` \[deg\] of Fy and Mz: camber `|a9| gamma_max` plus ply
/// steer. Ply steer is a fraction of a degree; at 10 deg the tire would run saturated at
/// zero slip.
pub const SHIFT_SH_MAX_DEG: f64 = 10.0;

/// Largest camber shift `|Sv| / Fz = |a10 Fz + a11| gamma_max / 1000` over the load range: as
/// the peak, [`peak_per_load_max`] (camber thrust of a leaning motorcycle is about the load).
pub fn camber_shift_per_load_max(channel: Channel) -> f64 {
    peak_per_load_max(channel)
}

/// Every extension parameter in magnitude (only rules out values no fit produces).
pub const EXTENSION_PARAMETER_ABS_MAX: f64 = 1e6;

/// Nominal and limit pressures \[kPa\]: from a deflated off-road tire to an aircraft tire.
pub const PRESSURE_KPA: Interval = Interval::new(10.0, 2000.0);

/// Limits of the forward speed |vx| [m/s] (150 m/s = 540 km/h).
pub const SPEED_MPS: Interval = Interval::new(0.0, 150.0);

/// Nominal speed V0 [m/s]: the extensions divide by it; below walking pace no speed effect
/// is measured.
pub const NOMINAL_SPEED_MPS: Interval = Interval::new(0.5, 150.0);

/// Nominal and limit tread temperatures, and the optimum of the temperature window \[degC\]:
/// rubber is glassy below about -60 degC and degrades above about 250 degC.
pub const TEMPERATURE_DEGC: Interval = Interval::new(-60.0, 250.0);

/// Each peak or stiffness scale of `inflation_pressure`, `speed_dependence` and `temperature`
/// over its condition's range: an operating condition changes friction or stiffness at most
/// tenfold. Their product is bounded again through the peak and B.
pub const CONDITION_SCALE: Interval = Interval::new(0.1, 10.0);

/// One row of the bounds: what is bounded, the allowed values, the unit.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub what: &'static str,
    pub allowed: String,
    pub unit: &'static str,
}

/// The general bounds as rows: the limits and coefficients, then the extensions' general
/// bounds. [`crate::bounds_table`] adds each effect's own rows.
pub fn general_rows() -> Vec<Row> {
    let mut rows = coefficient_rows();
    rows.extend(extension_rows());
    rows
}

pub(crate) fn row(what: &'static str, allowed: String, unit: &'static str) -> Row {
    Row {
        what,
        allowed,
        unit,
    }
}

/// `<= max`.
pub(crate) fn abs(max: f64) -> String {
    format!("<= {max}")
}

/// The limits, the coefficients, the factors and shifts they give.
fn coefficient_rows() -> Vec<Row> {
    vec![
        row("limits.fz_max_N", FZ_MAX_N.to_string(), "N"),
        row("limits.gamma_max_deg", GAMMA_MAX_DEG.to_string(), "deg"),
        row("each coefficient", abs(COEFFICIENT_ABS_MAX), "paper's"),
        row("C", SHAPE_C.to_string(), "1"),
        row(
            "peak |D| / Fz, Fx and Fy (friction)",
            format!("(0, {FRICTION_MAX}]"),
            "1",
        ),
        row(
            "peak |D| / Fz, Mz (lever arm)",
            format!("(0, {LEVER_ARM_MAX_M}]"),
            "m",
        ),
        row("B", STIFFNESS_B.to_string(), "1/deg, 1/%"),
        row("E", CURVATURE_E.to_string(), "1"),
        row(
            "Fy: |a4 atan(a5 Fz)|",
            format!("< pi ({FY_STIFFNESS_PHASE_MAX:.4})"),
            "rad",
        ),
        row(
            "Mz, Fx: |a5| fz_max",
            abs(EXPONENT_A5_FZ_MAX),
            "1 (Fz in kN)",
        ),
        row("1 - a12 gamma_max, 1 - a13 gamma_max", "> 0".into(), "1"),
        row(
            "|Sh| = |a9| gamma_max + |Sh_deg + Sh_per_kN Fz| + |Sh_camber_per_kN| fz_max gamma_max",
            abs(SHIFT_SH_MAX_DEG),
            "deg",
        ),
        row(
            "camber |Sv| / Fz",
            format!("<= {FRICTION_MAX} (Fy), {LEVER_ARM_MAX_M} (Mz)"),
            "1, m",
        ),
    ]
}

/// The extensions' general bounds: every parameter, the range of conditions, the scales.
fn extension_rows() -> Vec<Row> {
    vec![
        row(
            "each extension parameter",
            abs(EXTENSION_PARAMETER_ABS_MAX),
            "its own",
        ),
        row(
            "nominal and limit pressures",
            PRESSURE_KPA.to_string(),
            "kPa",
        ),
        row("nominal speed V0", NOMINAL_SPEED_MPS.to_string(), "m/s"),
        row("speed limits", SPEED_MPS.to_string(), "m/s"),
        row(
            "nominal and limit temperatures",
            TEMPERATURE_DEGC.to_string(),
            "degC",
        ),
        row(
            "each peak or stiffness scale over its range",
            CONDITION_SCALE.to_string(),
            "1",
        ),
    ]
}
