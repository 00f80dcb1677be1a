//! The 1987 model of one channel, prepared for fitting: the measured rows in the formula's
//! units, and the channel's coefficients as a parameter vector.

use mf87::extensions::relaxation_step;
use mf87::{Channel, Params, channel_factors, units};

use crate::data::{Dataset, Quantity};
use crate::effects::{self, Conditions, EffectId, Nominal};

/// Camber coefficients of the lateral channels: a9..a13 (indices 9..=13 in `NAMES`).
const CAMBER_COEFFICIENTS: std::ops::RangeInclusive<usize> = 9..=13;

/// Camber beyond this [deg] somewhere in the data: the camber coefficients are fitted.
pub const CAMBER_VARIES_DEG: f64 = 0.05;

/// One channel's measured rows, converted once to the formula's units.
#[derive(Debug, Clone)]
pub struct ChannelData {
    pub channel: Channel,
    pub run: Vec<i64>,
    /// Load [kN].
    pub fz_kn: Vec<f64>,
    /// Slip in the formula's units: alpha [deg] for Fy and Mz, sigma [percent] for Fx.
    pub slip: Vec<f64>,
    /// Camber [deg] (zeros when not measured).
    pub gamma_deg: Vec<f64>,
    /// Measured force [N] or moment [N.m].
    pub measured: Vec<f64>,
    /// The other slip, where measured: slip ratio for Fy and Mz, slip angle [rad] for Fx.
    pub other_slip: Option<Vec<f64>>,
    pub time: Option<Vec<f64>>,
    pub speed: Option<Vec<f64>>,
    pub pressure: Option<Vec<f64>>,
    pub temperature: Option<Vec<f64>>,
}

impl ChannelData {
    /// The channel's rows, or `None` when the measurement or its slip is missing.
    pub fn from_dataset(ds: &Dataset, channel: Channel) -> Option<ChannelData> {
        let (measured, slip, to_formula): (_, _, fn(f64) -> f64) = match channel {
            Channel::Fx => (
                ds.fx.as_ref()?,
                ds.kappa.as_ref()?,
                units::slip_ratio_to_percent,
            ),
            Channel::Fy => (
                ds.fy.as_ref()?,
                ds.alpha.as_ref()?,
                units::radians_to_degrees,
            ),
            Channel::Mz => (
                ds.mz.as_ref()?,
                ds.alpha.as_ref()?,
                units::radians_to_degrees,
            ),
        };
        let gamma = ds.column(Quantity::Gamma);
        Some(ChannelData {
            channel,
            run: ds.run.clone(),
            fz_kn: ds
                .fz
                .iter()
                .map(|f| units::newtons_to_kilonewtons(*f))
                .collect(),
            slip: slip.iter().map(|s| to_formula(*s)).collect(),
            gamma_deg: match (channel, gamma) {
                (Channel::Fx, _) | (_, None) => vec![0.0; ds.len()],
                (_, Some(g)) => g.iter().map(|g| units::radians_to_degrees(*g)).collect(),
            },
            measured: measured.clone(),
            other_slip: match channel {
                Channel::Fx => ds.alpha.clone(),
                Channel::Fy | Channel::Mz => ds.kappa.clone(),
            },
            time: ds.time.clone(),
            speed: ds.speed.clone(),
            pressure: ds.pressure.clone(),
            temperature: ds.temperature.clone(),
        })
    }

    pub fn len(&self) -> usize {
        self.measured.len()
    }

    pub fn is_empty(&self) -> bool {
        self.measured.is_empty()
    }

    /// The subset at positions `keep` (positions into this channel's rows).
    pub fn subset(&self, keep: &[usize]) -> ChannelData {
        let pick = |v: &[f64]| keep.iter().map(|&i| v[i]).collect();
        let pick_opt = |v: &Option<Vec<f64>>| v.as_deref().map(pick);
        ChannelData {
            channel: self.channel,
            run: keep.iter().map(|&i| self.run[i]).collect(),
            fz_kn: pick(&self.fz_kn),
            slip: pick(&self.slip),
            gamma_deg: pick(&self.gamma_deg),
            measured: pick(&self.measured),
            other_slip: pick_opt(&self.other_slip),
            time: pick_opt(&self.time),
            speed: pick_opt(&self.speed),
            pressure: pick_opt(&self.pressure),
            temperature: pick_opt(&self.temperature),
        }
    }

