use super::strip::{run, ShipSweepParams};
use super::*;
use crate::bem::IrregularFrequencies;
use crate::green::FreeSurface;
use crate::sweep::Solver;
use num_complex::Complex64;
use std::f64::consts::PI;
use std::path::Path;

const RHO: f64 = 1025.0;
const G: f64 = 9.81;

fn prismatic(stations: &[f64], section: &str, modes: &str) -> Ship {
    let mut text = String::from("<ship name=\"prism\">\n");
    for x in stations {
        text.push_str(&format!("<station x=\"{x}\">{section}</station>\n"));
    }
    text.push_str(modes);
    text.push_str("</ship>\n");
    Ship::from_xml_str(&text, "prism.xml", Path::new(".")).unwrap()
}

fn params(ship: &Ship, omega: &[f64], headings: &[f64]) -> ShipSweepParams {
    ShipSweepParams {
        omega: omega.to_vec(),
        headings: headings.to_vec(),
        panels: crate::PanelParams {
            body_panels: 32,
            ..crate::PanelParams::default()
        },
        panels_with_corners: crate::PanelParams {
            body_panels: 32,
            ..crate::PanelParams::default()
        },
        extrapolation_levels: 2,
        levels_with_corners: 2,
        ..ShipSweepParams::for_ship(ship)
    }
}

/// The 2D solve of the same section with the same discretization: `A~ / rho` and the
/// exciting force per `rho g a` for a wave of transverse cosine 1.
fn section_2d(
    ship: &Ship,
    omega: f64,
) -> (
    nalgebra::DMatrix<Complex64>,
    nalgebra::DMatrix<Complex64>,
    nalgebra::DMatrix<f64>,
) {
    let hull = ship.sections()[0].ship_section(&[]).unwrap();
    let solver = Solver::new(
        &hull,
        &crate::PanelParams {
            body_panels: 32,
            ..crate::PanelParams::default()
        },
        2,
    )
    .unwrap();
    let wave = solver
        .solve_waves(
            FreeSurface::Wave {
                wavenumber: omega * omega / G,
            },
            IrregularFrequencies::RemoveWithLid,
            &[1.0],
        )
        .unwrap();
    let inf = solver
        .solve(FreeSurface::Dirichlet, IrregularFrequencies::Keep)
        .unwrap();
    (
        wave.added_mass,
        wave.wave_forces.unwrap().haskind,
        inf.added_mass.map(|z| z.re),
    )
}

fn close(a: Complex64, b: Complex64, scale: f64, what: &str) {
    assert!(
        (a - b).norm() <= 1e-10 * scale,
        "{what}: {a} vs {b} (scale {scale})"
    );
}

