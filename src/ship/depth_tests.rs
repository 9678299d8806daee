//! A ship in finite water depth: the file's `depth`, the sweep's depth, and the incident
//! wave's phase along the ship with the finite-depth wavenumber.

use super::strip::{run, wave_phase, ShipSweepParams};
use super::*;
use crate::units::WaterDepth;
use num_complex::Complex64;
use std::f64::consts::PI;
use std::path::Path;

const G: f64 = 9.81;

fn ship_text(root_attributes: &str) -> String {
    format!(
        "<ship name=\"prism\"{root_attributes}>\n\
         <station x=\"-5\"><semicircle radius=\"1\"/></station>\n\
         <station x=\"5\"><semicircle radius=\"1\"/></station>\n</ship>\n"
    )
}

fn ship(root_attributes: &str) -> Result<Ship, ShipError> {
    Ship::from_xml_str(&ship_text(root_attributes), "prism.xml", Path::new("."))
}

#[test]
fn the_ship_files_depth_is_read_strictly_and_is_the_sweeps_default() {
    let deep = ship("").unwrap();
    assert_eq!(deep.depth(), WaterDepth::Infinite);
    assert_eq!(ShipSweepParams::for_ship(&deep).depth, WaterDepth::Infinite);
    let finite = ship(" depth=\"12.5\"").unwrap();
    assert_eq!(finite.depth(), WaterDepth::Finite(12.5));
    assert_eq!(
        ShipSweepParams::for_ship(&finite).depth,
        WaterDepth::Finite(12.5)
    );
    for bad in ["0", "-3", "nan", "inf", "x", ""] {
        let e = ship(&format!(" depth=\"{bad}\"")).unwrap_err().to_string();
        assert!(
            e.starts_with("prism.xml:1:") && e.contains(&format!("depth=\"{bad}\"")),
            "{bad}: {e}"
        );
    }
}

#[test]
fn the_wave_phase_along_the_ship_uses_the_depths_wavenumber() {
    let omega = 0.8;
    let deep = WaterDepth::Infinite.wavenumber(omega, G).unwrap();
    // Deep water: the formula the strip integration always used, bit for bit.
    for (heading, x) in [(0.0, 3.0), (45.0, -7.5), (180.0, 12.0)] {
        let along = deep * f64::to_radians(heading).cos();
        assert_eq!(
            wave_phase(deep, heading, x),
            Complex64::new(0.0, -along * x).exp()
        );
    }
    // h = 10 m, kh about 0.8: the wave is shorter than in deep water, and the phase repeats
    // over the finite-depth wavelength 2 pi / k, not the deep one.
    let k = WaterDepth::Finite(10.0).wavenumber(omega, G).unwrap();
    assert!((omega * omega - G * k * (k * 10.0).tanh()).abs() < 1e-12);
    assert!(k > 1.2 * deep);
    let wavelength = 2.0 * PI / k;
    assert!((wave_phase(k, 0.0, wavelength) - 1.0).norm() < 1e-12);
    assert!((wave_phase(k, 0.0, 2.0 * PI / deep) - 1.0).norm() > 0.5);
    // Head seas: the wave meets the bow (x > 0) first; a quarter wavelength aft lags by pi/2.
    let quarter = wave_phase(k, 180.0, -wavelength / 4.0);
    assert!((quarter - Complex64::new(0.0, -1.0)).norm() < 1e-12);
    // Beam seas: the same phase at every station, in any depth.
    assert!((wave_phase(k, 90.0, 40.0) - 1.0).norm() < 1e-12);
}

#[test]
fn a_finite_depth_ship_sweep_is_refused_by_name() {
    let ship = ship(" depth=\"10\"").unwrap();
    let params = ShipSweepParams {
        omega: vec![0.5, 1.0],
        ..ShipSweepParams::for_ship(&ship)
    };
    let e = run(&ship, &params, &|_, _| {}).unwrap_err().to_string();
    assert!(e.contains("depth"), "{e}");
    // A 0.5 m depth above the 1 m keel: refused before any solve.
    let shallow = ShipSweepParams {
        depth: WaterDepth::Finite(0.5),
        ..params
    };
    assert!(run(&ship, &shallow, &|_, _| {}).is_err());
}
