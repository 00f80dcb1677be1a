//! Parameter sets: the coefficient table of the paper as a serde type, and its validation.
//!
//! Field names are the paper's (`C`, `a1`..`a13`). A JSON parameter file must name every
//! coefficient of every channel and nothing else: incomplete or misspelled files are rejected.
//! An optional `extensions` section carries fitted extensions ([`crate::extensions`]).

use serde::{Deserialize, Serialize};

use crate::bounds;
use crate::channel::Channel;
pub use crate::error::ParamError;
use crate::error::{Num, invalid};
use crate::extensions::schema::Extensions;
use crate::formula::channel_factors;
use crate::units;

/// The paper's coefficient table (Tables 1 and 2 of SAE 870421, read with the seed errata).
pub const PAPER_TABLE_JSON: &str = include_str!("../data/pacejka87.json");

macro_rules! coefficient_set {
    ($(#[$meta:meta])* $name:ident { $($field:ident),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        #[allow(non_snake_case)]
        pub struct $name {
            $(pub $field: f64,)+
        }

        impl $name {
            /// Coefficient names, in table order; a coefficient's index is its position here.
            pub const NAMES: &'static [&'static str] = &[$(stringify!($field)),+];

            /// The coefficient at `index` (see [`Self::NAMES`]).
            pub fn get(&self, index: usize) -> Option<f64> {
                [$(self.$field),+].get(index).copied()
            }

            /// Mutable access to the coefficient at `index` (see [`Self::NAMES`]).
            pub fn get_mut(&mut self, index: usize) -> Option<&mut f64> {
                [$(&mut self.$field),+].into_iter().nth(index)
            }
        }
    };
}

coefficient_set!(
    /// Coefficients of a channel with load and camber influence (Fy, Mz).
    LateralCoefficients { C, a1, a2, a3, a4, a5, a6, a7, a8, a9, a10, a11, a12, a13 }
);

coefficient_set!(
    /// Coefficients of the longitudinal channel (Fx): load influence only.
    LongitudinalCoefficients { C, a1, a2, a3, a4, a5, a6, a7, a8 }
);

/// The range over which a parameter set is validated and the model is used.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Limits {
    /// Largest vertical load [N]; larger loads are clamped to it.
    pub fz_max_N: f64,
    /// Largest camber magnitude [deg]; larger cambers are clamped to it.
    pub gamma_max_deg: f64,
}

/// A limit of the validity range, in SI units at the interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LimitVar {
    /// Largest vertical load [N].
    FzMax,
    /// Largest camber magnitude [rad].
    GammaMax,
}

impl LimitVar {
    pub const ALL: [LimitVar; 2] = [LimitVar::FzMax, LimitVar::GammaMax];

    /// The limit's interface name.
    pub fn name(self) -> &'static str {
        match self {
            LimitVar::FzMax => "Fz_max",
            LimitVar::GammaMax => "gamma_max",
        }
    }

    pub fn from_name(name: &str) -> Option<LimitVar> {
        LimitVar::ALL.into_iter().find(|v| v.name() == name)
    }

    /// The limit in SI units (N, rad).
    pub fn get(self, limits: &Limits) -> f64 {
        match self {
            LimitVar::FzMax => limits.fz_max_N,
            LimitVar::GammaMax => units::degrees_to_radians(limits.gamma_max_deg),
        }
    }

    /// Sets the limit from SI units (N, rad).
    pub fn set(self, limits: &mut Limits, value: f64) {
        match self {
            LimitVar::FzMax => limits.fz_max_N = value,
            LimitVar::GammaMax => limits.gamma_max_deg = units::radians_to_degrees(value),
        }
    }
}

/// A complete parameter set of the 1987 Magic Formula.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Params {
    /// Where the coefficients come from (free text, optional).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    pub Fy: LateralCoefficients,
    pub Mz: LateralCoefficients,
    pub Fx: LongitudinalCoefficients,
    pub limits: Limits,
    /// Fitted extensions of the model; absent: the 1987 model alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extensions: Option<Extensions>,
}

/// Loads sampled when a channel's factors are checked over (0, fz_max].
const VALIDATION_LOAD_SAMPLES: usize = 256;

impl Default for Params {
    /// The paper's table.
    fn default() -> Self {
        Self::paper_table()
    }
}

