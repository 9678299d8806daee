//! The section solver in water of finite depth: the energy identity with the finite-depth
//! group velocity, Haskind against the direct solve, symmetry, deep-water recovery,
//! convergence under refinement, the interior lid at an irregular frequency, and the limits.

use hydrofmu::bem::{BemError, IrregularFrequencies, RadiationSolution};
use hydrofmu::green::finite_depth::wavenumber;
use hydrofmu::green::FreeSurface;
use hydrofmu::sweep::Solver;
use hydrofmu::units::WaterDepth;
use hydrofmu::{Hull, PanelParams};
use nalgebra::DMatrix;
use num_complex::Complex64;

fn solver(hull: &Hull, panels: usize, levels: usize, depth: WaterDepth) -> Solver {
    let params = PanelParams {
        body_panels: panels,
        ..PanelParams::default()
    };
    Solver::with_depth(hull, &params, levels, depth).unwrap()
}

fn solve(solver: &Solver, nu: f64) -> RadiationSolution {
    solver
        .solve(
            FreeSurface::Wave { wavenumber: nu },
            IrregularFrequencies::RemoveWithLid,
        )
        .unwrap()
}

fn largest(m: &DMatrix<Complex64>) -> f64 {
    m.iter().map(|z| z.norm()).fold(0.0, f64::max)
}

#[test]
fn energy_identity_with_the_group_velocity_haskind_and_symmetry() {
    // -Im A~_jj / rho = (k/nu) (|x_j(0)|^2 + |x_j(180)|^2) / (2 (1 + 2kh / sinh 2kh)):
    // b_jj = rho g (|x0|^2 + |x180|^2) / (4 c_g), c_g = (omega/2k)(1 + 2kh/sinh 2kh).
    let hull = Hull::semicircle(1.0).unwrap();
    for h in [1.2, 2.0, 5.0] {
        let solver = solver(&hull, 128, 2, WaterDepth::Finite(h));
        for nu in [0.05, 0.3, 1.0, 2.5, 6.0] {
            let s = solve(&solver, nu);
            let k = wavenumber(nu, h).unwrap();
            let factor = k / nu / (2.0 * (1.0 + 2.0 * k * h / (2.0 * k * h).sinh()));
            let w = s.wave_forces.as_ref().unwrap();
            let scale = largest(&s.added_mass);
            let force_scale = largest(&w.direct);
            for j in 0..s.added_mass.nrows() {
                let energy = factor * (w.direct[(j, 0)].norm_sqr() + w.direct[(j, 1)].norm_sqr());
                let damping = -s.added_mass[(j, j)].im;
                assert!(
                    (energy - damping).abs() < 2e-3 * scale,
                    "h {h} nu {nu} dof {j}: {energy} against {damping}"
                );
                for heading in 0..2 {
                    let d = (w.haskind[(j, heading)] - w.direct[(j, heading)]).norm();
                    assert!(
                        d < 2e-3 * force_scale,
                        "h {h} nu {nu} dof {j}: Haskind {d:e}"
                    );
                }
            }
            assert!(
                s.reciprocity_residual < 1e-3,
                "h {h} nu {nu}: {}",
                s.reciprocity_residual
            );
        }
    }
}

/// `|A_ij(h) - A_ij(deep)| / sqrt(|A_ii A_jj|)` for every entry, and the largest difference
/// of the direct exciting force relative to its largest entry.
fn differences(deep: &RadiationSolution, finite: &RadiationSolution) -> (DMatrix<f64>, f64) {
    let (a, b) = (&deep.added_mass, &finite.added_mass);
    let entries = DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| {
        (a[(i, j)] - b[(i, j)]).norm() / (a[(i, i)].norm() * a[(j, j)].norm()).sqrt()
    });
    let force = match (&deep.wave_forces, &finite.wave_forces) {
        (Some(x), Some(y)) => largest(&(&x.direct - &y.direct)) / largest(&x.direct),
        _ => 0.0,
    };
    (entries, force)
}

