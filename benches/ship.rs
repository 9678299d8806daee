//! The ship's sweep (docs/SHIPS.md): the speed case of 41 distinct semicircle stations solved in
//! their 9 DOFs each (examples/ships/semicircles.xml) at 100 frequencies and 5 headings with the
//! defaults (64 panels, 3 levels) on 2 threads; and the 41-station Wigley-like ship of Lewis
//! sections (20 distinct, rigid DOFs and one bending mode).
//!
//! ```sh
//! cargo bench --bench ship
//! ```

use criterion::{criterion_group, criterion_main, Criterion};
use hydrofmu::ship::{strip, Ship, ShipSweepParams};
use std::hint::black_box;
use std::path::Path;

fn ship(name: &str) -> Ship {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/ships")
        .join(name);
    Ship::from_file(&path).expect("example ship")
}

fn sweeps(c: &mut Criterion) {
    let mut group = c.benchmark_group("ship sweep");
    group.sample_size(10);
    for (label, file) in [
        (
            "41 semicircles x 9 DOFs, 100 frequencies",
            "semicircles.xml",
        ),
        (
            "Wigley-like, 41 Lewis stations, 100 frequencies",
            "wigley.xml",
        ),
    ] {
        let ship = ship(file);
        let params = ShipSweepParams {
            threads: 2,
            ..ShipSweepParams::for_ship(&ship)
        };
        assert_eq!(params.omega.len(), 100);
        group.bench_function(label, |b| {
            b.iter(|| black_box(strip::run(&ship, &params, &|_, _| {}).expect("sweep")))
        });
    }
    group.finish();
}

criterion_group!(benches, sweeps);
criterion_main!(benches);
