//! The default fit on inputs nobody tuned it to: the example ship sections (midship, barge)
//! as `fmu-pack fit` sweeps them, and WAMIT's own 7-frequency hemisphere. Each must meet the
//! 1 % tolerance with at most the states a passive vector fit of the same data needs (the
//! peers' column of the identification table, docs/IDENTIFICATION.md), be passive by the
//! exact check, and forget a velocity pulse. Times are measured by
//! `cargo run --release -p fmu-pack --example identification`, not here.

use hydrofmu::database::import::{import, ImportParams};
use hydrofmu::hull::Hull;
use hydrofmu::identify::{self, FitParams, FitReport, FrequencyResponse};
use hydrofmu::scene::Scene;
use std::path::Path;

mod common;
use common::assert_passive_and_forgets_a_pulse;

/// The scene's default fit of a hull (all DOFs, kR 0.05 .. 5).
fn scene_fit(hull: Hull) -> (FrequencyResponse, FitReport) {
    let built = Scene::new(hull).build().unwrap();
    let sweep = built.sweep(&|_, _| {}).unwrap();
    let response = built.response(&sweep).unwrap();
    let fit = built.fit(&response).unwrap();
    (response.fitted, fit)
}

/// [`scene_fit`] of a hull file in `examples/hulls`.
fn section_fit(file: &str) -> (FrequencyResponse, FitReport) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/hulls")
        .join(file);
    scene_fit(Hull::from_file(&path).unwrap())
}

/// The midship section (6 DOFs: sway, heave, roll and three plating modes). Before: 6 states
/// at 50.7 %, tolerance missed (every order >= 2 failed the passivity enforcement). Peer: a
/// passive vector fit with 36 states at 0.66 %. Measured: 30 states, 0.903 % (the symmetric
/// and antisymmetric blocks, 3 directions each, at orders 4, poles refined under the
/// passivity constraints, and 6; the mesh is mirror-symmetric). The order search is sensitive
/// to the data at 1e-4: the meshes of before gave 23 and 27 states.
#[test]
fn midship_meets_the_tolerance_with_fewer_states_than_a_vector_fit() {
    let (_, fit) = section_fit("midship.xml");
    eprintln!(
        "midship: {} states, {:.3} %, notes {:?}",
        fit.states,
        100.0 * fit.max_relative_error,
        fit.notes
    );
    assert!(fit.tolerance_met, "{}", fit.max_relative_error);
    assert!(fit.states <= 30, "{}", fit.states);
    assert!(!fit.network.substructures.is_empty());
    assert_passive_and_forgets_a_pulse(&fit.network);
}

/// The barge section. Before: 6 states at 60.4 %. Peer: 36 states at 0.97 %. Measured: 33
/// states, 0.951 % (3-direction blocks at orders 5, poles refined, and 6).
#[test]
fn barge_meets_the_tolerance_with_at_most_a_vector_fits_states() {
    let (_, fit) = section_fit("barge.xml");
    eprintln!(
        "barge: {} states, {:.3} %, notes {:?}",
        fit.states,
        100.0 * fit.max_relative_error,
        fit.notes
    );
    assert!(fit.tolerance_met, "{}", fit.max_relative_error);
    assert!(fit.states <= 33, "{}", fit.states);
    assert_passive_and_forgets_a_pulse(&fit.network);
}

/// WAMIT's hemisphere at 7 frequencies (tests/data/wamit). Before: 12 states at 5.2 %, order
/// 7 refused. Peer: 21 states at 0.21 %. Measured: 13 states, 0.670 % (three one-dimensional
/// blocks at orders 4, 4 and 5), and a note that says what the network assumes between the 7
/// points.
#[test]
fn seven_frequencies_are_fitted_with_fewer_poles_than_points() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/wamit/sphere.1");
    let database = import(&path, &ImportParams::new()).unwrap();
    let fit = identify::fit(
        &database.response(),
        &FitParams {
            noise: Some(database.noise.clone()),
            ..FitParams::default()
        },
    )
    .unwrap();
    eprintln!(
        "sphere: {} states, {:.4} %, order {}, notes {:?}",
        fit.states,
        100.0 * fit.max_relative_error,
        fit.order,
        fit.notes
    );
    assert_eq!(fit.points, 7);
    assert!(fit.tolerance_met, "{}", fit.max_relative_error);
    assert!(fit.states <= 13, "{}", fit.states);
    // Fewer poles per invariant block than points.
    assert!(fit.order < 7, "{}", fit.order);
    assert!(
        fit.notes.iter().any(|n| n.contains("only 7 frequencies")),
        "{:?}",
        fit.notes
    );
    assert_passive_and_forgets_a_pulse(&fit.network);
}

