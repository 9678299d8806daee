//! Mutation fuzzing of every file parser the component and `fmu-pack` read (docs/STABILITY.md):
//! the generic XML reader, network files (read, realized, stepped, every value read finite or
//! refused), hull files (read, panelled), the options file, the excitation table, ship files,
//! PDStrip offset files and the restoring table. Each target starts from valid files and the
//! crafted cases of the hostile-input issue, mutates them (bit flips, XML-ish bytes, deleted,
//! repeated or spliced ranges, numbers replaced by extreme ones, truncation) and asserts that
//! nothing panics and that what is accepted is usable: a network realizes and steps, a hull
//! gives panels.
//!
//! Bounded: `HYDROFMU_FUZZ_CASES` cases per target (default 2000) and `HYDROFMU_FUZZ_SECONDS`
//! seconds per target (default 30), whichever ends first. A long run:
//!
//! ```sh
//! HYDROFMU_FUZZ_CASES=1000000 HYDROFMU_FUZZ_SECONDS=1200 \
//!     cargo test --release --test fuzz -- --nocapture --test-threads 1
//! ```
//!
//! A failing input is written to `target/fuzz-failures/<target>-<case>.txt`.
//!
//! Each target prints its counts (`fuzz NAME: N cases, M accepted`; `tests/run.sh` runs this
//! file with `--nocapture`) and asserts a minimum of executed and of accepted cases, set to
//! all 2000 default cases (each target runs them in 0.1 to 3 s of its 30 s budget in a debug
//! build on a 2-core machine; the slowest, ship files, took 10 s with six other builds
//! running, so the budget leaves room for a machine 10x slower than usual) and about three quarters of the measured accepted count
//! (both scaled down with `HYDROFMU_FUZZ_CASES`): a mutator that produces nothing usable, or
//! a parser that refuses everything, fails.

use hydrofmu::fmu::Resources;
use hydrofmu::hull::Hull;
use hydrofmu::hydrostatics::Table;
use hydrofmu::network::Network;
use hydrofmu::panels::{self, PanelParams};
use hydrofmu::ship::Ship;
use hydrofmu::waves::ExcitationTable;
use hydrofmu::{Model, ModelOptions};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

#[path = "../benches/common/mod.rs"]
#[allow(dead_code)]
mod common;

/// Deterministic numbers (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Most inputs kept for mutation (the seeds, then accepted mutants).
const CORPUS: usize = 256;

/// Largest accepted mutant kept for breeding: larger ones are tried once (their limits are
/// what they test) but would slow every later case.
const BREEDING_BYTES: usize = 32 * 1024;

/// Bytes that matter to the formats.
const BYTES: &[u8] = b"<>/=\"' \n\t&;#-+.eE0123456789,:xXn!?";

/// Numbers that break naive arithmetic.
const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1e308",
    "-1e308",
    "1e-320",
    "1e154",
    "1e250",
    "NaN",
    "inf",
    "-inf",
    "4294967296",
    "18446744073709551616",
    "9999999999",
    "-1",
    "1e-160",
    "3.0e+",
];

