//! The candidate effects as the diagnosis knows them: standard physical extensions of the
//! Magic Formula, each with few parameters, in the forms of the Magic Formula literature. Each
//! acts on one channel's factors (peak D, stiffness BCD, shifts) or output, with parameters of
//! its own per channel, so every channel stays a separate least-squares problem.
//!
//! An effect's identifier is mf87's [`Extension`], and its math, parameter names and the
//! channels it applies to live in [`mf87::extensions`], which the FMU runs too. What tire-gap
//! knows beyond that (its form for reports, the columns it needs, starting values, its home
//! rows, its driving input for the extrapolation check and the figures, the conditions that
//! drive it, its own plausibility check and the experiments that separate it from another
//! effect) is one [`Effect`] implementation per effect, one file each; no other code of the
//! diagnosis names an effect. Adding an effect: its math in mf87, a file here, its arm in
//! [`of`], and synth's truth form (docs/development.md, "Adding an effect: tire-gap and
//! synth").

mod camber_peak;
mod combined_slip;
mod inflation_pressure;
mod ply_steer_conicity;
mod relaxation_length;
mod rolling_resistance;
mod signature;
mod slip_ratio_shift;
mod speed_dependence;
mod temperature;

use mf87::extensions::ChannelExtensions;
use mf87::{Channel, Real};

use crate::data::Quantity;
use crate::method::prepare::channel_data::{ChannelData, Column};

pub use mf87::extensions::{Conditions, Extension, Nominal};
use signature::Departure;
pub use signature::{Activity, Signature};

/// What the data vary of what an effect's terms depend on (beyond the effect's own driving
/// input): the load and the camber across runs ([`crate::method::diagnose::design::identifies`]). A term of
/// a condition the data hold still is not identified, and is held at its neutral start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Identifies {
    pub load: bool,
    pub camber: bool,
    /// The runs' speeds spread enough for a speed effect to be tested (rolling resistance's
    /// growth with speed tells its constant part from a vertical shift's).
    pub speed: bool,
    /// The runs' speeds take a middle level too, so a curvature in the speed is told from a
    /// line.
    pub speed_curvature: bool,
}

impl Identifies {
    /// Every term.
    pub const ALL: Identifies = Identifies {
        load: true,
        camber: true,
        speed: true,
        speed_curvature: true,
    };
}

/// What the diagnosis, the extrapolation check and the figures know of one candidate effect.
pub trait Effect: Sync {
    /// The identifier.
    fn kind(&self) -> Extension;

    /// The form fitted, for reports.
    fn form(&self) -> &'static str;

    /// The columns the effect needs beyond the channel's own (measurement, slip, load).
    fn needs(&self, channel: Channel) -> &'static [Quantity];

    /// Starting values of the fit, in the order of mf87's parameter names.
    fn starting_values(&self) -> &'static [f64];

    /// Starting values on `channel`: [`Effect::starting_values`] unless a term that does not
    /// act on the channel must be 0 there.
    fn starting_values_on(&self, _channel: Channel) -> Vec<f64> {
        self.starting_values().to_vec()
    }