#[test]
fn very_deep_water_recovers_deep_water() {
    // The bottom's effect falls like (R/h)^2 and 1/(nu h)^2 (a physical effect: heave in long
    // waves feels a bottom a thousand radii down at 1e-3); at h/R = 1e3 and kR >= 1 every
    // entry is within 1e-6 of its scale (measured at most 7.7e-7, heave at kR = 8).
    let hull = Hull::semicircle(1.0).unwrap();
    let deep = solver(&hull, 64, 1, WaterDepth::Infinite);
    let finite = solver(&hull, 64, 1, WaterDepth::Finite(1e3));
    let shallower = solver(&hull, 64, 1, WaterDepth::Finite(1e2));
    for nu in [1.0, 3.0, 8.0] {
        let a = solve(&deep, nu);
        let (entries, force) = differences(&a, &solve(&finite, nu));
        assert!(
            entries.max() < 1e-6 && force < 1e-6,
            "nu {nu}: {entries} {force:e}"
        );
    }
    let a = deep
        .solve(FreeSurface::Dirichlet, IrregularFrequencies::Keep)
        .unwrap();
    let b = finite
        .solve(FreeSurface::Dirichlet, IrregularFrequencies::Keep)
        .unwrap();
    let (entries, _) = differences(&a, &b);
    assert!(entries.max() < 1e-6, "A_inf: {entries}");
    // The (R/h)^2 law: ten times deeper, a hundred times closer (heave at nu = 1, rigid-lid
    // sway).
    let a = solve(&deep, 1.0);
    let ratio = differences(&a, &solve(&shallower, 1.0)).0[(1, 1)]
        / differences(&a, &solve(&finite, 1.0)).0[(1, 1)];
    assert!((ratio - 100.0).abs() < 10.0, "heave: {ratio}");
    let lid = |s: &Solver| {
        s.solve(FreeSurface::RigidLid, IrregularFrequencies::Keep)
            .unwrap()
    };
    let a = lid(&deep);
    let ratio =
        differences(&a, &lid(&shallower)).0[(0, 0)] / differences(&a, &lid(&finite)).0[(0, 0)];
    assert!((ratio - 100.0).abs() < 10.0, "rigid-lid sway: {ratio}");
}

#[test]
fn refinement_converges() {
    let hull = Hull::semicircle(1.0).unwrap();
    let depth = WaterDepth::Finite(2.0);
    let solved: Vec<RadiationSolution> = [32, 64, 128, 256]
        .iter()
        .map(|&n| solve(&solver(&hull, n, 1, depth), 1.0))
        .collect();
    let steps: Vec<f64> = solved
        .windows(2)
        .map(|w| largest(&(&w[1].added_mass - &w[0].added_mass)) / largest(&w[1].added_mass))
        .collect();
    // First order: each doubling about halves the change.
    for pair in steps.windows(2) {
        assert!(pair[1] < 0.7 * pair[0], "{steps:?}");
    }
    assert!(steps[2] < 5e-3, "{steps:?}");
}

#[test]
fn the_interior_lid_removes_the_first_irregular_frequency_in_finite_depth() {
    // The interior problem depends on nu alone: the semicircle's first irregular frequency
    // is nu R = 1.8182 in any depth.
    let hull = Hull::semicircle(1.0).unwrap();
    let params = PanelParams {
        body_panels: 128,
        ..PanelParams::default()
    };
    let solver = Solver::with_depth(&hull, &params, 1, WaterDepth::Finite(2.0)).unwrap();
    let at = |nu: f64, irregular| {
        solver
            .solve(FreeSurface::Wave { wavenumber: nu }, irregular)
            .unwrap()
            .added_mass
    };
    let lid = IrregularFrequencies::RemoveWithLid;
    let (below, above) = (at(1.8182 - 0.02, lid), at(1.8182 + 0.02, lid));
    let middle = (&below + &above) * Complex64::new(0.5, 0.0);
    let scale = largest(&middle);
    let with_lid = largest(&(at(1.8182, lid) - &middle)) / scale;
    let plain = largest(&(at(1.8182, IrregularFrequencies::Keep) - &middle)) / scale;
    assert!(with_lid < 2e-3, "with the lid: {with_lid:e}");
    assert!(
        plain > 10.0 * with_lid,
        "plain {plain:e}, with the lid {with_lid:e}"
    );
}

