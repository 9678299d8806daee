//! The sea at one communication point: `Sea::evaluate` (elevation and the exciting force of
//! 9 DOFs) for a JONSWAP sea at 50 to 400 components, times `k h` (h = 0.01 s) and
//! accumulated `t += h`, against the direct sum. A calm step of the default network costs
//! 424 ns (`cargo bench --bench step`); the sea must cost at most about that again.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use hydrofmu::waves::{ExcitationTable, Sea, WaveKind, WaveParams, DEFAULT_COMPONENTS};

mod common;

fn table() -> ExcitationTable {
    ExcitationTable::from_csv_str(&common::synthetic_excitation_csv(), "bench").unwrap()
}

fn sea(table: &ExcitationTable, components: usize) -> Sea {
    let params = WaveParams {
        kind: WaveKind::Jonswap,
        height: 2.0,
        period: 8.0,
        components,
        ..WaveParams::default()
    };
    Sea::new(&params, Some(table), 1025.0, 9.81, 0.0).unwrap()
}

fn evaluate(c: &mut Criterion) {
    let table = table();
    let h = 0.01;
    let mut forces = [0.0; 9];
    for components in [50, 64, 100, 200, 400] {
        let sea = sea(&table, components);
        let mut scratch = sea.scratch();
        let mut k = 0u64;
        c.bench_function(&format!("evaluate, 9 DOFs, {components} components"), |b| {
            b.iter(|| {
                k += 1;
                black_box(sea.evaluate(k as f64 * h, &mut scratch, &mut forces));
                black_box(&forces);
            })
        });
    }
    let sea = sea(&table, DEFAULT_COMPONENTS);
    let mut scratch = sea.scratch();
    let mut time = 0.0;
    c.bench_function(
        &format!("evaluate, 9 DOFs, {DEFAULT_COMPONENTS} components, time t += h"),
        |b| {
            b.iter(|| {
                time += h;
                black_box(sea.evaluate(time, &mut scratch, &mut forces));
                black_box(&forces);
            })
        },
    );
    let mut k = 0u64;
    c.bench_function(
        &format!("direct sum, 9 DOFs, {DEFAULT_COMPONENTS} components"),
        |b| {
            b.iter(|| {
                k += 1;
                black_box(sea.evaluate_direct(k as f64 * h, &mut forces));
                black_box(&forces);
            })
        },
    );
}

criterion_group!(benches, evaluate);
criterion_main!(benches);
