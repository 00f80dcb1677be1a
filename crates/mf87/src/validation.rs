//! [`Params::validate`]: a parameter set gives finite forces of a physical size everywhere
//! in its validity range. The bounds are [`crate::bounds`] and each effect's own; a rejection
//! names the parameter, its value and the bound. [`bounds_table`] lists them all.
//!
//! In this order: the limits, each channel's coefficients alone, the extensions' own values
//! ([`crate::extensions`]' validation), the coefficients with the extensions (scaled peak and
//! B, total shifts), and last the general caps on magnitudes, so that a value is named with
//! the bound that means something for it.

use crate::bounds;
use crate::channel::Channel;
use crate::coefficients::{LimitVar, Limits};
use crate::error::{Num, ParamError, invalid};
use crate::evaluate::channel_factors;
use crate::extensions::Extension;
use crate::extensions::schema::Extensions;
use crate::extensions::validation::{ScaleExtremes, Stage};
use crate::params::Params;
use crate::units;

/// Loads sampled when a channel's factors are checked over (0, fz_max].
const VALIDATION_LOAD_SAMPLES: usize = 256;

impl Params {
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
            ext.validate_specific(self.limits.fz_max_N)?;
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
        let row = Row::new(self, channel);
        row.check_finite()?;
        row.check_shape()?;
        let peak_per_load = row.check_peak()?;
        row.check_stiffness_law()?;
        if let Channel::Fy | Channel::Mz = channel {
            row.check_camber()?;
        }
        let b = row.check_b_and_e()?;
        // Last, so that a coefficient is named with the bound that means something for it.
        row.check_magnitudes()?;
        Ok(ChannelSummary { peak_per_load, b })
    }

    /// The base coefficients with the extensions: the peak and B with every scale at its
    /// extreme (the scales depend on different conditions, so their extremes combine), then
    /// each effect's own checks with the base coefficients (e.g. the shifts).
    fn validate_with_extensions(
        &self,
        channel: Channel,
        summary: &ChannelSummary,
        ext: &Extensions,
    ) -> Result<(), ParamError> {
        let with = WithExtensions {
            channel,
            summary,
            scales: ext.scale_extremes(channel, self.limits.fz_max_N),
            prefix: format!("extensions.{channel}"),
        };
        with.check_peak()?;
        with.check_b()?;
        ext.check_effects(channel, Stage::WithBase(self.base()))
    }
}

/// Every bound as a row, for the table of docs/parameters.md: the general ones
/// ([`bounds::general_rows`]), then each effect's own, in [`Extension::ALL`] order.
pub fn bounds_table() -> Vec<bounds::Row> {
    let mut rows = bounds::general_rows();
    for kind in Extension::ALL {
        rows.extend(kind.bound_rows());
    }
    rows
}

/// The values a coefficient may take on its own, whatever the others are: the shape factor C
/// within [`bounds::SHAPE_C`], every other within [`bounds::COEFFICIENT_ABS_MAX`] in magnitude.
/// [`Params::validate`] checks these and what the coefficients give together.
pub fn coefficient_allowed(index: usize) -> bounds::Interval {
    if index == 0 {
        bounds::SHAPE_C
    } else {
        bounds::Interval::new(-bounds::COEFFICIENT_ABS_MAX, bounds::COEFFICIENT_ABS_MAX)
    }
}

/// The values a limit may take, in SI units (N, rad): [`bounds::FZ_MAX_N`],
/// [`bounds::GAMMA_MAX_DEG`].
pub fn limit_allowed(limit: LimitVar) -> bounds::Interval {
    match limit {
        LimitVar::FzMax => bounds::FZ_MAX_N,
        LimitVar::GammaMax => bounds::Interval::new(
            units::degrees_to_radians(bounds::GAMMA_MAX_DEG.lo),
            units::degrees_to_radians(bounds::GAMMA_MAX_DEG.hi),
        ),
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

/// One channel's coefficient row with the limits, for the checks of the base coefficients.
struct Row<'a> {
    params: &'a Params,
    channel: Channel,
    /// The coefficient names, in index order.
    names: &'static [&'static str],
    fz_max_n: f64,
    fz_max_kn: f64,
    gamma_max: f64,
}

