//! The 1987 model of one channel, prepared for fitting: the measured rows in the formula's
//! units, and the channel's coefficients as a parameter vector.

use mf87::params::{LateralCoefficients, LongitudinalCoefficients};
use mf87::{Channel, Params, channel_factors, units};

use crate::data::{Dataset, Quantity};

/// Camber coefficients of the lateral channels: a9..a13 (indices 9..=13 in `NAMES`).
const CAMBER_COEFFICIENTS: std::ops::RangeInclusive<usize> = 9..=13;

/// One channel's measured rows, converted once to the formula's units.
#[derive(Debug, Clone)]
pub struct ChannelData {
    pub channel: Channel,
    /// Row numbers in the dataset.
    pub rows: Vec<usize>,
    pub run: Vec<i64>,
    /// Load [kN].
    pub fz_kn: Vec<f64>,
    /// Slip in the formula's units: alpha [deg] for Fy and Mz, sigma [percent] for Fx.
    pub slip: Vec<f64>,
    /// Camber [deg] (zeros when not measured).
    pub gamma_deg: Vec<f64>,
    /// Measured force [N] or moment [N.m].
    pub measured: Vec<f64>,
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
        let rows: Vec<usize> = (0..ds.len()).collect();
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
                (Channel::Fx, _) | (_, None) => vec![0.0; rows.len()],
                (_, Some(g)) => g.iter().map(|g| units::radians_to_degrees(*g)).collect(),
            },
            measured: measured.clone(),
            rows,
        })
    }

    pub fn len(&self) -> usize {
        self.rows.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The subset at positions `keep` (positions into this channel's rows).
    pub fn subset(&self, keep: &[usize]) -> ChannelData {
        let pick = |v: &[f64]| keep.iter().map(|&i| v[i]).collect();
        ChannelData {
            channel: self.channel,
            rows: keep.iter().map(|&i| self.rows[i]).collect(),
            run: keep.iter().map(|&i| self.run[i]).collect(),
            fz_kn: pick(&self.fz_kn),
            slip: pick(&self.slip),
            gamma_deg: pick(&self.gamma_deg),
            measured: pick(&self.measured),
        }
    }

    /// Whether camber varies in these rows (else the camber coefficients are not identifiable).
    pub fn has_camber(&self) -> bool {
        self.gamma_deg.iter().any(|g| g.abs() > 0.05)
    }
}

/// The base model of one channel: which coefficients are free, the rest held at `params`.
#[derive(Debug, Clone)]
pub struct BaseModel {
    pub channel: Channel,
    /// The full parameter set; free coefficients are overwritten from the parameter vector.
    pub params: Params,
    /// Indices (into the channel's coefficient names) of the free coefficients.
    pub free: Vec<usize>,
}

impl BaseModel {
    /// All coefficients free, except camber ones when camber does not vary in the data.
    pub fn new(params: Params, channel: Channel, camber_identifiable: bool) -> BaseModel {
        let free = (0..coefficient_names(channel).len())
            .filter(|i| {
                channel == Channel::Fx || camber_identifiable || !CAMBER_COEFFICIENTS.contains(i)
            })
            .collect();
        BaseModel {
            channel,
            params,
            free,
        }
    }

    /// Free coefficient names, e.g. `Fy.a3`.
    pub fn free_names(&self) -> Vec<String> {
        let names = coefficient_names(self.channel);
        self.free
            .iter()
            .map(|&i| format!("{}.{}", self.channel, names[i]))
            .collect()
    }

    /// The current values of the free coefficients.
    pub fn theta(&self) -> Vec<f64> {
        self.free
            .iter()
            .map(|&i| self.params.coefficient(self.channel, i).unwrap_or(f64::NAN))
            .collect()
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

    /// Predictions for every row of `data` with coefficients `theta`.
    pub fn predict(&self, theta: &[f64], data: &ChannelData, out: &mut [f64]) {
        let p = self.params_with(theta);
        for i in 0..data.len() {
            out[i] = if data.fz_kn[i] <= 0.0 {
                0.0
            } else {
                channel_factors(&p, self.channel, data.fz_kn[i], data.gamma_deg[i])
                    .eval(data.slip[i])
            };
        }
    }
}

/// The coefficient names of a channel, in parameter-file order.
pub fn coefficient_names(channel: Channel) -> &'static [&'static str] {
    match channel {
        Channel::Fx => LongitudinalCoefficients::NAMES,
        Channel::Fy | Channel::Mz => LateralCoefficients::NAMES,
    }
}

/// The physical quantity a channel measures.
pub fn measured_quantity(channel: Channel) -> Quantity {
    match channel {
        Channel::Fx => Quantity::Fx,
        Channel::Fy => Quantity::Fy,
        Channel::Mz => Quantity::Mz,
    }
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

    #[test]
    fn base_model_with_the_table_reproduces_mf87() {
        let ds = dataset();
        let data = ChannelData::from_dataset(&ds, Channel::Fy).unwrap();
        assert!(ChannelData::from_dataset(&ds, Channel::Fx).is_none());
        let model = BaseModel::new(Params::paper_table(), Channel::Fy, data.has_camber());
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
        assert_eq!(model.free_names()[0], "Fy.C");
    }
}
