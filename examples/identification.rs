//! The identification on inputs nobody tuned it to: the default fit of each case, its states,
//! largest error, the exact passivity check and the fit's wall time, as the markdown table of
//! docs/IDENTIFICATION.md.
//!
//! ```sh
//! cargo run --release -p fmu-pack --example identification [CASE | FILE.1 | FILE.nc ...]
//! ```
//!
//! Cases: `midship`, `barge`, `pontoon` (examples/hulls, the scene defaults: all DOFs,
//! kR 0.05 .. 5), `semicircle`, `circle15` (the circle at H/R 1.5), `sphere7`
//! (tests/data/wamit/sphere.1); a section case followed by `@H` is swept in water of depth
//! H metres (`midship@30`, `semicircle@2`) and fitted as the scene fits it (slow poles allowed
//! below the band, docs/FINITE_DEPTH.md "The fit in finite depth"); any other argument is a
//! database file, fitted over all its frequencies with its reciprocity gap as the noise floor.
//! Without arguments: the built-in cases. Set `ENTRIES=1` to print every entry's error and
//! noise.

use hydrofmu::database::import::{import, ImportParams};
use hydrofmu::hull::Hull;
use hydrofmu::identify::{self, FitParams, FrequencyResponse};
use hydrofmu::scene::Scene;
use hydrofmu::units::WaterDepth;
use std::path::Path;
use std::time::Instant;

struct Case {
    name: String,
    data: FrequencyResponse,
    band: (f64, f64),
    noise: Option<nalgebra::DMatrix<f64>>,
    pole_range_below: f64,
}

fn section(name: &str, hull: Hull, depth: WaterDepth) -> Case {
    let mut scene = Scene::new(hull);
    scene.sweep.depth = depth;
    let built = scene.build().expect("scene");
    let sweep = built.sweep(&|_, _| {}).expect("sweep");
    let response = built.response(&sweep).expect("response");
    Case {
        name: name.to_string(),
        data: response.fitted,
        band: built.band(),
        noise: None,
        pole_range_below: identify::pole_range_below(depth, true),
    }
}

fn database(name: &str, path: &Path) -> Result<Case, String> {
    let db = import(path, &ImportParams::new()).map_err(|e| e.to_string())?;
    Ok(Case {
        name: name.to_string(),
        data: db.response(),
        band: (0.0, f64::INFINITY),
        noise: Some(db.noise.clone()),
        pole_range_below: identify::POLE_RANGE,
    })
}

fn case(name: &str) -> Result<Case, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let hull = |file: &str| {
        Hull::from_file(&root.join("examples/hulls").join(file)).map_err(|e| e.to_string())
    };
    let (base, depth) = match name.split_once('@') {
        Some((base, metres)) => {
            let metres: f64 = metres
                .parse()
                .map_err(|_| format!("{name}: the water depth after @ is not a number"))?;
            (base, WaterDepth::new(metres).map_err(|e| e.to_string())?)
        }
        None => (name, WaterDepth::Infinite),
    };
    Ok(match base {
        "midship" | "barge" | "pontoon" => section(name, hull(&format!("{base}.xml"))?, depth),
        "semicircle" => section(
            name,
            Hull::semicircle(1.0).map_err(|e| e.to_string())?,
            depth,
        ),
        "circle15" => section(
            name,
            Hull::circle(1.0, 1.5).map_err(|e| e.to_string())?,
            depth,
        ),
        "sphere7" => database(name, &root.join("tests/data/wamit/sphere.1"))?,
        file => database(file, Path::new(file))?,
    })
}

fn main() {
    let mut names: Vec<String> = std::env::args().skip(1).collect();
    if names.is_empty() {
        names = [
            "midship",
            "barge",
            "pontoon",
            "sphere7",
            "circle15",
            "semicircle",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
    }
    println!("| input | DOFs | points | states | largest error | tolerance | passive | fit time |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut all_notes = Vec::new();
    for name in &names {
        let case = match case(name) {
            Ok(case) => case,
            Err(e) => {
                eprintln!("{name}: {e}");
                continue;
            }
        };
        let params = FitParams {
            band: case.band,
            noise: case.noise.clone(),
            pole_range_below: case.pole_range_below,
            ..FitParams::default()
        };
        let start = Instant::now();
        let result = identify::fit(&case.data, &params);
        let time = start.elapsed().as_secs_f64();
        let report = match result {
            Ok(report) => report,
            Err(e) => {
                println!("| {} | failed after {time:.1} s: {e} |", case.name);
                continue;
            }
        };
        let check = hydrofmu::passivity::check(&report.network.state_space().unwrap(), 1e-9);
        println!(
            "| {} | {} | {} | {} | {:.3} % | {:.3} %{} | {} | {:.1} s |",
            case.name,
            case.data.dof_count(),
            report.points,
            report.states,
            100.0 * report.max_relative_error,
            100.0 * report.tolerance,
            if report.tolerance_met {
                ""
            } else {
                " (NOT met)"
            },
            if check.passive { "yes" } else { "NO" },
            time
        );
        for note in &report.notes {
            all_notes.push(format!("- {}: {note}", case.name));
        }
        if std::env::var("ENTRIES").is_ok() {
            let n = case.data.dof_count();
            for i in 0..n {
                for j in i..n {
                    let scale = report.error_scale[(i, j)];
                    let noise = case.noise.as_ref().map_or(0.0, |m| m[(i, j)] / scale);
                    eprintln!(
                        "    {:>8} {:>8} error {:.3} % noise {:.3} %",
                        case.data.dof_names[i],
                        case.data.dof_names[j],
                        100.0 * report.max_error[(i, j)] / scale,
                        100.0 * noise
                    );
                }
            }
        }
    }
    if !all_notes.is_empty() {
        println!("\nNotes of the fits:\n");
        for note in all_notes {
            println!("{note}");
        }
    }
}
