//! Step 6: the fitted parameters as a parameter file the FMU reads: the base coefficients
//! and the selected effects as mf87 extensions, around the fit's nominal conditions.

use mf87::Params;

use crate::data::Dataset;
use crate::method::diagnose::Diagnosis;
use crate::method::fit::effects::Extension;
use crate::method::fit::model::ChannelModel;
use crate::method::fit::validity::ValidityRange;

/// The fitted model (base and selected effects) in the FMU's parameter-file format,
/// validated over the data's range.
pub fn parameter_file(d: &Diagnosis, ds: &Dataset) -> Result<String, String> {
    Ok(fitted_parameters(&d.models, &d.verdict, ds)?.to_json())
}

/// The fitted coefficients of every measured channel (the paper's table for the others) and
/// each channel model's effects as extensions. The validity range covers the measured loads,
/// cambers and conditions, with a margin.
pub fn fitted_parameters(
    models: &[ChannelModel],
    selected: &[Extension],
    ds: &Dataset,
) -> Result<Params, String> {
    let mut params = ValidityRange::of(ds).parameters(models)?;
    params.source = Some(format!(
        "tire-gap {} fit of {} ({} rows); effects selected: [{}]",
        env!("CARGO_PKG_VERSION"),
        ds.source,
        ds.len(),
        selected
            .iter()
            .map(|e| e.name())
            .collect::<Vec<_>>()
            .join(", ")
    ));
    Ok(params)
}

#[cfg(test)]
mod tests {
    use mf87::{Channel, Inputs, LaggedSlip, OperatingConditions, SignConvention, units};

    use super::*;
    use crate::data::Column;
    use crate::method::fit::effects::{Identifies, Nominal};
    use crate::method::fit::validity::condition_limits;
    use crate::method::prepare::channel_data::ChannelData;
    use mf87::extensions::ConditionLimits;

    /// Two runs of 300 rows at 100 Hz with every input and condition varying.
    fn dataset() -> Dataset {
        let n = 600;
        let rows: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let col = |f: &dyn Fn(f64) -> f64| -> Vec<f64> { rows.iter().map(|i| f(*i)).collect() };
        Dataset {
            source: "export test".into(),
            run: col(&|i| if i < 300.0 { 1.0 } else { 2.0 })
                .iter()
                .map(|r| *r as i64)
                .collect(),
            time: Some(col(&|i| (i % 300.0) * 0.01).into()),
            speed: Some(col(&|i| 14.0 + 6.0 * (i * 0.013).sin()).into()),
            fz: col(&|i| 4000.0 + 1800.0 * (i * 0.021).sin()).into(),
            alpha: Some(col(&|i| 6f64.to_radians() * (i * 0.05).sin()).into()),
            kappa: Some(col(&|i| 0.08 * (i * 0.037).cos()).into()),
            gamma: Some(col(&|i| 2f64.to_radians() * (i * 0.011).sin()).into()),
            pressure: Some(col(&|i| 220.0 + 40.0 * (i * 0.007).cos()).into()),
            temperature: Some(col(&|i| 50.0 + 30.0 * (i * 0.009).sin()).into()),
            fx: Some(vec![0.0; n].into()),
            fy: Some(vec![0.0; n].into()),
            mz: Some(vec![0.0; n].into()),
        }
    }

    /// A model of `channel` with `effects` at the given values (in the order added).
    fn model(channel: Channel, effects: &[(Extension, &[f64])]) -> ChannelModel {
        let nominal = Nominal {
            pressure_kpa: 220.0,
            speed_mps: 14.0,
            temperature_c: 50.0,
        };
        let mut params = Params::paper_table();
        params.Fy.a3 = 1150.0; // a fitted coefficient, exported too
        let mut m = ChannelModel::new(params, channel, true, nominal);
        m.effects = effects.iter().map(|(e, q)| (*e, q.to_vec())).collect();
        m
    }

