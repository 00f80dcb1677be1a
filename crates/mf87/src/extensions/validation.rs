//! Checks of the extensions' own values against [`crate::bounds`]: nominal conditions and
//! their range, every parameter finite and within its bound, and each peak or stiffness scale
//! within its bound over its condition's range ([`ScaleExtremes`]). What depends on the base
//! coefficients too is checked in [`crate::validation`] with these extremes.

use crate::bounds;
use crate::channel::Channel;
use crate::coefficients::BaseParams;
use crate::conditions::{ConditionLimits, ConditionVar, Conditions};
use crate::error::{Num, ParamError, invalid};
use crate::extensions::Extension;
use crate::extensions::effect::{Check, Effect, ScaleParameters, Scales, VisitChecked};
use crate::extensions::schema::Extensions;

/// A stage of the effects' own checks (see [`Effect`]), in the order they run.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Stage<'a> {
    /// [`Effect::check_allowed`].
    Allowed,
    /// [`Effect::check_range`].
    Range,
    /// [`Effect::check_nominal`].
    Nominal,
    /// [`Effect::check_with_base`], with the base coefficients.
    WithBase(BaseParams<'a>),
}

/// One stage of the checks, over a channel's effects.
struct Checker<'a> {
    ext: &'a Extensions,
    channel: Channel,
    stage: Stage<'a>,
}

impl VisitChecked for Checker<'_> {
    fn visit<E: Effect<Of<f64> = E>>(&mut self, kind: Extension, q: &E) -> Result<(), ParamError> {
        let c = Check {
            channel: self.channel,
            prefix: format!("extensions.{}.{kind}", self.channel),
            nominal: &self.ext.nominal,
            limits: &self.ext.limits,
        };
        match self.stage {
            Stage::Allowed => q.check_allowed(&c),
            Stage::Range => q.check_range(&c),
            Stage::Nominal => q.check_nominal(&c),
            Stage::WithBase(base) => q.check_with_base(&c, &base),
        }
    }
}

impl Extensions {
    /// Checks the extensions' own values against [`crate::bounds`]: nominal conditions and
    /// their range, every parameter finite and within its bound, and each peak or stiffness
    /// scale within [`bounds::CONDITION_SCALE`] over its condition's range and loads up to
    /// `fz_max_n` \[N\]. What depends on the base coefficients too (the scaled peak and B, the
    /// total shifts) is checked by [`crate::Params::validate`].
    pub fn validate(&self, fz_max_n: f64) -> Result<(), ParamError> {
        self.validate_specific(fz_max_n)?;
        self.validate_magnitudes()
    }

    /// Every bound but the general cap on magnitudes ([`Self::validate_magnitudes`]), which
    /// comes last so that a value is named with the bound that means something for it.
    pub(crate) fn validate_specific(&self, fz_max_n: f64) -> Result<(), ParamError> {
        self.validate_nominal()?;
        self.validate_limits()?;
        for channel in Channel::ALL {
            self.validate_channel(channel, fz_max_n)?;
        }
        Ok(())
    }

