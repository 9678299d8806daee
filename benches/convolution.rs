//! The radiation force of the default 9-DOF semicircle network by direct convolution over a
//! 6000-step history (the classic alternative to the network), one step; compare with the
//! network's step through the C ABI (`cargo bench --bench step`).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use hydrofmu::network::Network;
use nalgebra::DVector;

// Its unit tests run in tests/convolution.rs; not every item is used here.
#[allow(dead_code)]
#[path = "common/convolution.rs"]
mod convolution;
use convolution::ConvolutionForce;

/// The network `fmu-pack` fits for the built-in semicircle with default settings
/// (regenerate: `cargo run --release -p fmu-pack -- fit semicircle --network-out
/// examples/networks/semicircle_9dof.xml`).
const NETWORK: &str = include_str!("../examples/networks/semicircle_9dof.xml");

fn step(c: &mut Criterion) {
    let network = Network::from_xml_str(NETWORK, "semicircle_9dof.xml").unwrap();
    let ss = network.state_space().unwrap();
    let n = network.dof_count();
    // The same force as the network's over 6000 steps of history (h = 0.01 s: 60 s).
    let mut convolution = ConvolutionForce::new(&ss, 0.01, 6000).unwrap();
    let mut velocity = DVector::zeros(n);
    let mut force = DVector::zeros(n);
    let mut k = 0u64;
    c.bench_function(
        "convolution step, semicircle 9 DOFs, 6000-step history",
        |b| {
            b.iter(|| {
                let phase = (k % 1000) as f64 * 1e-3;
                for (i, x) in velocity.iter_mut().enumerate() {
                    *x = phase + i as f64 * 0.1;
                }
                k += 1;
                convolution.push(&velocity, &mut force).unwrap();
                black_box(&force);
            })
        },
    );
}

criterion_group!(benches, step);
criterion_main!(benches);