/// A prismatic ship of one section is L times the 2D section in sway, heave, roll and their
/// couplings; pitch and yaw are the heave and sway values times `integral x^2 dx = L^3/12`
/// (stations symmetric about x = 0), and the couplings through `integral x dx` vanish.
#[test]
fn a_prismatic_ship_is_the_section_times_its_length_in_every_rigid_dof() {
    let stations = [-5.0, -2.0, 0.0, 1.0, 5.0];
    let ship = prismatic(&stations, "<semicircle radius=\"1\"/>", "");
    assert_eq!(ship.dof_names(), ["sway", "heave", "roll", "pitch", "yaw"]);
    let omega = [0.8, 2.5];
    let result = run(&ship, &params(&ship, &omega, &[90.0]), &|_, _| {}).unwrap();
    let length: f64 = 10.0;
    let second_moment = length.powi(3) / 12.0;
    for (w, &om) in omega.iter().enumerate() {
        let (a2, x2, inf2) = section_2d(&ship, om);
        let a = &result.added_mass[w];
        let scale = RHO * a2[(1, 1)].norm() * second_moment;
        let rho = Complex64::new(RHO, 0.0);
        // sway heave roll block.
        for i in 0..3 {
            for j in 0..3 {
                close(a[(i, j)], a2[(i, j)] * rho * length, scale, "strip block");
            }
        }
        close(a[(3, 3)], a2[(1, 1)] * rho * second_moment, scale, "pitch");
        close(a[(4, 4)], a2[(0, 0)] * rho * second_moment, scale, "yaw");
        close(a[(4, 2)], Complex64::default(), scale, "yaw-roll");
        close(a[(3, 1)], Complex64::default(), scale, "pitch-heave");
        // Beam seas (heading 90 = the section's 2D heading 0): no phase along the ship.
        let x = &result.excitation[w];
        let force_scale = RHO * G * x2[(1, 0)].norm() * length;
        for j in 0..3 {
            close(
                x[(j, 0)],
                x2[(j, 0)] * RHO * G * length,
                force_scale,
                "beam-sea force",
            );
        }
        close(
            x[(3, 0)],
            Complex64::default(),
            force_scale,
            "beam-sea pitch moment",
        );
        let inf = &result.added_mass_inf;
        assert!((inf[(3, 3)] - inf2[(1, 1)] * RHO * second_moment).abs() < 1e-10 * scale);
    }
    // Hydrostatics of the semicircle, R = 1: B = 2, A = pi/2, z_B = -4/(3 pi).
    let c = &result.stiffness_hydrostatic;
    let rho_g = RHO * G;
    let area = PI / 2.0;
    let z_b = -4.0 / (3.0 * PI);
    let expected_heave = rho_g * 2.0 * length;
    assert!(
        (c[(1, 1)] - expected_heave).abs() < 1e-3 * expected_heave,
        "{}",
        c[(1, 1)]
    );
    let expected_pitch = rho_g * (2.0 * second_moment + area * length * z_b);
    assert!(
        (c[(3, 3)] - expected_pitch).abs() < 1e-3 * expected_pitch,
        "{}",
        c[(3, 3)]
    );
    // Roll about the waterline centre: I_wp + A z_B = 2/3 - 2/3 = 0 (neutral).
    let expected_roll = rho_g * (2.0 / 3.0 + area * z_b) * length;
    assert!(
        (c[(2, 2)] - expected_roll).abs() < 1e-9 * expected_heave,
        "{}",
        c[(2, 2)]
    );
    assert!(c[(1, 3)].abs() < 1e-9 * expected_heave, "{}", c[(1, 3)]);
}

/// A girder mode that equals a rigid shape gives that rigid DOF's entries: `w = -x` is pitch,
/// `v = x` is yaw. (The restoring differs by the rigid pitch's `rho g V z_B`, which an elastic
/// mode leaves to the structural model.)
#[test]
fn a_girder_mode_equal_to_a_rigid_shape_gives_the_rigid_entries() {
    let stations = [-6.0, -3.0, 0.0, 2.0, 4.0];
    let mut modes = String::from("<mode name=\"vb\">");
    for x in stations {
        modes.push_str(&format!("<at w=\"{}\"/>", -x));
    }
    modes.push_str("</mode><mode name=\"hb\">");
    for x in stations {
        modes.push_str(&format!("<at x=\"{x}\" v=\"{x}\"/>"));
    }
    modes.push_str("</mode>");
    let ship = prismatic(
        &stations,
        "<lewis breadth=\"3\" draft=\"1\" area_coefficient=\"0.9\"/>",
        &modes,
    );
    let result = run(
        &ship,
        &params(&ship, &[1.5], &[0.0, 30.0, 150.0]),
        &|_, _| {},
    )
    .unwrap();
    let (pitch, yaw, vb, hb) = (3, 4, 5, 6);
    let a = &result.added_mass[0];
    let scale = a[(pitch, pitch)].norm();
    for (rigid, mode) in [(pitch, vb), (yaw, hb)] {
        for k in 0..7 {
            close(a[(mode, k)], a[(rigid, k)], scale, "added mass row");
        }
        for h in 0..3 {
            let x = &result.excitation[0];
            close(
                x[(mode, h)],
                x[(rigid, h)],
                x[(pitch, 0)].norm(),
                "excitation",
            );
        }
    }
    let c = &result.stiffness_hydrostatic;
    let v_zb = {
        let form = Hull::lewis(3.0, 1.0, 0.9).unwrap();
        let h = crate::hydrostatics::stiffness(&form).unwrap();
        h.submerged_area * h.centre_of_buoyancy[1] * 10.0 * RHO * G
    };
    assert!((c[(pitch, pitch)] - c[(vb, vb)] - v_zb).abs() < 1e-9 * c[(pitch, pitch)].abs());
    assert!((c[(vb, 1)] - c[(pitch, 1)]).abs() < 1e-9 * c[(pitch, pitch)].abs());
}