    /// Positions of parameters fitted alone first on `channel`, before all of the effect's
    /// parameters are (a fit of many parameters from a neutral start converges in fewer of
    /// its costly iterations from there, and terms that could stand in for others start from
    /// where those others leave them); empty: none.
    fn first_fitted(&self, _channel: Channel) -> &'static [usize] {
        &[]
    }

    /// Whether, before the effect is fitted from its neutral start, the base coefficients are
    /// refitted on the rows outside its home (see [`Effect::home_rows`]): where a base fitted
    /// on every row has absorbed the effect (a combined-slip weight lowers the peak and
    /// stiffness the 1987 curve takes), the effect is then fitted on the curve of the rows it
    /// does not act on, as a Magic Formula is fitted to pure slip before combined slip.
    fn base_first_off_home(&self) -> bool {
        false
    }

    /// Positions of the parameters held at their starting values on `channel` when the data
    /// vary only what `identifies` says: terms of a load or camber the data hold still, and
    /// terms that do not act on the channel.
    fn held(&self, _channel: Channel, _identifies: Identifies) -> Vec<usize> {
        Vec::new()
    }

    /// Positions of the parameters the model uses by magnitude (the fit itself is
    /// unconstrained, so they may go negative).
    fn magnitudes(&self) -> &'static [usize] {
        &[]
    }

    /// The rows where the effect, if present, must show (its "home"): the paired test is run
    /// there, so a candidate that merely soaks up a misfit of the base formula elsewhere is
    /// not claimed. `None`: every row.
    fn home_rows(&self, data: &ChannelData) -> Option<Vec<bool>>;

    /// Where the effect's driver acts on `data` and where it is idle (`form`: the data's
    /// nominal conditions and the candidate's fitted parameters): a claim needs its held-out gain per row to be larger where the
    /// driver acts than where it is idle (see the `signature` module). `Err`: why that cannot be said.
    fn signature(&self, data: &ChannelData, form: &Form) -> Result<Signature, String>;

    /// The input whose run-level value ranks the runs in the extrapolation check; `None`
    /// without the column it needs.
    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver>;

    /// The input the effect acts through, per row, for the driver figures; or the column that
    /// is missing.
    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String>;

    /// The conditions whose level across runs sets the effect's size, for the design's
    /// confounding check: by default the columns it needs.
    fn driving_conditions(&self, channel: Channel) -> &'static [Quantity] {
        self.needs(channel)
    }

    /// Why a candidate fit with these values (as the model uses them, see [`model_values`])
    /// is not physical on `data`, beyond the FMU's bounds; `None` if nothing is wrong.
    fn implausible(&self, _data: &ChannelData, _values: &[f64]) -> Option<String> {
        None
    }

    /// The experiment that separates this effect from `other` when the data cannot tell them
    /// apart, if one is known beyond the general one (see [`separating_test`]). A pair is
    /// described in the file of one of its two effects only.
    fn separating_test(&self, _other: Extension) -> Option<&'static str> {
        None
    }

    /// Parameter names (mf87's) and starting values.
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        self.kind()
            .parameter_names()
            .iter()
            .copied()
            .zip(self.starting_values().iter().copied())
            .collect()
    }
}

/// What tire-gap knows of the effect `kind`.
pub fn of(kind: Extension) -> &'static dyn Effect {
    match kind {
        Extension::CombinedSlip => &combined_slip::CombinedSlip,
        Extension::RelaxationLength => &relaxation_length::RelaxationLength,
        Extension::InflationPressure => &inflation_pressure::InflationPressure,
        Extension::SpeedDependence => &speed_dependence::SpeedDependence,
        Extension::PlySteerConicity => &ply_steer_conicity::PlySteerConicity,
        Extension::RollingResistance => &rolling_resistance::RollingResistance,
        Extension::Temperature => &temperature::Temperature,
        Extension::SlipRatioShift => &slip_ratio_shift::SlipRatioShift,
        Extension::CamberPeak => &camber_peak::CamberPeak,
    }
}

/// A run-level driving input of the extrapolation check.
pub struct RunDriver {
    /// What it is, e.g. "median pressure \[kPa\]".
    pub name: &'static str,
    /// Its value per row.
    pub values: Column,
    /// A run's level is its 95th percentile ("largest ..."), else its median.
    pub largest: bool,
    /// Runs whose level is not above this are not ranked: they always train.
    pub floor: f64,
}

impl RunDriver {
    /// A run's level is its median; every run is ranked.
    fn median(name: &'static str, values: Column) -> RunDriver {
        RunDriver {
            name,
            values,
            largest: false,
            floor: f64::NEG_INFINITY,
        }
    }
}

/// A row-level driving input of the driver figures.
pub struct RowDriver {
    pub axis: String,
    /// Per row; NaN where the effect does not act.
    pub x: Column,
    /// Binning range; `None`: from the data's 0.5 % and 99.5 % quantiles.
    pub range: Option<(f64, f64)>,
}

/// Nominal conditions for evaluating an effect's parts that do not depend on them.
const NEUTRAL: Nominal = Nominal {
    pressure_kpa: 200.0,
    speed_mps: 10.0,
    temperature_c: 40.0,
};

/// A measured column, or the message that names it missing.
fn column(c: &Option<Column>, name: &str) -> Result<Column, String> {
    c.clone().ok_or_else(|| format!("no {name} column"))
}

