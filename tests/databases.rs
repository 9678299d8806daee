//! Imported WAMIT databases: real WAMIT v7.2 output (the WEC-Sim floating hemisphere,
//! tests/data/wamit/README.md) parses to known values, and hostile or inconsistent files are
//! refused with the file, line and field, or reported.
//!
//! SI values at rho = 1000 kg/m^3, g = 9.81 m/s^2, ULEN = 1 m, the run's own. The file's
//! numbers have 7 digits: parsed values are compared to 1e-6 relative; the closed forms of the
//! hemisphere (R = 5 m) to WAMIT's discretization error (2500 panels), measured 3e-4..1.3e-3.

use hydrofmu::database::import::{self, ImportParams};
use hydrofmu::database::wamit::{self, Source, WamitParams, WamitTexts};
use hydrofmu::database::Database;
use num_complex::Complex64;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

const RHO: f64 = 1000.0;
const G: f64 = 9.81;
const RADIUS: f64 = 5.0;
const SURGE: usize = 0;
const HEAVE: usize = 2;
const ROLL: usize = 3;
const PITCH: usize = 4;

fn data(name: &str) -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/wamit")
            .join(name),
    )
    .unwrap()
}

fn params() -> ImportParams {
    let mut p = ImportParams::new();
    p.wamit = WamitParams {
        rho: RHO,
        g: G,
        ..WamitParams::default()
    };
    p
}

/// A directory with the three files, `edit`ed, written as `sphere.*`.
fn files(tag: &str, edit: impl Fn(&str, String) -> Option<String>) -> PathBuf {
    // One folder per call: the tests run in parallel threads and several read the plain files.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!(
        "hydrofmu-databases-{tag}-{}-{call}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for ext in ["1", "3", "hst"] {
        let name = format!("sphere.{ext}");
        if let Some(text) = edit(ext, data(&name)) {
            std::fs::write(dir.join(&name), text).unwrap();
        }
    }
    dir.join("sphere.1")
}

fn sphere() -> Database {
    import::import(&files("plain", |_, t| Some(t)), &params()).unwrap()
}

fn close(a: f64, b: f64, relative: f64) -> bool {
    (a - b).abs() <= relative * b.abs()
}

#[test]
fn the_hemisphere_parses_to_the_files_values_in_si() {
    let db = sphere();
    // The source names the file, not the folder it was read from (archives carry it).
    assert_eq!(db.source, "imported from WAMIT files (sphere.1)");
    let dir = std::env::temp_dir().display().to_string();
    let mut table = Vec::new();
    db.write_excitation_table(&mut table).unwrap();
    let written = String::from_utf8(table).unwrap();
    assert!(
        written.contains("(sphere.1)") && !written.contains(&dir),
        "{written}"
    );
    assert_eq!(
        db.dof_names,
        ["surge", "sway", "heave", "roll", "pitch", "yaw"]
    );
    // Ascending, although the file lists the periods descending.
    assert_eq!(db.omega.len(), 7);
    assert!(db.omega.windows(2).all(|w| w[0] < w[1]));
    let one = db
        .omega
        .iter()
        .position(|w| (w - 1.0).abs() < 1e-5)
        .unwrap();
    assert!(close(db.omega[one], 2.0 * PI / 6.283188, 1e-12));
    // `0 3 3 1.308590E+02`: A_inf, rho L^3.
    assert!(close(db.added_mass_inf[(HEAVE, HEAVE)], 130_859.0, 1e-6));
    // `6.283188E+00 3 3 1.521805E+02 8.834739E+01`: a = rho A, b = rho omega B.
    let a = db.added_mass[one][(HEAVE, HEAVE)];
    assert!(close(a.re, 152_180.5, 1e-6));
    assert!(close(
        -a.im * db.omega[one],
        88_347.39 * db.omega[one],
        1e-6
    ));
    // Rotations: rho L^5, the file's `0 5 5` (A55 at omega = inf).
    let a55: f64 = data("sphere.1")
        .lines()
        .find(|l| l.split_whitespace().take(3).collect::<Vec<_>>() == ["0.000000E+00", "5", "5"])
        .and_then(|l| l.split_whitespace().nth(3))
        .unwrap()
        .parse()
        .unwrap();
    assert!(close(db.added_mass_inf[(PITCH, PITCH)], a55 * RHO, 1e-6));
    // `.hst`: C33 = 78.48768 rho g L^2, C44 = 522.9197 rho g L^4.
    assert!(close(
        db.stiffness_hydrostatic[(HEAVE, HEAVE)],
        78.48768 * RHO * G,
        1e-6
    ));
    assert!(close(
        db.stiffness_hydrostatic[(ROLL, ROLL)],
        522.9197 * RHO * G,
        1e-6
    ));
    // `.3`, T = 6.283188, beta 0, mode 3: Re 40.57642, Im 9.367009 (rho g L^2 per metre).
    assert_eq!(db.headings, [0.0]);
    let x3 = db.excitation[one][(HEAVE, 0)];
    assert!(close(x3.re, 40.57642 * RHO * G, 1e-6) && close(x3.im, 9.367009 * RHO * G, 1e-6));
    // The long-wave limit is the heave column of the restoring.
    let long = db.excitation_long_wave.as_ref().unwrap();
    assert!(close(
        long[HEAVE],
        db.stiffness_hydrostatic[(HEAVE, HEAVE)],
        1e-12
    ));
    assert_eq!(db.reference_length, 1.0);
    assert!(db.failures.is_empty(), "{:?}", db.failures);
}

