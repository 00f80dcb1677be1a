//! The 1987 model of one channel, prepared for fitting: the channel's coefficients and its
//! effects' parameters as one parameter vector, evaluated on a [`ChannelData`].

use mf87::extensions::relaxation_step;
use mf87::{Channel, Params, channel_factors};

use crate::channel_data::ChannelData;
use crate::effects::{self, Conditions, Extension, Nominal};

/// Camber coefficients of the lateral channels: a9..a13 (indices 9..=13 in `NAMES`).
const CAMBER_COEFFICIENTS: std::ops::RangeInclusive<usize> = 9..=13;

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
    pub effects: Vec<(Extension, Vec<f64>)>,
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
    pub fn with_effect(&self, effect: Extension) -> ChannelModel {
        let mut m = self.clone();
        let start = effects::of(effect)
            .parameters()
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
            for (n, _) in effects::of(*e).parameters() {
                out.push(format!("{}.{}.{n}", self.channel, e.name()));
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
        let mut effects: Vec<(Extension, &[f64])> = Vec::with_capacity(self.effects.len());
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
    use crate::data::Dataset;

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
            .with_effect(Extension::SpeedDependence)
            .with_effect(Extension::RelaxationLength);
        let mut out2 = vec![0.0; data.len()];
        with.predict(&with.theta(), &data, &mut out2);
        assert_eq!(out, out2);
        assert_eq!(with.names().last().unwrap(), "Fy.relaxation_length.sigma_m");
        let theta = with.theta();
        assert_eq!(with.updated(&theta).theta(), theta);
    }
}