/// The home of effects on stiffness, peak or the slip's history: they act on the force the
/// slip makes, so they cannot show where the channel's own slip is near zero (Fx in pure
/// cornering). |alpha| >= 1 deg for Fy and Mz, |sigma| >= 1 % for Fx.
fn where_slip_acts(data: &ChannelData) -> Option<Vec<bool>> {
    Some(data.slip.iter().map(|s| s.abs() >= 1.0).collect())
}

/// A candidate's fitted form, for its signature: the data's nominal conditions and the
/// effect's parameters as the model uses them (see [`model_values`]).
#[derive(Debug, Clone, Copy)]
pub struct Form<'a> {
    pub nominal: &'a Nominal,
    pub values: &'a [f64],
}

/// The least change of peak and stiffness (a sum of relative changes) that counts as the form
/// acting, at the median force of the rows where it can show: half a per cent, below what a
/// rig resolves of a tire's grip.
const FORM_ACTS: f64 = 0.005;

/// The share of the channel's force scale (the 90th percentile of |force| on the rows where
/// its slip acts) below which a row's force is too small for a change of peak or stiffness to
/// show: such rows (Fx on a cornering run at free rolling) tell nothing of the effect.
const FORCE_SHOWS: f64 = 0.25;

/// The signature of an effect that scales the peak and the slip stiffness by a function of an
/// operating condition measured in `values` (pressure, speed, temperature, camber), named with
/// its unit in `words`: active where its fitted `form` changes the curve most, idle where it
/// changes it little (see [`Departure::spread`]), on the rows where the channel's own slip
/// acts and its force is large enough for a change of the curve to show (elsewhere a change
/// of stiffness or peak cannot show). The correction is the form's relative change of peak
/// and stiffness from their mean over those rows, times the force: a model without the
/// effect settles near that mean (the base fitted on every row), so the effect's held-out
/// gain must lie where its form departs from it, and most where the force it scales is
/// large. By the form rather than by the condition's departure from its nominal
/// level, so that an effect stronger on one side (a grip window whose optimum lies beyond the
/// temperatures measured) is judged where it acts.
fn by_form(
    kind: Extension,
    data: &ChannelData,
    form: &Form,
    (words, values): ((&str, &str), &Option<Column>),
) -> Result<Signature, String> {
    let (name, unit) = words;
    let values = column(values, name)?;
    let ext = channel_extensions([(kind, form.values)]);
    let slip_acts = |i: usize| data.slip[i].abs() >= 1.0;
    let scale = crate::quantiles::quantile_of(
        || {
            (0..data.len())
                .filter(|&i| slip_acts(i))
                .map(|i| data.measured[i].abs())
        },
        0.9,
    )
    .unwrap_or(0.0);
    let acts = |i: usize| slip_acts(i) && data.measured[i].abs() >= FORCE_SHOWS * scale;
    let at = |i: usize| -> (f64, f64) {
        let x = row_conditions(data, i, form.nominal);
        let mut mf = UNIT;
        ext.apply_to_factors(form.nominal, &x, &mut mf);
        (mf.d.abs().ln(), (mf.b * mf.c * mf.d).abs().ln())
    };
    let logs: Vec<(f32, f32)> = (0..data.len())
        .map(|i| match acts(i) {
            true => {
                let (d, k) = at(i);
                (d as f32, k as f32)
            }
            false => (f32::NAN, f32::NAN),
        })
        .collect();
    let mean = |f: fn(&(f32, f32)) -> f32| {
        crate::method::stats::mean(logs.iter().map(|v| f64::from(f(v))))
    };
    let (md, mk) = (mean(|v| v.0), mean(|v| v.1));
    // The correction the form makes at a row: its change of peak and stiffness from their
    // mean, times the force there (what a model without the effect gets wrong by).
    let correction = |i: usize| {
        let change = (f64::from(logs[i].0) - md).abs() + (f64::from(logs[i].1) - mk).abs();
        change * data.measured[i].abs()
    };
    let force = crate::quantiles::median_of(|| {
        (0..data.len())
            .filter(|&i| acts(i))
            .map(|i| data.measured[i].abs())
    })
    .unwrap_or(0.0);
    let force_unit = match data.channel {
        Channel::Mz => "N.m",
        Channel::Fx | Channel::Fy => "N",
    };
    let d = Departure {
        name: "|correction of the fitted form|".into(),
        unit: force_unit,
        rows: data.len(),
        at: &correction,
    };
    let mut s = d.spread(FORM_ACTS * force);
    // Where that is, in the condition's own units.
    let range = |want: Activity| {
        let v = (0..data.len())
            .filter(|&i| s.rows[i] == want)
            .map(|i| values[i]);
        let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        });
        match lo <= hi {
            true => format!("{name} {lo:.1} to {hi:.1} {unit}"),
            false => format!("no row of {name}"),
        }
    };
    s.driver = format!("{name} through the fitted form [{unit}]");
    s.active = format!("{} ({})", s.active, range(Activity::Active));
    s.idle = format!("{} ({})", s.idle, range(Activity::Idle));
    Ok(s)
}