#[test]
fn the_hemisphere_meets_its_closed_forms() {
    let db = sphere();
    let volume = 2.0 * PI * RADIUS.powi(3) / 3.0;
    // Heave A_inf of a floating hemisphere: phi = 0 on the surface, the odd image: half a
    // sphere's 1/2 rho V_sphere = rho V / 2. WAMIT: -3.1e-4.
    assert!(close(
        db.added_mass_inf[(HEAVE, HEAVE)],
        RHO * volume / 2.0,
        1e-3
    ));
    // C33 = rho g pi R^2 (-6.6e-4); C44 = rho g (pi R^4 / 4 + V (z_B - z_G)), z_B - z_G =
    // 0.125 m about the body origin 2 m below the centre (-1.3e-3).
    let c33 = RHO * G * PI * RADIUS * RADIUS;
    assert!(close(db.stiffness_hydrostatic[(HEAVE, HEAVE)], c33, 1e-3));
    let c44 = RHO * G * (PI * RADIUS.powi(4) / 4.0 + volume * 0.125);
    assert!(close(db.stiffness_hydrostatic[(ROLL, ROLL)], c44, 2e-3));
    // Pitch about a point 2 m below the centre moves the sphere 2 m in surge: X5 = 2 X1 in
    // modulus and phase (WAMIT: 3e-4).
    for x in &db.excitation {
        let ratio = x[(PITCH, 0)] / x[(SURGE, 0)];
        assert!((ratio - Complex64::new(2.0, 0.0)).norm() < 1e-3, "{ratio}");
    }
    // Long waves towards +x in exp(+i omega t): heave in phase with the crest at the origin,
    // surge 90 deg ahead (the fluid's acceleration).
    let first = &db.excitation[0];
    assert!(first[(HEAVE, 0)].arg().to_degrees().abs() < 1.0);
    assert!((first[(SURGE, 0)].arg().to_degrees() - 90.0).abs() < 1.0);
}

#[test]
fn damping_and_exciting_force_obey_the_haskind_relation() {
    // Axisymmetric body, water depth 50 m: B33 = k |X3|^2 / (4 rho g C_g) with
    // omega^2 = g k tanh(k h), C_g = (omega / 2k)(1 + 2kh / sinh 2kh). Checks that .1 and .3
    // pair by frequency and scale alike: measured within 1e-3 at every period.
    let db = sphere();
    let depth = 50.0;
    for (k_index, omega) in db.omega.iter().enumerate() {
        let mut k = omega * omega / G;
        for _ in 0..100 {
            k = omega * omega / (G * (k * depth).tanh());
        }
        let group = omega / (2.0 * k) * (1.0 + 2.0 * k * depth / (2.0 * k * depth).sinh());
        let x3 = db.excitation[k_index][(HEAVE, 0)].norm();
        let haskind = k * x3 * x3 / (4.0 * RHO * G * group);
        let b33 = -db.added_mass[k_index][(HEAVE, HEAVE)].im * omega;
        assert!(
            close(b33, haskind, 2e-3),
            "omega {omega}: {b33} vs {haskind}"
        );
    }
}

