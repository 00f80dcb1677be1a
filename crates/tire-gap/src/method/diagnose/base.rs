//! Steps 1-3: the channels the data can support and its reference conditions; the 1987
//! model fitted on all data (several starts) and on each fold's training runs, its held-out
//! error against the noise floor, and where the gap lies.

use mf87::{Channel, Params};

use super::plausibility::Plausibility;
use super::state::{ChannelState, gap_regions, summary};
use super::{ChannelBaseline, DiagnoseError, Options, Stopped};
use crate::data::{Dataset, Quantity};
use crate::method::diagnose::regions::Region;
use crate::method::fit::channel_fit::{
    SMOOTHING_WINDOW, Start, cross_validate, fit_channel, noise_floor, systematic_mse,
};
use crate::method::fit::effects::Nominal;
use crate::method::fit::model::ChannelModel;
use crate::method::observer::Observer;
use crate::method::parallel::parallel_map;
use crate::method::prepare::adequacy::{self, Limitation};
use crate::method::prepare::channel_data::ChannelData;
use crate::method::prepare::cv::Folds;
use crate::method::stats::CompactResiduals;
use crate::quantiles::median_of;

/// Reference conditions: medians of the data (defaults where a column is missing).
pub fn nominal_of(ds: &Dataset) -> Nominal {
    let median = |q: Quantity| {
        let column = ds.column(q)?;
        median_of(|| column.iter().copied())
    };
    let med = |q: Quantity, default: f64| median(q).filter(|m| *m > 0.0).unwrap_or(default);
    Nominal {
        pressure_kpa: med(Quantity::Pressure, 200.0),
        speed_mps: med(Quantity::Speed, 10.0),
        temperature_c: median(Quantity::Temperature).unwrap_or(25.0),
    }
}

/// The error when no channel is left, with each limitation that took one away.
fn nothing_to_diagnose(ds: &Dataset, limitations: &[Limitation]) -> DiagnoseError {
    let reasons: Vec<String> = limitations
        .iter()
        .map(|l| format!("{}: {}", l.subject, l.reason))
        .collect();
    DiagnoseError(format!(
        "{}: no channel can be diagnosed: {}",
        ds.source,
        reasons.join("; ")
    ))
}

/// The measured channels the data can support, with the limitations of those it cannot.
pub(super) fn channels_to_diagnose(
    ds: &Dataset,
    folds: &Folds,
    limitations: &mut Vec<Limitation>,
) -> Result<Vec<ChannelData>, DiagnoseError> {
    let measured = ChannelData::channels_of(ds, &[Channel::Fx, Channel::Fy, Channel::Mz]);
    if measured.is_empty() {
        return Err(DiagnoseError(
            "no measured channel with its slip: nothing to fit".into(),
        ));
    }
    let coefficients = measured
        .iter()
        .map(adequacy::fitted_coefficients)
        .max()
        .unwrap_or(0);
    adequacy::check_runs(ds, folds, coefficients).map_err(DiagnoseError)?;
    let mut channels = Vec::new();
    // Mz shares Fy's slip angle: a unit that Fy's sweeps doubt is doubted for Mz too.
    let alpha_doubt = measured
        .iter()
        .find(|d| d.channel == Channel::Fy)
        .and_then(adequacy::slip_unit_doubt);
    // The channels checked side by side.
    let checked = parallel_map(&measured, |data| match (&alpha_doubt, data.channel) {
        (Some(why), Channel::Mz) => Some(Limitation::new(
            "Mz",
            format!(
                "not diagnosed, implausible: its slip angle is Fy's, doubted by Fy's sweeps: {why}"
            ),
        )),
        _ => adequacy::check_channel(data, folds),
    });
    for (data, limitation) in measured.into_iter().zip(checked) {
        match limitation {
            Some(limitation) => limitations.push(limitation),
            None => channels.push(data),
        }
    }
    if channels.is_empty() {
        return Err(nothing_to_diagnose(ds, limitations));
    }
    limitations.extend(adequacy::load_range(ds));
    Ok(channels)
}

