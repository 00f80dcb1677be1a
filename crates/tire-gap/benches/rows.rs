//! What one row of a fit costs: the 1987 model of each channel, alone and with each effect at
//! its starting values, evaluated (`value`) and differentiated by every parameter
//! (`jacobian`, [`ChannelModel::jacobian`] as the fits call it) on 20,000 rows with every
//! condition measured; for combined slip also in one forward pass (`jacobian_one_pass`,
//! [`ChannelModel::jacobian_forward`]), against which the chain rule through the factors is
//! chosen. Throughput is in rows.
//!
//! Run with `cargo bench -p tire-gap --bench rows`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput};
use mf87::extensions::{Extension, Nominal};
use mf87::{Channel, Params};
use nalgebra::DMatrix;
use tire_gap::method::fit::model::ChannelModel;
use tire_gap::method::prepare::channel_data::ChannelData;

const ROWS: usize = 20_000;

/// Rows spread over load 1.5..6.5 kN, slip -12..12, camber -4..4 deg and the conditions, by a
/// multiplicative sequence (no two neighbours alike).
fn data(channel: Channel) -> ChannelData {
    let f = |i: usize, a: f64, b: f64| a + b * ((i * 7919 % 61) as f64 / 61.0);
    ChannelData {
        channel,
        run: (0..ROWS).map(|i| (i / 200) as i64).collect(),
        fz_kn: (0..ROWS).map(|i| f(i, 1.5, 5.0)).collect(),
        slip: (0..ROWS).map(|i| f(i, -12.0, 24.0)).collect(),
        gamma_deg: (0..ROWS).map(|i| f(i, -4.0, 8.0)).collect(),
        measured: vec![0.0; ROWS].into(),
        other_slip: Some((0..ROWS).map(|i| f(i, -0.2, 0.4)).collect()),
        time: None,
        speed: Some((0..ROWS).map(|i| f(i, 5.0, 25.0)).collect()),
        pressure: Some((0..ROWS).map(|i| f(i, 180.0, 120.0)).collect()),
        temperature: Some((0..ROWS).map(|i| f(i, 20.0, 70.0)).collect()),
        counted: None,
    }
}

fn bench_rows(c: &mut Criterion) {
    let nominal = Nominal {
        pressure_kpa: 220.0,
        speed_mps: 15.0,
        temperature_c: 40.0,
    };
    let mut group = c.benchmark_group("rows");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(300));
    group.measurement_time(Duration::from_secs(1));
    group.throughput(Throughput::Elements(ROWS as u64));
    for channel in Channel::ALL {
        let data = data(channel);
        let base = ChannelModel::new(Params::paper_table(), channel, true, nominal);
        let mut models = vec![("base", base.clone())];
        for e in Extension::ALL.into_iter().filter(|e| e.applies_to(channel)) {
            models.push((e.name(), base.with_effect(e)));
        }
        for (name, model) in models {
            let theta = model.theta();
            let all: Vec<usize> = (0..theta.len()).collect();
            let mut out = vec![0.0; ROWS];
            let mut jac = DMatrix::zeros(ROWS, theta.len());
            group.bench_function(format!("{channel}/{name}/value"), |b| {
                b.iter(|| model.predict(black_box(&theta), &data, &mut out))
            });
            group.bench_function(format!("{channel}/{name}/jacobian"), |b| {
                b.iter(|| model.jacobian(black_box(&theta), &all, &data, &mut jac))
            });
            if name == Extension::CombinedSlip.name() {
                group.bench_function(format!("{channel}/{name}/jacobian_one_pass"), |b| {
                    b.iter(|| model.jacobian_forward(black_box(&theta), &all, &data, &mut jac))
                });
            }
        }
    }
    group.finish();
}

criterion::criterion_group!(benches, bench_rows);
criterion::criterion_main!(benches);