/// A Magic Formula of unit factors: what an effect does to it is its relative change.
const UNIT: mf87::MagicFormula = mf87::MagicFormula {
    b: 1.0,
    c: 1.0,
    d: 1.0,
    e: 0.0,
    sh: 0.0,
    sv: 0.0,
};

/// Row `i`'s conditions as the model sees them (missing conditions at their nominal level).
fn row_conditions(data: &ChannelData, i: usize, nominal: &Nominal) -> Conditions {
    let at = |c: &Option<Column>, default: f64| c.as_ref().map_or(default, |c| c[i]);
    let to_si = match data.channel {
        Channel::Fx => mf87::units::percent_to_slip_ratio(1.0),
        Channel::Fy | Channel::Mz => mf87::units::degrees_to_radians(1.0),
    };
    Conditions {
        fz_kn: data.fz_kn[i],
        gamma: mf87::units::degrees_to_radians(data.gamma_deg[i]),
        own_slip: data.slip[i] * to_si,
        other_slip: at(&data.other_slip, 0.0),
        speed: at(&data.speed, nominal.speed_mps),
        pressure: at(&data.pressure, nominal.pressure_kpa),
        temperature: at(&data.temperature, nominal.temperature_c),
    }
}

/// The name and unit of a channel's own slip in the formula's units.
fn slip_words(channel: Channel) -> (&'static str, &'static str) {
    match channel {
        Channel::Fx => ("|slip ratio|", "%"),
        Channel::Fy | Channel::Mz => ("|slip angle|", "deg"),
    }
}

/// The signature of an effect that shows near zero slip: active where the channel's slip is
/// below `limit` in magnitude (the formula's units), idle from twice that.
fn near_zero_signature(data: &ChannelData, limit: f64) -> Signature {
    let (name, unit) = slip_words(data.channel);
    signature::near_zero(&data.slip, name, unit, limit, 2.0 * limit)
}

/// The rows where the channel's slip is below `limit` in magnitude (the formula's units).
fn where_slip_near_zero(data: &ChannelData, limit: f64) -> Option<Vec<bool>> {
    Some(data.slip.iter().map(|s| s.abs() < limit).collect())
}

/// The channel's slip where it is below `limit` in magnitude, NaN elsewhere: the row driver
/// of effects that show near zero slip.
fn slip_near_zero(data: &ChannelData, limit: f64) -> Column {
    data.slip
        .iter()
        .map(|&s| if s.abs() < limit { s } else { f64::NAN })
        .collect()
}

/// The fitted parameters `q` of `kind` as the model uses them (see [`Effect::magnitudes`]).
pub fn model_values<T: Real>(kind: Extension, q: &[T]) -> Vec<T> {
    let mut v = q.to_vec();
    // Optional parameters not given are 0 (as in a parameter file).
    v.resize(kind.parameter_names().len(), T::from(0.0));
    for &i in of(kind).magnitudes() {
        v[i] = mf87::real::abs(v[i]);
    }
    v
}

