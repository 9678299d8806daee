//! One co-simulation step of the default 9-DOF semicircle network through the C ABI (set 9
//! velocities, fmi2DoStep, get 9 forces; target <= 1 us on one core), in calm water and in a
//! JONSWAP sea of the default 64 components (Hs 2 m, Tp 8 s; a synthetic excitation table in
//! the resources; target <= 2 x the calm step), and the same sea with the slow drift by
//! Newman (`wave.drift` 2, a synthetic drift table nonzero in every DOF; target <= 1.5 x the
//! sea without drift); and in calm water the branch-chain network of
//! the same data (`CoupledMethod::Chains`), for the ratio in one run; and the calm step of the
//! default network through the FMI 3.0 functions (fmi3SetFloat64, fmi3DoStep, fmi3GetFloat64).
//! In calm water with viscous damping and a current (`resources/viscous.csv`: a diagonal
//! linear and a quadratic damping in every DOF, `current.speed` 0.5 m/s; target <= 1 us, for
//! the ratio to the calm step without them), and the same with a ship's 20 cross-flow strips
//! (`resources/crossflow.csv`; the network's DOFs roll and cb1 named yaw and pitch, the current
//! at 60 deg; target <= 1 us). The baseline of the same run: the plain dense step of the default network, no FMI around it
//! (`x+ = Phi x + Gamma0 u + Gamma1 u'`, `y = C x+ + D u` with dense matrices, 9 velocities
//! copied in and 9 forces out); the FMU step's cost is quoted as a ratio to it.
//! The same radiation force by direct convolution: `cargo bench -p fmu-pack --bench
//! convolution`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use hydrofmu::discretize::discretize;
use hydrofmu::fmi::*;
use hydrofmu::fmu::description::{
    DEFAULT_G, DEFAULT_RHO, FIRST_PER_HULL_REFERENCE, VR_WAVE_HEIGHT, VR_WAVE_KIND, VR_WAVE_PERIOD,
};
use hydrofmu::model::Resources;
use hydrofmu::network::Network;
use nalgebra::DVector;
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
    bench_plain_dense(c, NETWORK);
    bench_network(
        c,
        NETWORK,
        "",
        &[
            "calm water",
            "JONSWAP, 64 components",
            "JONSWAP, 64 components, with slow drift",
        ],
    );
    bench_viscous(c, NETWORK, 0);
    bench_viscous(c, NETWORK, 20);
    bench_fmi3(c, NETWORK);
    bench_network(c, CHAINS, " (branch chains)", &["calm water"]);
}

/// The plain dense step of the network at the FMU's default rho and g, with no FMI around
/// it: the exact discrete update over h = 0.01 s with the input ramped over the step
/// (`discretize` with first-order hold of the state space: dense `Phi`, `Gamma0`, `Gamma1`),
/// `x+ = Phi x + Gamma0 u + Gamma1 u'`, then `y = C x+ + D u`, plus copying the 9 velocities
/// in and the 9 forces out. `u'` is the master's rate, zero as in the FMU benches (the
/// product is computed all the same).
fn bench_plain_dense(c: &mut Criterion, text: &str) {
    let network = Network::from_xml_str(text, "network.xml")
        .unwrap()
        .scaled(DEFAULT_RHO, DEFAULT_G);
    let ss = network.state_space().unwrap();
    let h = 0.01;
    let step = discretize(&ss.a, &ss.b, h, true).unwrap();
    let gamma1 = step.gamma1.clone().unwrap();
    let (states, n) = (ss.a.nrows(), ss.b.ncols());
    let (mut x, mut next) = (DVector::zeros(states), DVector::zeros(states));
    let (mut u, rate, mut y) = (DVector::zeros(n), DVector::zeros(n), DVector::zeros(n));
    let (mut v, mut f) = (vec![0.0; n], vec![0.0; n]);
    let mut k = 0u64;
    let name = format!("plain dense step, {states} states, {n} inputs/outputs (baseline)");
    c.bench_function(&name, |b| {
        b.iter(|| {
            let phase = (k % 1000) as f64 * 1e-3;
            for (i, x) in v.iter_mut().enumerate() {
                *x = phase + i as f64 * 0.1;
            }
            k += 1;
            u.copy_from_slice(black_box(&v));
            next.gemv(1.0, &step.phi, &x, 0.0);
            next.gemv(1.0, &step.gamma0, &u, 1.0);
            next.gemv(1.0, &gamma1, black_box(&rate), 1.0);
            std::mem::swap(&mut x, &mut next);
            y.gemv(1.0, &ss.c, &x, 0.0);
            y.gemv(1.0, &ss.d, &u, 1.0);
            f.copy_from_slice(y.as_slice());
            black_box(&f);
        })
    });
    assert!(x.iter().all(|x| x.is_finite()), "the plain step diverged");
}