#[test]
fn headers_d_exponents_tabs_and_missing_symmetry_entries_are_read_alike() {
    let plain = sphere();
    // No header, Fortran D exponents, tabs.
    let recast = files("recast", |_, text| {
        Some(
            text.lines()
                .skip(1)
                .map(|l| {
                    l.replace('E', "D")
                        .split_whitespace()
                        .collect::<Vec<_>>()
                        .join("\t")
                })
                .collect::<Vec<_>>()
                .join("\n"),
        )
    });
    let db = import::import(&recast, &params()).unwrap();
    assert_eq!(db.added_mass, plain.added_mass);
    assert_eq!(db.excitation, plain.excitation);
    // The (1,2) and (2,1) pairs left out at every frequency (a symmetry plane): zero.
    let sparse = files("sparse", |ext, text| {
        Some(if ext == "1" {
            text.lines()
                .filter(|l| {
                    let f: Vec<&str> = l.split_whitespace().collect();
                    !(f.len() >= 4
                        && ((f[1] == "1" && f[2] == "2") || (f[1] == "2" && f[2] == "1")))
                })
                .collect::<Vec<_>>()
                .join("\n")
        } else {
            text
        })
    });
    let db = import::import(&sparse, &params()).unwrap();
    assert_eq!(db.added_mass[3][(0, 1)], Complex64::new(0.0, 0.0));
    assert_eq!(
        db.added_mass[3][(HEAVE, HEAVE)],
        plain.added_mass[3][(HEAVE, HEAVE)]
    );
}

/// The error of reading the sphere with `.1` edited by `edit` (lines, header kept).
fn radiation_error(edit: impl Fn(Vec<String>) -> Vec<String>) -> String {
    let lines: Vec<String> = data("sphere.1").lines().map(str::to_string).collect();
    let text = edit(lines).join("\n");
    let texts = WamitTexts {
        radiation: Source {
            name: "sphere.1",
            text: &text,
        },
        excitation: None,
        hydrostatics: None,
    };
    wamit::read("sphere", texts, &WamitParams::default())
        .map(|_| "accepted".to_string())
        .unwrap_or_else(|e| e.to_string())
}

#[test]
fn malformed_radiation_files_are_refused_with_file_line_and_field() {
    // A truncated file: the last row cut short.
    let e = radiation_error(|mut l| {
        let last = l.pop().unwrap();
        l.push(
            last.split_whitespace()
                .take(3)
                .collect::<Vec<_>>()
                .join(" "),
        );
        l
    });
    assert!(
        e.starts_with("sphere.1:325:") && e.contains("3 fields"),
        "{e}"
    );
    // A truncated file: the last row missing.
    let e = radiation_error(|mut l| {
        l.pop();
        l
    });
    assert!(
        e.contains("truncated or incomplete") && e.contains("(6,6) missing"),
        "{e}"
    );
    // A NaN row.
    let e = radiation_error(|mut l| {
        l[195] = l[195].replace("1.521805E+02", "NaN");
        l
    });
    assert!(
        e.starts_with("sphere.1:196:") && e.contains("field A (column 4)"),
        "{e}"
    );
    // An entry written twice.
    let e = radiation_error(|mut l| {
        let copy = l[195].clone();
        l.push(copy);
        l
    });
    assert!(e.contains("written twice (lines 196 and 326)"), "{e}");
    // A frequency written twice with a rounding difference.
    let e = radiation_error(|mut l| {
        let block: Vec<String> = l
            .iter()
            .filter(|x| x.trim_start().starts_with("6.283188E+00"))
            .map(|x| x.replace("6.283188E+00", "6.283189E+00"))
            .collect();
        l.extend(block);
        l
    });
    assert!(e.contains("the same to 1e-6"), "{e}");
    // A finite period without B.
    let e = radiation_error(|mut l| {
        l[195] = l[195]
            .split_whitespace()
            .take(4)
            .collect::<Vec<_>>()
            .join(" ");
        l
    });
    assert!(
        e.starts_with("sphere.1:196:") && e.contains("needs A and B"),
        "{e}"
    );
    // A negative period other than -1, a mode index 0.
    let e = radiation_error(|mut l| {
        l[195] = l[195].replace("6.283188E+00", "-2.0E+00");
        l
    });
    assert!(e.contains("field PER (column 1)"), "{e}");
    let e = radiation_error(|mut l| {
        l[195] = l[195].replacen("     3     3", "     0     3", 1);
        l
    });
    assert!(e.contains("field I (column 2)"), "{e}");
    // Only limits.
    let e = radiation_error(|l| l.into_iter().take(73).collect());
    assert!(e.contains("no row at a finite frequency"), "{e}");
    // Generalized modes need ULEN = 1.
    let lines: Vec<String> = data("sphere.1")
        .lines()
        .map(|l| l.replacen("     6     6", "     7     7", 1))
        .collect();
    let text = lines.join("\n");
    let texts = WamitTexts {
        radiation: Source {
            name: "g.1",
            text: &text,
        },
        excitation: None,
        hydrostatics: None,
    };
    let params = WamitParams {
        length_scale: 2.0,
        ..WamitParams::default()
    };
    let e = wamit::read("g", texts, &params).unwrap_err().to_string();
    assert!(e.contains("ULEN = 1"), "{e}");
    let ok = wamit::read("g", texts, &WamitParams::default()).unwrap();
    assert!(ok.database.dof_names.contains(&"mode7".to_string()));
}

