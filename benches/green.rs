//! Benchmarks of the free-surface Green function: the scaled exponential integral `e^z E1(z)`
//! at the arguments of a 100-panel semicircle's centre pairs (kR 0.05 .. 10), building a
//! wave Green function, and the panel integrals of that semicircle (rigid lid and wave; the wave
//! part alone pair by pair and from prepared [`PanelPairs`], and their preparation).
//!
//! ```sh
//! cargo bench --bench green
//! ```

use criterion::{criterion_group, criterion_main, Criterion};
use hydrofmu::green::{self, FreeSurface, GreenFunction, PanelIntegral, PanelPairs, Point};
use num_complex::Complex64;
use std::f64::consts::PI;
use std::hint::black_box;

const PANELS: usize = 100;

fn semicircle_nodes() -> Vec<Point> {
    (0..=PANELS)
        .map(|i| {
            let t = PI * i as f64 / PANELS as f64;
            [-t.cos(), -t.sin()]
        })
        .collect()
}

fn centres(nodes: &[Point]) -> Vec<Point> {
    nodes
        .windows(2)
        .map(|w| [0.5 * (w[0][0] + w[1][0]), 0.5 * (w[0][1] + w[1][1])])
        .collect()
}

/// kR from 0.05 to 10, 20 points (R = 1 m, so k = kR).
fn wavenumbers() -> Vec<f64> {
    (0..20)
        .map(|j| 0.05 * 200f64.powf(j as f64 / 19.0))
        .collect()
}

fn exponential_integral(c: &mut Criterion) {
    let centres = centres(&semicircle_nodes());
    let mut args = Vec::new();
    for k in wavenumbers() {
        for x in &centres {
            for x0 in &centres {
                args.push(Complex64::new(
                    k * (x[1] + x0[1]),
                    -k * (x[0] - x0[0]).abs(),
                ));
            }
        }
    }
    c.bench_function("e^z E1(z), 200000 arguments of a semicircle sweep", |b| {
        b.iter(|| {
            args.iter()
                .map(|&z| green::scaled_exp_integral(black_box(z)))
                .sum::<Complex64>()
        })
    });
}

fn green_function(c: &mut Criterion) {
    c.bench_function("GreenFunction::new (wave, builds its table)", |b| {
        b.iter(|| {
            GreenFunction::new(FreeSurface::Wave {
                wavenumber: black_box(1.0),
            })
            .unwrap()
        })
    });
    let nodes = semicircle_nodes();
    let centres = centres(&nodes);
    // Sum of d/dy over every (centre, panel) pair of the semicircle.
    let over_pairs = |integral: &dyn Fn(Point, Point, Point) -> PanelIntegral| {
        let mut acc = Complex64::new(0.0, 0.0);
        for x in &centres {
            for w in nodes.windows(2) {
                acc += integral(*x, w[0], w[1]).gradient[1];
            }
        }
        acc
    };
    let sweep = |g: &GreenFunction| over_pairs(&|x, a, b| g.panel_integral(x, a, b));
    let rigid = GreenFunction::new(FreeSurface::RigidLid).unwrap();
    c.bench_function(
        "panel integrals, rigid lid, 100-panel semicircle (10^4)",
        |b| b.iter(|| sweep(black_box(&rigid))),
    );
    let waves: Vec<GreenFunction> = wavenumbers()
        .into_iter()
        .map(|k| GreenFunction::new(FreeSurface::Wave { wavenumber: k }).unwrap())
        .collect();
    c.bench_function(
        "panel integrals, wave, 100-panel semicircle at 20 kR (2 x 10^5)",
        |b| b.iter(|| waves.iter().map(|g| sweep(black_box(g))).sum::<Complex64>()),
    );
    // The wave part alone, pair by pair and from prepared pairs (what a sweep does).
    let beyond =
        |g: &GreenFunction| over_pairs(&|x, a, b| g.panel_integral_beyond_dirichlet(x, a, b));
    c.bench_function(
        "wave part, pair by pair, 100-panel semicircle at 20 kR (2 x 10^5)",
        |b| {
            b.iter(|| {
                waves
                    .iter()
                    .map(|g| beyond(black_box(g)))
                    .sum::<Complex64>()
            })
        },
    );
    let pairs = PanelPairs::new(
        centres
            .iter()
            .flat_map(|&x| nodes.windows(2).map(move |w| (x, w[0], w[1]))),
    );
    let mut values = Vec::new();
    c.bench_function(
        "wave part, prepared pairs, 100-panel semicircle at 20 kR (2 x 10^5)",
        |b| {
            b.iter(|| {
                let mut acc = Complex64::new(0.0, 0.0);
                for g in &waves {
                    black_box(g).panel_integrals_beyond_dirichlet(&pairs, &mut values);
                    acc += values.iter().map(|v| v.gradient[1]).sum::<Complex64>();
                }
                acc
            })
        },
    );
    c.bench_function("PanelPairs::new, 100-panel semicircle (10^4 pairs)", |b| {
        b.iter(|| {
            PanelPairs::new(
                centres
                    .iter()
                    .flat_map(|&x| nodes.windows(2).map(move |w| (x, w[0], w[1]))),
            )
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = exponential_integral, green_function
}
criterion_main!(benches);