/// A resources folder for `text` (tag: a distinct folder per caller); its GUID.
fn resources(text: &str, tag: &str) -> (std::path::PathBuf, CString) {
    let dir = std::env::temp_dir().join(format!("hydrofmu-bench-{}-{tag}", std::process::id()));
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
    std::fs::write(dir.join(Resources::DRIFT_FILE), synthetic_drift_csv()).unwrap();
    let guid = CString::new(Resources::read(&dir).unwrap().guid()).unwrap();
    (dir, guid)
}

/// A synthetic 9-DOF drift table (R = 1 m, the excitation table's kR grid, headings 0 and
/// 180), nonzero in every DOF so that none is skipped.
fn synthetic_drift_csv() -> String {
    let mut text = format!(
        "# modes: {}\n# convention: exp(+i omega t)\n# R: 1 m\n\
         # length exponents: 0 0 1 0 0 1 0 0 1\nkR,j,heading,value\n",
        common::MODES.join(" ")
    );
    for i in 0..201 {
        let kr = 0.01 * 1000f64.powf(i as f64 / 200.0);
        for (heading, sign) in [(0, 1.0), (180, -1.0)] {
            for j in 0..common::MODES.len() {
                let value = sign * 0.1 * (1.0 + j as f64) * kr / (1.0 + kr);
                text += &format!("{kr:e},{},{heading},{value:e}\n", j + 1);
            }
        }
    }
    text
}

/// Callbacks without a logger or memory functions.
fn silent_callbacks() -> fmi2CallbackFunctions {
    fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut::<c_void>(),
    }
}

/// A co-simulation instance of the resources at `uri`.
///
/// # Safety
/// `callbacks` must outlive the instance.
unsafe fn instantiate(
    guid: &CString,
    uri: &CString,
    callbacks: &fmi2CallbackFunctions,
) -> fmi2Component {
    let comp = fmi2Instantiate(
        c"bench".as_ptr(),
        fmi2CoSimulation,
        guid.as_ptr(),
        uri.as_ptr(),
        callbacks,
        0,
        0,
    );
    assert!(!comp.is_null());
    comp
}