impl<'a> Row<'a> {
    fn new(params: &'a Params, channel: Channel) -> Row<'a> {
        let fz_max_n = params.limits.fz_max_N;
        Row {
            params,
            channel,
            names: Params::coefficient_names(channel),
            fz_max_n,
            fz_max_kn: units::newtons_to_kilonewtons(fz_max_n),
            gamma_max: params.limits.gamma_max_deg,
        }
    }

    /// The coefficient's name in messages, e.g. `Mz.a13`.
    fn name(&self, i: usize) -> String {
        format!("{}.{}", self.channel, self.names[i])
    }

    fn coef(&self, i: usize) -> f64 {
        self.params.coefficient(self.channel, i).unwrap_or(f64::NAN)
    }

    /// The rejection of coefficient `i` for `reason`.
    fn invalid(&self, i: usize, reason: &str) -> ParamError {
        invalid(&self.name(i), self.coef(i), reason)
    }

    fn check_finite(&self) -> Result<(), ParamError> {
        for i in 0..self.names.len() {
            if !self.coef(i).is_finite() {
                return Err(self.invalid(i, "must be a finite number"));
            }
        }
        Ok(())
    }

    fn check_shape(&self) -> Result<(), ParamError> {
        if !coefficient_allowed(0).contains(self.coef(0)) {
            return Err(self.invalid(
                0,
                &format!("the shape factor C must lie in {}", bounds::SHAPE_C),
            ));
        }
        Ok(())
    }

    /// The peak D = a1 Fz^2 + a2 Fz: no zero inside the load range, and |D| / Fz within its
    /// cap. Returns the largest |D| / Fz.
    fn check_peak(&self) -> Result<f64, ParamError> {
        let fz_max_n = self.fz_max_n;
        // D / Fz = (a1 Fz + a2) / 1000 [N/N, or m for Mz] is linear in Fz [kN]: its ends are
        // its extremes, and it has no zero inside (0, fz_max] iff both ends agree in sign.
        let (a1, a2) = (self.coef(1), self.coef(2));
        let per_load = |fz_kn: f64| (a1 * fz_kn + a2) / units::kilonewtons_to_newtons(1.0);
        let (low, high) = (per_load(0.0), per_load(self.fz_max_kn));
        if low == 0.0 || high == 0.0 || low.signum() != high.signum() {
            return Err(self.invalid(
                2,
                &format!(
                    "the peak D = a1 Fz^2 + a2 Fz (a1 = {a1}) reaches 0 for a load in (0, {fz_max_n} N]; \
                     C D must not vanish inside the validity range"
                ),
            ));
        }
        let cap = bounds::peak_per_load_max(self.channel);
        let (what, unit) = self.channel.per_load_meaning();
        for (index, value, at) in [
            (2, low, "as Fz -> 0".to_string()),
            (1, high, format!("at Fz = {fz_max_n} N")),
        ] {
            if value.abs() > cap {
                return Err(self.invalid(
                    index,
                    &format!(
                        "the peak per load |D| / Fz ({what}) is {}{unit} {at}; it must be at most {cap}{unit} \
                         over the load range",
                        Num(value.abs())
                    ),
                ));
            }
        }
        Ok(low.abs().max(high.abs()))
    }

    /// The load dependence of the stiffness BCD: Fy's `a3 sin(a4 atan(a5 Fz))` keeps its
    /// sign, the `e^(-a5 Fz)` of Mz and Fx changes by a bounded factor.
    fn check_stiffness_law(&self) -> Result<(), ParamError> {
        let (fz_max_n, fz_max_kn) = (self.fz_max_n, self.fz_max_kn);
        match self.channel {
            Channel::Fy => {
                let (a4, a5) = (self.coef(4), self.coef(5));
                let phase = a4 * (a5 * fz_max_kn).atan();
                if phase.is_nan() || phase.abs() >= bounds::FY_STIFFNESS_PHASE_MAX {
                    return Err(self.invalid(
                        4,
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
                let a5 = self.coef(5);
                if (a5 * fz_max_kn).abs() > bounds::EXPONENT_A5_FZ_MAX {
                    return Err(self.invalid(
                        5,
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
        Ok(())
    }

    /// Camber terms of Fy and Mz: B (1 - a12 |gamma|) and E / (1 - a13 |gamma|) defined, the
    /// shifts Sh = a9 gamma and Sv = (a10 Fz^2 + a11 Fz) gamma bounded.
    fn check_camber(&self) -> Result<(), ParamError> {
        let (names, gamma_max) = (self.names, self.gamma_max);
        for (index, what) in [(12, "B (1 - a12 |gamma|)"), (13, "E / (1 - a13 |gamma|)")] {
            let a = self.coef(index);
            if 1.0 - a * gamma_max <= 0.0 {
                return Err(self.invalid(
                    index,
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
        let sh = (self.coef(9) * gamma_max).abs();
        if sh > bounds::SHIFT_SH_MAX_DEG {
            return Err(self.invalid(
                9,
                &format!(
                    "the camber shift |Sh| = |a9| gamma_max is {sh} deg; it must be at most {} deg",
                    bounds::SHIFT_SH_MAX_DEG,
                    sh = Num(sh)
                ),
            ));
        }
        self.check_camber_sv()
    }

    /// The camber shift per load |Sv| / Fz within its cap at both ends of the load range.
    fn check_camber_sv(&self) -> Result<(), ParamError> {
        let (fz_max_n, gamma_max) = (self.fz_max_n, self.gamma_max);
        // Sv / Fz = (a10 Fz + a11) gamma / 1000 is linear in Fz [kN].
        let cap = bounds::camber_shift_per_load_max(self.channel);
        let (what, unit) = self.channel.per_load_meaning();
        let (a10, a11) = (self.coef(10), self.coef(11));
        for (index, fz_kn, at) in [
            (11, 0.0, "as Fz -> 0".to_string()),
            (10, self.fz_max_kn, format!("at Fz = {fz_max_n} N")),
        ] {
            let per_load =
                ((a10 * fz_kn + a11) * gamma_max).abs() / units::kilonewtons_to_newtons(1.0);
            if per_load > cap {
                return Err(self.invalid(
                    index,
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

    /// B = BCD / (C D) and E over the load range, at both camber extremes (B is linear in
    /// |gamma|, E monotone). E is quadratic in Fz: its vertex is added. Returns the smallest
    /// and largest B.
    fn check_b_and_e(&self) -> Result<(f64, f64), ParamError> {
        let cambers: &[f64] = match self.channel {
            Channel::Fy | Channel::Mz => &[0.0, self.gamma_max],
            Channel::Fx => &[0.0],
        };
        let (a6, a7) = (self.coef(6), self.coef(7));
        let mut loads = validation_loads(self.fz_max_kn);
        let vertex = -a7 / (2.0 * a6);
        if vertex > 0.0 && vertex < self.fz_max_kn {
            loads.push(vertex);
        }
        let mut b = (f64::INFINITY, f64::NEG_INFINITY);
        for &fz_kn in &loads {
            for &gamma_deg in cambers {
                let mf = channel_factors(self.params, self.channel, fz_kn, gamma_deg);
                if !bounds::STIFFNESS_B.contains(mf.b) {
                    return Err(self.b_out_of_bounds(mf.b, fz_kn, gamma_deg));
                }
                if !bounds::CURVATURE_E.contains(mf.e) {
                    return Err(self.e_out_of_bounds(mf.e, fz_kn, gamma_deg));
                }
                b = (b.0.min(mf.b), b.1.max(mf.b));
            }
        }
        Ok(b)
    }

    /// B out of its bounds at `fz_kn`, `gamma_deg`: named by a3 at zero camber, else a12.
    fn b_out_of_bounds(&self, b: f64, fz_kn: f64, gamma_deg: f64) -> ParamError {
        let b_unit = match self.channel {
            Channel::Fx => "1/percent",
            Channel::Fy | Channel::Mz => "1/deg",
        };
        let fz_n = units::kilonewtons_to_newtons(fz_kn);
        let fz_max_n = self.fz_max_n;
        let index = if gamma_deg == 0.0 { 3 } else { 12 };
        self.invalid(
            index,
            &format!(
                "the stiffness factor B = BCD / (C D) is {} at Fz = {fz_n} N, gamma = {gamma_deg} deg; \
                 it must lie in {} {b_unit} over (0, {fz_max_n} N]",
                Num(b),
                bounds::STIFFNESS_B
            ),
        )
    }

    /// E out of its bounds at `fz_kn`, `gamma_deg`: named by a13 if E is within them at zero
    /// camber, else by the term of E = a6 Fz^2 + a7 Fz + a8 that dominates there.
    fn e_out_of_bounds(&self, e: f64, fz_kn: f64, gamma_deg: f64) -> ParamError {
        let fz_n = units::kilonewtons_to_newtons(fz_kn);
        let at_zero_camber = channel_factors(self.params, self.channel, fz_kn, 0.0).e;
        let index = if bounds::CURVATURE_E.contains(at_zero_camber) {
            13
        } else {
            let (a6, a7) = (self.coef(6), self.coef(7));
            let terms = [a6 * fz_kn * fz_kn, a7 * fz_kn, self.coef(8)];
            let largest = (0..3)
                .max_by(|i, j| terms[*i].abs().total_cmp(&terms[*j].abs()))
                .unwrap_or(2);
            6 + largest
        };
        self.invalid(
            index,
            &format!(
                "the curvature factor E is {} at Fz = {fz_n} N, gamma = {gamma_deg} deg; \
                 it must lie in {} over the load and camber range",
                Num(e),
                bounds::CURVATURE_E
            ),
        )
    }

    /// Every coefficient within [`bounds::COEFFICIENT_ABS_MAX`] in magnitude.
    fn check_magnitudes(&self) -> Result<(), ParamError> {
        for i in 0..self.names.len() {
            if self.coef(i).abs() > bounds::COEFFICIENT_ABS_MAX {
                return Err(self.invalid(
                    i,
                    &format!(
                        "must lie within +-{} (a coefficient of the 1987 table)",
                        bounds::COEFFICIENT_ABS_MAX
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// One channel's base coefficients with its extensions' scales at their extremes.
struct WithExtensions<'a> {
    channel: Channel,
    summary: &'a ChannelSummary,
    /// The extremes of each scaling extension of the channel.
    scales: Vec<ScaleExtremes>,
    /// `extensions.{channel}`, for parameter names.
    prefix: String,
}

impl WithExtensions<'_> {
    /// The peak per load with every peak scale at its largest.
    fn check_peak(&self) -> Result<(), ParamError> {
        let (prefix, scales) = (&self.prefix, &self.scales);
        let cap = bounds::peak_per_load_max(self.channel);
        let (what, unit) = self.channel.per_load_meaning();
        let largest_peak: f64 = scales.iter().map(|s| s.peak.max).product();
        let peak = self.summary.peak_per_load * largest_peak;
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
        Ok(())
    }

    /// B with the factors s_k / s_d at their extremes.
    fn check_b(&self) -> Result<(), ParamError> {
        let (prefix, scales) = (&self.prefix, &self.scales);
        let (b_min, b_max) = self.summary.b;
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
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn single_values_are_checked_against_the_bounds() {
        assert!(!limit_allowed(LimitVar::GammaMax).contains(-0.1));
        assert!(!limit_allowed(LimitVar::GammaMax).contains(f64::NAN));
        assert!(limit_allowed(LimitVar::GammaMax).contains(10f64.to_radians()));
        assert!(!limit_allowed(LimitVar::FzMax).contains(5.0));
        assert!(!coefficient_allowed(0).contains(0.0));
        assert!(coefficient_allowed(3).contains(-1e9) && !coefficient_allowed(3).contains(2e9));
        // The paper's table lies inside.
        let p = Params::paper_table();
        for channel in Channel::ALL {
            for (i, _) in Params::coefficient_names(channel).iter().enumerate() {
                let c = p.coefficient(channel, i).unwrap();
                assert!(coefficient_allowed(i).contains(c), "{channel} {i} = {c}");
            }
        }
    }

    #[test]
    fn relaxation_lengths_are_zero_or_at_least_a_millimetre() {
        use crate::conditions::{ConditionLimits, Nominal};
        use crate::extensions::{ChannelExtensions, RelaxationLength};
        let with = |sigma_m: f64| {
            let mut p = Params::paper_table();
            let nominal = Nominal {
                pressure_kpa: 200.0,
                speed_mps: 10.0,
                temperature_c: 60.0,
            };
            let mut ext = Extensions::new(nominal, ConditionLimits::default());
            ext.Fy = ChannelExtensions {
                relaxation_length: Some(RelaxationLength { sigma_m }),
                ..ChannelExtensions::default()
            };
            p.extensions = Some(ext);
            p.validate()
        };
        assert!(with(0.0).is_ok());
        assert!(with(0.001).is_ok() && with(5.0).is_ok());
        let msg = with(5e-324).unwrap_err().to_string();
        assert!(
            msg.contains("extensions.Fy.relaxation_length.sigma_m = 5e-324")
                && msg.contains("[0.001, 5] m"),
            "{msg}"
        );
        assert!(with(-0.3).is_err() && with(5.1).is_err());
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