    #[test]
    fn exported_file_makes_mf87_reproduce_the_fitted_predictions() {
        use Extension::*;
        let ds = dataset();
        let models = [
            model(
                Channel::Fy,
                &[
                    (CombinedSlip, &[7.0, 1.05]),
                    // A negative fitted relaxation length: the model uses its magnitude.
                    (RelaxationLength, &[-0.35]),
                    (InflationPressure, &[0.3, -0.15]),
                    (PlySteerConicity, &[0.2, 35.0]),
                    (Temperature, &[0.15, 8.0, 0.1]),
                ],
            ),
            model(
                Channel::Mz,
                &[
                    (RelaxationLength, &[0.25]),
                    (SpeedDependence, &[-0.05]),
                    (PlySteerConicity, &[-0.1, 2.0]),
                    (CombinedSlip, &[5.0, 0.9]),
                ],
            ),
            model(
                Channel::Fx,
                &[
                    (RollingResistance, &[0.012, 0.003]),
                    (CombinedSlip, &[6.0, 1.0]),
                    (InflationPressure, &[0.2, 0.1]),
                    (RelaxationLength, &[0.5]),
                    (SpeedDependence, &[0.04]),
                ],
            ),
        ];
        let text = fitted_parameters(&models, &[CombinedSlip, RelaxationLength], &ds)
            .unwrap()
            .to_json();
        let params = Params::from_json(&text).unwrap();
        let ext = params.extensions.as_ref().unwrap();
        assert_eq!(params.Fy.a3, 1150.0);
        assert_eq!(ext.Fy.relaxation_length_m(), Some(0.35));
        assert_eq!(ext.Fx.rolling_resistance.map(|r| r.q1), Some(0.012));
        assert!(text.contains("effects selected: [combined_slip, relaxation_length]"));

        // mf87 row by row, with the relaxation lag advanced as the FMU does it.
        let column = |c: &Option<Column>, i: usize| c.as_ref().unwrap()[i];
        let inputs_at = |i: usize| Inputs {
            fz: ds.fz[i],
            alpha: column(&ds.alpha, i),
            kappa: column(&ds.kappa, i),
            gamma: column(&ds.gamma, i),
        };
        let conditions_at = |i: usize| OperatingConditions {
            vx: column(&ds.speed, i),
            p: units::kilopascals_to_pascals(column(&ds.pressure, i)),
            t_tread: units::celsius_to_kelvin(column(&ds.temperature, i)),
        };
        let mut lagged = LaggedSlip::default();
        let mut rows = Vec::new();
        for i in 0..ds.len() {
            let inputs = inputs_at(i);
            lagged = if i == 0 || ds.run[i] != ds.run[i - 1] {
                LaggedSlip::steady(&params, &inputs)
            } else {
                let distance =
                    column(&ds.speed, i).abs() * (column(&ds.time, i) - column(&ds.time, i - 1));
                lagged.advanced(&params, &inputs, distance)
            };
            let out = |lagged: &LaggedSlip| {
                mf87::evaluate_extended(
                    &params,
                    &inputs,
                    &conditions_at(i),
                    lagged,
                    SignConvention::Paper,
                )
            };
            // The lag matters: in these sweeps the steady-state outputs differ.
            if i % 300 > 2 {
                assert_ne!(out(&lagged), out(&LaggedSlip::steady(&params, &inputs)));
            }
            rows.push(out(&lagged));
        }
        let mut worst: f64 = 0.0;
        for m in &models {
            let data = ChannelData::from_dataset(&ds, m.channel).unwrap();
            let predicted = m.predictions(&data);
            for (i, (row, p)) in rows.iter().zip(&predicted).enumerate() {
                let got = match m.channel {
                    Channel::Fx => row.fx,
                    Channel::Fy => row.fy,
                    Channel::Mz => row.mz,
                };
                let error = (got - p).abs() / p.abs().max(1.0);
                assert!(
                    error <= 1e-9,
                    "{} row {i}: mf87 {got} vs tire-gap {p}",
                    m.channel
                );
                worst = worst.max(error);
            }
        }
        eprintln!("largest relative difference mf87 vs tire-gap: {worst:e}");
    }