fn bench_network(c: &mut Criterion, text: &str, label: &str, seas: &[&str]) {
    let (dir, guid) = resources(text, &label.len().to_string());
    let uri = CString::new(format!("file://{}", dir.display())).unwrap();
    let callbacks = silent_callbacks();
    let network = Network::from_xml_str(text, "network.xml").unwrap();
    let states = network.state_space().unwrap().state_count();
    let n = network.dof_count() as u32;
    let velocity: Vec<u32> = (0..n).map(|i| FIRST_PER_HULL_REFERENCE + i).collect();
    let force: Vec<u32> = (0..n).map(|i| FIRST_PER_HULL_REFERENCE + n + i).collect();
    for &sea in seas {
        unsafe {
            let comp = instantiate(&guid, &uri, &callbacks);
            assert_eq!(fmi2EnterInitializationMode(comp), fmi2OK);
            if sea.starts_with("JONSWAP") {
                let kind = [VR_WAVE_KIND];
                assert_eq!(fmi2SetInteger(comp, kind.as_ptr(), 1, &JONSWAP), fmi2OK);
                let refs = [VR_WAVE_HEIGHT, VR_WAVE_PERIOD];
                let values = [2.0, 8.0];
                assert_eq!(fmi2SetReal(comp, refs.as_ptr(), 2, values.as_ptr()), fmi2OK);
            }
            if sea.ends_with("with slow drift") {
                // wave.drift: the last variable, after force_drift.<dof>.
                let drift = [drift_reference(n)];
                assert_eq!(fmi2SetInteger(comp, drift.as_ptr(), 1, &2), fmi2OK);
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

/// The calm-water step of an FMU with viscous damping in every DOF and a current, and with
/// `strips` cross-flow strips of a ship (none: a section).
fn bench_viscous(c: &mut Criterion, text: &str, strips: usize) {
    use hydrofmu::fmu::variables::Quantity;
    use hydrofmu::fmu::{DofUnit, Layout};
    use hydrofmu::model::crossflow::{write_csv, Strip};
    use hydrofmu::model::viscous::Frame;
    // A ship: two DOFs renamed yaw and pitch (the tables of the section then do not apply).
    let text = match strips {
        0 => text.to_string(),
        _ => text
            .replace("name=\"roll\"", "name=\"yaw\"")
            .replace("name=\"cb1\"", "name=\"pitch\""),
    };
    let text = text.as_str();
    let (dir, _) = resources(text, &format!("viscous-{strips}"));
    let network = Network::from_xml_str(text, "network.xml").unwrap();
    let names = network.dof_names.clone();
    let n = names.len();
    let linear = nalgebra::DMatrix::from_diagonal_element(n, n, 200.0);
    let quadratic = DVector::from_element(n, 1000.0);
    let frame = match strips {
        0 => Frame::Section,
        _ => Frame::Body,
    };
    let csv = hydrofmu::model::viscous::write_csv(&names, frame, &linear, &quadratic);
    std::fs::write(dir.join(Resources::VISCOUS_FILE), csv).unwrap();
    if strips > 0 {
        std::fs::remove_file(dir.join(Resources::EXCITATION_FILE)).unwrap();
        std::fs::remove_file(dir.join(Resources::DRIFT_FILE)).unwrap();
        let strips: Vec<Strip> = (0..strips)
            .map(|k| Strip {
                x: -50.0 + 100.0 * k as f64 / (strips - 1) as f64,
                weight: 5.0,
                draft: 4.0 + 0.05 * k as f64,
                breadth: 12.0,
                cd_sway: 1.1,
                cd_heave: 0.8,
            })
            .collect();
        std::fs::write(dir.join(Resources::CROSSFLOW_FILE), write_csv(&strips)).unwrap();
    }
    let guid = CString::new(Resources::read(&dir).unwrap().guid()).unwrap();
    let uri = CString::new(format!("file://{}", dir.display())).unwrap();
    let callbacks = silent_callbacks();
    let dofs = names.iter().map(|d| DofUnit::new(d, 0, false)).collect();
    let layout = Layout::new(dofs, false)
        .unwrap()
        .with_viscous(&linear, &quadratic)
        .unwrap();
    let current = [
        layout.value_reference(Quantity::CurrentSpeed).unwrap(),
        layout.value_reference(Quantity::CurrentHeading).unwrap(),
    ];
    let states = network.state_space().unwrap().state_count();
    let velocity: Vec<u32> = (0..n as u32)
        .map(|i| FIRST_PER_HULL_REFERENCE + i)
        .collect();
    let force: Vec<u32> = (0..n as u32)
        .map(|i| FIRST_PER_HULL_REFERENCE + n as u32 + i)
        .collect();
    unsafe {
        let comp = instantiate(&guid, &uri, &callbacks);
        assert_eq!(fmi2EnterInitializationMode(comp), fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(comp), fmi2OK);
        let (speed, heading) = (0.5, if strips > 0 { 60.0 } else { 0.0 });
        assert_eq!(
            fmi2SetReal(comp, current.as_ptr(), 2, [speed, heading].as_ptr()),
            fmi2OK
        );
        let h = 0.01;
        let (mut t, mut k) = (0.0, 0u64);
        let (mut v, mut f) = (vec![0.0; n], vec![0.0; n]);
        let name = match strips {
            0 => format!(
                "doStep + setReal(9) + getReal(9), semicircle 9 DOFs, {states} states, calm water, viscous damping and current"
            ),
            _ => format!(
                "doStep + setReal(9) + getReal(9), 9 DOFs, {states} states, calm water, viscous damping, current and {strips} cross-flow strips"
            ),
        };
        c.bench_function(&name, |b| {
            b.iter(|| {
                let phase = (k % 1000) as f64 * 1e-3;
                for (i, x) in v.iter_mut().enumerate() {
                    *x = phase + i as f64 * 0.1;
                }
                assert_eq!(fmi2SetReal(comp, velocity.as_ptr(), n, v.as_ptr()), fmi2OK);
                assert_eq!(fmi2DoStep(comp, t, h, 1), fmi2OK);
                t = (k + 1) as f64 * h;
                k += 1;
                assert_eq!(fmi2GetReal(comp, force.as_ptr(), n, f.as_mut_ptr()), fmi2OK);
                black_box(&f);
            })
        });
        fmi2FreeInstance(comp);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The value reference of `wave.drift` for `n` DOFs without accelerations.
fn drift_reference(n: u32) -> u32 {
    use hydrofmu::fmu::{DofUnit, Layout};
    let dofs = common::MODES[..n as usize]
        .iter()
        .map(|name| DofUnit::new(name, 0, false))
        .collect();
    let layout = Layout::new(dofs, false).unwrap().with_drift().unwrap();
    let drift =
        hydrofmu::fmu::variables::Quantity::Wave(hydrofmu::fmu::variables::WaveParameter::Drift);
    layout.value_reference(drift).unwrap()
}

/// The calm-water step through the FMI 3.0 functions, for the ratio to FMI 2.0 in one run.
fn bench_fmi3(c: &mut Criterion, text: &str) {
    let (dir, guid) = resources(text, "fmi3");
    let path = CString::new(format!("{}/", dir.display())).unwrap();
    let network = Network::from_xml_str(text, "network.xml").unwrap();
    let states = network.state_space().unwrap().state_count();
    let n = network.dof_count() as u32;
    let velocity: Vec<u32> = (0..n).map(|i| FIRST_PER_HULL_REFERENCE + i).collect();
    let force: Vec<u32> = (0..n).map(|i| FIRST_PER_HULL_REFERENCE + n + i).collect();
    unsafe {
        let inst = fmi3InstantiateCoSimulation(
            c"bench".as_ptr(),
            guid.as_ptr(),
            path.as_ptr(),
            0,
            0,
            0,
            0,
            std::ptr::null(),
            0,
            std::ptr::null_mut(),
            None,
            std::ptr::null(),
        );
        assert!(!inst.is_null());
        assert_eq!(
            fmi3EnterInitializationMode(inst, 0, 0.0, 0.0, 0, 0.0),
            fmi3OK
        );
        assert_eq!(fmi3ExitInitializationMode(inst), fmi3OK);
        let h = 0.01;
        let (mut t, mut k) = (0.0, 0u64);
        let (mut v, mut f) = (vec![0.0; n as usize], vec![0.0; n as usize]);
        let (mut event, mut stop, mut early, mut last) = (0u8, 0u8, 0u8, 0.0);
        let name = format!(
            "fmi3DoStep + fmi3SetFloat64(9) + fmi3GetFloat64(9), semicircle 9 DOFs, {states} states, calm water"
        );
        c.bench_function(&name, |b| {
            b.iter(|| {
                let phase = (k % 1000) as f64 * 1e-3;
                for (i, x) in v.iter_mut().enumerate() {
                    *x = phase + i as f64 * 0.1;
                }
                let count = velocity.len();
                assert_eq!(
                    fmi3SetFloat64(inst, velocity.as_ptr(), count, v.as_ptr(), count),
                    fmi3OK
                );
                let status =
                    fmi3DoStep(inst, t, h, 1, &mut event, &mut stop, &mut early, &mut last);
                assert_eq!(status, fmi3OK);
                t = (k + 1) as f64 * h;
                k += 1;
                assert_eq!(
                    fmi3GetFloat64(inst, force.as_ptr(), count, f.as_mut_ptr(), count),
                    fmi3OK
                );
                black_box(&f);
            })
        });
        fmi3FreeInstance(inst);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, step);
criterion_main!(benches);