#[test]
fn limits_in_finite_depth() {
    let hull = Hull::semicircle(1.0).unwrap();
    let h = 2.0;
    let solver = solver(&hull, 128, 2, WaterDepth::Finite(h));
    let zero = solver
        .solve(FreeSurface::RigidLid, IrregularFrequencies::Keep)
        .unwrap()
        .added_mass;
    let infinite = solver
        .solve(FreeSurface::Dirichlet, IrregularFrequencies::Keep)
        .unwrap()
        .added_mass;
    // Sway tends to the channel's rigid-lid value as omega -> 0 (its damping over omega
    // vanishes like omega: the flow passes under the keel rather than into long waves) ...
    let low = solve(&solver, 1e-4).added_mass;
    let lower = solve(&solver, 1e-6).added_mass;
    let d = (low[(0, 0)].re - zero[(0, 0)].re).abs() / zero[(0, 0)].re;
    assert!(
        d < 1e-3,
        "sway A(0): {} against {}",
        low[(0, 0)],
        zero[(0, 0)]
    );
    let fall = lower[(0, 0)].im / low[(0, 0)].im;
    assert!(
        (fall - 0.1).abs() < 0.02,
        "sway damping / omega falls by {fall}"
    );
    // ... while heave (net flux out along the channel) diverges like 1/omega.
    let growth = lower[(1, 1)].norm() / low[(1, 1)].norm();
    assert!(
        (growth - 10.0).abs() < 1.0,
        "heave grows by {growth} for omega / 10"
    );
    // At high frequency the bottom changes A~ as it changes A_inf (the Dirichlet strip's).
    let deep = self::solver(&hull, 128, 2, WaterDepth::Infinite);
    let deep_infinite = deep
        .solve(FreeSurface::Dirichlet, IrregularFrequencies::Keep)
        .unwrap()
        .added_mass;
    // The bottom's effect on A~ tends to its effect on A_inf like 1/nu (measured sway 6.3e-3,
    // 3.1e-3, 1.5e-3 at nu R = 10, 20, 40).
    let change_inf = &infinite - &deep_infinite;
    let gap = |nu: f64| {
        let change = solve(&solver, nu).added_mass - solve(&deep, nu).added_mass;
        [(0, 0), (1, 1)].map(|(i, j)| (change[(i, j)] - change_inf[(i, j)]).norm())
    };
    let (near, nearer) = (gap(20.0), gap(40.0));
    for entry in 0..2 {
        let ratio = nearer[entry] / near[entry];
        assert!(
            (ratio - 0.5).abs() < 0.1,
            "entry {entry}: {near:?} then {nearer:?}"
        );
        assert!(near[entry] < 0.2 * change_inf[(entry, entry)].norm());
    }
}

#[test]
fn bad_depths_and_hulls_on_the_bottom_are_refused_by_name() {
    let hull = Hull::semicircle(1.0).unwrap();
    let params = PanelParams::default();
    for depth in [1.0, 0.999, 0.5] {
        let error = Solver::with_depth(&hull, &params, 1, WaterDepth::Finite(depth))
            .err()
            .expect("a hull on the bottom");
        let message = error.to_string();
        assert!(
            message.contains("bottom") && message.contains(&format!("{depth}")),
            "{message}"
        );
    }
    for depth in [0.0, -2.0, f64::NAN] {
        let error = Solver::with_depth(&hull, &params, 1, WaterDepth::Finite(depth))
            .err()
            .expect("an invalid depth");
        assert!(error.to_string().contains("depth"), "{error}");
        assert!(WaterDepth::new(depth).is_err());
    }
    assert!(matches!(
        hydrofmu::bem::Problem::with_depth(
            hydrofmu::panels::discretize(&hull, &params).unwrap(),
            WaterDepth::Finite(0.5)
        )
        .err(),
        Some(BemError::BelowBottom { .. })
    ));
}

#[test]
fn long_waves_in_finite_depth_give_the_hydrostatic_force() {
    // As k -> 0 the incident wave's horizontal velocity tends to a sqrt(g/h), but the sway
    // force still vanishes (like k, k ~ omega / sqrt(gh)): x_j -> integral n_j ds.
    let hull = Hull::semicircle(1.0).unwrap();
    let solver = solver(&hull, 128, 2, WaterDepth::Finite(2.0));
    let force = |nu: f64| solve(&solver, nu).wave_forces.unwrap().direct;
    let (low, lower) = (force(1e-4), force(1e-6));
    assert!(
        (lower[(1, 0)] - Complex64::new(2.0, 0.0)).norm() < 1e-2,
        "{}",
        lower[(1, 0)]
    );
    let fall = lower[(0, 0)].norm() / low[(0, 0)].norm();
    assert!((fall - 0.1).abs() < 0.02, "sway falls by {fall} for k / 10");
}

#[test]
fn hull_files_carry_the_water_depth() {
    let file = |depth: &str| {
        format!(
            "<hull name=\"box\" half_beam=\"1\"{depth}><contour><point x=\"1\" y=\"0\"/>\
             <point x=\"1\" y=\"-1\"/><point x=\"-1\" y=\"-1\"/><point x=\"-1\" y=\"0\"/>\
             </contour><rigid name=\"heave\" kind=\"heave\"/></hull>"
        )
    };
    let hull = Hull::from_xml_str(&file(" depth=\"3.5\""), "box.xml").unwrap();
    assert_eq!(hull.water_depth(), WaterDepth::Finite(3.5));
    let again = Hull::from_xml_str(&hull.to_xml_string(), "again.xml").unwrap();
    assert_eq!(again.water_depth(), WaterDepth::Finite(3.5));
    let deep = Hull::from_xml_str(&file(""), "box.xml").unwrap();
    assert_eq!(deep.water_depth(), WaterDepth::Infinite);
    for bad in ["0", "-2", "x", "inf"] {
        let error = Hull::from_xml_str(&file(&format!(" depth=\"{bad}\"")), "box.xml")
            .unwrap_err()
            .to_string();
        assert!(error.contains("depth"), "{bad}: {error}");
    }
}
