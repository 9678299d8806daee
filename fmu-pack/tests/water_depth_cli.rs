//! `fmu-pack sweep --water-depth`: finite depth for sections, its table line, and clear
//! errors for a bad depth and a hull on the bottom; the drift table in finite depth.

mod common;
use common::fmu_pack;

fn sweep(extra: &[&str]) -> (bool, String, String) {
    let mut args = vec![
        "sweep",
        "semicircle",
        "--panels",
        "16",
        "--levels",
        "1",
        "--kr",
        "0.5:1:2",
        "--dofs",
        "sway,heave",
        "-o",
        "-",
    ];
    args.extend_from_slice(extra);
    fmu_pack(&args)
}

#[test]
fn the_table_carries_the_water_depth() {
    let (ok, csv, err) = sweep(&["--water-depth", "3"]);
    assert!(ok, "{err}");
    assert!(csv.lines().any(|l| l == "# depth: 3"), "{csv}");
    let (ok, csv, err) = sweep(&["--water-depth", "inf"]);
    assert!(ok, "{err}");
    assert!(csv.lines().any(|l| l == "# depth: inf"), "{csv}");
}

#[test]
fn bad_depths_are_refused_by_name() {
    for bad in ["0", "-2", "nan"] {
        let (ok, _, err) = sweep(&["--water-depth", bad]);
        assert!(!ok);
        assert!(
            err.contains("--water-depth") && err.contains("finite and > 0"),
            "{bad}: {err}"
        );
    }
    let (ok, _, err) = sweep(&["--water-depth", "0.9"]);
    assert!(!ok);
    assert!(err.contains("bottom") && err.contains("keel"), "{err}");
}

#[test]
fn the_drift_table_carries_the_water_depth() {
    let dir = common::folder("water-depth-drift");
    let path = dir.join("drift.csv");
    let (ok, _, err) = sweep(&["--water-depth", "3", "--drift", path.to_str().unwrap()]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.lines().any(|l| l == "# depth: 3"), "{text}");
    // kR 0.5 and 1 for sway and heave, headings 0 and 180: every value finite.
    let rows: Vec<f64> = text
        .lines()
        .skip_while(|l| *l != "kR,j,heading,value")
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(rows.len(), 8, "{text}");
    assert!(rows.iter().all(|v| v.is_finite()), "{text}");
}
