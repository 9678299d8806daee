//! The cost of the largest networks the component accepts (docs/STABILITY.md): a new step
//! size of a network at `MAX_NETWORK_STATES` in blocks of `MAX_SUBSTRUCTURE_STATES` (one
//! exponential per block), and the instantiation of a network at `MAX_NETWORK_DOFS`.
//!
//! ```sh
//! cargo bench --bench limits
//! ```

use criterion::{criterion_group, criterion_main, Criterion};
use hydrofmu::network::{
    Branch, Network, NetworkForm, Stage, Substructure, MAX_NETWORK_DOFS, MAX_NETWORK_STATES,
    MAX_SUBSTRUCTURE_STATES,
};
use hydrofmu::{Model, ModelOptions};
use nalgebra::{DMatrix, DVector};
use std::hint::black_box;

/// Deterministic numbers in [-0.5, 0.5) (a linear congruential generator).
struct Numbers(u64);

impl Numbers {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

const OPTIONS: ModelOptions = ModelOptions {
    keep_inf_mass: false,
    guid: None,
};

/// 9 DOFs, substructures of the largest size up to the largest network (random springs,
/// light damping: passive by construction).
fn largest_substructures() -> Network {
    let n = 9;
    let mut rng = Numbers(3);
    let half = MAX_SUBSTRUCTURE_STATES / 2;
    let subs = (0..MAX_NETWORK_STATES / MAX_SUBSTRUCTURE_STATES)
        .map(|_| Substructure {
            masses: half,
            spring_incidence: DMatrix::from_fn(half, half + n, |_, _| rng.next()),
            spring_relaxation: DMatrix::zeros(half, half),
            damping: DMatrix::identity(half + n, half + n) * 0.1,
        })
        .collect();
    let names = (0..n).map(|i| format!("q{i}")).collect();
    Network::from_substructures(names, DMatrix::identity(n, n), subs, 1025.0, 9.81)
}

/// `MAX_NETWORK_DOFS` DOFs and one-stage branches up to the largest network.
fn most_dofs() -> Network {
    let n = MAX_NETWORK_DOFS;
    let mut rng = Numbers(5);
    let stage = Stage {
        mass: 1.0,
        stiffness: 1.0,
        damping: 1.0,
    };
    let branches = (0..MAX_NETWORK_STATES / 2)
        .map(|_| Branch {
            direction: DVector::from_fn(n, |_, _| rng.next()),
            stages: vec![stage],
        })
        .collect();
    Network {
        dof_names: (0..n).map(|i| format!("q{i}")).collect(),
        added_mass_inf: DMatrix::identity(n, n),
        branches,
        substructures: Vec::new(),
        rho: 1025.0,
        g: 9.81,
        form: NetworkForm::Coupled,
    }
}

fn limits(c: &mut Criterion) {
    let mut group = c.benchmark_group("limits");
    group.sample_size(10);
    let network = largest_substructures();
    let mut model = Model::new(&network, OPTIONS).expect("model");
    // Five step sizes cycle through the four-entry cache: every step is a new step size.
    let steps = [0.010, 0.011, 0.012, 0.013, 0.014];
    let mut k = 0;
    group.bench_function(
        "new step size, 2048 states in 4 substructures of 512",
        |b| {
            b.iter(|| {
                let h = steps[k % steps.len()];
                k += 1;
                model.step(model.time(), black_box(h)).expect("step");
            })
        },
    );
    let network = most_dofs();
    group.bench_function("instantiate, 1000 DOFs, 1024 one-stage branches", |b| {
        b.iter(|| Model::new(black_box(&network), OPTIONS).expect("model"))
    });
    group.finish();
}

criterion_group!(benches, limits);
criterion_main!(benches);