/// A channel's effects, with fitted parameters `q` in the order of [`Effect::parameters`], as
/// mf87 extensions (each as the model uses it, see [`model_values`]), over any number type.
pub fn channel_extensions<'a, T: Real + 'a>(
    effects: impl IntoIterator<Item = (Extension, &'a [T])>,
) -> ChannelExtensions<T> {
    let mut ext = ChannelExtensions::<T>::default();
    for (kind, q) in effects {
        // The vectors are built from mf87's names (`parameters`): the lengths agree.
        ext.set(kind, &model_values(kind, q))
            .expect("effect parameters follow mf87's parameter names");
    }
    ext
}

/// The experiment that separates two effects the data cannot tell apart: the one either
/// effect names (see [`Effect::separating_test`]), else runs that vary one's input and hold
/// the other's.
pub fn separating_test(a: Extension, b: Extension) -> String {
    let (a, b) = if a <= b { (a, b) } else { (b, a) };
    match of(a)
        .separating_test(b)
        .or_else(|| of(b).separating_test(a))
    {
        Some(test) => test.into(),
        None => format!(
            "runs that vary the input of {} while holding the input of {} constant, and the reverse",
            a.name(),
            b.name()
        ),
    }
}

/// The help text of an option that takes effect names: `lead`, the identifiers of every
/// effect in mf87's order, comma-separated, then `tail`.
pub fn names_help(lead: &str, tail: &str) -> String {
    format!("{lead}{}{tail}", Extension::NAMES.join(", "))
}

/// Effects named by their identifiers (`combined_slip`, ...; `all` for every one), sorted
/// and each once; blank names are skipped. An unknown name is an error listing the known.
pub fn parse_names<S: AsRef<str>>(names: &[S]) -> Result<Vec<Extension>, String> {
    let mut effects = Vec::new();
    for name in names {
        let name = name.as_ref().trim();
        if name.is_empty() {
            continue;
        }
        if name == "all" {
            effects.extend(Extension::ALL);
            continue;
        }
        let e = Extension::from_name(name).ok_or_else(|| {
            format!(
                "unknown effect `{name}`; known: {}, all",
                Extension::NAMES.join(", ")
            )
        })?;
        effects.push(e);
    }
    effects.sort();
    effects.dedup();
    Ok(effects)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_has_its_own_effect_with_mf87_s_parameters() {
        // The names, their round trip and serde are mf87's (tested there).
        for kind in Extension::ALL {
            let e = of(kind);
            assert_eq!(e.kind(), kind);
            assert_eq!(
                e.starting_values().len(),
                kind.parameter_names().len(),
                "{kind}"
            );
            let names: Vec<&str> = e.parameters().iter().map(|p| p.0).collect();
            assert_eq!(names, kind.parameter_names(), "{kind}");
            assert!(!e.form().is_empty());
        }
    }

    #[test]
    fn a_pair_s_separating_test_is_described_once() {
        for a in Extension::ALL {
            for b in Extension::ALL {
                let both = [of(a).separating_test(b), of(b).separating_test(a)];
                assert!(both.iter().flatten().count() <= 1, "{a} and {b}");
            }
        }
        let t = separating_test(Extension::Temperature, Extension::SpeedDependence);
        assert!(t.starts_with("repeat sweeps at two speeds"), "{t}");
        let general = separating_test(Extension::PlySteerConicity, Extension::CombinedSlip);
        assert_eq!(
            general,
            "runs that vary the input of combined_slip while holding the input of \
             ply_steer_conicity constant, and the reverse"
        );
    }

    #[test]
    fn rolling_resistance_and_a_slip_ratio_shift_are_told_apart_by_speed_and_radius() {
        use Extension::{RollingResistance, SlipRatioShift};
        let t = separating_test(SlipRatioShift, RollingResistance);
        assert_eq!(t, separating_test(RollingResistance, SlipRatioShift));
        assert!(
            t.contains("several speeds") && t.contains("effective rolling radius"),
            "{t}"
        );
    }

    #[test]
    fn a_slip_ratio_shift_holds_its_vertical_shift_where_speeds_test_rolling_resistance() {
        let shift = of(Extension::SlipRatioShift);
        let one_speed = Identifies {
            speed: false,
            ..Identifies::ALL
        };
        assert!(shift.held(Channel::Fx, one_speed).is_empty());
        let held: Vec<&str> = shift
            .held(Channel::Fx, Identifies::ALL)
            .iter()
            .map(|&i| Extension::SlipRatioShift.parameter_names()[i])
            .collect();
        assert_eq!(held, ["Sv", "Sv_per_kN"]);
    }

    #[test]
    fn speed_dependence_bends_only_where_the_runs_take_a_middle_speed() {
        let speed = of(Extension::SpeedDependence);
        let names = Extension::SpeedDependence.parameter_names();
        let line = Identifies {
            speed_curvature: false,
            ..Identifies::ALL
        };
        for ch in Channel::ALL {
            let held: Vec<&str> = speed.held(ch, line).iter().map(|&i| names[i]).collect();
            assert_eq!(held, ["w"], "{ch}");
            assert!(speed.held(ch, Identifies::ALL).is_empty(), "{ch}");
        }
    }

    #[test]
    fn combined_slip_fits_the_weights_camber_term_on_fx_only() {
        let names = Extension::CombinedSlip.parameter_names();
        let held = |ch: Channel| -> Vec<&str> {
            of(Extension::CombinedSlip)
                .held(ch, Identifies::ALL)
                .iter()
                .map(|&i| names[i])
                .collect()
        };
        assert!(!held(Channel::Fx).contains(&"B_camber"));
        assert!(
            held(Channel::Fy).contains(&"B_camber") && !held(Channel::Fy).contains(&"Sv_camber")
        );
        assert!(held(Channel::Mz).contains(&"B_camber"));
    }

    #[test]
    fn starting_values_are_neutral_where_the_form_allows() {
        use mf87::MagicFormula;
        let nominal = Nominal {
            pressure_kpa: 220.0,
            speed_mps: 15.0,
            temperature_c: 50.0,
        };
        let x: Conditions = Conditions {
            fz_kn: 4.0,
            gamma: 0.02,
            own_slip: 0.05,
            other_slip: 0.0,
            speed: 25.0,
            pressure: 260.0,
            temperature: 80.0,
        };
        let mf: MagicFormula = MagicFormula {
            b: 0.2,
            c: 1.3,
            d: 4000.0,
            e: -0.5,
            sh: 0.0,
            sv: 0.0,
        };
        let start = |e: Extension| -> Vec<f64> { of(e).starting_values().to_vec() };
        for e in [
            Extension::InflationPressure,
            Extension::SpeedDependence,
            Extension::Temperature,
            Extension::PlySteerConicity,
            Extension::SlipRatioShift,
        ] {
            let q = start(e);
            let mut m = mf;
            channel_extensions([(e, &q[..])]).apply_to_factors(&nominal, &x, &mut m);
            assert_eq!(m, mf, "{e}");
        }
        // Peak scaling keeps the cornering stiffness BCD.
        let mut m = mf;
        channel_extensions([(Extension::SpeedDependence, &[-0.1][..])])
            .apply_to_factors(&nominal, &x, &mut m);
        assert!((m.b * m.c * m.d - mf.b * mf.c * mf.d).abs() < 1e-9);
        assert!(m.d < mf.d);
        // Combined slip weight is 1 at zero other slip and falls with it.
        let combined =
            channel_extensions([(Extension::CombinedSlip, &start(Extension::CombinedSlip)[..])]);
        assert_eq!(combined.apply_to_output(&nominal, &x, &mf, 100.0), 100.0);
        let x2 = Conditions {
            other_slip: 0.1,
            ..x
        };
        assert!(combined.apply_to_output(&nominal, &x2, &mf, 100.0) < 80.0);
        // Rolling resistance opposes forward rolling.
        let rolling = channel_extensions([(Extension::RollingResistance, &[0.01, 0.0][..])]);
        assert!((rolling.apply_to_output(&nominal, &x, &mf, 0.0) + 40.0).abs() < 1e-9);
        // The slip-ratio shift moves the curve along the slip [percent]: 0.01 + 0.005 x 4 kN.
        let mut m = mf;
        channel_extensions([(Extension::SlipRatioShift, &[0.01, 0.005][..])])
            .apply_to_factors(&nominal, &x, &mut m);
        assert!((m.sh - 3.0).abs() < 1e-12 && m.sv == 0.0, "{m:?}");
        // The fit's relaxation parameter may go negative; the model uses its magnitude.
        let relax = channel_extensions([(Extension::RelaxationLength, &[-0.4][..])]);
        assert_eq!(relax.relaxation_length_m(), Some(0.4));
    }
}
