//! Step 6: the fitted parameters as a parameter file the FMU reads.

use mf87::{Channel, Params};

use crate::data::Dataset;
use crate::diagnose::Diagnosis;

/// The fitted coefficients of every measured channel (the paper's table for the others) in
/// the FMU's parameter-file format, validated over the data's load range.
pub fn parameter_file(d: &Diagnosis, ds: &Dataset) -> Result<String, String> {
    let mut params = Params::paper_table();
    for model in &d.models {
        let fitted = model.params_with(&model.theta());
        match model.channel {
            Channel::Fx => params.Fx = fitted.Fx,
            Channel::Fy => params.Fy = fitted.Fy,
            Channel::Mz => params.Mz = fitted.Mz,
        }
    }
    // The validity range covers the measured loads and cambers, with a margin.
    let fz_max = ds.fz.iter().copied().fold(0.0, f64::max);
    params.limits.fz_max_N = (1.1 * fz_max).max(1000.0);
    if let Some(g) = ds.gamma.as_ref() {
        let g_max = g.iter().map(|x| x.abs().to_degrees()).fold(0.0, f64::max);
        params.limits.gamma_max_deg = params.limits.gamma_max_deg.max(1.1 * g_max).min(89.0);
    }
    params.source = Some(format!(
        "tire-gap {} fit of {} ({} rows); effects selected: [{}] (their parameters are in the report)",
        env!("CARGO_PKG_VERSION"),
        ds.source,
        ds.len(),
        d.verdict
            .iter()
            .map(|e| e.id())
            .collect::<Vec<_>>()
            .join(", ")
    ));
    params
        .validate()
        .map_err(|e| format!("the fitted parameters are not valid over the data's range: {e}"))?;
    Ok(params.to_json())
}