/// The Lewis form with B/(2T) = 1 and sigma = pi/4 is the semicircle: the same ship either way.
#[test]
fn the_lewis_semicircle_gives_the_semicircle_ship() {
    let stations = [-2.0, 2.0];
    let semicircle = prismatic(&stations, "<semicircle radius=\"1\"/>", "");
    let lewis = prismatic(
        &stations,
        &format!(
            "<lewis breadth=\"2\" draft=\"1\" area_coefficient=\"{}\"/>",
            PI / 4.0
        ),
        "",
    );
    let p = params(&semicircle, &[1.0, 3.0], &[180.0]);
    let a = run(&semicircle, &p, &|_, _| {}).unwrap();
    let b = run(&lewis, &p, &|_, _| {}).unwrap();
    for w in 0..2 {
        let scale = a.added_mass[w][(1, 1)].norm();
        for (x, y) in a.added_mass[w].iter().zip(b.added_mass[w].iter()) {
            close(*x, *y, 1e2 * scale, "Lewis semicircle");
        }
    }
}

fn refused(text: &str, words: &[&str]) {
    let e = Ship::from_xml_str(text, "bad.xml", Path::new("."))
        .unwrap_err()
        .to_string();
    for word in words {
        assert!(e.contains(word), "'{word}' not in: {e}");
    }
    assert!(e.starts_with("bad.xml:"), "{e}");
}

#[test]
fn bad_ship_files_name_the_station_and_the_field() {
    let semi = "<semicircle radius=\"1\"/>";
    refused(
        &format!("<ship name=\"s\"><station x=\"0\">{semi}</station><station x=\"-1\">{semi}</station></ship>"),
        &["station 2", "x = -1", "increasing x"],
    );
    refused(
        &format!("<ship name=\"s\"><station x=\"0\">{semi}</station><station x=\"0\">{semi}</station></ship>"),
        &["station 2", "each once"],
    );
    refused(
        &format!("<ship name=\"s\"><station x=\"0\">{semi}</station><station x=\"1\">{semi}</station><mode name=\"m\"><at w=\"1\"/></mode></ship>"),
        &["bad.xml:1:", "mode 'm' has 1", "2 stations"],
    );
    refused(
        &format!("<ship name=\"s\"><station x=\"0\">{semi}</station><station x=\"1\">{semi}</station><mode name=\"m\"><at w=\"1\"/><at w=\"NaN\"/></mode></ship>"),
        &["mode 'm', station 2", "w"],
    );
    refused(
        &format!("<ship name=\"s\"><station x=\"0\">{semi}</station><station x=\"1\">{semi}</station><mode name=\"m\"><at w=\"1\"/><at cb9=\"1\"/></mode></ship>"),
        &["station 2", "no elastic DOF 'cb9'"],
    );
    refused(
        &format!("<ship name=\"s\"><station x=\"0\">{semi}</station><station x=\"1\"><lewis breadth=\"10\" draft=\"1\" area_coefficient=\"0.2\"/></station></ship>"),
        &["station 2 at x = 1 m", "Lewis form"],
    );
    refused(
        &format!("<ship name=\"s\"><station x=\"0\">{semi}</station><station x=\"inf\">{semi}</station></ship>"),
        &["x=\"inf\"", "not a finite number"],
    );
    refused(
        "<ship name=\"s\"><station x=\"0\"/><station x=\"1\"/></ship>",
        &["no station has a section"],
    );
    refused(
        &format!("<ship name=\"s\"><station x=\"0\">{semi}</station><station x=\"1\">{semi}</station><rigid dofs=\"surge heave\"/></ship>"),
        &["'surge'", "left out"],
    );
}