/// One mutated input from `seed` (and sometimes a piece of another corpus member).
fn mutate(rng: &mut Rng, seed: &[u8], corpus: &[Vec<u8>]) -> Vec<u8> {
    let mut out = seed.to_vec();
    let limit = 4 * seed.len() + 65_536;
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(out.len() + 1);
        match rng.below(8) {
            0 if !out.is_empty() => {
                let i = at.min(out.len() - 1);
                out[i] ^= 1 << rng.below(8);
            }
            1 if !out.is_empty() => {
                let i = at.min(out.len() - 1);
                out[i] = BYTES[rng.below(BYTES.len())];
            }
            2 => {
                let end = (at + 1 + rng.below(64)).min(out.len());
                out.drain(at.min(end)..end);
            }
            3 if out.len() < limit => {
                let end = (at + 1 + rng.below(256)).min(out.len());
                let piece = out[at.min(end)..end].to_vec();
                let most = if rng.below(8) == 0 { 1000 } else { 4 };
                let times = 1 + rng.below(most);
                let to = rng.below(out.len() + 1);
                for _ in 0..times {
                    out.splice(to..to, piece.iter().copied());
                    if out.len() > limit {
                        break;
                    }
                }
            }
            4 => {
                // A number: the digits around `at` become an extreme value.
                let is_num = |b: u8| b.is_ascii_digit() || b"+-.eE".contains(&b);
                let (mut lo, mut hi) = (at.min(out.len()), at.min(out.len()));
                while lo > 0 && is_num(out[lo - 1]) {
                    lo -= 1;
                }
                while hi < out.len() && is_num(out[hi]) {
                    hi += 1;
                }
                let value = NUMBERS[rng.below(NUMBERS.len())].as_bytes();
                out.splice(lo..hi, value.iter().copied());
            }
            5 if !corpus.is_empty() => {
                let other = &corpus[rng.below(corpus.len())];
                let from = rng.below(other.len());
                let end = (from + 1 + rng.below(512)).min(other.len());
                out.splice(at..at, other[from..end].iter().copied());
            }
            6 => out.truncate(at),
            _ => {
                let b = BYTES[rng.below(BYTES.len())];
                out.insert(at, b);
            }
        }
        out.truncate(limit);
    }
    out
}

/// The fewest cases a target must execute and accept at the default case count (module docs).
#[derive(Clone, Copy)]
struct Minimum {
    executed: u64,
    accepted: u64,
}