#[test]
fn inconsistent_companions_are_refused_or_reported() {
    // A .3 row whose modulus/phase disagree with Re/Im (the sign of Im flipped by hand).
    let path = files("conjugated-row", |ext, text| {
        Some(if ext == "3" {
            text.replace("4.057642E+01  9.367009E+00", "4.057642E+01 -9.367009E+00")
        } else {
            text
        })
    });
    let e = import::import(&path, &params()).unwrap_err().to_string();
    assert!(e.contains("sphere.3:22:") && e.contains("disagree"), "{e}");
    // No .3 and no .hst: a warning each, radiation only.
    let path = files("alone", |ext, text| (ext == "1").then_some(text));
    let db = import::import(&path, &params()).unwrap();
    assert!(db.excitation.is_empty());
    assert!(db
        .warnings
        .iter()
        .any(|w| w.contains("sphere.3") && w.contains("wave.kind")));
    assert!(db.warnings.iter().any(|w| w.contains("sphere.hst")));
    // A .hst of another length scale (x 100): the long-wave heave force no longer meets C33.
    let path = files("mixed", |ext, text| {
        Some(if ext == "hst" {
            text.replace("7.848768E+01", "7.848768E+03")
        } else {
            text
        })
    });
    let db = import::import(&path, &params()).unwrap();
    assert!(
        db.warnings
            .iter()
            .any(|w| w.contains("different runs or length scales")),
        "{:?}",
        db.warnings
    );
    assert!(sphere().warnings.is_empty(), "{:?}", sphere().warnings);
    // A .3 holding other periods than the .1: nothing pairs.
    let path = files("other-run", |ext, text| {
        Some(if ext == "3" {
            text.replace("E+01  0.000000E+00", "E+02  0.000000E+00")
                .replace("E+00  0.000000E+00", "E+01  0.000000E+00")
        } else {
            text
        })
    });
    let e = import::import(&path, &params()).unwrap_err().to_string();
    assert!(e.contains("different runs"), "{e}");
}

/// The sphere with the heave damping at omega = 1.2 rad/s (T = 5.235991 s) multiplied by
/// `factor`.
fn heave_damping_at_1_2(tag: &str, factor: f64) -> PathBuf {
    files(tag, |ext, text| {
        Some(if ext == "1" {
            text.lines()
                .map(|l| {
                    let f: Vec<&str> = l.split_whitespace().collect();
                    if f.len() == 5 && f[0] == "5.235991E+00" && f[1] == "3" && f[2] == "3" {
                        let b: f64 = f[4].parse::<f64>().unwrap() * factor;
                        format!("{} {} {} {} {b:E}", f[0], f[1], f[2], f[3])
                    } else {
                        l.to_string()
                    }
                })
                .collect::<Vec<_>>()
                .join("\n")
        } else {
            text
        })
    })
}