/// The circle at H/R 1.5 (sway, heave, roll; kR 0.05 .. 5): its damping vanishes towards
/// the band's top (`exp(-2 k H)`), so the passivity constraints bind there. Before: 12 states
/// (order 6 per block) at 0.303 %; the relocated poles at order 4 give 1.24 % once passive.
/// Peer: 8 states at 0.70 %. Measured: 8 states, 0.792 % (order 4 per block, poles refined
/// under the constraints), and a note naming the refined blocks.
#[test]
fn a_submerged_circle_meets_the_tolerance_with_a_vector_fits_states() {
    let (_, fit) = scene_fit(Hull::circle(1.0, 1.5).unwrap());
    eprintln!(
        "circle: {} states, {:.3} %, notes {:?}",
        fit.states,
        100.0 * fit.max_relative_error,
        fit.notes
    );
    assert!(fit.tolerance_met, "{}", fit.max_relative_error);
    assert!(fit.states <= 8, "{}", fit.states);
    assert!(
        fit.notes.iter().any(|n| n.contains("poles moved")),
        "{:?}",
        fit.notes
    );
    assert_passive_and_forgets_a_pulse(&fit.network);
}

/// The midship section in 30 m of water (`h/R` 4.1; its draft 6.5 m): 2D data in finite
/// depth, whose heave-like damping tends to a constant at zero frequency, carried by a slow
/// pole below the band (`identify::pole_range_below`). Before: 18 states at 16.9 %, tolerance
/// missed (every candidate with such a pole refused). Measured: 27 states, 0.93 %. The pulse
/// is forgotten: the slow pole's share of the force is its rate over the band's (module docs
/// of `identify::params`).
#[test]
fn the_midship_in_finite_depth_meets_the_tolerance() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hulls/midship.xml");
    let mut scene = Scene::new(Hull::from_file(&path).unwrap());
    scene.sweep.depth = hydrofmu::units::WaterDepth::Finite(30.0);
    let built = scene.build().unwrap();
    let response = built.response(&built.sweep(&|_, _| {}).unwrap()).unwrap();
    let fit = built.fit(&response).unwrap();
    eprintln!(
        "midship in 30 m: {} states, {:.3} %, notes {:?}",
        fit.states,
        100.0 * fit.max_relative_error,
        fit.notes
    );
    assert!(fit.tolerance_met, "{}", fit.max_relative_error);
    assert!(fit.states <= 30, "{}", fit.states);
    assert_passive_and_forgets_a_pulse(&fit.network);
}

/// A noisy database: the hemisphere with `A~_15` and `A~_51` (surge-pitch) moved apart by 6 %
/// of `sqrt(s_1 s_5)`, in alternating directions from one frequency to the next (the mean, the
/// data fitted, unchanged). The import records the gap; the fit still aims at the 1 %
/// tolerance but is judged against the 3 % noise floor, with a note naming the entry.
#[test]
fn noise_above_the_tolerance_sets_the_floor_with_a_note() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/wamit/sphere.1");
    let text = std::fs::read_to_string(&path).unwrap();
    let database = import(&path, &ImportParams::new()).unwrap();
    let data = database.response();
    let scales = identify::dof_scales(&data.added_mass).unwrap();
    // Surge (1) and pitch (5): the .1 gives A / (rho L^k), L = 1 m.
    let gap = 0.03 * (scales[0] * scales[4]).sqrt() / database.rho;
    let mut periods: Vec<&str> = Vec::new();
    let noisy: String = text
        .lines()
        .map(|line| {
            let fields: Vec<&str> = line.split_whitespace().collect();
            let coupling = [("1", "5", 1.0), ("5", "1", -1.0)]
                .iter()
                .find(|(i, j, _)| fields.len() == 5 && fields[1] == *i && fields[2] == *j)
                .map(|c| c.2);
            let Some(side) = coupling else {
                return line.to_string();
            };
            if !periods.contains(&fields[0]) {
                periods.push(fields[0]);
            }
            let k = periods.iter().position(|p| *p == fields[0]).unwrap();
            let sign = if k % 2 == 0 { side } else { -side };
            let a: f64 = fields[3].parse().unwrap();
            format!(
                "{} {} {} {:.6E} {}",
                fields[0],
                fields[1],
                fields[2],
                a + sign * gap,
                fields[4]
            )
        })
        .collect::<Vec<_>>()
        .join("\n");
    let dir = std::env::temp_dir().join(format!("hydrofmu-noise-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let noisy_path = dir.join("sphere.1");
    std::fs::write(&noisy_path, noisy).unwrap();
    let params = ImportParams {
        spikes: None,
        ..ImportParams::new()
    };
    let noisy = import(&noisy_path, &params).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let fit = identify::fit(
        &noisy.response(),
        &FitParams {
            noise: Some(noisy.noise.clone()),
            ..FitParams::default()
        },
    )
    .unwrap();
    eprintln!(
        "noisy sphere: tolerance {:.4} %, error {:.4} %, notes {:?}",
        100.0 * fit.tolerance,
        100.0 * fit.max_relative_error,
        fit.notes
    );
    // The floor is the gap over sqrt(s_surge s_pitch), 3 % to the file's 7 digits.
    assert!((fit.tolerance - 0.03).abs() < 1e-5, "{}", fit.tolerance);
    let note = fit
        .notes
        .iter()
        .find(|n| n.contains("noise"))
        .expect("a noise note");
    assert!(note.contains("surge-pitch"), "{note}");
    assert!(fit.tolerance_met, "{}", fit.max_relative_error);
    // The search still aims at 1 %: the mean is the clean data, fitted as well (0.998 %).
    assert!(fit.max_relative_error <= 0.01, "{}", fit.max_relative_error);
}
