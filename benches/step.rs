//! One co-simulation step through the C ABI for a 9-DOF-sized system: set 9 velocities,
//! fmi2DoStep, get 9 forces (target: <= 1 us on one core).
//!
//! The network (docs/NETWORK_FORMAT.md): 9 DOFs, one 2-stage chain per DOF with a little coupling to
//! the next DOF: 36 network states.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use hydrofmu::fmi2::*;
use hydrofmu::model::Resources;
use hydrofmu::model_description::FIRST_PER_HULL_REFERENCE;
use std::ffi::{c_void, CString};

const DOFS: [&str; 9] = [
    "sway", "heave", "roll", "cb1", "cb2", "cb3", "cb4", "cb5", "cb6",
];

fn network_xml() -> String {
    let n = DOFS.len();
    let mut s = String::from("<network format_version=\"1\" form=\"coupled\" rho=\"1\" g=\"1\">\n");
    for d in DOFS {
        s += &format!("  <dof name=\"{d}\"/>\n");
    }
    s += "  <added_mass_inf>\n";
    for i in 0..n {
        let row: Vec<&str> = (0..n)
            .map(|j| if i == j { "0.3" } else { "0.01" })
            .collect();
        s += &format!("    <row>{}</row>\n", row.join(" "));
    }
    s += "  </added_mass_inf>\n";
    for i in 0..n {
        let attachment: Vec<String> = (0..n)
            .map(|j| {
                if j == i {
                    "1".into()
                } else if j == (i + 1) % n {
                    "0.1".into()
                } else {
                    "0".into()
                }
            })
            .collect();
        s += &format!(
            "  <branch>\n    <direction>{}</direction>\n",
            attachment.join(" ")
        );
        s += "    <stage mass=\"0.5434\" stiffness=\"0.2339\" damping=\"0.9962\"/>\n";
        s += "    <stage mass=\"0.1877\" stiffness=\"0.5522\" damping=\"0.2453\"/>\n";
        s += "  </branch>\n";
    }
    s + "</network>\n"
}

fn step(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("hydrofmu-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(Resources::NETWORK_FILE), network_xml()).unwrap();
    std::fs::write(
        dir.join(Resources::OPTIONS_FILE),
        Resources::options_text(false),
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
    let n = DOFS.len() as u32;
    let velocity: Vec<u32> = (0..n).map(|i| FIRST_PER_HULL_REFERENCE + i).collect();
    let force: Vec<u32> = (0..n).map(|i| FIRST_PER_HULL_REFERENCE + n + i).collect();
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
        assert_eq!(fmi2ExitInitializationMode(comp), fmi2OK);
        let h = 0.01;
        let mut t = 0.0;
        let mut k = 0u64;
        let mut v = vec![0.0; DOFS.len()];
        let mut f = vec![0.0; DOFS.len()];
        c.bench_function("doStep + getReal(9) + setReal(9), 9 DOFs, 36 states", |b| {
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
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, step);
criterion_main!(benches);
