//! Loads every hull file shipped in `examples/hulls/` and checks it against independent
//! geometric facts (waterline width, section area by the divergence theorem).

use hydrofmu::hull::{DofKind, Hull, RigidKind};
use std::path::{Path, PathBuf};

fn example_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hulls");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml"))
        .collect();
    files.sort();
    files
}

fn load(stem: &str) -> Hull {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/hulls")
        .join(format!("{stem}.xml"));
    Hull::from_file(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Section area A = -integral_C y n_y ds (divergence theorem with the body's outward normal
/// -n; the free-surface lid has y = 0). Midpoint rule: exact on straight segments.
fn section_area(hull: &Hull) -> f64 {
    let knots = hull.breakpoints();
    let mut area = 0.0;
    for pair in knots.windows(2) {
        let (a, b) = (hull.point(pair[0]), hull.point(pair[1]));
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        let mid = 0.5 * (pair[0] + pair[1]);
        area -= hull.point(mid)[1] * hull.normal(mid)[1] * length;
    }
    area
}

#[test]
fn every_example_file_loads_and_round_trips() {
    let files = example_files();
    assert!(files.len() >= 4, "{files:?}");
    let mut prints = Vec::new();
    for path in &files {
        let hull = Hull::from_file(path).unwrap_or_else(|e| panic!("{e}"));
        let stem = path.file_stem().unwrap().to_str().unwrap();
        assert_eq!(hull.name(), stem);
        // Shipped files are written counter-clockwise with waterline points exactly on y = 0.
        assert!(hull.notes().is_empty(), "{stem}: {:?}", hull.notes());
        assert_eq!(&hull.dof_names()[..3], ["sway", "heave", "roll"]);
        let back = Hull::from_xml_str(&hull.to_xml_string(), "canonical").unwrap();
        assert_eq!(back.fingerprint(), hull.fingerprint());
        prints.push(hull.fingerprint());
    }
    prints.sort();
    prints.dedup();
    assert_eq!(prints.len(), files.len());
}

/// Area a polygonal fillet of radius `r` (`segments` chords) removes from a corner where the
/// contour turns by `turn` radians: the sharp corner minus the arc sector, plus the chord caps.
fn fillet_loss(r: f64, turn: f64, segments: u32) -> f64 {
    let chord_angle = turn / f64::from(segments);
    r * r * (turn / 2.0).tan() - r * r * turn / 2.0
        + f64::from(segments) * r * r / 2.0 * (chord_angle - chord_angle.sin())
}

/// Area of the midship section from its defining numbers: keel 8 m deep, 12-degree deadrise,
/// 10-degree flare to the 12 m half-beam waterline point, 3 m bilge of 8 chords.
fn midship_area() -> f64 {
    let (dead, flare) = (12f64.to_radians(), 10f64.to_radians());
    // Corner: (0, -8) + a (cos dead, sin dead) = (12, 0) - b (sin flare, cos flare).
    let (d1, d2) = ([dead.cos(), dead.sin()], [flare.sin(), flare.cos()]);
    let det = -d1[0] * d2[1] + d2[0] * d1[1];
    let a = (-12.0 * d2[1] + d2[0] * 8.0) / det;
    let corner = [a * d1[0], -8.0 + a * d1[1]];
    // Right half (0,-8), corner, (12,0), (0,0) by the shoelace formula.
    let half = 0.5 * ((corner[0] * 8.0) + (12.0 * -corner[1]));
    let turn = (90.0f64 - 10.0 - 12.0).to_radians();
    2.0 * (half - fillet_loss(3.0, turn, 8))
}

#[test]
fn ship_sections_are_plausible() {
    let right_angle = std::f64::consts::FRAC_PI_2;
    for (stem, expected_area) in [
        ("barge", 100.0 - 2.0 * fillet_loss(2.0, right_angle, 8)),
        ("midship", midship_area()),
    ] {
        let hull = load(stem);
        assert!(!hull.is_closed());
        let points = hull.breakpoints().len();
        assert!((30..=80).contains(&points), "{stem}: {points} points");
        let (left, right) = (hull.point(0.0), hull.point(1.0));
        assert_eq!((left[1], right[1]), (0.0, 0.0));
        let beam = right[0] - left[0];
        assert!((10.0..=30.0).contains(&beam), "{stem}: beam {beam}");
        assert_eq!(hull.reference_half_beam(), beam / 2.0);
        // Waterline width from the normals: integral_C n_y ds = beam, integral_C n_x ds = 0.
        let knots = hull.breakpoints();
        let (mut nx, mut ny) = (0.0, 0.0);
        for pair in knots.windows(2) {
            let (a, b) = (hull.point(pair[0]), hull.point(pair[1]));
            let length = (b[0] - a[0]).hypot(b[1] - a[1]);
            let n = hull.normal(0.5 * (pair[0] + pair[1]));
            nx += n[0] * length;
            ny += n[1] * length;
        }
        // Sums of ~40 segment terms of size ~1 m: round-off only.
        assert!(
            nx.abs() < 1e-9 && (ny - beam).abs() < 1e-9,
            "{stem}: {nx} {ny}"
        );
        let area = section_area(&hull);
        // Coordinates are rounded to 0.1 mm: ~40 m of contour moves the area by < 4e-3 m^2.
        assert!(
            (area - expected_area).abs() < 4e-3,
            "{stem}: area {area} vs {expected_area}"
        );
        let elastic: Vec<usize> = (0..hull.dof_count())
            .filter(|&j| hull.dof_kind(j) == Some(DofKind::Elastic))
            .collect();
        assert!((2..=3).contains(&elastic.len()), "{stem}");
        for j in elastic {
            let largest = (0..=400)
                .map(|i| hull.normal_displacement(j, f64::from(i) / 400.0).abs())
                .fold(0.0, f64::max);
            assert!(largest > 0.5, "{stem}: mode {j} barely moves the contour");
        }
    }
}

#[test]
fn pontoon_is_closed_and_submerged() {
    let hull = load("pontoon");
    assert!(hull.is_closed());
    assert_eq!(
        hull.dof_kind(2),
        Some(DofKind::Rigid {
            kind: RigidKind::Roll,
            reference: [0.0, -12.0]
        })
    );
    assert_eq!(hull.point(0.0), hull.point(1.0));
    let top = (0..=1000)
        .map(|i| hull.point(f64::from(i) / 1000.0)[1])
        .fold(f64::NEG_INFINITY, f64::max);
    assert!((top + 9.0).abs() < 1e-12, "top at {top}");
    // 12 m x 6 m minus four 1.5 m corners of 4 chords; rounding to 0.1 mm: < 4e-3 m^2.
    let expected = 72.0 - 4.0 * fillet_loss(1.5, std::f64::consts::FRAC_PI_2, 4);
    let area = section_area(&hull);
    assert!((area - expected).abs() < 4e-3, "area {area} vs {expected}");
}

#[test]
fn semicircle_file_is_the_builtin() {
    let file = load("semicircle");
    let builtin = Hull::semicircle(1.0).unwrap();
    assert_eq!(file.fingerprint(), builtin.fingerprint());
    assert_eq!(file.dof_names(), builtin.dof_names());
    // Area of the half disc, pi/2, from a 200-panel midpoint sum along the exact arc.
    let mut area = 0.0;
    let n = 200;
    for i in 0..n {
        let s = (f64::from(i) + 0.5) / f64::from(n);
        let ds = builtin.contour_length() / f64::from(n);
        area -= builtin.point(s)[1] * builtin.normal(s)[1] * ds;
    }
    // Midpoint rule error ~ (pi/200)^2 / 24 relative.
    assert!(
        (area - std::f64::consts::FRAC_PI_2).abs() < 2e-5,
        "area {area}"
    );
}