    /// The slip rate within runs [slip units per s], by central differences over the rows of
    /// a run in file order; 0 where a row has no neighbour in its run or time does not advance.
    /// `None` without time.
    pub fn slip_rate(&self) -> Option<Vec<f64>> {
        let t = self.time.as_ref()?;
        let n = self.len();
        let same = |a: usize, b: usize| self.run[a] == self.run[b];
        Some(
            (0..n)
                .map(|i| {
                    let lo = if i > 0 && same(i - 1, i) { i - 1 } else { i };
                    let hi = if i + 1 < n && same(i + 1, i) {
                        i + 1
                    } else {
                        i
                    };
                    let dt = t[hi] - t[lo];
                    if hi > lo && dt > 0.0 {
                        (self.slip[hi] - self.slip[lo]) / dt
                    } else {
                        0.0
                    }
                })
                .collect(),
        )
    }

    /// Whether camber varies in these rows (else the camber coefficients are not identifiable).
    pub fn has_camber(&self) -> bool {
        self.gamma_deg.iter().any(|g| g.abs() > CAMBER_VARIES_DEG)
    }
}

/// The model of one channel: the 1987 formula with its free coefficients, plus any effects.
/// Its parameter vector is the free coefficients followed by each effect's parameters.
#[derive(Debug, Clone)]
pub struct ChannelModel {
    pub channel: Channel,
    /// The full parameter set; free coefficients are overwritten from the parameter vector.
    pub params: Params,
    /// Indices (into the channel's coefficient names) of the free coefficients.
    pub free: Vec<usize>,
    /// The effects added, in order, with their current parameter values.
    pub effects: Vec<(EffectId, Vec<f64>)>,
    pub nominal: Nominal,
}

impl ChannelModel {
    /// The base model: all coefficients free, except camber ones when camber does not vary.
    pub fn new(
        params: Params,
        channel: Channel,
        camber_identifiable: bool,
        nominal: Nominal,
    ) -> ChannelModel {
        let free = (0..Params::coefficient_names(channel).len())
            .filter(|i| {
                channel == Channel::Fx || camber_identifiable || !CAMBER_COEFFICIENTS.contains(i)
            })
            .collect();
        ChannelModel {
            channel,
            params,
            free,
            effects: Vec::new(),
            nominal,
        }
    }

    /// This model with `effect` added at its starting values.
    pub fn with_effect(&self, effect: EffectId) -> ChannelModel {
        let mut m = self.clone();
        let start = effect
            .parameters(self.channel)
            .iter()
            .map(|p| p.1)
            .collect();
        m.effects.push((effect, start));
        m
    }

    /// Parameter names, e.g. `Fy.a3`, `Fy.speed_dependence.v`.
    pub fn names(&self) -> Vec<String> {
        let names = Params::coefficient_names(self.channel);
        let mut out: Vec<String> = self
            .free
            .iter()
            .map(|&i| format!("{}.{}", self.channel, names[i]))
            .collect();
        for (e, _) in &self.effects {
            for (n, _) in e.parameters(self.channel) {
                out.push(format!("{}.{}.{n}", self.channel, e.id()));
            }
        }
        out
    }

    /// The current parameter vector.
    pub fn theta(&self) -> Vec<f64> {
        let mut t: Vec<f64> = self
            .free
            .iter()
            .map(|&i| self.params.coefficient(self.channel, i).unwrap_or(f64::NAN))
            .collect();
        for (_, q) in &self.effects {
            t.extend(q);
        }
        t
    }

    /// This model with its parameters set from `theta`.
    pub fn updated(&self, theta: &[f64]) -> ChannelModel {
        let mut m = self.clone();
        m.params = self.params_with(theta);
        let mut rest = &theta[self.free.len()..];
        for (_, q) in &mut m.effects {
            let (mine, others) = rest.split_at(q.len());
            q.copy_from_slice(mine);
            rest = others;
        }
        m
    }

    /// The parameter set with the free coefficients taken from `theta`.
    pub fn params_with(&self, theta: &[f64]) -> Params {
        let mut p = self.params.clone();
        for (&i, &v) in self.free.iter().zip(theta) {
            if let Some(c) = p.coefficient_mut(self.channel, i) {
                *c = v;
            }
        }
        p
    }

    /// Predictions for every row of `data` with the model's own parameters.
    pub fn predictions(&self, data: &ChannelData) -> Vec<f64> {
        let mut out = vec![0.0; data.len()];
        self.predict(&self.theta(), data, &mut out);
        out
    }

    /// Model minus measurement for every row of `data` with parameters `theta`, into the
    /// first `data.len()` entries of `out`.
    pub fn residuals(&self, theta: &[f64], data: &ChannelData, out: &mut [f64]) {
        let out = &mut out[..data.len()];
        self.predict(theta, data, out);
        for (r, y) in out.iter_mut().zip(&data.measured) {
            *r -= y;
        }
    }

