//! One co-simulation step of the default 9-DOF semicircle network through the C ABI (set 9
//! velocities, fmi2DoStep, get 9 forces; target <= 1 us on one core), in calm water and in a
//! JONSWAP sea of the default 64 components (Hs 2 m, Tp 8 s; a synthetic excitation table in
//! the resources; target <= 2 x the calm step); and in calm water the branch-chain network of
//! the same data (`CoupledMethod::Chains`), for the ratio in one run. The same radiation force
//! by direct convolution: `cargo bench -p fmu-pack --bench convolution`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use hydrofmu::fmi2::*;
use hydrofmu::fmu::description::{
    FIRST_PER_HULL_REFERENCE, VR_WAVE_HEIGHT, VR_WAVE_KIND, VR_WAVE_PERIOD,
};
use hydrofmu::model::Resources;
use hydrofmu::network::Network;
use std::ffi::{c_void, CString};

mod common;

/// The network `fmu-pack` fits for the built-in semicircle with default settings
/// (regenerate: `cargo run --release -p fmu-pack -- fit semicircle --network-out
/// examples/networks/semicircle_9dof.xml`).
const NETWORK: &str = include_str!("../examples/networks/semicircle_9dof.xml");

/// The same data fitted by branch chains (56 states, 0.98 %).
const CHAINS: &str = include_str!("../examples/networks/semicircle_9dof_chains.xml");

/// `wave.kind` 2: JONSWAP.
const JONSWAP: i32 = 2;

fn step(c: &mut Criterion) {
    bench_network(c, NETWORK, "", &["calm water", "JONSWAP, 64 components"]);
    bench_network(c, CHAINS, " (branch chains)", &["calm water"]);
}

fn bench_network(c: &mut Criterion, text: &str, label: &str, seas: &[&str]) {
    let dir = std::env::temp_dir().join(format!(
        "hydrofmu-bench-{}-{}",
        std::process::id(),
        label.len()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(Resources::NETWORK_FILE), text).unwrap();
    std::fs::write(
        dir.join(Resources::OPTIONS_FILE),
        Resources::options_text(false),
    )
    .unwrap();
    std::fs::write(
        dir.join(Resources::EXCITATION_FILE),
        common::synthetic_excitation_csv(),
    )
    .unwrap();
    let guid = CString::new(Resources::read(&dir).unwrap().guid()).unwrap();
    let uri = CString::new(format!("file://{}", dir.display())).unwrap();
    let callbacks = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut::<c_void>(),
    };
    let network = Network::from_xml_str(text, "network.xml").unwrap();
    let states = network.state_space().unwrap().state_count();
    let n = network.dof_count() as u32;
    let velocity: Vec<u32> = (0..n).map(|i| FIRST_PER_HULL_REFERENCE + i).collect();
    let force: Vec<u32> = (0..n).map(|i| FIRST_PER_HULL_REFERENCE + n + i).collect();
    for &sea in seas {
        unsafe {
            let comp = fmi2Instantiate(
                c"bench".as_ptr(),
                fmi2CoSimulation,
                guid.as_ptr(),
                uri.as_ptr(),
                &callbacks,
                0,
                0,
            );
            assert!(!comp.is_null());
            assert_eq!(fmi2EnterInitializationMode(comp), fmi2OK);
            if sea.starts_with("JONSWAP") {
                let kind = [VR_WAVE_KIND];
                assert_eq!(fmi2SetInteger(comp, kind.as_ptr(), 1, &JONSWAP), fmi2OK);
                let refs = [VR_WAVE_HEIGHT, VR_WAVE_PERIOD];
                let values = [2.0, 8.0];
                assert_eq!(fmi2SetReal(comp, refs.as_ptr(), 2, values.as_ptr()), fmi2OK);
            }
            assert_eq!(fmi2ExitInitializationMode(comp), fmi2OK);
            let h = 0.01;
            let mut t = 0.0;
            let mut k = 0u64;
            let mut v = vec![0.0; n as usize];
            let mut f = vec![0.0; n as usize];
            let name = format!(
                "doStep + setReal(9) + getReal(9), semicircle 9 DOFs, {states} states{label}, {sea}"
            );
            c.bench_function(&name, |b| {
                b.iter(|| {
                    let phase = (k % 1000) as f64 * 1e-3;
                    for (i, x) in v.iter_mut().enumerate() {
                        *x = phase + i as f64 * 0.1;
                    }
                    assert_eq!(
                        fmi2SetReal(comp, velocity.as_ptr(), velocity.len(), v.as_ptr()),
                        fmi2OK
                    );
                    assert_eq!(fmi2DoStep(comp, t, h, 1), fmi2OK);
                    t = (k + 1) as f64 * h;
                    k += 1;
                    assert_eq!(
                        fmi2GetReal(comp, force.as_ptr(), force.len(), f.as_mut_ptr()),
                        fmi2OK
                    );
                    black_box(&f);
                })
            });
            fmi2FreeInstance(comp);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, step);
criterion_main!(benches);
