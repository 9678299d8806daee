//! The identification on inputs nobody tuned it to: the default fit of every case, its states,
//! error, passivity and time (docs/IDENTIFICATION.md).
//!
//! ```sh
//! cargo run --release -p fmu-pack --example identification [CASE ...]
//! ```

use hydrofmu::database::import::{import, ImportParams};
use hydrofmu::hull::Hull;
use hydrofmu::identify::{self, FitParams, FrequencyResponse};
use hydrofmu::scene::Scene;
use std::path::Path;
use std::time::Instant;

struct Case {
    name: &'static str,
    data: FrequencyResponse,
    band: (f64, f64),
    noise: Option<nalgebra::DMatrix<f64>>,
}

fn section(name: &'static str, hull: Hull) -> Case {
    let built = Scene::new(hull).build().expect("scene");
    let sweep = built.sweep(&|_, _| {}).expect("sweep");
    let response = built.response(&sweep).expect("response");
    Case {
        name,
        data: response.fitted,
        band: built.band(),
        noise: None,
    }
}

fn database(name: &'static str, path: &str) -> Option<Case> {
    if !Path::new(path).exists() {
        eprintln!("{name}: {path} not found, skipped");
        return None;
    }
    let db = import(Path::new(path), &ImportParams::new()).expect("import");
    Some(Case {
        name,
        data: db.response(),
        band: (0.0, f64::INFINITY),
        noise: Some(db.reciprocity_gap.clone()),
    })
}

fn case(name: &str) -> Option<Case> {
    let root = env!("CARGO_MANIFEST_DIR");
    match name {
        "midship" => Some(section(
            "midship",
            Hull::from_file(Path::new(&format!("{root}/../examples/hulls/midship.xml"))).unwrap(),
        )),
        "barge" => Some(section(
            "barge",
            Hull::from_file(Path::new(&format!("{root}/../examples/hulls/barge.xml"))).unwrap(),
        )),
        "pontoon" => Some(section(
            "pontoon",
            Hull::from_file(Path::new(&format!("{root}/../examples/hulls/pontoon.xml"))).unwrap(),
        )),
        "semicircle" => Some(section("semicircle", Hull::semicircle(1.0).unwrap())),
        "circle15" => Some(section("circle15", Hull::circle(1.0, 1.5).unwrap())),
        "sphere7" => database("sphere7", &format!("{root}/../tests/data/wamit/sphere.1")),
        "sphere420" => database("sphere420", "/tmp/w/sphere420/sphere.1"),
        "capybox" => database("capybox", "/tmp/w/capybox/box.1"),
        other => {
            eprintln!("unknown case {other}");
            None
        }
    }
}

fn main() {
    let names: Vec<String> = std::env::args().skip(1).collect();
    let names = if names.is_empty() {
        [
            "midship",
            "barge",
            "sphere7",
            "circle15",
            "semicircle",
            "capybox",
            "sphere420",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    } else {
        names
    };
    if names.first().map(String::as_str) == Some("vf") {
        let case = case(&names[1]).unwrap();
        let pairs: usize = names[2].parse().unwrap();
        let real: usize = names[3].parse().unwrap();
        let lo = case
            .data
            .omega
            .iter()
            .copied()
            .filter(|w| *w >= case.band.0)
            .fold(f64::INFINITY, f64::min);
        let hi = case
            .data
            .omega
            .iter()
            .copied()
            .filter(|w| *w <= case.band.1)
            .fold(0.0, f64::max);
        let params = hydrofmu::identify::vector_fitting::VectorFitParams {
            complex_pairs: pairs,
            real_poles: real,
            band: (lo, hi),
            ..Default::default()
        };
        let start = Instant::now();
        let (fit, enf) =
            hydrofmu::identify::vector_fitting::passive_block_vector_fit(&case.data, &params)
                .unwrap();
        println!(
            "{:.2} s, error {:.4} %, states {}",
            start.elapsed().as_secs_f64(),
            100.0 * fit.max_error,
            fit.state_count()
        );
        for e in enf {
            println!("  {e:?}");
        }
        for p in &fit.poles {
            println!("  pole {p}");
        }
        return;
    }
    for name in &names {
        let Some(case) = case(name) else { continue };
        let params = FitParams {
            band: case.band,
            noise: case.noise.clone(),
            max_order: std::env::var("MAX_ORDER").map_or(12, |v| v.parse().unwrap()),
            ..FitParams::default()
        };
        let start = Instant::now();
        let result = identify::fit(&case.data, &params);
        let time = start.elapsed().as_secs_f64();
        match result {
            Ok(report) => {
                let check =
                    hydrofmu::passivity::check(&report.network.state_space().unwrap(), 1e-9);
                println!(
                    "{:<11} {} DOFs {} pts: {} states, {:.3} %, met {}, passive {}, {:.1} s",
                    case.name,
                    case.data.dof_count(),
                    report.points,
                    report.states,
                    100.0 * report.max_relative_error,
                    report.tolerance_met,
                    check.passive,
                    time
                );
                for note in &report.notes {
                    println!("    note: {note}");
                }
                if std::env::var("ENTRIES").is_ok() {
                    let n = case.data.dof_count();
                    for i in 0..n {
                        for j in i..n {
                            let scale = report.error_scale[(i, j)];
                            let noise = case.noise.as_ref().map_or(0.0, |m| m[(i, j)] / scale);
                            println!(
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
            Err(e) => println!("{:<11} failed after {time:.1} s: {e}", case.name),
        }
    }
}