#[test]
fn negative_damping_is_kept_out_and_reported() {
    // An irregular frequency's symptom that needs no neighbours: B33 < 0 at 1.2 rad/s.
    let path = heave_damping_at_1_2("negative", -1.0);
    let db = import::import(&path, &params()).unwrap();
    assert_eq!(db.omega.len(), 6);
    assert_eq!(db.excitation.len(), 6);
    assert_eq!(db.failures.len(), 1, "{:?}", db.failures);
    assert!((db.failures[0].0 - 1.2).abs() < 1e-5);
    assert!(db.failures[0].1.contains("irregular-frequency spike"));
    assert!(db.failures[0].1.contains("negative damping"));
    // Asked not to search, every frequency stays.
    let keep = ImportParams {
        spikes: None,
        ..params()
    };
    assert_eq!(import::import(&path, &keep).unwrap().omega.len(), 7);
}

#[test]
fn on_a_grid_too_coarse_to_resolve_the_curve_no_jump_is_called_a_spike() {
    // The hemisphere's 7 frequencies are up to 0.8 rad/s apart: its own curves deviate from
    // their neighbours' polynomials as much as a 60 % jump would, so the outlier test (which
    // asks for 8 times the median deviation) removes nothing; the Capytaine test shows a real
    // irregular frequency found on a 0.1 rad/s grid.
    let db = import::import(&heave_damping_at_1_2("coarse", 1.6), &params()).unwrap();
    assert_eq!(db.omega.len(), 7);
    assert!(sphere().failures.is_empty());
}

#[test]
fn a_missing_a_inf_is_estimated_and_said_so() {
    let path = files("no-limits", |ext, text| {
        Some(if ext == "1" {
            text.lines()
                .filter(|l| !l.trim_start().starts_with("0.000000E+00"))
                .collect::<Vec<_>>()
                .join("\n")
        } else {
            text
        })
    });
    let db = import::import(&path, &params()).unwrap();
    let note = db
        .notes
        .iter()
        .find(|n| n.contains("Kramers-Kronig"))
        .expect("a note");
    assert!(note.contains("spread"), "{note}");
    let given = sphere().added_mass_inf;
    // Seven frequencies up to 2.4 rad/s (kR = 2.9): the heave estimate is 0.15 % below the
    // file's own value (measured), within the 3.2 % the note states; 1 % asserted.
    let estimate = db.added_mass_inf[(HEAVE, HEAVE)];
    let truth = given[(HEAVE, HEAVE)];
    assert!(close(estimate, truth, 0.01), "{estimate} vs {truth}");
    assert!(note.contains("heave 3.2 %"), "{note}");
}

/// The sphere's `.1` and `.3` with the first column in rad/s (WAMIT's IPEROUT = 2; the limits
/// as HAMS writes them: 0 is omega = 0, -1 is omega = inf), and a `.cfg` saying so.
fn in_rad_per_second(tag: &str, cfg: &str) -> PathBuf {
    let path = files(tag, |ext, text| {
        Some(if ext == "hst" {
            text
        } else {
            text.lines()
                .map(|l| {
                    let mut f: Vec<String> = l.split_whitespace().map(str::to_string).collect();
                    match f.first().and_then(|x| x.parse::<f64>().ok()) {
                        Some(per) => {
                            f[0] = match per {
                                -1.0 => "0".to_string(),
                                0.0 => "-1".to_string(),
                                t => format!("{:.9E}", 2.0 * PI / t),
                            };
                            f.join(" ")
                        }
                        None => l.to_string(),
                    }
                })
                .collect::<Vec<_>>()
                .join("\n")
        })
    });
    std::fs::write(path.with_extension("cfg"), cfg).unwrap();
    path
}

#[test]
fn the_cfg_beside_the_files_says_what_the_first_column_holds() {
    let plain = sphere();
    let path = in_rad_per_second("cfg", "IPERIN=2\nIPEROUT=2   ! output in rad/s\nNUMHDR=1\n");
    let db = import::import(&path, &params()).unwrap();
    assert!(db
        .notes
        .iter()
        .any(|n| n.contains("sphere.cfg") && n.contains("rad/s")));
    for (a, b) in db.omega.iter().zip(&plain.omega) {
        assert!(close(*a, *b, 1e-9));
    }
    // The values are the same (the periods' 7 digits make the damping's omega differ by 1e-7).
    for (a, b) in db.added_mass.iter().zip(&plain.added_mass) {
        assert!((a - b).norm() <= 1e-6 * b.norm());
    }
    assert_eq!(db.added_mass_inf, plain.added_mass_inf);
    // Without the cfg's word the rad/s column reads as periods: a different database.
    let blind = ImportParams {
        read_cfg: false,
        ..params()
    };
    let wrong = import::import(&path, &blind).unwrap();
    assert!(!close(wrong.omega[0], plain.omega[0], 1e-3));
    // A wavenumber column is refused, naming the cfg's line.
    let path = in_rad_per_second("cfg-kl", "ILOG=1\nIPEROUT=3\n");
    let e = import::import(&path, &params()).unwrap_err().to_string();
    assert!(
        e.contains("sphere.cfg:2:") && e.contains("wavenumber"),
        "{e}"
    );
}

