//! Benchmarks of the hydrodynamic pipeline: one radiation solve, and the full default sweep of
//! the semicircle (9 DOFs, kR = 0.01 .. 10, 201 points) on 1 and 2 threads, with and without
//! the exciting forces; and the same sweep in deep water and in water of depth `h/R = 2` and
//! `2000` (docs/FINITE_DEPTH.md, "Speed").
//!
//! ```sh
//! cargo bench --bench sweep
//! ```

use criterion::{criterion_group, criterion_main, Criterion};
use hydrofmu::bem::{self, IrregularFrequencies};
use hydrofmu::green::FreeSurface;
use hydrofmu::hull::Hull;
use hydrofmu::panels::{self, PanelParams};
use hydrofmu::sweep::{self, SweepParams};
use hydrofmu::units::WaterDepth;
use std::hint::black_box;

fn single_solve(c: &mut Criterion) {
    let hull = Hull::semicircle(1.0).unwrap();
    let mesh = panels::discretize(&hull, &PanelParams::default()).unwrap();
    c.bench_function("solve one frequency, semicircle, default panels", |b| {
        b.iter(|| {
            bem::solve(
                black_box(&mesh),
                FreeSurface::Wave { wavenumber: 1.0 },
                IrregularFrequencies::RemoveWithLid,
            )
            .unwrap()
        })
    });
}

fn full_sweep(c: &mut Criterion) {
    let hull = Hull::semicircle(1.0).unwrap();
    let mut group = c.benchmark_group("semicircle default sweep");
    group.sample_size(10);
    for threads in [1, 2] {
        let params = SweepParams {
            threads,
            ..SweepParams::default()
        };
        group.bench_function(format!("{threads} threads"), |b| {
            b.iter(|| sweep::run(black_box(&hull), &params, &|_, _| {}).unwrap())
        });
    }
    // The exciting forces' share of the sweep, measured in the same run.
    let radiation_only = SweepParams {
        excitation: false,
        ..SweepParams::default()
    };
    group.bench_function("2 threads, radiation only", |b| {
        b.iter(|| sweep::run(black_box(&hull), &radiation_only, &|_, _| {}).unwrap())
    });
    group.finish();
}

fn finite_depth_sweep(c: &mut Criterion) {
    let hull = Hull::semicircle(1.0).unwrap();
    let mut group = c.benchmark_group("semicircle default sweep, water depth");
    group.sample_size(10);
    // Deep water first: the reference of the ratios.
    for (name, depth) in [
        ("deep", WaterDepth::Infinite),
        ("h/R = 2", WaterDepth::Finite(2.0)),
        ("h/R = 2000", WaterDepth::Finite(2000.0)),
    ] {
        let params = SweepParams {
            depth,
            ..SweepParams::default()
        };
        group.bench_function(name, |b| {
            b.iter(|| sweep::run(black_box(&hull), &params, &|_, _| {}).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, single_solve, full_sweep, finite_depth_sweep);
criterion_main!(benches);
