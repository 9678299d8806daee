//! Benchmarks of the identification on the panel method's own semicircle data (the issue's
//! cases): sway alone (the automatic form, where the series chain and the rational fit compete,
//! and the rational fit at 5 states), the full 9x9 coupled network (default: the rational path)
//! in the default band kR 0.05 .. 5 and the wide band kR 0.01 .. 5, and the branch chains; and
//! the default fit of the midship section (examples/hulls/midship.xml, the scene's defaults),
//! an input the identification was not tuned to (docs/IDENTIFICATION.md).
//!
//! ```sh
//! cargo bench --bench fit
//! ```

use criterion::{criterion_group, criterion_main, Criterion};
use hydrofmu::fmu::description::{DEFAULT_G, DEFAULT_RHO};
use hydrofmu::hull::Hull;
use hydrofmu::identify::{self, CoupledMethod, FitParams, FrequencyResponse};
use hydrofmu::network::NetworkForm;
use hydrofmu::sweep::{self, SweepParams};
use hydrofmu::units;
use std::hint::black_box;

fn semicircle() -> FrequencyResponse {
    let params = SweepParams {
        kr: sweep::log_grid(0.01, 5.0, 150).expect("grid"),
        ..SweepParams::default()
    };
    let result =
        sweep::run(&Hull::semicircle(1.0).expect("hull"), &params, &|_, _| {}).expect("sweep");
    FrequencyResponse::from_sweep(&result, DEFAULT_RHO, DEFAULT_G)
}

/// The band from kR `lo` to `hi`, widened by rounding.
fn band(lo: f64, hi: f64) -> (f64, f64) {
    let omega = |kr| units::omega_from_kr(kr, 1.0, DEFAULT_G);
    (omega(lo) * 0.999, omega(hi) * 1.001)
}

fn fits(c: &mut Criterion) {
    let data = semicircle();
    let sway = data.select(&["sway"]).expect("sway");
    let automatic = FitParams {
        band: band(0.05, 5.0),
        ..FitParams::default()
    };
    c.bench_function("fit sway, automatic (chain or rational), kR 0.05..5", |b| {
        b.iter(|| identify::fit(black_box(&sway), &automatic).expect("fit"))
    });
    let rational = FitParams {
        form: Some(NetworkForm::Coupled),
        order: Some(5),
        ..automatic.clone()
    };
    c.bench_function("fit sway, rational, 5 states, kR 0.05..5", |b| {
        b.iter(|| identify::fit(black_box(&sway), &rational).expect("fit"))
    });
    let mut group = c.benchmark_group("coupled");
    group.sample_size(10);
    group.bench_function("fit 9x9, default (rational), kR 0.05..5", |b| {
        b.iter(|| identify::fit(black_box(&data), &automatic).expect("fit"))
    });
    let wide = FitParams {
        band: band(0.01, 5.0),
        ..FitParams::default()
    };
    group.bench_function("fit 9x9, default (rational), kR 0.01..5", |b| {
        b.iter(|| identify::fit(black_box(&data), &wide).expect("fit"))
    });
    let chains = FitParams {
        coupled_method: CoupledMethod::Chains,
        ..automatic.clone()
    };
    group.bench_function("fit 9x9, branch chains, kR 0.05..5", |b| {
        b.iter(|| identify::fit(black_box(&data), &chains).expect("fit"))
    });
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hulls/midship.xml");
    let built = hydrofmu::scene::Scene::new(Hull::from_file(&path).expect("hull"))
        .build()
        .expect("scene");
    let midship = built
        .response(&built.sweep(&|_, _| {}).expect("sweep"))
        .expect("response");
    group.bench_function("fit midship 6 DOFs, default, kR 0.05..5", |b| {
        b.iter(|| built.fit(black_box(&midship)).expect("fit"))
    });
    group.finish();
}

criterion_group!(benches, fits);
criterion_main!(benches);