impl Params {
    /// The paper's coefficient table (Tables 1 and 2 with the seed errata applied).
    pub fn paper_table() -> Params {
        Self::from_json(PAPER_TABLE_JSON).expect("the bundled coefficient table is valid")
    }

    /// Parses and validates a JSON parameter set: an object with named fields (a UTF-8 byte
    /// order mark before it is skipped).
    pub fn from_json(text: &str) -> Result<Params, ParamError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let format = |e: serde_json::Error| ParamError::Format(e.to_string());
        // serde reads a struct from an array of its fields in order too; the format names
        // every value, so no array may appear anywhere.
        let tree: serde_json::Value = serde_json::from_str(text).map_err(format)?;
        if !tree.is_object() {
            return Err(ParamError::Format(format!(
                "the parameter set must be a JSON object with named fields, not {}",
                json_kind(&tree)
            )));
        }
        if let Some(path) = first_array(&tree, String::new()) {
            return Err(ParamError::Format(format!(
                "`{path}` is a JSON array; the format names every value: write an object \
                 with named fields"
            )));
        }
        // Parsed again from the text, so that errors carry line and column.
        let params: Params = serde_json::from_str(text).map_err(format)?;
        params.validate()?;
        Ok(params)
    }

    /// The parameter set as pretty JSON, in the format [`Params::from_json`] reads.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("parameters serialize")
    }

    /// A coefficient by channel and index (index into the channel's `NAMES`).
    pub fn coefficient(&self, channel: Channel, index: usize) -> Option<f64> {
        match channel {
            Channel::Fy => self.Fy.get(index),
            Channel::Mz => self.Mz.get(index),
            Channel::Fx => self.Fx.get(index),
        }
    }

    /// Mutable access to a coefficient by channel and index.
    pub fn coefficient_mut(&mut self, channel: Channel, index: usize) -> Option<&mut f64> {
        match channel {
            Channel::Fy => self.Fy.get_mut(index),
            Channel::Mz => self.Mz.get_mut(index),
            Channel::Fx => self.Fx.get_mut(index),
        }
    }

    /// A channel's coefficient names (`C`, `a1`, ...), in parameter-file order: a
    /// coefficient's index is its position here.
    pub fn coefficient_names(channel: Channel) -> &'static [&'static str] {
        match channel {
            Channel::Fy | Channel::Mz => LateralCoefficients::NAMES,
            Channel::Fx => LongitudinalCoefficients::NAMES,
        }
    }

    /// The index of a coefficient name (`C`, `a1`, ...) in a channel, if the channel has it.
    pub fn coefficient_index(channel: Channel, name: &str) -> Option<usize> {
        Self::coefficient_names(channel)
            .iter()
            .position(|n| *n == name)
    }

    /// Checks that the set gives finite forces of a physical size everywhere in its validity
    /// range: loads in (0, fz_max_N], cambers within +-gamma_max_deg and, with extensions,
    /// their range of conditions. The bounds are [`crate::bounds`]; a rejection names the
    /// parameter, its value and the bound.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.validate_limits()?;
        let mut summaries = Vec::with_capacity(Channel::ALL.len());
        for channel in Channel::ALL {
            summaries.push(self.validate_channel(channel)?);
        }
        if let Some(ext) = &self.extensions {
            ext.validate_specific()?;
            for (channel, summary) in Channel::ALL.into_iter().zip(&summaries) {
                self.validate_with_extensions(channel, summary, ext)?;
            }
            ext.validate_magnitudes()?;
        }
        Ok(())
    }

    fn validate_limits(&self) -> Result<(), ParamError> {
        let Limits {
            fz_max_N,
            gamma_max_deg,
        } = self.limits;
        if !bounds::FZ_MAX_N.contains(fz_max_N) {
            return Err(invalid(
                "limits.fz_max_N",
                fz_max_N,
                &format!(
                    "the top of the load range must lie in {} N",
                    bounds::FZ_MAX_N
                ),
            ));
        }
        if !bounds::GAMMA_MAX_DEG.contains(gamma_max_deg) {
            return Err(invalid(
                "limits.gamma_max_deg",
                gamma_max_deg,
                &format!("the camber range must lie in {} deg", bounds::GAMMA_MAX_DEG),
            ));
        }
        Ok(())
    }

    /// The base coefficients of one channel alone (no extensions).
    fn validate_channel(&self, channel: Channel) -> Result<ChannelSummary, ParamError> {
        let names = Self::coefficient_names(channel);
        let name = |i: usize| format!("{channel}.{}", names[i]);
        let coef = |i: usize| self.coefficient(channel, i).unwrap_or(f64::NAN);
        for i in 0..names.len() {
            let value = coef(i);
            if !value.is_finite() {
                return Err(invalid(&name(i), value, "must be a finite number"));
            }
        }
        let c = coef(0);
        if !bounds::SHAPE_C.contains(c) {
            return Err(invalid(
                &name(0),
                c,
                &format!("the shape factor C must lie in {}", bounds::SHAPE_C),
            ));
        }
        let fz_max_n = self.limits.fz_max_N;
        let fz_max_kn = units::newtons_to_kilonewtons(fz_max_n);
        // D / Fz = (a1 Fz + a2) / 1000 [N/N, or m for Mz] is linear in Fz [kN]: its ends are
        // its extremes, and it has no zero inside (0, fz_max] iff both ends agree in sign.
        let (a1, a2) = (coef(1), coef(2));
        let per_load = |fz_kn: f64| (a1 * fz_kn + a2) / units::kilonewtons_to_newtons(1.0);
        let (low, high) = (per_load(0.0), per_load(fz_max_kn));
        if low == 0.0 || high == 0.0 || low.signum() != high.signum() {
            return Err(invalid(
                &name(2),
                a2,
                &format!(
                    "the peak D = a1 Fz^2 + a2 Fz (a1 = {a1}) reaches 0 for a load in (0, {fz_max_n} N]; \
                     C D must not vanish inside the validity range"
                ),
            ));
        }
        let cap = bounds::peak_per_load_max(channel);
        let (what, unit) = per_load_meaning(channel);
        for (index, value, at) in [
            (2, low, "as Fz -> 0".to_string()),
            (1, high, format!("at Fz = {fz_max_n} N")),
        ] {
            if value.abs() > cap {
                return Err(invalid(
                    &name(index),
                    coef(index),
                    &format!(
                        "the peak per load |D| / Fz ({what}) is {}{unit} {at}; it must be at most {cap}{unit} \
                         over the load range",
                        Num(value.abs())
                    ),
                ));
            }
        }
        match channel {
            Channel::Fy => {
                let (a4, a5) = (coef(4), coef(5));
                let phase = a4 * (a5 * fz_max_kn).atan();
                if phase.is_nan() || phase.abs() >= bounds::FY_STIFFNESS_PHASE_MAX {
                    return Err(invalid(
                        &name(4),
                        a4,
                        &format!(
                            "|a4 atan(a5 Fz)| (a5 = {a5}) reaches {} at Fz = {fz_max_n} N; it must stay \
                             below pi, else the cornering stiffness a3 sin(a4 atan(a5 Fz)) vanishes \
                             inside the load range",
                            Num(phase.abs())
                        ),
                    ));
                }
            }
            Channel::Mz | Channel::Fx => {
                let a5 = coef(5);
                if (a5 * fz_max_kn).abs() > bounds::EXPONENT_A5_FZ_MAX {
                    return Err(invalid(
                        &name(5),
                        a5,
                        &format!(
                            "|a5| Fz_max = {} (Fz in kN) must be at most {}: the stiffness factor \
                             e^(-a5 Fz) may change by at most e^{} over the load range",
                            (a5 * fz_max_kn).abs(),
                            bounds::EXPONENT_A5_FZ_MAX,
                            bounds::EXPONENT_A5_FZ_MAX
                        ),
                    ));
                }
            }
        }
        let gamma_max = self.limits.gamma_max_deg;
        let cambers: &[f64] = match channel {
            Channel::Fy | Channel::Mz => &[0.0, gamma_max],
            Channel::Fx => &[0.0],
        };
        if let Channel::Fy | Channel::Mz = channel {
            self.validate_camber(channel, fz_max_kn)?;
        }
        // B = BCD / (C D) and E over the load range, at both camber extremes (B is linear in
        // |gamma|, E monotone). E is quadratic in Fz: its vertex is added.
        let (a6, a7) = (coef(6), coef(7));
        let mut loads = validation_loads(fz_max_kn);
        let vertex = -a7 / (2.0 * a6);
        if vertex > 0.0 && vertex < fz_max_kn {
            loads.push(vertex);
        }
        let b_unit = match channel {
            Channel::Fx => "1/percent",
            Channel::Fy | Channel::Mz => "1/deg",
        };
        let mut summary = ChannelSummary {
            peak_per_load: low.abs().max(high.abs()),
            b: (f64::INFINITY, f64::NEG_INFINITY),
        };
        for &fz_kn in &loads {
            for &gamma_deg in cambers {
                let mf = channel_factors(self, channel, fz_kn, gamma_deg);
                let fz_n = units::kilonewtons_to_newtons(fz_kn);
                if !bounds::STIFFNESS_B.contains(mf.b) {
                    let index = if gamma_deg == 0.0 { 3 } else { 12 };
                    return Err(invalid(
                        &name(index),
                        coef(index),
                        &format!(
                            "the stiffness factor B = BCD / (C D) is {} at Fz = {fz_n} N, gamma = {gamma_deg} deg; \
                             it must lie in {} {b_unit} over (0, {fz_max_n} N]",
                            Num(mf.b),
                            bounds::STIFFNESS_B
                        ),
                    ));
                }
                if !bounds::CURVATURE_E.contains(mf.e) {
                    let at_zero_camber = channel_factors(self, channel, fz_kn, 0.0).e;
                    let index = if bounds::CURVATURE_E.contains(at_zero_camber) {
                        13
                    } else {
                        // The term of E = a6 Fz^2 + a7 Fz + a8 that dominates there.
                        let terms = [a6 * fz_kn * fz_kn, a7 * fz_kn, coef(8)];
                        let largest = (0..3)
                            .max_by(|i, j| terms[*i].abs().total_cmp(&terms[*j].abs()))
                            .unwrap_or(2);
                        6 + largest
                    };
                    return Err(invalid(
                        &name(index),
                        coef(index),
                        &format!(
                            "the curvature factor E is {} at Fz = {fz_n} N, gamma = {gamma_deg} deg; \
                             it must lie in {} over the load and camber range",
                            Num(mf.e),
                            bounds::CURVATURE_E
                        ),
                    ));
                }
                summary.b = (summary.b.0.min(mf.b), summary.b.1.max(mf.b));
            }
        }
        // Last, so that a coefficient is named with the bound that means something for it.
        for i in 0..names.len() {
            if coef(i).abs() > bounds::COEFFICIENT_ABS_MAX {
                return Err(invalid(
                    &name(i),
                    coef(i),
                    &format!(
                        "must lie within +-{} (a coefficient of the 1987 table)",
                        bounds::COEFFICIENT_ABS_MAX
                    ),
                ));
            }
        }
        Ok(summary)
    }

    /// Camber terms of Fy and Mz: B (1 - a12 |gamma|) and E / (1 - a13 |gamma|) defined, the
    /// shifts Sh = a9 gamma and Sv = (a10 Fz^2 + a11 Fz) gamma bounded.
    fn validate_camber(&self, channel: Channel, fz_max_kn: f64) -> Result<(), ParamError> {
        let names = Self::coefficient_names(channel);
        let name = |i: usize| format!("{channel}.{}", names[i]);
        let coef = |i: usize| self.coefficient(channel, i).unwrap_or(f64::NAN);
        let gamma_max = self.limits.gamma_max_deg;
        for (index, what) in [(12, "B (1 - a12 |gamma|)"), (13, "E / (1 - a13 |gamma|)")] {
            let a = coef(index);
            if 1.0 - a * gamma_max <= 0.0 {
                return Err(invalid(
                    &name(index),
                    a,
                    &format!(
                        "1 - {} |gamma| must stay > 0 for |gamma| <= gamma_max_deg = {gamma_max} \
                         (needs {} < {}), else {what} breaks down",
                        names[index],
                        names[index],
                        1.0 / gamma_max
                    ),
                ));
            }
        }
        let sh = (coef(9) * gamma_max).abs();
        if sh > bounds::SHIFT_SH_MAX_DEG {
            return Err(invalid(
                &name(9),
                coef(9),
                &format!(
                    "the camber shift |Sh| = |a9| gamma_max is {sh} deg; it must be at most {} deg",
                    bounds::SHIFT_SH_MAX_DEG,
                    sh = Num(sh)
                ),
            ));
        }
        // Sv / Fz = (a10 Fz + a11) gamma / 1000 is linear in Fz [kN].
        let cap = bounds::camber_shift_per_load_max(channel);
        let (what, unit) = per_load_meaning(channel);
        let (a10, a11) = (coef(10), coef(11));
        let fz_max_n = self.limits.fz_max_N;
        for (index, fz_kn, at) in [
            (11, 0.0, "as Fz -> 0".to_string()),
            (10, fz_max_kn, format!("at Fz = {fz_max_n} N")),
        ] {
            let per_load =
                ((a10 * fz_kn + a11) * gamma_max).abs() / units::kilonewtons_to_newtons(1.0);
            if per_load > cap {
                return Err(invalid(
                    &name(index),
                    coef(index),
                    &format!(
                        "the camber shift per load |Sv| / Fz ({what}) is {per_load}{unit} {at} and \
                         gamma = {gamma_max} deg; it must be at most {cap}{unit}",
                        per_load = Num(per_load)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The base coefficients with the extensions: the peak and B with every scale at its
    /// extreme (the scales depend on different conditions, so their extremes combine), and
    /// the shifts with ply steer and conicity added.
    fn validate_with_extensions(
        &self,
        channel: Channel,
        summary: &ChannelSummary,
        ext: &Extensions,
    ) -> Result<(), ParamError> {
        let prefix = format!("extensions.{channel}");
        let scales = ext.scale_extremes(channel);
        let fz_max_n = self.limits.fz_max_N;
        // Peak per load.
        let cap = bounds::peak_per_load_max(channel);
        let (what, unit) = per_load_meaning(channel);
        let largest_peak: f64 = scales.iter().map(|s| s.peak.max).product();
        let peak = summary.peak_per_load * largest_peak;
        if let Some(s) = scales
            .iter()
            .max_by(|a, b| a.peak.max.total_cmp(&b.peak.max))
            .filter(|_| peak.is_nan() || peak > cap)
        {
            let (name, value) = s.peak_parameter;
            return Err(invalid(
                &format!("{prefix}.{}.{name}", s.kind),
                value,
                &format!(
                    "with the peak scales at their largest (this one {} at {}) the peak per load |D| / Fz \
                     ({what}) reaches {peak}{unit}; it must be at most {cap}{unit}",
                    Num(s.peak.max),
                    s.at(s.peak.max_at),
                    peak = Num(peak)
                ),
            ));
        }
        // B with the factors s_k / s_d at their extremes.
        let (b_min, b_max) = summary.b;
        let low: f64 = scales.iter().map(|s| s.ratio.min).product();
        let high: f64 = scales.iter().map(|s| s.ratio.max).product();
        for (b, culprit) in [
            (
                b_min * low,
                scales
                    .iter()
                    .min_by(|a, b| a.ratio.min.total_cmp(&b.ratio.min)),
            ),
            (
                b_max * high,
                scales
                    .iter()
                    .max_by(|a, b| a.ratio.max.total_cmp(&b.ratio.max)),
            ),
        ] {
            if let Some(s) = culprit.filter(|_| !bounds::STIFFNESS_B.contains(b)) {
                let (name, value) = s.b_parameter();
                return Err(invalid(
                    &format!("{prefix}.{}.{name}", s.kind),
                    value,
                    &format!(
                        "with the stiffness and peak scales at their extremes the stiffness factor B \
                         reaches {b} (base range [{b_min}, {b_max}]); it must lie in {}",
                        bounds::STIFFNESS_B,
                        b = Num(b)
                    ),
                ));
            }
        }
        // Ply steer and conicity on the shifts.
        if let Some(q) = ext.channel(channel).ply_steer_conicity {
            let camber_sh = match channel {
                Channel::Fy => (self.Fy.a9 * self.limits.gamma_max_deg).abs(),
                Channel::Mz => (self.Mz.a9 * self.limits.gamma_max_deg).abs(),
                Channel::Fx => 0.0,
            };
            let sh = camber_sh + q.Sh_deg.abs();
            if sh > bounds::SHIFT_SH_MAX_DEG {
                return Err(invalid(
                    &format!("{prefix}.ply_steer_conicity.Sh_deg"),
                    q.Sh_deg,
                    &format!(
                        "the horizontal shift |Sh| = |a9| gamma_max + |Sh_deg| reaches {sh} deg; it must \
                         be at most {} deg",
                        bounds::SHIFT_SH_MAX_DEG,
                        sh = Num(sh)
                    ),
                ));
            }
            let share = bounds::ply_steer_sv_share(channel);
            let sv_max = share * fz_max_n;
            if q.Sv.abs() > sv_max {
                let sv_unit = if channel == Channel::Mz { "N.m" } else { "N" };
                return Err(invalid(
                    &format!("{prefix}.ply_steer_conicity.Sv"),
                    q.Sv,
                    &format!(
                        "the offset |Sv| must be at most {share}{unit} x fz_max = {sv_max} {sv_unit}"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// What a channel's value per N of load is, and its unit suffix.
fn per_load_meaning(channel: Channel) -> (&'static str, &'static str) {
    match channel {
        Channel::Fx | Channel::Fy => ("friction coefficient", ""),
        Channel::Mz => ("lever arm", " m"),
    }
}

/// Loads [kN] at which B and E are checked: near zero (B tends to a limit there) and
/// evenly over the range up to `fz_max_kn`.
fn validation_loads(fz_max_kn: f64) -> Vec<f64> {
    let near_zero = [1e-9, 1e-6, 1e-3].map(|share| share * fz_max_kn);
    let even = (1..=VALIDATION_LOAD_SAMPLES)
        .map(|k| fz_max_kn * k as f64 / VALIDATION_LOAD_SAMPLES as f64);
    near_zero.into_iter().chain(even).collect()
}

/// What the checks of the base coefficients found, for the checks with extensions.
struct ChannelSummary {
    /// The largest |D| / Fz over the load range [N/N, or m for Mz].
    peak_per_load: f64,
    /// The smallest and largest B over loads and cambers.
    b: (f64, f64),
}

/// The dotted path of the first array in `value`, if any.
fn first_array(value: &serde_json::Value, path: String) -> Option<String> {
    match value {
        serde_json::Value::Array(_) => Some(path),
        serde_json::Value::Object(fields) => fields.iter().find_map(|(name, v)| {
            let inner = if path.is_empty() {
                name.clone()
            } else {
                format!("{path}.{name}")
            };
            first_array(v, inner)
        }),
        _ => None,
    }
}

fn json_kind(value: &serde_json::Value) -> &'static str {
    match value {
        serde_json::Value::Null => "null",
        serde_json::Value::Bool(_) => "a boolean",
        serde_json::Value::Number(_) => "a number",
        serde_json::Value::String(_) => "a string",
        serde_json::Value::Array(_) => "an array",
        serde_json::Value::Object(_) => "an object",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_table_has_errata_values() {
        let p = Params::paper_table();
        // Erratum 1: Fy a8 is 0.707, not the Mz row's -4.04.
        assert_eq!(p.Fy.a8, 0.707);
        assert_eq!(p.Mz.a8, -4.04);
        assert_eq!((p.Fy.C, p.Mz.C, p.Fx.C), (1.30, 2.40, 1.65));
    }

    #[test]
    fn json_round_trip_is_lossless() {
        let p = Params::paper_table();
        assert_eq!(Params::from_json(&p.to_json()).unwrap(), p);
    }

    #[test]
    fn incomplete_or_unknown_fields_are_rejected() {
        let mut v: serde_json::Value = serde_json::from_str(PAPER_TABLE_JSON).unwrap();
        v["Fy"].as_object_mut().unwrap().remove("a7");
        let err = Params::from_json(&v.to_string()).unwrap_err();
        assert!(err.to_string().contains("a7"), "{err}");

        let mut v: serde_json::Value = serde_json::from_str(PAPER_TABLE_JSON).unwrap();
        v["Fx"]["a9"] = serde_json::json!(0.0);
        let err = Params::from_json(&v.to_string()).unwrap_err();
        assert!(err.to_string().contains("a9"), "{err}");
    }

    #[test]
    fn a_byte_order_mark_is_skipped() {
        let text = format!("\u{feff}{PAPER_TABLE_JSON}");
        assert_eq!(Params::from_json(&text).unwrap(), Params::paper_table());
        // Only at the start.
        let err = Params::from_json(&format!("{PAPER_TABLE_JSON}\u{feff}")).unwrap_err();
        assert!(matches!(err, ParamError::Format(_)), "{err}");
    }

    #[test]
    fn arrays_in_place_of_objects_are_rejected() {
        let table: serde_json::Value = serde_json::from_str(PAPER_TABLE_JSON).unwrap();
        let values = |channel: &str| -> serde_json::Value {
            let ch = Channel::from_name(channel).unwrap();
            Params::coefficient_names(ch)
                .iter()
                .map(|n| table[channel][*n].clone())
                .collect()
        };
        // serde_json itself reads a struct from its fields in order.
        let limits: Limits = serde_json::from_str("[10000.0, 10.0]").unwrap();
        assert_eq!(limits.fz_max_N, 10000.0);

        let mut v = table.clone();
        v["Mz"] = values("Mz");
        let err = Params::from_json(&v.to_string()).unwrap_err().to_string();
        assert!(
            err.contains("`Mz` is a JSON array") && err.contains("object with named fields"),
            "{err}"
        );
        let mut v = table.clone();
        v["limits"] = serde_json::json!([10000.0, 10.0]);
        let err = Params::from_json(&v.to_string()).unwrap_err().to_string();
        assert!(err.contains("`limits` is a JSON array"), "{err}");
        let whole = serde_json::json!([values("Fy"), values("Mz"), values("Fx"), [10000.0, 10.0]]);
        let err = Params::from_json(&whole.to_string())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("must be a JSON object with named fields, not an array"),
            "{err}"
        );
        let mut v = table.clone();
        v["extensions"] = serde_json::json!({
            "nominal": { "pressure_kPa": 220.0, "speed_mps": 15.0, "temperature_degC": 40.0 },
            "Fx": { "rolling_resistance": [0.01, 0.002] }
        });
        let err = Params::from_json(&v.to_string()).unwrap_err().to_string();
        assert!(
            err.contains("`extensions.Fx.rolling_resistance` is a JSON array"),
            "{err}"
        );
        let err = Params::from_json("42").unwrap_err().to_string();
        assert!(err.contains("not a number"), "{err}");
    }

    #[test]
    fn coefficient_access_by_name_and_index_agree() {
        let mut p = Params::paper_table();
        let i = Params::coefficient_index(Channel::Mz, "a13").unwrap();
        assert_eq!(p.coefficient(Channel::Mz, i), Some(0.070));
        *p.coefficient_mut(Channel::Mz, i).unwrap() = 0.05;
        assert_eq!(p.Mz.a13, 0.05);
        assert_eq!(Params::coefficient_index(Channel::Fx, "a13"), None);
        assert_eq!(Params::coefficient_index(Channel::Fx, "C"), Some(0));
    }

    fn rejected(edit: impl FnOnce(&mut Params)) -> String {
        let mut p = Params::paper_table();
        edit(&mut p);
        p.validate().unwrap_err().to_string()
    }

    #[test]
    fn zero_peak_is_rejected_with_name_and_value() {
        let msg = rejected(|p| p.Fy.C = 0.0);
        assert!(msg.contains("Fy.C = 0"), "{msg}");
        let msg = rejected(|p| p.Fx.a2 = 0.0);
        assert!(msg.contains("Fx.a2 = 0"), "{msg}");
        // D of Fy changes sign at 1011 / 22.1 = 45.7 kN: inside the range if fz_max is 50 kN.
        let msg = rejected(|p| p.limits.fz_max_N = 50_000.0);
        assert!(msg.contains("Fy.a2"), "{msg}");
    }

    #[test]
    fn camber_singularity_inside_range_is_rejected() {
        // 1 - a13 |gamma| = 0 at 14.3 deg for the paper's Mz: reject a range that reaches it.
        let msg = rejected(|p| p.limits.gamma_max_deg = 15.0);
        assert!(msg.contains("Mz.a13"), "{msg}");
        let msg = rejected(|p| p.Fy.a12 = 0.2);
        assert!(msg.contains("Fy.a12 = 0.2"), "{msg}");
    }

    #[test]
    fn non_finite_coefficients_and_limits_are_rejected() {
        let msg = rejected(|p| p.Mz.a5 = f64::NAN);
        assert!(msg.contains("Mz.a5 = NaN"), "{msg}");
        let msg = rejected(|p| p.limits.fz_max_N = f64::INFINITY);
        assert!(msg.contains("limits.fz_max_N"), "{msg}");
    }

    #[test]
    fn vanishing_stiffness_is_rejected() {
        let msg = rejected(|p| p.Fy.a3 = 0.0);
        assert!(
            msg.contains("Fy.a3 = 0") && msg.contains("B = BCD"),
            "{msg}"
        );
    }
}