#[test]
fn a_fully_submerged_section_is_refused() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-ship-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("deep.xml"),
        "<hull name=\"deep\" half_beam=\"1\"><circle radius=\"1\" depth=\"3\"/><rigid name=\"heave\" kind=\"heave\"/></hull>",
    )
    .unwrap();
    let e = Ship::from_xml_str(
        "<ship name=\"s\"><station x=\"0\"><hull file=\"deep.xml\"/></station><station x=\"1\"><semicircle radius=\"1\"/></station></ship>",
        "bad.xml",
        &dir,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("station 1") && e.contains("fully submerged"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The restoring of a Lewis section: breadth B in heave, area sigma B T (the quadrature runs
/// over the smooth form, not one straight segment).
#[test]
fn a_lewis_section_has_its_breadth_and_area() {
    let form = Hull::lewis(3.0, 1.0, 0.9).unwrap();
    let h = crate::hydrostatics::stiffness(&form).unwrap();
    assert!((h.waterline_breadth - 3.0).abs() < 1e-12);
    assert!(
        (h.submerged_area - 2.7).abs() < 1e-6,
        "{}",
        h.submerged_area
    );
    assert!((h.stiffness_per_rho_g[(1, 1)] - 3.0).abs() < 1e-12);
    assert!(h.centre_of_buoyancy[1] < 0.0 && h.centre_of_buoyancy[1] > -0.5);
}

#[test]
fn a_lewis_hull_file_round_trips_and_takes_rigid_dofs_only() {
    let text = "<hull name=\"l\" half_beam=\"1.5\"><lewis breadth=\"3\" draft=\"1\" area_coefficient=\"0.9\"/><rigid name=\"heave\" kind=\"heave\"/></hull>";
    let hull = Hull::from_xml_str(text, "l.xml").unwrap();
    let again = Hull::from_xml_str(&hull.to_xml_string(), "again.xml").unwrap();
    assert_eq!(hull.fingerprint(), again.fingerprint());
    assert_eq!(hull.point(0.5), again.point(0.5));
    let with_mode = "<hull name=\"l\" half_beam=\"1.5\"><lewis breadth=\"3\" draft=\"1\" area_coefficient=\"0.9\"/><mode name=\"m\"><u x=\"0\" y=\"1\"/></mode></hull>";
    let e = Hull::from_xml_str(with_mode, "m.xml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("rigid DOFs only"), "{e}");
}

fn structural_barge(extra_station: &str, girder: &str) -> Result<Ship, ShipError> {
    let mut text = String::from("<ship name=\"girder\">\n");
    for k in 0..21 {
        let x = -50.0 + 5.0 * k as f64;
        let attributes = if k == 10 {
            extra_station.to_string()
        } else {
            "mass=\"5e4\" bending_stiffness_vertical=\"1e12\" torsional_stiffness=\"4e11\" roll_inertia=\"6e5\"".to_string()
        };
        text.push_str(&format!(
            "<station x=\"{x}\" {attributes}><lewis breadth=\"10\" draft=\"5\" area_coefficient=\"0.95\"/></station>\n"
        ));
    }
    text.push_str(&format!("<rigid dofs=\"heave pitch\"/>{girder}</ship>\n"));
    Ship::from_xml_str(&text, "girder.xml", Path::new("."))
}

/// `<girder_modes>` computes the free-free modes of the stations' structure: for a uniform
/// girder the textbook first bending mode (beta L = 4.7300) and torsion mode (pi / L), in the
/// DOF order of the file, with their dry properties.
#[test]
fn girder_modes_come_from_the_stations_structure() {
    let uniform = "mass=\"5e4\" bending_stiffness_vertical=\"1e12\" torsional_stiffness=\"4e11\" roll_inertia=\"6e5\"";
    let ship = structural_barge(uniform, "<girder_modes vertical=\"2\" torsion=\"1\"/>").unwrap();
    assert_eq!(ship.dof_names(), ["heave", "pitch", "vb1", "vb2", "t1"]);
    let modes = ship.girder_modes();
    let length: f64 = 100.0;
    let bending = 4.730_040_744_862_704_f64.powi(2) * (1e12 / (5e4 * length.powi(4))).sqrt();
    assert!((modes[0].1.natural_frequency / bending - 1.0).abs() < 1e-4);
    let torsion = PI / length * (4e11_f64 / 6e5).sqrt();
    assert!((modes[2].1.natural_frequency / torsion - 1.0).abs() < 2e-3);
    // The computed vb1 at the stations is the analytic shape of examples/ships/generate.py.
    let beta_l = 4.730_040_744_862_704_f64;
    let s = (beta_l.cosh() - beta_l.cos()) / (beta_l.sinh() - beta_l.sin());
    let shape = |z: f64| z.cosh() + z.cos() - s * (z.sinh() + z.sin());
    for (k, station) in ship.stations().iter().enumerate() {
        let exact = shape(beta_l * (station.x / length + 0.5)) / shape(0.0);
        let motion = ship.motion(2, k);
        assert!(
            (motion.heave - exact).abs() < 1e-4,
            "{k}: {} vs {exact}",
            motion.heave
        );
        assert_eq!((motion.sway, motion.roll), (0.0, 0.0));
        assert!((ship.motion(4, k).roll - 1.0).abs() < 1e-12 || k > 0);
    }
}

#[test]
fn girder_modes_need_every_station_s_structure() {
    let e = structural_barge("mass=\"5e4\"", "<girder_modes vertical=\"1\"/>")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("station 11 at x = 0 m has no bending_stiffness_vertical"),
        "{e}"
    );
    let e = structural_barge("mass=\"NaN\"", "<girder_modes vertical=\"1\"/>")
        .unwrap_err()
        .to_string();
    assert!(e.contains("station 11 at x = 0 m: mass = \"NaN\""), "{e}");
    let e = structural_barge("mass=\"-1\" bending_stiffness_vertical=\"1\"", "")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("station 11 at x = 0 m: mass = \"-1\" must be a positive"),
        "{e}"
    );
    let uniform = "mass=\"5e4\" bending_stiffness_vertical=\"1e12\"";
    let e = structural_barge(uniform, "<girder_modes vertical=\"2.5\"/>")
        .unwrap_err()
        .to_string();
    assert!(e.contains("whole number"), "{e}");
}

/// A ship whose stations come from a PDStrip offset file is the same ship as one written
/// with the same sections as hull files: identical added mass and restoring.
#[test]
fn a_pdstrip_offset_file_gives_the_same_ship_as_its_hull_files() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-pdstrip-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Base line at the keel, waterline at z = 3 (not the reference draft 2: given explicitly).
    let mut offsets = String::from("3 F 2.0\n");
    for x in [-20.0, 0.0, 20.0] {
        offsets.push_str(&format!("{x} 5 0\n4 4 2 -4 -4\n3 0.5 0 0.5 3\n"));
    }
    std::fs::write(dir.join("hull.out"), offsets).unwrap();
    std::fs::write(
        dir.join("section.xml"),
        "<hull name=\"v\" half_beam=\"4\"><contour><point x=\"-4\" y=\"0\"/><point x=\"-4\" y=\"-2.5\"/>\
         <point x=\"2\" y=\"-3\"/><point x=\"4\" y=\"-2.5\"/><point x=\"4\" y=\"0\"/></contour>\
         <rigid name=\"sway\" kind=\"sway\"/></hull>",
    )
    .unwrap();
    let from_offsets = Ship::from_xml_str(
        "<ship name=\"p\"><offsets file=\"hull.out\" format=\"pdstrip\" waterline=\"3\"/></ship>",
        "p.xml",
        &dir,
    )
    .unwrap();
    let mut stations = String::new();
    for x in [-20.0, 0.0, 20.0] {
        stations.push_str(&format!(
            "<station x=\"{x}\"><hull file=\"section.xml\"/></station>"
        ));
    }
    let from_hulls = Ship::from_xml_str(
        &format!("<ship name=\"p\">{stations}</ship>"),
        "h.xml",
        &dir,
    )
    .unwrap();
    assert_eq!(from_offsets.sections().len(), 1);
    let p = params(&from_offsets, &[0.9], &[90.0]);
    let (a, b) = (
        run(&from_offsets, &p, &|_, _| {}).unwrap(),
        run(&from_hulls, &p, &|_, _| {}).unwrap(),
    );
    // The offsets run starboard-first here (y = 4 .. -4), reversed on reading: the same contour.
    let scale = a.added_mass[0][(1, 1)].norm();
    for (x, y) in a.added_mass[0].iter().zip(b.added_mass[0].iter()) {
        close(*x, *y, scale, "offsets against hull files");
    }
    assert!(
        (&a.stiffness_hydrostatic - &b.stiffness_hydrostatic).amax()
            < 1e-9 * a.stiffness_hydrostatic.amax()
    );
    let e = Ship::from_xml_str(
        "<ship name=\"p\"><offsets file=\"hull.out\" format=\"pdstrip\"/></ship>",
        "p.xml",
        &dir,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("section 1 at x = -20 m") && e.contains("waterline"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_offset_file_alone_is_a_ship_of_rigid_dofs() {
    let text = "2 T 5\n-10 3 0\n0 5 5 0 0 5\n10 3 0\n0 5 5 0 0 5\n";
    let ship = Ship::from_offsets_str("box", text, "box.out", None).unwrap();
    assert_eq!(ship.dof_names(), RIGID_DOFS);
    assert_eq!(ship.sections().len(), 1);
    let e =
        Ship::from_offsets_str("box", "2 T 5\n-10 3 0\n0 5 5 0 0\n", "box.out", None).unwrap_err();
    assert_eq!(e.line(), Some(3));
    assert!(e.to_string().starts_with("box.out:3: the file ends"), "{e}");
}

/// Sizes the parameters decide are refused before anything is allocated.
#[test]
fn a_sweep_too_large_is_refused_before_it_starts() {
    let ship = prismatic(&[-1.0, 1.0], "<semicircle radius=\"1\"/>", "");
    let many = ShipSweepParams {
        omega: vec![1.0; super::strip::MAX_SECTION_SOLVES + 1],
        ..params(&ship, &[1.0], &[0.0])
    };
    let e = run(&ship, &many, &|_, _| {}).unwrap_err().to_string();
    assert!(e.contains("section solves; at most 250000"), "{e}");
    for (headings, words) in [(vec![], "0 headings"), (vec![f64::NAN], "not finite")] {
        let p = ShipSweepParams {
            headings,
            ..params(&ship, &[1.0], &[0.0])
        };
        let e = run(&ship, &p, &|_, _| {}).unwrap_err().to_string();
        assert!(e.contains(words), "{e}");
    }
    let p = ShipSweepParams {
        omega: vec![-1.0],
        ..params(&ship, &[1.0], &[0.0])
    };
    assert!(run(&ship, &p, &|_, _| {})
        .unwrap_err()
        .to_string()
        .contains("-1 rad/s"));
}

/// A Wigley-like ship of 9 stations whose sections are hull files of 33 points per side
/// (a finely described symmetric hull, as dense offsets give): head and following seas give
/// no sway, roll or yaw force, and beam seas from port and starboard give mirrored forces, to
/// rounding (every section's mesh is mirror-symmetric by construction). With the nearest-node
/// snapping of before, a 41-station Wigley of such sections felt a head-sea sway force of 3 %
/// of the beam-sea one.
#[test]
fn a_symmetric_ship_feels_no_transverse_force_in_head_seas() {
    let folder = std::env::temp_dir().join(format!("hydrofmu-wigley-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let per_side = 33;
    let draft = 1.0;
    let mut ship_text = String::from("<ship name=\"wigley\">\n");
    for (k, x) in [-20.0f64, -15.0, -10.0, -5.0, 0.0, 5.0, 10.0, 15.0, 20.0]
        .iter()
        .enumerate()
    {
        let half_beam = 2.0 * (1.0 - (x / 22.0).powi(2));
        let hull = crate::hull::wigley_section_xml(&format!("s{k}"), half_beam, draft, per_side);
        std::fs::write(folder.join(format!("s{k}.xml")), hull).unwrap();
        ship_text.push_str(&format!(
            "<station x=\"{x}\"><hull file=\"s{k}.xml\"/></station>\n"
        ));
    }
    ship_text.push_str("</ship>\n");
    let ship = Ship::from_xml_str(&ship_text, "wigley.xml", &folder).unwrap();
    std::fs::remove_dir_all(&folder).ok();
    let names = ship.dof_names();
    let index = |name: &str| names.iter().position(|d| *d == name).unwrap();
    let (sway, heave, roll, yaw) = (index("sway"), index("heave"), index("roll"), index("yaw"));
    let omega = [0.8, 1.6, 2.6];
    let result = run(
        &ship,
        &params(&ship, &omega, &[0.0, 90.0, 180.0, 270.0]),
        &|_, _| {},
    )
    .unwrap();
    for (w, x) in result.excitation.iter().enumerate() {
        let beam = x[(sway, 1)].norm();
        for heading in [0, 2] {
            for dof in [sway, roll, yaw] {
                let ratio = x[(dof, heading)].norm() / beam;
                assert!(
                    ratio < 1e-12,
                    "omega {}: dof {dof} heading {heading}: {ratio:e}",
                    omega[w]
                );
            }
        }
        // Port and starboard: sway, roll and yaw change sign, heave does not.
        for (dof, sign) in [(sway, -1.0), (heave, 1.0), (roll, -1.0), (yaw, -1.0)] {
            let d = (x[(dof, 1)] - x[(dof, 3)] * sign).norm() / beam;
            assert!(d < 1e-12, "omega {}: dof {dof}: {d:e}", omega[w]);
        }
    }
}

/// The station spacing's estimate: a prismatic ship's rigid sway, heave and roll integrate
/// exactly with every second station (no change); the example Wigley's pointed ends (empty
/// end stations) change sway, roll and yaw by several per cent (measured with the defaults:
/// yaw force 8.1 %, sway 3.0 %), heave hardly.
#[test]
fn the_ship_report_estimates_the_station_spacing_error() {
    let ship = prismatic(
        &[-5.0, -2.0, 0.0, 1.0, 5.0],
        "<semicircle radius=\"1\"/>",
        "",
    );
    let result = run(&ship, &params(&ship, &[0.8, 2.5], &[90.0]), &|_, _| {}).unwrap();
    let note = result
        .notes
        .iter()
        .find(|n| n.starts_with("station spacing"))
        .expect("a spacing note");
    for dof in ["sway A~ 0.00 %", "heave A~ 0.00 %", "roll A~ 0.00 %"] {
        assert!(note.contains(dof), "{note}");
    }
    assert!(
        !result
            .warnings
            .iter()
            .any(|w| w.contains("station spacing")),
        "{:?} {note}",
        result.warnings
    );
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ships/wigley.xml");
    let ship = Ship::from_file(&path).unwrap();
    let result = run(
        &ship,
        &params(&ship, &[0.6, 1.2], &[45.0, 90.0]),
        &|_, _| {},
    )
    .unwrap();
    let note = result
        .notes
        .iter()
        .find(|n| n.starts_with("station spacing"))
        .expect("a spacing note");
    let percent = |what: &str| -> f64 {
        let at = note.find(what).unwrap() + what.len();
        note[at..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    assert!(percent("yaw A~ ") > 2.0, "{note}");
    assert!(percent("heave A~ ") < 0.5, "{note}");
    // Yaw and sway beyond 2 %: a warning names them, not heave.
    let warning = result
        .warnings
        .iter()
        .find(|w| w.starts_with("station spacing"))
        .expect("a spacing warning");
    assert!(
        warning.contains("yaw ") && !warning.contains("heave "),
        "{warning}"
    );
}

#[test]
fn sections_of_the_same_shape_under_other_names_are_solved_once() {
    // A fore-and-aft symmetric ship given by one file per station: the mirrored stations'
    // files differ in their names only.
    let dir = std::env::temp_dir().join(format!("hydrofmu-names-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let sections = [("a", 1.0), ("b", 1.5), ("c", 1.0), ("d", 1.2)];
    for (name, half_beam) in sections {
        let text = crate::hull::wigley_section_xml(name, half_beam, 0.5, 5);
        std::fs::write(dir.join(format!("{name}.xml")), text).unwrap();
    }
    let stations: String = sections
        .iter()
        .enumerate()
        .map(|(k, (name, _))| format!("<station x=\"{k}\"><hull file=\"{name}.xml\"/></station>"))
        .collect();
    let ship = Ship::from_xml_str(
        &format!("<ship name=\"s\">{stations}</ship>"),
        "s.xml",
        &dir,
    )
    .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    // a and c are one shape; b and d differ in half-beam.
    assert_eq!(ship.sections().len(), 3);
}

#[test]
fn headings_equal_modulo_360_are_refused_before_any_solve() {
    // Two headings of one direction would make one table column twice (an archive that does
    // not instantiate): refused with both named.
    let ship = prismatic(&[-1.0, 0.0, 1.0], "<semicircle radius=\"1\"/>", "");
    for (headings, named) in [
        (vec![0.0, 360.0], "headings 0 and 360"),
        (vec![90.0, 180.0, -270.0], "headings 90 and -270"),
        (vec![45.0, 45.0 + 1e-12], "are the same direction"),
    ] {
        let e = run(&ship, &params(&ship, &[1.0], &headings), &|_, _| {})
            .unwrap_err()
            .to_string();
        assert!(e.contains(named), "{headings:?}: {e}");
    }
    // Close but distinct directions stay.
    assert!(run(&ship, &params(&ship, &[1.0], &[0.0, 359.9]), &|_, _| {}).is_ok());
}

/// Runs `work` on a thread and returns its answer, failing if none comes within 20 s.
fn promptly<T: Send + 'static>(work: impl FnOnce() -> T + Send + 'static) -> T {
    let (sender, receiver) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = sender.send(work());
    });
    receiver
        .recv_timeout(std::time::Duration::from_secs(20))
        .expect("no answer within 20 s")
}

/// A named pipe at `path`, or `None` (with the reason printed) where `mkfifo` is unavailable.
fn named_pipe(path: &Path) -> Option<std::path::PathBuf> {
    match std::process::Command::new("mkfifo").arg(path).status() {
        Ok(status) if status.success() => Some(path.to_path_buf()),
        other => {
            eprintln!("named pipe case skipped: mkfifo is unavailable here ({other:?})");
            None
        }
    }
}

/// A ship whose section file or offset file is `/dev/zero`, a named pipe or a file one byte
/// over the limit is refused at once, naming the file and the reason.
#[test]
fn section_and_offset_files_that_never_end_are_refused_promptly() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-endless-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let over = dir.join("over.xml");
    std::fs::File::create(&over)
        .unwrap()
        .set_len(crate::xml::MAX_INPUT_BYTES as u64 + 1)
        .unwrap();
    let mut cases = vec![
        (std::path::PathBuf::from("/dev/zero"), "(a device)"),
        (
            over,
            "larger than the limit MAX_INPUT_BYTES = 67108864 bytes",
        ),
    ];
    if let Some(pipe) = named_pipe(&dir.join("pipe")) {
        cases.push((pipe, "(a named pipe)"));
    }
    for (file, reason) in cases {
        let name = file.display().to_string();
        let texts = [
            format!(
                "<ship name=\"s\"><station x=\"0\"><hull file=\"{name}\"/></station>\
                 <station x=\"1\"><semicircle radius=\"1\"/></station></ship>"
            ),
            format!("<ship name=\"s\"><offsets file=\"{name}\" format=\"pdstrip\"/></ship>"),
        ];
        for text in texts {
            let folder = dir.clone();
            let e = promptly(move || Ship::from_xml_str(&text, "s.xml", &folder))
                .unwrap_err()
                .to_string();
            assert!(e.contains(&name) && e.contains(reason), "{e}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
