//! Tests of the panel solver: limits, symmetry, reciprocity and the exciting forces.

use super::*;
use crate::hull::Hull;
use crate::panels::{self, PanelParams};

#[test]
fn symmetric_meshes_have_a_mirror_map_and_asymmetric_ones_none() {
    for hull in [
        Hull::semicircle(1.0).unwrap(),
        Hull::circle(1.0, 1.1).unwrap(),
    ] {
        let mesh = panels::discretize(&hull, &PanelParams::default()).unwrap();
        let map = mirror_map(&mesh).expect("symmetric mesh");
        assert!(map.iter().enumerate().all(|(p, &q)| map[q] == p));
    }
    let mut mesh =
        panels::discretize(&Hull::semicircle(1.0).unwrap(), &PanelParams::default()).unwrap();
    mesh.body[3].centre[0] += 1e-3;
    assert!(mirror_map(&mesh).is_none());
}

#[test]
fn the_mirrored_solve_matches_the_general_one() {
    // Odd body and lid counts: a panel on the axis in each, its own image.
    for (hull, panels) in [
        (Hull::semicircle(1.0).unwrap(), 33),
        (Hull::semicircle(1.0).unwrap(), 32),
        (Hull::circle(1.0, 1.5).unwrap(), 31),
    ] {
        let params = PanelParams {
            body_panels: panels,
            lid_density: 0.45,
            ..PanelParams::default()
        };
        let mesh = panels::discretize(&hull, &params).unwrap();
        let mirrored = Problem::new(mesh.clone()).unwrap();
        assert!(mirrored.mirror.is_some());
        let unprepared = Problem::with_pairs(mesh.clone(), false).unwrap();
        let mut general = Problem::new(mesh).unwrap();
        general.mirror = None;
        general.wave_pairs = Some(WavePairs::new(&general.mesh, None));
        for surface in [
            FreeSurface::Wave { wavenumber: 0.7 },
            FreeSurface::Wave { wavenumber: 2.9 },
            FreeSurface::RigidLid,
            FreeSurface::Dirichlet,
        ] {
            let irregular = IrregularFrequencies::RemoveWithLid;
            let a = mirrored.solve(surface, irregular).unwrap();
            let b = general.solve(surface, irregular).unwrap();
            let difference = |x: &DMatrix<Complex64>, y: &DMatrix<Complex64>| {
                let scale = y.iter().map(|z| z.norm()).fold(0.0, f64::max);
                (x - y).iter().map(|z| z.norm()).fold(0.0, f64::max) / scale
            };
            let d = difference(&a.added_mass, &b.added_mass);
            assert!(d <= 1e-12, "{panels} panels, {surface:?}: {d:e}");
            // Pair by pair (one frequency) against the prepared pairs (measured 2.0e-16).
            let c = unprepared.solve(surface, irregular).unwrap();
            let d = difference(&c.added_mass, &a.added_mass);
            assert!(
                d <= 2e-15,
                "{panels} panels, {surface:?}, unprepared: {d:e}"
            );
            if let (Some(x), Some(y)) = (a.wave_forces, b.wave_forces) {
                let d = difference(&x.direct, &y.direct);
                assert!(d <= 1e-12, "{panels} panels, {surface:?}: {d:e}");
            }
        }
    }
}