    /// Predictions for every row of `data` with parameters `theta`: the model as mf87
    /// evaluates it with these effects as extensions (what the FMU runs).
    pub fn predict(&self, theta: &[f64], data: &ChannelData, out: &mut [f64]) {
        let p = self.params_with(theta);
        let mut rest = &theta[self.free.len()..];
        let mut effects: Vec<(EffectId, &[f64])> = Vec::with_capacity(self.effects.len());
        for (e, q) in &self.effects {
            let (mine, others) = rest.split_at(q.len());
            effects.push((*e, mine));
            rest = others;
        }
        let ext = effects::channel_extensions(effects);
        let slip = match ext.relaxation_length_m() {
            Some(sigma_m) => std::borrow::Cow::Owned(lagged_slip(data, sigma_m)),
            None => std::borrow::Cow::Borrowed(&data.slip),
        };
        let column =
            |c: &Option<Vec<f64>>, i: usize, default: f64| c.as_ref().map_or(default, |v| v[i]);
        for i in 0..data.len() {
            if data.fz_kn[i] <= 0.0 {
                out[i] = 0.0;
                continue;
            }
            if ext.is_empty() {
                out[i] = channel_factors(&p, self.channel, data.fz_kn[i], data.gamma_deg[i])
                    .eval(slip[i]);
                continue;
            }
            let x = Conditions {
                fz_kn: data.fz_kn[i],
                other_slip: column(&data.other_slip, i, 0.0),
                speed: column(&data.speed, i, self.nominal.speed_mps),
                pressure: column(&data.pressure, i, self.nominal.pressure_kpa),
                temperature: column(&data.temperature, i, self.nominal.temperature_c),
            };
            out[i] = ext.evaluate(
                &p,
                self.channel,
                &self.nominal,
                data.gamma_deg[i],
                slip[i],
                &x,
            );
        }
    }
}

/// The slip after a first-order lag over travelled distance (mf87's relaxation step),
/// restarted at every new run or backward step in time. Without time and speed, no lag.
fn lagged_slip(data: &ChannelData, sigma_m: f64) -> Vec<f64> {
    let (Some(time), Some(speed)) = (&data.time, &data.speed) else {
        return data.slip.clone();
    };
    let mut out = Vec::with_capacity(data.len());
    let mut lagged = 0.0;
    for i in 0..data.len() {
        let restart = i == 0 || data.run[i] != data.run[i - 1] || time[i] <= time[i - 1];
        lagged = if restart {
            data.slip[i]
        } else {
            let distance = speed[i].abs() * (time[i] - time[i - 1]);
            relaxation_step(lagged, data.slip[i], distance, sigma_m)
        };
        out.push(lagged);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dataset() -> Dataset {
        let n = 40;
        let alpha: Vec<f64> = (0..n)
            .map(|i| (i as f64 - 20.0).to_radians() * 0.5)
            .collect();
        let p = Params::paper_table();
        let mut fy = Vec::new();
        for a in &alpha {
            let o = mf87::evaluate(
                &p,
                &mf87::Inputs {
                    fz: 3000.0,
                    alpha: *a,
                    kappa: 0.0,
                    gamma: 0.0,
                },
                mf87::SignConvention::Paper,
            );
            fy.push(o.fy);
        }
        Dataset {
            source: "test".into(),
            run: vec![1; n],
            fz: vec![3000.0; n],
            alpha: Some(alpha),
            fy: Some(fy),
            ..Dataset::default()
        }
    }

    fn nominal() -> Nominal {
        Nominal {
            pressure_kpa: 220.0,
            speed_mps: 15.0,
            temperature_c: 40.0,
        }
    }

    #[test]
    fn base_model_with_the_table_reproduces_mf87() {
        let ds = dataset();
        let data = ChannelData::from_dataset(&ds, Channel::Fy).unwrap();
        assert!(ChannelData::from_dataset(&ds, Channel::Fx).is_none());
        let model = ChannelModel::new(
            Params::paper_table(),
            Channel::Fy,
            data.has_camber(),
            nominal(),
        );
        assert_eq!(
            model.free.len(),
            9,
            "camber coefficients held without camber data"
        );
        let mut out = vec![0.0; data.len()];
        model.predict(&model.theta(), &data, &mut out);
        for (a, b) in out.iter().zip(&data.measured) {
            assert!((a - b).abs() < 1e-9 * b.abs().max(1.0));
        }
        assert_eq!(model.names()[0], "Fy.C");
        // Effects at neutral values change nothing; the relaxation lag needs time and speed.
        let with = model
            .with_effect(EffectId::SpeedDependence)
            .with_effect(EffectId::RelaxationLength);
        let mut out2 = vec![0.0; data.len()];
        with.predict(&with.theta(), &data, &mut out2);
        assert_eq!(out, out2);
        assert_eq!(with.names().last().unwrap(), "Fy.relaxation_length.sigma_m");
        let theta = with.theta();
        assert_eq!(with.updated(&theta).theta(), theta);
    }
}