/// `database` written as WAMIT files and read back (ULEN = 1, its rho and g, no checks).
fn round_trip(database: &Database) -> Database {
    let files = wamit::write(database);
    let texts = WamitTexts {
        radiation: Source {
            name: "rt.1",
            text: &files.radiation,
        },
        excitation: files
            .excitation
            .as_deref()
            .map(|text| Source { name: "rt.3", text }),
        hydrostatics: Some(Source {
            name: "rt.hst",
            text: &files.hydrostatics,
        }),
    };
    let params = WamitParams {
        rho: database.rho,
        g: database.g,
        ..WamitParams::default()
    };
    wamit::read(&database.name, texts, &params)
        .unwrap()
        .database
}

/// Largest difference of two complex tables over the largest entry of the first.
fn relative_gap(a: &[nalgebra::DMatrix<Complex64>], b: &[nalgebra::DMatrix<Complex64>]) -> f64 {
    let scale = a
        .iter()
        .flat_map(|m| m.iter())
        .map(|z| z.norm())
        .fold(0.0, f64::max);
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| (x - y).iter().map(|z| z.norm()).collect::<Vec<_>>())
        .fold(0.0, f64::max)
        / scale
}

#[test]
fn a_database_written_as_wamit_files_reads_back() {
    // The hemisphere: every table back to the 10 digits written.
    let db = sphere();
    let back = round_trip(&db);
    assert_eq!(back.dof_names, db.dof_names);
    assert_eq!(back.omega.len(), db.omega.len());
    for (a, b) in back.omega.iter().zip(&db.omega) {
        assert!(close(*a, *b, 1e-9));
    }
    assert!(relative_gap(&db.added_mass, &back.added_mass) < 1e-9);
    assert!(relative_gap(&db.excitation, &back.excitation) < 1e-9);
    assert!((&db.added_mass_inf - &back.added_mass_inf).amax() < 1e-9 * db.added_mass_inf.amax());
    assert!(
        (&db.stiffness_hydrostatic - &back.stiffness_hydrostatic).amax()
            < 1e-9 * db.stiffness_hydrostatic.amax()
    );
    assert_eq!(back.headings, db.headings);
}

#[test]
fn a_ships_girder_mode_keeps_its_name_through_wamit_files() {
    use hydrofmu::ship::{strip, Ship, ShipSweepParams};
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ships/flexible_barge.xml");
    let ship = Ship::from_file(&path).unwrap();
    let mut params = ShipSweepParams::for_ship(&ship);
    params.omega = vec![0.5, 1.0, 1.5];
    params.headings = vec![180.0, 90.0];
    params.panels.body_panels = 32;
    params.panels_with_corners.body_panels = 32;
    params.extrapolation_levels = 1;
    params.levels_with_corners = 1;
    let db = strip::run(&ship, &params, &|_, _| {}).unwrap();
    let back = round_trip(&db);
    // Rigid DOFs keep their WAMIT index and name; the girder modes are 7, 8, ... by name.
    assert_eq!(back.dof_names, db.dof_names);
    assert!(db.dof_names.iter().any(|d| d == "vb1"));
    assert_eq!(
        wamit::mode_indices(&db.dof_names)[db.dof_names.iter().position(|d| d == "vb1").unwrap()],
        7 + db
            .dof_names
            .iter()
            .filter(|d| !wamit::RIGID_MODES.contains(&d.as_str()))
            .position(|d| d == "vb1")
            .unwrap()
    );
    assert!(relative_gap(&db.added_mass, &back.added_mass) < 1e-9);
    // Headings come back ascending; each heading's forces to the digits written.
    assert_eq!(back.headings, [90.0, 180.0]);
    let h = |d: &Database, heading: f64| d.headings.iter().position(|x| *x == heading).unwrap();
    for heading in [90.0, 180.0] {
        for k in 0..db.omega.len() {
            let largest = db.excitation[k]
                .iter()
                .map(|z| z.norm())
                .fold(0.0, f64::max);
            for j in 0..db.dof_names.len() {
                let a = db.excitation[k][(j, h(&db, heading))];
                let b = back.excitation[k][(j, h(&back, heading))];
                assert!((a - b).norm() <= 1e-9 * largest, "{heading} {k} {j}");
            }
        }
    }
}