    #[test]
    fn every_effect_at_all_its_parameters_reproduces_in_mf87() {
        // Every effect on every channel, each parameter moved off its starting value (the
        // MF 6.1-strength terms included: combined slip's shifts, load and camber terms and
        // induced force, pressure's second-order and load terms, the slip-ratio shift's Sv).
        let ds = dataset();
        // Each parameter moved off its starting value, but for those the effect holds on
        // the channel (terms that do not act there).
        let moved = |kind: Extension, channel: Channel| -> Vec<f64> {
            let effect = crate::method::fit::effects::of(kind);
            let start = effect.starting_values_on(channel);
            let held = effect.held(channel, Identifies::ALL);
            (0..kind.parameter_names().len())
                .map(|k| {
                    let v = start.get(k).copied().unwrap_or(0.0);
                    match held.contains(&k) {
                        true => v,
                        false => v + (0.02 * v.abs() + 0.002) * (1.0 + k as f64).sin(),
                    }
                })
                .collect()
        };
        let without_lag: Vec<Extension> = Extension::ALL
            .into_iter()
            .filter(|e| *e != Extension::RelaxationLength)
            .collect();
        let models = [Channel::Fx, Channel::Fy, Channel::Mz].map(|c| {
            let values: Vec<(Extension, Vec<f64>)> = without_lag
                .iter()
                .filter(|e| e.applies_to(c))
                .map(|&e| (e, moved(e, c)))
                .collect();
            let effects: Vec<(Extension, &[f64])> =
                values.iter().map(|(e, q)| (*e, q.as_slice())).collect();
            model(c, &effects)
        });
        let params = fitted_parameters(&models, &without_lag, &ds)
            .unwrap_or_else(|e| panic!("not exported: {e}"));
        let params = Params::from_json(&params.to_json()).unwrap();
        let column = |c: &Option<Column>, i: usize| c.as_ref().unwrap()[i];
        for m in &models {
            let data = ChannelData::from_dataset(&ds, m.channel).unwrap();
            let predicted = m.predictions(&data);
            for (i, p) in predicted.iter().enumerate() {
                let inputs = Inputs {
                    fz: ds.fz[i],
                    alpha: column(&ds.alpha, i),
                    kappa: column(&ds.kappa, i),
                    gamma: column(&ds.gamma, i),
                };
                let conditions = OperatingConditions {
                    vx: column(&ds.speed, i),
                    p: units::kilopascals_to_pascals(column(&ds.pressure, i)),
                    t_tread: units::celsius_to_kelvin(column(&ds.temperature, i)),
                };
                let row = mf87::evaluate_extended(
                    &params,
                    &inputs,
                    &conditions,
                    &LaggedSlip::steady(&params, &inputs),
                    SignConvention::Paper,
                );
                let got = match m.channel {
                    Channel::Fx => row.fx,
                    Channel::Fy => row.fy,
                    Channel::Mz => row.mz,
                };
                assert!(
                    (got - p).abs() <= 1e-9 * p.abs().max(1.0),
                    "{} row {i}: mf87 {got} vs tire-gap {p}",
                    m.channel
                );
            }
        }
    }

    #[test]
    fn without_effects_no_extensions_and_ranges_from_the_data() {
        let ds = dataset();
        let base = [model(Channel::Fy, &[])];
        let p = fitted_parameters(&base, &[], &ds).unwrap();
        assert!(p.extensions.is_none());
        assert!(!p.to_json().contains("extensions"));
        let limits = condition_limits(&ds);
        // Speed 8..20 m/s, widened by 1.2 m/s each side.
        assert!(
            (limits.speed_min_mps - 6.8).abs() < 1e-3 && (limits.speed_max_mps - 21.2).abs() < 1e-3
        );
        let no_columns = Dataset {
            speed: None,
            pressure: None,
            temperature: None,
            ..ds
        };
        assert_eq!(condition_limits(&no_columns), ConditionLimits::default());
    }

    #[test]
    fn extensions_invalid_over_the_data_range_are_refused_with_a_message() {
        // Pressure 180..260 kPa widened to 172..268; p0 = 220: d = -5 makes the peak
        // scale 1 - 5 * 0.218 < 0 at the top.
        let ds = dataset();
        let bad = [model(
            Channel::Fy,
            &[(Extension::InflationPressure, &[0.0, -5.0])],
        )];
        let err = fitted_parameters(&bad, &[], &ds).unwrap_err();
        assert!(
            err.contains("not valid over the data's range")
                && err.contains("extensions.Fy.inflation_pressure.d = -5"),
            "{err}"
        );
    }

    #[test]
    fn the_camber_range_is_the_datas() {
        // Camber +-2 deg in the data: a fitted a13 of 0.2 is valid up to 5 deg.
        let ds = dataset();
        let mut fy = model(Channel::Fy, &[]);
        let a13 = fy.names().iter().position(|n| n == "Fy.a13").unwrap();
        let mut theta = fy.theta();
        theta[a13] = 0.2;
        fy = fy.updated(&theta);
        let p = fitted_parameters(std::slice::from_ref(&fy), &[], &ds).unwrap();
        assert!(
            (p.limits.gamma_max_deg - 2.2).abs() < 1e-4,
            "{}",
            p.limits.gamma_max_deg
        );
        // Over +-6 deg it would be singular: refused, naming it.
        let mut wide = ds.clone();
        wide.gamma = wide.gamma.map(|g| g.iter().map(|x| 3.0 * x).collect());
        let e = fitted_parameters(&[fy], &[], &wide).unwrap_err();
        assert!(e.contains("Fy.a13 = 0.2"), "{e}");
        // Without camber in the data, the paper's range stays.
        let mut flat = ds;
        flat.gamma = None;
        let p = fitted_parameters(&[model(Channel::Fy, &[])], &[], &flat).unwrap();
        assert_eq!(
            p.limits.gamma_max_deg,
            Params::paper_table().limits.gamma_max_deg
        );
    }
}
