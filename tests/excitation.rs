//! The exciting force of incident waves against exact limits, identities, the digitized Vugts
//! curves and refinement.
//!
//! Forces are per `rho g a` (R = 1 m), `x_j = X_j / (rho g a)`. The accuracy target of the
//! default settings is 1e-3 of the largest |x_j| of the DOF over the band, as for the added
//! mass; identities that hold for the discrete solution hold far tighter.

use hydrofmu::bem::{IrregularFrequencies, WaveForces};
use hydrofmu::green::FreeSurface;
use hydrofmu::hull::Hull;
use hydrofmu::panels::PanelParams;
use hydrofmu::sweep::{Solver, SweepParams};
use nalgebra::DMatrix;
use num_complex::Complex64;

fn solver(hull: &Hull) -> Solver {
    Solver::new(
        hull,
        &PanelParams::for_hull(hull),
        SweepParams::default().extrapolation_levels,
    )
    .unwrap()
}

/// Added mass per rho and the wave forces at `kr` (R = 1).
fn solve(solver: &Solver, kr: f64) -> (DMatrix<Complex64>, WaveForces) {
    let s = solver
        .solve(
            FreeSurface::Wave { wavenumber: kr },
            IrregularFrequencies::RemoveWithLid,
        )
        .unwrap();
    (s.added_mass, s.wave_forces.unwrap())
}

#[test]
fn explore() {
    let hull = Hull::semicircle(1.0).unwrap();
    let solver = solver(&hull);
    for kr in [0.001, 0.01, 0.1, 0.5, 1.0, 1.8182, 2.0, 5.0, 10.0] {
        let (a, w) = solve(&solver, kr);
        for j in 0..9 {
            let energy = w.haskind[(j, 0)].norm_sqr() + w.haskind[(j, 1)].norm_sqr();
            let b = -2.0 * a[(j, j)].im;
            println!(
                "kR {kr} j {j} H {:.6} D {:.6} FK {:.6} |H-D| {:.2e} energy {energy:.6e} 2b {b:.6e}",
                w.haskind[(j, 0)],
                w.direct[(j, 0)],
                w.froude_krylov[(j, 0)],
                (w.haskind[(j, 0)] - w.direct[(j, 0)]).norm()
            );
        }
    }
}

#[test]
fn explore_high() {
    let hull = Hull::semicircle(1.0).unwrap();
    let text = std::fs::read_to_string("/tmp/ex1024.csv").unwrap();
    let mut reference = std::collections::HashMap::new();
    for line in text.lines().filter(|l| !l.starts_with('#') && !l.starts_with("kR")) {
        let f: Vec<&str> = line.split(',').collect();
        reference.insert((f[0].to_string(), f[1].parse::<usize>().unwrap(), f[2].to_string()), Complex64::new(f[3].parse().unwrap(), f[4].parse().unwrap()));
    }
    for levels in [3, 4] {
        let solver = Solver::new(&hull, &PanelParams::default(), levels).unwrap();
        for kr in ["7.852356346100721e0", "8.128305161640993e0", "9.332543007969916e0", "1e1"] {
            let (_, w) = solve(&solver, kr.parse().unwrap());
            for j in [0usize, 1, 4, 5] {
                let r = reference[&(kr.to_string(), j + 1, "0".to_string())];
                println!("levels {levels} kR {kr} j {j} haskind err {:.2e} direct err {:.2e}", (w.haskind[(j, 0)] - r).norm(), (w.direct[(j, 0)] - r).norm());
            }
        }
    }
}