#[test]
fn a_header_cannot_make_a_generalized_mode_rigid() {
    // A header naming generalized mode 7 'heave' keeps it generalized ('mode7'), with a note:
    // downstream, DOF names decide what is rigid.
    use hydrofmu::ship::{strip, Ship, ShipSweepParams};
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ships/flexible_barge.xml");
    let ship = Ship::from_file(&path).unwrap();
    let mut params = ShipSweepParams::for_ship(&ship);
    params.omega = vec![0.5, 1.0];
    params.headings = vec![180.0];
    params.panels.body_panels = 16;
    params.panels_with_corners.body_panels = 16;
    params.extrapolation_levels = 1;
    params.levels_with_corners = 1;
    let db = strip::run(&ship, &params, &|_, _| {}).unwrap();
    let files = wamit::write(&db);
    assert!(
        files.radiation.contains("7=vb1"),
        "{}",
        &files.radiation[..200]
    );
    let radiation = files.radiation.replace("7=vb1", "7=heave");
    let texts = WamitTexts {
        radiation: Source {
            name: "crafted.1",
            text: &radiation,
        },
        excitation: None,
        hydrostatics: None,
    };
    let read = wamit::read("crafted", texts, &WamitParams::default()).unwrap();
    let names = &read.database.dof_names;
    assert_eq!(
        names.iter().filter(|d| *d == "heave").count(),
        1,
        "{names:?}"
    );
    assert!(names.iter().any(|d| d == "mode7"), "{names:?}");
    assert!(
        read.database
            .notes
            .iter()
            .any(|n| n.contains("generalized mode 7 'heave'")),
        "{:?}",
        read.database.notes
    );
}

#[test]
fn a_database_written_as_a_capytaine_dataset_reads_back() {
    use hydrofmu::database::capytaine;
    let db = sphere();
    let path = std::env::temp_dir().join(format!("hydrofmu-export-{}.nc", std::process::id()));
    capytaine::write(&db, &path).unwrap();
    let keep_all = ImportParams {
        spikes: None,
        ..params()
    };
    let back = import::import(&path, &keep_all).unwrap();
    assert_eq!(back.dof_names, db.dof_names);
    assert_eq!(back.headings, db.headings);
    for (a, b) in back.omega.iter().zip(&db.omega) {
        assert!(close(*a, *b, 1e-15));
    }
    // Binary doubles: the same numbers up to the damping's omega * (1 / omega).
    assert!(relative_gap(&db.added_mass, &back.added_mass) < 1e-14);
    assert!(relative_gap(&db.excitation, &back.excitation) < 1e-14);
    assert!((&db.added_mass_inf - &back.added_mass_inf).amax() <= 1e-14 * db.added_mass_inf.amax());
    assert_eq!(back.stiffness_hydrostatic, db.stiffness_hydrostatic);
    let _ = std::fs::remove_file(&path);
}

/// A `.3` whose rows repeat at BETA = 360 (or -360) beside BETA = 0: one direction twice, which
/// would give the FMU's table a duplicated column; the reader refuses it at the first such row.
#[test]
fn headings_equal_modulo_360_are_refused_by_the_reader() {
    // The sphere's `.3` with its rows repeated at a second heading (`field`, BETA as written).
    let with_second_heading = |tag: &str, field: &str| {
        files(tag, |ext, text| {
            if ext != "3" {
                return Some(text);
            }
            let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
            let repeated: Vec<String> = lines[1..]
                .iter()
                .map(|row| row.replacen(" 0.000000E+00 ", field, 1))
                .collect();
            lines.extend(repeated);
            Some(lines.join("\n") + "\n")
        })
    };
    for (beta, field) in [(360.0, " 3.600000E+02 "), (-360.0, "-3.600000E+02 ")] {
        let path = with_second_heading("headings-360", field);
        let e = import::import(&path, &params()).unwrap_err().to_string();
        assert!(
            e.contains("sphere.3:44:")
                && e.contains(&format!(
                    "headings 0 and {beta} are the same direction (equal modulo 360 degrees)"
                )),
            "{e}"
        );
    }
    // 0 and 180 are two directions: read.
    let path = with_second_heading("headings-180", " 1.800000E+02 ");
    let db = import::import(&path, &params()).unwrap();
    assert_eq!(db.headings, vec![0.0, 180.0]);
}

