//! What the steps share: a channel's current model with its held-out residuals, whether its
//! systematic gap can be told from the noise, and its error summary.

use mf87::Channel;

use super::{ChannelBaseline, Options};
use crate::method::diagnose::regions::{Region, rank, regions};
use crate::method::fit::channel_fit::{ErrorSummary, SMOOTHING_WINDOW, systematic_mse};
use crate::method::fit::model::ChannelModel;
use crate::method::parallel::parallel_map;
use crate::method::prepare::channel_data::ChannelData;
use crate::method::stats::CompactResiduals;

/// State of one channel during selection.
#[derive(Clone)]
pub(super) struct ChannelState {
    pub(super) data: ChannelData,
    pub(super) noise: f64,
    pub(super) full: ChannelModel,
    /// One model per fold, each fitted on the other folds.
    pub(super) fold_models: Vec<ChannelModel>,
    /// The held-out residuals of the current model (shared by the copies of a state).
    pub(super) residuals: CompactResiduals,
    /// Mean square of the base model's systematic held-out residual, less the white part.
    pub(super) base_gap_sq: f64,
}

/// Whether a systematic gap (a mean square above the white part) can be told from the noise:
/// it must reach the least gain the method credits any effect with (`min_noise_gain` noise
/// variances). A share of a smaller gap would be a ratio of noise to noise.
pub(super) fn gap_measurable(gap_sq: f64, noise: f64, options: &Options) -> bool {
    gap_sq > 0.0 && gap_sq >= options.min_noise_gain * noise * noise
}

/// The reason a channel's gap is not measurable, for the report.
pub(super) fn no_gap_reason(gap_sq: f64, noise: f64, options: &Options) -> String {
    format!(
        "no measurable gap: the systematic part of its held-out residual exceeds \
         the white part by {:.3} noise variances, below the {} that any effect must gain; there \
         is no share of a gap to close",
        gap_sq.max(0.0) / (noise * noise),
        options.min_noise_gain
    )
}

/// The held-out error of a channel's current residuals, and whether its gap is measurable.
pub(super) fn summary(
    state: &ChannelState,
    in_sample_rms: Option<f64>,
    options: &Options,
) -> ChannelBaseline {
    let residuals = &state.residuals;
    let heldout = ErrorSummary::of(residuals.as_single(), &state.data.fz_kn);
    let white = state.noise * state.noise / SMOOTHING_WINDOW as f64;
    let gap_sq = systematic_mse(&state.data.run, residuals.as_single()) - white;
    ChannelBaseline {
        channel: state.data.channel,
        unit: if state.data.channel == Channel::Mz {
            "N.m"
        } else {
            "N"
        },
        heldout,
        in_sample_rms,
        noise_floor: state.noise,
        gap: (heldout.rms.powi(2) - state.noise.powi(2)).max(0.0).sqrt(),
        no_gap: (!gap_measurable(gap_sq, state.noise, options))
            .then(|| no_gap_reason(gap_sq, state.noise, options)),
    }
}

/// Where the gap lies, ranked: regions of the channels' current residuals, leaving out the
/// channels whose summary says they have no measurable gap (they hold only noise).
pub(super) fn gap_regions(states: &[ChannelState], summaries: &[ChannelBaseline]) -> Vec<Region> {
    let with_gap: Vec<&ChannelState> = states
        .iter()
        .zip(summaries)
        .filter(|(_, b)| b.no_gap.is_none())
        .map(|(s, _)| s)
        .collect();
    // The channels side by side.
    let per_channel = parallel_map(&with_gap, |s| regions(&s.data, s.residuals.as_single()));
    rank(per_channel.into_iter().flatten().collect())
}