/// The base model of one channel: fitted on all data, and per fold for held-out residuals.
struct BaseFit {
    in_sample_rms: f64,
    noise: f64,
    full: ChannelModel,
    fold_models: Vec<ChannelModel>,
    residuals: CompactResiduals,
    base_gap_sq: f64,
}

/// Steps 1-2 for one channel: the 1987 model fitted on all data (several starts) and on each
/// fold's training runs, its held-out residuals and their noise floor.
fn fit_base(
    data: &ChannelData,
    folds: &Folds,
    paper: &Params,
    nominal: Nominal,
    plausibility: &Plausibility,
    observer: &dyn Observer,
) -> Result<BaseFit, DiagnoseError> {
    let channel = data.channel;
    let start = ChannelModel::new(paper.clone(), channel, data.has_camber(), nominal)
        .identifying(crate::method::diagnose::design::identifies(data));
    let exports = |m: &ChannelModel| plausibility.exports(m);
    let fit = fit_channel(data, &start, Start::Multi, Some(&exports)).ok_or_else(|| {
        DiagnoseError(format!(
            "the fit of {channel} failed (non-finite model values)"
        ))
    })?;
    observer.step();
    let folded = fold_fits(data, folds, &fit.model, plausibility, observer)
        .ok_or_else(|| DiagnoseError(format!("cross-validation of {channel} failed")))?;
    Ok(BaseFit {
        in_sample_rms: fit.rms(data),
        noise: folded.noise,
        full: fit.model,
        fold_models: folded.fold_models,
        residuals: folded.residuals,
        base_gap_sq: folded.base_gap_sq,
    })
}

/// The base model refitted on each fold's training runs, warm-started from the all-data fit
/// `full`, with its held-out residuals, their noise floor and the systematic gap. The fold
/// fits are held to the FMU's bounds, as the all-data fit is: the held-out residuals are those
/// of models a parameter file can hold, and the candidates' fold fits, which start from them,
/// start within the bounds.
struct FoldFits {
    fold_models: Vec<ChannelModel>,
    residuals: CompactResiduals,
    noise: f64,
    base_gap_sq: f64,
}

fn fold_fits(
    data: &ChannelData,
    folds: &Folds,
    full: &ChannelModel,
    plausibility: &Plausibility,
    observer: &dyn Observer,
) -> Option<FoldFits> {
    let exports = |m: &ChannelModel| plausibility.exports(m);
    // A fold whose training fit fails keeps the all-data fit.
    let (fold_models, residuals) = cross_validate::<f32>(data, folds, |train, _| {
        if observer.cancelled() {
            return None;
        }
        let model = fit_channel(train, full, Start::Warm, Some(&exports))
            .map_or_else(|| full.clone(), |f| f.model);
        observer.step();
        Some(model)
    })?;
    let noise = noise_floor(&data.run, &residuals);
    let white = noise * noise / SMOOTHING_WINDOW as f64;
    let base_gap_sq = (systematic_mse(&data.run, &residuals) - white).max(0.0);
    Some(FoldFits {
        fold_models,
        residuals: CompactResiduals::from_single(residuals),
        noise,
        base_gap_sq,
    })
}

/// The channels' base models (fitted on all data) cross-validated on another assignment of
/// runs to folds, in parallel; a channel whose cross-validation fails keeps `states`' folds.
pub(super) fn refold(
    states: &[ChannelState],
    folds: &Folds,
    plausibility: &Plausibility,
    observer: &dyn Observer,
) -> Vec<ChannelState> {
    observer.stage(
        &format!("the 1987 model on fold assignment {}", folds.seed),
        (states.len() * folds.k) as u64,
    );
    let folded = parallel_map(states, |s| {
        fold_fits(&s.data, folds, &s.full, plausibility, observer)
    });
    states
        .iter()
        .zip(folded)
        .map(|(s, f)| match f {
            Some(f) => ChannelState {
                data: s.data.clone(),
                noise: f.noise,
                full: s.full.clone(),
                fold_models: f.fold_models,
                residuals: f.residuals,
                base_gap_sq: f.base_gap_sq,
            },
            None => s.clone(),
        })
        .collect()
}