/// The sphere imported at length scale `length` (ULEN) and fitted over all its frequencies in
/// DOF units of that length, as `fmu-pack fit` does.
fn fit_at_length_scale(
    length: f64,
) -> Result<(Database, hydrofmu::identify::FitReport), hydrofmu::identify::IdentifyError> {
    let mut p = params();
    p.wamit.length_scale = length;
    let db = import::import(&files("length", |_, t| Some(t)), &p).unwrap();
    let factors: Vec<f64> = db
        .dof_units
        .iter()
        .map(|d| length.powi(i32::from(d.length_exponent)))
        .collect();
    let band = (
        db.omega[0] * (1.0 - 1e-12),
        db.omega[db.omega.len() - 1] * (1.0 + 1e-12),
    );
    let fit_params = hydrofmu::identify::FitParams {
        band,
        noise: Some(db.noise.clone()),
        ..Default::default()
    };
    let report = hydrofmu::identify::fit_in_dof_units(&db.response(), &fit_params, &factors)?;
    Ok((db, report))
}

#[test]
fn a_fit_is_as_good_at_any_length_scale_and_reports_its_written_network() {
    // At ULEN = 1e6 m the translations' added mass (2e23 kg) was below 1e-6 of the rotations'
    // (7e35 kg m^2): measured against that floor, heave was left unfitted (94.6 % off) under
    // a verdict of 0.67 %; at 1e30 m the error scales overflowed and a network of no states
    // was reported at 0 %.
    let (_, reference) = fit_at_length_scale(1.0).unwrap();
    for length in [1.0, 1e6, 1e-3] {
        let (db, report) = fit_at_length_scale(length).unwrap();
        assert!(report.tolerance_met, "{length}");
        assert_eq!(report.states, reference.states, "{length}");
        // Measured: equal to 1.1e-10 (0.66982 % at each scale).
        assert!(
            close(
                report.max_relative_error,
                reference.max_relative_error,
                3e-10
            ),
            "{length}: {} against {}",
            report.max_relative_error,
            reference.max_relative_error
        );
        // The written file, read back, misses the data by what the report says.
        let written =
            hydrofmu::network::Network::from_xml_str(&report.network.to_xml_string(), "written")
                .unwrap();
        let n = db.dof_names.len();
        let mut worst: f64 = 0.0;
        let mut diagonal = vec![0.0f64; n];
        let mut own_scale = vec![0.0f64; n];
        for (w, a) in db.omega.iter().zip(&db.added_mass) {
            let h = written.added_mass_tf(*w);
            for i in 0..n {
                own_scale[i] = own_scale[i].max(a[(i, i)].norm());
                diagonal[i] = diagonal[i].max((h[(i, i)] - a[(i, i)]).norm());
                for j in 0..n {
                    let e = (h[(i, j)] - a[(i, j)]).norm() / report.error_scale[(i, j)];
                    worst = worst.max(e);
                }
            }
        }
        assert!(
            close(worst, report.max_relative_error, 1e-12),
            "{length}: written {worst}, reported {}",
            report.max_relative_error
        );
        // Every DOF that moves water (all but yaw) within the tolerance of its own scale.
        for i in 0..5 {
            let own = diagonal[i] / own_scale[i];
            assert!(
                own < report.tolerance,
                "{length}: {} {own}",
                db.dof_names[i]
            );
        }
    }
    // Beyond what the fit represents (and a network file holds): refused, naming the range.
    let error = fit_at_length_scale(1e30).unwrap_err().to_string();
    assert!(error.contains("outside the range 1e-50 .. 1e50"), "{error}");
}
