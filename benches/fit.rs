//! Benchmarks of the identification on the panel method's own semicircle data: a one-DOF
//! series chain (sway, 2 added DOFs) and the full 9x9 coupled network.
//!
//! ```sh
//! cargo bench --bench fit
//! ```

use criterion::{criterion_group, criterion_main, Criterion};
use hydrofmu::fmu::description::{DEFAULT_G, DEFAULT_RHO};
use hydrofmu::hull::Hull;
use hydrofmu::identify::{self, FitParams, FrequencyResponse};
use hydrofmu::network::NetworkForm;
use hydrofmu::sweep::{self, SweepParams};
use hydrofmu::units;
use std::hint::black_box;

fn semicircle() -> FrequencyResponse {
    let params = SweepParams {
        kr: sweep::log_grid(0.01, 4.5, 120).expect("grid"),
        ..SweepParams::default()
    };
    let result =
        sweep::run(&Hull::semicircle(1.0).expect("hull"), &params, &|_, _| {}).expect("sweep");
    FrequencyResponse::from_sweep(&result, DEFAULT_RHO, DEFAULT_G)
}

fn omega(kr: f64) -> f64 {
    units::omega_from_kr(kr, 1.0, DEFAULT_G)
}

fn fits(c: &mut Criterion) {
    let data = semicircle();
    let sway = data.select(&["sway"]).expect("sway");
    let chain = FitParams {
        form: Some(NetworkForm::SeriesChain),
        band: (omega(0.01) * 0.999, omega(4.0) * 1.001),
        order: Some(2),
        ..FitParams::default()
    };
    c.bench_function("fit sway, series chain, 2 added DOFs", |b| {
        b.iter(|| identify::fit(black_box(&sway), &chain).expect("fit"))
    });
    let coupled = FitParams {
        form: Some(NetworkForm::Coupled),
        band: (omega(0.05) * 0.999, omega(4.0) * 1.001),
        ..FitParams::default()
    };
    let mut group = c.benchmark_group("coupled");
    group.sample_size(10);
    group.bench_function("fit 9x9 coupled network, default 1 % tolerance", |b| {
        b.iter(|| identify::fit(black_box(&data), &coupled).expect("fit"))
    });
    group.finish();
}

criterion_group!(benches, fits);
criterion_main!(benches);