/// A channel with its base model, ready for selection.
pub(super) struct BaseChannel {
    pub(super) state: ChannelState,
    /// RMS of the fit on all data, on the rows it was fitted to.
    pub(super) in_sample_rms: f64,
}

/// Steps 1-2 on every channel, in parallel. A channel whose noise floor cannot be estimated
/// against its error is left out with a limitation; none left is an error. Cancelled: the
/// channels not yet started are skipped.
pub(super) fn fit_channels(
    ds: &Dataset,
    channels: Vec<ChannelData>,
    folds: &Folds,
    nominal: Nominal,
    plausibility: &Plausibility,
    limitations: &mut Vec<Limitation>,
    observer: &dyn Observer,
) -> Result<Vec<BaseChannel>, Stopped> {
    observer.stage(
        &format!(
            "fitting the 1987 model to {} ({} rows), on all runs and per fold",
            channels
                .iter()
                .map(|d| d.channel.name())
                .collect::<Vec<_>>()
                .join(", "),
            ds.len()
        ),
        (channels.len() * (folds.k + 1)) as u64,
    );
    let paper = Params::paper_table();
    let fitted = parallel_map(&channels, |data| match observer.cancelled() {
        true => Err(Stopped::Cancelled),
        false => Ok(fit_base(
            data,
            folds,
            &paper,
            nominal,
            plausibility,
            observer,
        )?),
    });
    // A channel cancelled halfway fails its fits: the cancellation is the outcome.
    if observer.cancelled() {
        return Err(Stopped::Cancelled);
    }
    let mut kept = Vec::new();
    for (data, fit) in channels.into_iter().zip(fitted) {
        let fit = fit?;
        let rms = fit.residuals.mse().sqrt();
        match adequacy::noise_floor_limitation(data.channel, fit.noise, rms) {
            Some(limitation) => limitations.push(limitation),
            None => kept.push(BaseChannel {
                in_sample_rms: fit.in_sample_rms,
                state: ChannelState {
                    data,
                    noise: fit.noise,
                    full: fit.full,
                    fold_models: fit.fold_models,
                    residuals: fit.residuals,
                    base_gap_sq: fit.base_gap_sq,
                },
            }),
        }
    }
    if kept.is_empty() {
        return Err(nothing_to_diagnose(ds, limitations).into());
    }
    Ok(kept)
}

/// The base model of one channel and its held-out residuals, kept for figures.
pub(super) struct BaseForFigures {
    pub(super) model: ChannelModel,
    pub(super) residuals: CompactResiduals,
}

/// The base model's error on every channel, and where its gap lies.
pub(super) struct Base {
    /// The channels, ready for selection.
    pub(super) states: Vec<ChannelState>,
    pub(super) baseline: Vec<ChannelBaseline>,
    pub(super) regions: Vec<Region>,
    pub(super) for_figures: Vec<BaseForFigures>,
}

/// Step 2's summary and step 3: the held-out error per channel (a channel whose gap cannot
/// be told from the noise gets a limitation: no effect is tested on it), and the regions
/// where the gap lies.
pub(super) fn baseline(
    fitted: Vec<BaseChannel>,
    options: &Options,
    limitations: &mut Vec<Limitation>,
) -> Base {
    let baseline: Vec<ChannelBaseline> = parallel_map(&fitted, |f| {
        summary(&f.state, Some(f.in_sample_rms), options)
    });
    for b in &baseline {
        if let Some(reason) = &b.no_gap {
            limitations.push(Limitation::new(
                b.channel.name(),
                format!("{reason}; no effect is tested on it"),
            ));
        }
    }
    let states: Vec<ChannelState> = fitted.into_iter().map(|f| f.state).collect();
    // Regions rank where a gap lies: channels without one hold only noise.
    let regions = gap_regions(&states, &baseline);
    let for_figures = states
        .iter()
        .map(|s| BaseForFigures {
            model: s.full.clone(),
            residuals: s.residuals.clone(),
        })
        .collect();
    Base {
        states,
        baseline,
        regions,
        for_figures,
    }
}