/// Runs `target` on mutations of `seeds` (and on the seeds themselves); a panic or an `Err`
/// (an accepted input that is not usable) fails the test, and so do fewer executed or
/// accepted cases than `minimum`. The first `valid` seeds are valid files and must be accepted.
fn fuzz(
    name: &str,
    seeds: &[String],
    valid: usize,
    minimum: Minimum,
    target: impl Fn(&str) -> Result<bool, String>,
) {
    let env = |key: &str, default: u64| {
        std::env::var(key)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let cases = env("HYDROFMU_FUZZ_CASES", 2000);
    let budget = Duration::from_secs(env("HYDROFMU_FUZZ_SECONDS", 30));
    let mut corpus: Vec<Vec<u8>> = seeds.iter().map(|s| s.as_bytes().to_vec()).collect();
    let mut rng = Rng(0x5EED ^ name.len() as u64);
    let start = Instant::now();
    let (mut done, mut accepted) = (0u64, 0u64);
    for case in 0..cases {
        if start.elapsed() > budget {
            break;
        }
        let bytes = match corpus.get(case as usize) {
            Some(seed) => seed.clone(),
            None => {
                let seed = rng.below(corpus.len());
                mutate(&mut rng, &corpus[seed], &corpus)
            }
        };
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let outcome = catch_unwind(AssertUnwindSafe(|| target(&text)));
        if (case as usize) < valid && !matches!(outcome, Ok(Ok(true))) {
            panic!("{name}: valid seed {case} was not accepted");
        }
        let failure = match outcome {
            Ok(Ok(ok)) => {
                accepted += u64::from(ok);
                // Accepted mutants breed further (a corpus of at most CORPUS inputs).
                if ok && case as usize >= seeds.len() && bytes.len() <= BREEDING_BYTES {
                    if corpus.len() < CORPUS {
                        corpus.push(bytes.clone());
                    } else {
                        let slot = seeds.len() + rng.below(CORPUS - seeds.len());
                        corpus[slot] = bytes.clone();
                    }
                }
                None
            }
            Ok(Err(why)) => Some(why),
            Err(_) => Some("panic".to_string()),
        };
        if let Some(why) = failure {
            let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fuzz-failures");
            let _ = std::fs::create_dir_all(&dir);
            let path = dir.join(format!("{name}-{case}.txt"));
            let _ = std::fs::write(&path, &bytes);
            panic!("{name}, case {case}: {why} (input: {})", path.display());
        }
        done += 1;
    }
    eprintln!(
        "fuzz {name}: {done} cases, {accepted} accepted, {:.1} s",
        start.elapsed().as_secs_f64()
    );
    // Fewer cases asked for: the minimums scale down in proportion.
    let executed = minimum.executed.min(cases);
    let accepted_at_least = minimum.accepted * executed / minimum.executed.max(1);
    assert!(
        done >= executed,
        "{name}: {done} cases executed, at least {executed} expected"
    );
    assert!(
        accepted >= accepted_at_least,
        "{name}: {accepted} cases accepted, at least {accepted_at_least} expected"
    );
}

/// All default cases executed, at least `accepted` accepted.
const fn all_cases_and(accepted: u64) -> Minimum {
    Minimum {
        executed: 2000,
        accepted,
    }
}

// Accepted counts measured at the default 2000 cases (a debug build, 0.1 to 3 s per target,
// every target reaching the case count before its time budget) in the comments.
const MIN_XML: Minimum = all_cases_and(470); // 623
const MIN_NETWORK: Minimum = all_cases_and(410); // 548
const MIN_HULL: Minimum = all_cases_and(430); // 573
const MIN_OPTIONS: Minimum = all_cases_and(530); // 707
const MIN_EXCITATION: Minimum = all_cases_and(60); // 84
const MIN_SHIP: Minimum = all_cases_and(125); // 167
const MIN_OFFSETS: Minimum = all_cases_and(60); // 83
const MIN_RESTORING: Minimum = all_cases_and(140); // 192
/// The three WAMIT files: radiation (65 accepted), excitation (38), hydrostatics (379).
const MIN_WAMIT: [Minimum; 3] = [all_cases_and(48), all_cases_and(28), all_cases_and(280)];
const MIN_WAMIT_DRIFT: Minimum = all_cases_and(28); // 38

fn read(path: &str) -> String {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(root.join(path)).unwrap()
}

/// `<a>` nested `levels` deep inside `<root>`.
fn nested(root: &str, inner: &str, levels: usize) -> String {
    format!(
        "<{root}>{}{}</{root}>",
        format!("<{inner}>").repeat(levels),
        format!("</{inner}>").repeat(levels)
    )
}

fn network_seeds() -> Vec<String> {
    let stage = r#"<stage mass="1" stiffness="1" damping="1"/>"#;
    let head = r#"<network format_version="1" form="coupled" rho="1025" g="9.81"><dof name="sway"/><added_mass_inf><row>1</row></added_mass_inf>"#;
    vec![
        read("examples/networks/seed_2dof.xml"),
        read("examples/networks/two-dof-sway-heave.xml"),
        read("examples/networks/semicircle_9dof.xml"),
        nested("network", "branch", 100),
        format!("{head}<branch><direction>1</direction>{}</branch></network>", stage.repeat(100)),
        format!(
            "{head}<branch><direction>1</direction><stage mass=\"1e154\" stiffness=\"1e250\" damping=\"1e-300\"/></branch></network>"
        ),
    ]
}

fn hull_seeds() -> Vec<String> {
    vec![
        read("examples/hulls/barge.xml"),
        read("examples/hulls/midship.xml"),
        read("examples/hulls/pontoon.xml"),
        read("examples/hulls/semicircle.xml"),
        // A floating section: mass properties and moorings.
        read("examples/hulls/pontoon.xml").replace(
            "</hull>",
            "<mass value=\"displaced\" x=\"0\" y=\"-0.2\" radius_of_gyration=\"0.3\">\
             <mooring dof=\"sway\" stiffness=\"1e3\" damping=\"5\"/></mass></hull>",
        ),
        nested("hull", "contour", 100),
        read("examples/hulls/barge.xml").replace("half_beam=\"", "half_beam=\"1e154"),
    ]
}

#[test]
fn fuzz_the_xml_reader() {
    let mut seeds = network_seeds();
    seeds.extend(hull_seeds());
    fuzz("xml", &seeds, 3, MIN_XML, |text| {
        Ok(hydrofmu::xml::parse(text).is_ok())
    });
}

#[test]
fn fuzz_network_files() {
    let options = ModelOptions {
        keep_inf_mass: false,
        guid: None,
    };
    fuzz("network", &network_seeds(), 3, MIN_NETWORK, |text| {
        let Ok(network) = Network::from_xml_str(text, "fuzz.xml") else {
            return Ok(false);
        };
        network
            .validate()
            .map_err(|e| format!("read but not valid: {e}"))?;
        if let Ok(mut model) = Model::new(&network, options.clone()) {
            use hydrofmu::fmu::variables::Quantity;
            let _ = model.set_value(Quantity::Velocity(0), 1.0);
            let _ = model.step(0.0, 0.01);
            // Every value read is finite, or the read fails.
            for q in (0..network.dof_count())
                .map(Quantity::Force)
                .chain([Quantity::Power, Quantity::Energy])
            {
                if let Ok(x) = model.value(q) {
                    if !x.is_finite() {
                        return Err(format!("{q:?} = {x} read without an error"));
                    }
                }
            }
        }
        Ok(true)
    });
}

#[test]
fn fuzz_hull_files() {
    fuzz("hull", &hull_seeds(), 5, MIN_HULL, |text| {
        let Ok(hull) = Hull::from_xml_str(text, "fuzz.xml") else {
            return Ok(false);
        };
        if let Some(mass) = hull.mass() {
            if let Ok(properties) = mass.properties(&hull, 1025.0) {
                if let Ok(statics) = hydrofmu::hydrostatics::stiffness(&hull) {
                    let _ =
                        hydrofmu::motion::Floating::new(&hull, &statics, &properties, 1025.0, 9.81);
                }
            }
        }
        let params = PanelParams {
            body_panels: 32,
            ..PanelParams::for_hull(&hull)
        };
        let _ = panels::discretize(&hull, &params);
        Ok(true)
    });
}

#[test]
fn fuzz_options_files() {
    let network = read("examples/networks/seed_2dof.xml");
    let seeds = vec![
        Resources::options_text(false),
        Resources::options_text(true),
        nested("hydrofmu_options", "x", 100),
    ];
    fuzz("options", &seeds, 2, MIN_OPTIONS, |text| {
        Ok(Resources::new(network.clone(), None, text.to_string()).is_ok())
    });
}

#[test]
fn fuzz_excitation_tables() {
    // A small table first (fast cases), then the synthetic 9-DOF one.
    let small = "# modes: sway heave\n# convention: exp(+i omega t)\n# R: 1 m\n\
                 # length exponents: 0 0\nkR,j,heading,re,im\n\
                 0.1,1,0,1.5,-0.2\n0.1,2,0,0.5,0.1\n1,1,0,0.3,-0.4\n1,2,0,0.2,0.05\n";
    // The synthetic 9-DOF table cut to its first 11 kR (198 rows): the format's every
    // feature at a tenth of the parsing time per case.
    let nine: String = common::synthetic_excitation_csv()
        .lines()
        .take(5 + 18 * 11)
        .map(|l| format!("{l}\n"))
        .collect();
    let seeds = vec![
        small.to_string(),
        nine.clone(),
        nine.replace("# R: 1 m", "# R: 1e308 m"),
    ];
    fuzz("excitation", &seeds, 2, MIN_EXCITATION, |text| {
        Ok(ExcitationTable::from_csv_str(text, "fuzz.csv").is_ok())
    });
}

#[test]
fn fuzz_ship_files() {
    let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ships");
    let small = "<ship name=\"s\"><station x=\"-5\" mass=\"1e4\" bending_stiffness_vertical=\"1e9\">\
                 <semicircle radius=\"1\"/></station><station x=\"0\" mass=\"1e4\" \
                 bending_stiffness_vertical=\"1e9\"><lewis breadth=\"2\" draft=\"1\" \
                 area_coefficient=\"0.9\"/></station><station x=\"5\" mass=\"1e4\" \
                 bending_stiffness_vertical=\"1e9\"/><rigid dofs=\"heave pitch\"/>\
                 <mode name=\"m\"><at w=\"1\" cb2=\"0.5\"/><at w=\"-1\"/><at x=\"5\" w=\"1\"/></mode>\
                 <girder_modes vertical=\"1\"/></ship>";
    let seeds = vec![
        small.to_string(),
        read("examples/ships/barge.xml"),
        nested("ship", "station", 100),
    ];
    fuzz("ship", &seeds, 2, MIN_SHIP, |text| {
        let Ok(ship) = Ship::from_xml_str(text, "fuzz.xml", &folder) else {
            return Ok(false);
        };
        // What was accepted is usable: every motion finite, the stations in order.
        for r in 0..ship.dofs().len() {
            for k in 0..ship.stations().len() {
                let m = ship.motion(r, k);
                if ![m.sway, m.heave, m.roll].iter().all(|v| v.is_finite()) {
                    return Err(format!("DOF {r} at station {k}: {m:?}"));
                }
            }
        }
        if ship.length().is_nan() || ship.length() <= 0.0 {
            return Err(format!("length {}", ship.length()));
        }
        Ok(true)
    });
}

#[test]
fn fuzz_pdstrip_offsets() {
    let seeds = vec![
        "3 T 5.0\n-10.0 3 0\n0.0 5.0 5.0 0.0 0.0 5.0\n0.0 3 0\n0 5 5\n0 0 5\n10.0D0 3 0\n\
         0.0 5.0 5.0 0.0 0.0 5.0\n"
            .to_string(),
        "2 F 2.0\n-20 5 0\n4 4 2 -4 -4\n2 0.5 0 0.5 2\n20 5 0\n4 4 2 -4 -4\n2 0.5 0 0.5 2\n"
            .to_string(),
    ];
    fuzz("offsets", &seeds, 2, MIN_OFFSETS, |text| {
        let Ok(ship) = Ship::from_offsets_str("fuzz", text, "fuzz.out", None) else {
            return Ok(false);
        };
        for hull in ship.sections() {
            let params = PanelParams {
                body_panels: 32,
                ..PanelParams::for_hull(hull)
            };
            let _ = panels::discretize(hull, &params);
        }
        Ok(true)
    });
}

#[test]
fn fuzz_restoring_tables() {
    let table = Table {
        modes: vec!["heave".into(), "pitch".into(), "vb1".into()],
        stiffness_per_rho_g: nalgebra::DMatrix::from_row_slice(
            3,
            3,
            &[1000.0, -5.0, 3.0, -5.0, 8.0e5, 1.0, 3.0, 1.0, 2.0e3],
        ),
    };
    let seeds = vec![table.to_csv("barge", "whole ship")];
    fuzz("restoring", &seeds, 1, MIN_RESTORING, |text| {
        let Ok(t) = Table::from_csv_str(text, "fuzz.csv") else {
            return Ok(false);
        };
        let n = t.modes.len();
        if t.stiffness_per_rho_g.shape() != (n, n)
            || !t.stiffness_per_rho_g.iter().all(|c| c.is_finite())
        {
            return Err("accepted a table of the wrong shape or with a non-finite entry".into());
        }
        Ok(true)
    });
}

/// The three WAMIT files, each mutated beside the other two intact: whatever is accepted goes
/// through the import's checks (spikes, A_inf, units) and comes out finite and consistent.
#[test]
fn fuzz_wamit_files() {
    use hydrofmu::database::import::{finish, ImportParams};
    use hydrofmu::database::wamit::{self, Source, WamitParams, WamitTexts};
    let files = [
        read("tests/data/wamit/sphere.1"),
        read("tests/data/wamit/sphere.3"),
        read("tests/data/wamit/sphere.hst"),
    ];
    for (which, name) in ["radiation", "excitation", "hydrostatics"]
        .iter()
        .enumerate()
    {
        let seeds = vec![files[which].clone()];
        fuzz(
            &format!("wamit-{name}"),
            &seeds,
            1,
            MIN_WAMIT[which],
            |text| {
                let mut texts = files.clone();
                texts[which] = text.to_string();
                let sources = WamitTexts {
                    radiation: Source {
                        name: "f.1",
                        text: &texts[0],
                    },
                    excitation: Some(Source {
                        name: "f.3",
                        text: &texts[1],
                    }),
                    hydrostatics: Some(Source {
                        name: "f.hst",
                        text: &texts[2],
                    }),
                };
                let Ok(imported) = wamit::read("f", sources, &WamitParams::default()) else {
                    return Ok(false);
                };
                let mut db = imported.database;
                if finish(&mut db, imported.added_mass_inf_given, &ImportParams::new()).is_err() {
                    return Ok(false);
                }
                let n = db.dof_names.len();
                let consistent = db.omega.len() == db.added_mass.len()
                    && db.excitation.len() == db.omega.len()
                    && db.added_mass.iter().all(|m| m.shape() == (n, n))
                    && db.omega.windows(2).all(|w| w[0] < w[1]);
                if !consistent || db.first_non_finite().is_some() {
                    return Err("accepted an inconsistent or non-finite database".into());
                }
                Ok(true)
            },
        );
    }
}

/// A WAMIT mean drift file (`.9`) beside the sphere's: whatever is accepted gives a drift on
/// the database's frequencies, of its DOFs and the file's headings, finite.
#[test]
fn fuzz_wamit_drift_files() {
    use hydrofmu::database::wamit::{self, Source, WamitParams, WamitTexts};
    let radiation = read("tests/data/wamit/sphere.1");
    let texts = WamitTexts {
        radiation: Source {
            name: "f.1",
            text: &radiation,
        },
        excitation: None,
        hydrostatics: None,
    };
    let imported = wamit::read("f", texts, &WamitParams::default()).unwrap();
    // The seed: every mode at every frequency, headings 0 and 90.
    let mut seed = String::from(" mean drift\n");
    for (k, omega) in imported.database.omega.iter().enumerate() {
        for beta in [0.0, 90.0] {
            for &mode in &imported.modes {
                let d = 0.1 * (k + mode) as f64 - 0.3;
                seed.push_str(&format!(
                    "{:.9E} {beta} {beta} {mode} {:.9E} {} {:.9E} 0.0\n",
                    2.0 * std::f64::consts::PI / omega,
                    d.abs(),
                    if d < 0.0 { 180 } else { 0 },
                    d
                ));
            }
        }
    }
    fuzz("wamit-drift", &[seed], 1, MIN_WAMIT_DRIFT, |text| {
        let mut database = imported.database.clone();
        let source = Source { name: "f.9", text };
        if wamit::read_drift(
            &mut database,
            &imported.modes,
            None,
            Some(source),
            &WamitParams::default(),
        )
        .is_err()
        {
            return Ok(false);
        }
        if database.drift.is_empty() {
            return Ok(false);
        }
        let (n, h) = (database.dof_names.len(), database.drift_headings.len());
        let consistent = database.drift.len() == database.omega.len()
            && database.drift.iter().all(|d| d.shape() == (n, h))
            && (1..=hydrofmu::database::MAX_HEADINGS).contains(&h);
        if !consistent || database.first_non_finite().is_some() {
            return Err("accepted an inconsistent or non-finite drift".into());
        }
        Ok(true)
    });
}