    /// Every parameter within [`bounds::EXTENSION_PARAMETER_ABS_MAX`] in magnitude.
    pub(crate) fn validate_magnitudes(&self) -> Result<(), ParamError> {
        for channel in Channel::ALL {
            let ext = self.channel(channel);
            for kind in ext.kinds() {
                let values = ext.get(kind).unwrap_or_default();
                for (name, v) in kind.parameter_names().iter().zip(values) {
                    if v.abs() > bounds::EXTENSION_PARAMETER_ABS_MAX {
                        return Err(invalid(
                            &format!("extensions.{channel}.{kind}.{name}"),
                            v,
                            &format!(
                                "must lie within +-{} (an extension parameter)",
                                bounds::EXTENSION_PARAMETER_ABS_MAX
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    fn validate_nominal(&self) -> Result<(), ParamError> {
        let n = &self.nominal;
        for (name, value, allowed, unit) in [
            ("pressure_kPa", n.pressure_kpa, bounds::PRESSURE_KPA, "kPa"),
            ("speed_mps", n.speed_mps, bounds::NOMINAL_SPEED_MPS, "m/s"),
            (
                "temperature_degC",
                n.temperature_c,
                bounds::TEMPERATURE_DEGC,
                "degC",
            ),
        ] {
            if !allowed.contains(value) {
                return Err(invalid(
                    &format!("extensions.nominal.{name}"),
                    value,
                    &format!("the nominal condition must lie in {allowed} {unit}"),
                ));
            }
        }
        Ok(())
    }

    fn validate_limits(&self) -> Result<(), ParamError> {
        let l = &self.limits;
        for (what, (min_name, min), (max_name, max), allowed, unit) in [
            (
                "speed",
                ("speed_min_mps", l.speed_min_mps),
                ("speed_max_mps", l.speed_max_mps),
                bounds::SPEED_MPS,
                "m/s",
            ),
            (
                "pressure",
                ("pressure_min_kPa", l.pressure_min_kPa),
                ("pressure_max_kPa", l.pressure_max_kPa),
                bounds::PRESSURE_KPA,
                "kPa",
            ),
            (
                "temperature",
                ("temperature_min_degC", l.temperature_min_degC),
                ("temperature_max_degC", l.temperature_max_degC),
                bounds::TEMPERATURE_DEGC,
                "degC",
            ),
        ] {
            for (name, value) in [(min_name, min), (max_name, max)] {
                if !allowed.contains(value) {
                    return Err(invalid(
                        &format!("extensions.limits.{name}"),
                        value,
                        &format!("a limit of the {what} must lie in {allowed} {unit}"),
                    ));
                }
            }
            if max < min {
                return Err(invalid(
                    &format!("extensions.limits.{max_name}"),
                    max,
                    &format!("the highest {what} must be >= {min_name} = {min}"),
                ));
            }
        }
        Ok(())
    }

    /// Each kind present applies to `channel` and has finite parameters.
    fn validate_kinds(&self, channel: Channel) -> Result<(), ParamError> {
        let ext = self.channel(channel);
        for kind in ext.kinds() {
            let values = ext.get(kind).unwrap_or_default();
            let names = kind.parameter_names();
            let name = |i: usize| format!("extensions.{channel}.{kind}.{}", names[i]);
            if !kind.applies_to(channel) {
                let on: Vec<&str> = Channel::ALL
                    .iter()
                    .filter(|c| kind.applies_to(**c))
                    .map(|c| c.name())
                    .collect();
                return Err(invalid(
                    &name(0),
                    values[0],
                    &format!(
                        "{kind} does not apply to {channel} (only to {})",
                        on.join(", ")
                    ),
                ));
            }
            for (i, v) in values.iter().enumerate() {
                if !v.is_finite() {
                    return Err(invalid(&name(i), *v, "must be a finite number"));
                }
            }
        }
        Ok(())
    }

    /// The kinds of `channel` with their own bounds, and each scale over its condition.
    fn validate_channel(&self, channel: Channel, fz_max_n: f64) -> Result<(), ParamError> {
        self.validate_kinds(channel)?;
        for stage in [Stage::Allowed, Stage::Range, Stage::Nominal] {
            self.check_effects(channel, stage)?;
        }
        for scales in self.scale_extremes(channel, fz_max_n) {
            scales.check(channel, &self.limits)?;
        }
        Ok(())
    }

    /// Runs `stage` of the checks of each effect of `channel`.
    pub(crate) fn check_effects(&self, channel: Channel, stage: Stage) -> Result<(), ParamError> {
        let mut checker = Checker {
            ext: self,
            channel,
            stage,
        };
        self.channel(channel).visit_checked(&mut checker)
    }

    /// The smallest and largest peak and stiffness scales of each scaling extension of
    /// `channel` over its condition's range and loads up to `fz_max_n` [N], and of the factor
    /// s_k / s_d they put on B.
    pub(crate) fn scale_extremes(&self, channel: Channel, fz_max_n: f64) -> Vec<ScaleExtremes> {
        struct Sweeps<'a> {
            ext: &'a Extensions,
            loads_kn: [f64; 2],
            out: Vec<ScaleExtremes>,
        }
        impl VisitChecked for Sweeps<'_> {
            fn visit<E: Effect<Of<f64> = E>>(
                &mut self,
                kind: Extension,
                q: &E,
            ) -> Result<(), ParamError> {
                let (n, Some(condition)) = (&self.ext.nominal, E::CONDITION) else {
                    return Ok(());
                };
                if let Some(parameters) = q.scale_parameters() {
                    let vertices: Vec<(f64, f64)> = self
                        .loads_kn
                        .iter()
                        .flat_map(|&fz| q.scale_vertices(n, fz).into_iter().map(move |v| (v, fz)))
                        .collect();
                    let loads = self.loads_kn;
                    let sweep =
                        self.ext
                            .sweep(kind, parameters, (&loads, &vertices), |at, fz_kn| {
                                let mut x = Conditions {
                                    fz_kn,
                                    ..Conditions::default()
                                };
                                match condition {
                                    ConditionVar::Speed => x.speed = at,
                                    ConditionVar::Pressure => x.pressure = at,
                                    ConditionVar::Temperature => x.temperature = at,
                                }
                                E::scales::<f64, f64>(q, n, &x)
                            });
                    self.out.extend(sweep);
                }
                Ok(())
            }
        }
        let mut sweeps = Sweeps {
            ext: self,
            loads_kn: [0.0, crate::units::newtons_to_kilonewtons(fz_max_n)],
            out: Vec::new(),
        };
        // Sweeps reject nothing.
        let _ = self.channel(channel).visit_checked(&mut sweeps);
        sweeps.out
    }

    /// The extremes of `scales(at, fz_kn)` over the range of `kind`'s condition and the
    /// `loads` (the ends of the load range: the scales are at most linear in the load): at the
    /// condition's ends and points between for the ratio, and at the `vertices` (condition
    /// value, load) of a quadratic scale that lie inside. `parameters` name the peak scale's
    /// parameter and the stiffness scale's, if any.
    fn sweep(
        &self,
        kind: Extension,
        parameters: ScaleParameters,
        (loads, vertices): (&[f64], &[(f64, f64)]),
        scales: impl Fn(f64, f64) -> Option<Scales>,
    ) -> Option<ScaleExtremes> {
        let condition = kind.condition()?;
        let (lo, hi) = self.limits.in_extension_units(condition);
        let mut points: Vec<(f64, f64)> = loads
            .iter()
            .flat_map(|&fz| {
                (0..=SCALE_SAMPLES)
                    .map(move |i| (lo + (hi - lo) * i as f64 / SCALE_SAMPLES as f64, fz))
            })
            .collect();
        points.extend(vertices.iter().filter(|v| lo < v.0 && v.0 < hi));
        let (peak_parameter, stiffness_parameter) = parameters;
        let mut e = ScaleExtremes {
            kind,
            condition,
            peak_parameter,
            stiffness_parameter,
            peak: Extremes::new(),
            stiffness: Extremes::new(),
            ratio: Extremes::new(),
        };
        for (at, fz_kn) in points {
            let s = scales(at, fz_kn)?;
            // As on a curve with D = B = 1: D becomes s_d, B s_k / s_d, their product BD.
            let (peak, ratio) = (s.peak, s.on_b());
            e.peak.add(peak, at);
            e.stiffness.add(ratio * peak, at);
            e.ratio.add(ratio, at);
        }
        Some(e)
    }
}

/// Points of a condition's range at which the scales are evaluated (besides the vertex of
/// the temperature window): the peak and stiffness scales are linear or quadratic (exact at
/// the ends and vertex), their ratio on B is sampled.
const SCALE_SAMPLES: usize = 64;

/// The smallest and largest value seen, and where.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Extremes {
    pub min: f64,
    pub min_at: f64,
    pub max: f64,
    pub max_at: f64,
}

impl Extremes {
    fn new() -> Extremes {
        Extremes {
            min: f64::INFINITY,
            min_at: f64::NAN,
            max: f64::NEG_INFINITY,
            max_at: f64::NAN,
        }
    }

    fn add(&mut self, value: f64, at: f64) {
        // A NaN becomes both extremes, so that every check fails on it.
        if value.is_nan() || value < self.min {
            (self.min, self.min_at) = (value, at);
        }
        if value.is_nan() || value > self.max {
            (self.max, self.max_at) = (value, at);
        }
    }
}

/// How a scaling extension's scales range over its condition.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ScaleExtremes {
    pub kind: Extension,
    pub condition: ConditionVar,
    /// The parameter of the peak scale, and of the stiffness scale if it has one.
    pub peak_parameter: (&'static str, f64),
    pub stiffness_parameter: Option<(&'static str, f64)>,
    /// Of the peak scale s_d, the stiffness scale s_k, and s_k / s_d (the factor on B).
    pub peak: Extremes,
    pub stiffness: Extremes,
    pub ratio: Extremes,
}

impl ScaleExtremes {
    /// Each scale within [`bounds::CONDITION_SCALE`].
    fn check(&self, channel: Channel, limits: &ConditionLimits) -> Result<(), ParamError> {
        let (symbol, unit) = self.condition.extension_symbol_and_unit();
        let (lo, hi) = limits.in_extension_units(self.condition);
        let kind = self.kind;
        for (scale, parameter, what) in [
            (&self.peak, Some(self.peak_parameter), "peak D"),
            (&self.stiffness, self.stiffness_parameter, "stiffness BCD"),
        ] {
            let Some((name, value)) = parameter else {
                continue;
            };
            for (s, at) in [(scale.min, scale.min_at), (scale.max, scale.max_at)] {
                if !bounds::CONDITION_SCALE.contains(s) {
                    return Err(invalid(
                        &format!("extensions.{channel}.{kind}.{name}"),
                        value,
                        &format!(
                            "the scale of the {what} is {s} at {symbol} = {at} {unit}; it must stay \
                             within {} over the range [{lo}, {hi}] {unit} (extensions.limits)",
                            bounds::CONDITION_SCALE,
                            s = Num(s)
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The parameter to name when B leaves its bounds through this scale (the stiffness
    /// scale's, else the peak's).
    pub fn b_parameter(&self) -> (&'static str, f64) {
        self.stiffness_parameter.unwrap_or(self.peak_parameter)
    }

    /// Where the condition is, for messages: e.g. `p = 400 kPa`.
    pub fn at(&self, value: f64) -> String {
        let (symbol, unit) = self.condition.extension_symbol_and_unit();
        format!("{symbol} = {value} {unit}")
    }
}
