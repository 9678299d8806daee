//! Capytaine NetCDF-3 datasets (`hydrofmu::database::capytaine`): small datasets written here
//! with the `netcdf3` crate, laid out as `cpt.io.xarray.separate_complex_values(ds)
//! .to_netcdf(path, engine="scipy")` writes them, with known values: the mapping (conjugated
//! exciting force, degrees, DOF names and units, `A_inf` from the `omega = inf` row, `rho`
//! rescaling, dimensions found by name) and the refusals (HDF5, missing variable, NaN, forward
//! speed, sizes, mutated headers).
//!
//! `HYDROFMU_FUZZ_CASES` sets the number of mutated files (default 3000).
//!
//! With `HYDROFMU_CAPYTAINE_BOX=DIR` (the output of `examples/databases/capytaine_box_barge.py
//! DIR`), the test `box_barge_matches_the_wamit_export` also compares `DIR/box.nc` with the
//! WAMIT files Capytaine exported beside it.

use hydrofmu::database::capytaine::{self, ImportedCapytaine};
use hydrofmu::database::import::{self, ImportParams};
use hydrofmu::database::wamit::{self, WamitParams};
use netcdf3::{DataSet, FileWriter, Version};
use num_complex::Complex64;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A synthetic dataset: its layout and which parts to spoil.
#[derive(Clone)]
struct Spec {
    influenced: Vec<&'static str>,
    radiating: Vec<&'static str>,
    /// The omega coordinate; 0 and inf are the limits (NaN exciting force there).
    omega: Vec<f64>,
    /// wave_direction, radians.
    directions: Vec<f64>,
    rho: f64,
    g: f64,
    forward_speed: f64,
    water_depth: f64,
    /// Dimension order of added_mass and radiation_damping.
    radiation_dims: [&'static str; 3],
    /// Dimension order of the exciting forces.
    force_dims: [&'static str; 4],
    /// Variables left out.
    omit: Vec<&'static str>,
    /// (variable, flat index) set to NaN.
    nan: Option<(&'static str, usize)>,
}

impl Spec {
    fn new() -> Spec {
        Spec {
            influenced: vec!["Heave", "Pitch", "Flex-Mode 2"],
            // Another order: radiating DOFs are matched by name.
            radiating: vec!["Pitch", "Heave", "Flex-Mode 2"],
            omega: vec![0.0, 0.5, 1.0, 1.5, 2.0, f64::INFINITY],
            directions: vec![0.0, PI / 2.0, PI],
            rho: 1000.0,
            g: 9.81,
            forward_speed: 0.0,
            water_depth: f64::INFINITY,
            radiation_dims: ["omega", "influenced_dof", "radiating_dof"],
            force_dims: ["complex", "omega", "wave_direction", "influenced_dof"],
            omit: Vec::new(),
            nan: None,
        }
    }
}

/// Capytaine's added mass at omega (inf: the limit), influenced DOF `i` and radiating DOF `r`
/// (indices into the spec's lists), in the file's SI.
fn added_mass(omega: f64, i: usize, r: usize) -> f64 {
    let base = 100.0 * (i + 1) as f64 + 10.0 * (r + 1) as f64;
    if omega.is_infinite() {
        base - 1.0
    } else {
        base + omega
    }
}

fn damping(omega: f64, i: usize, r: usize) -> f64 {
    if omega == 0.0 || omega.is_infinite() {
        0.0
    } else {
        50.0 * (i + 1) as f64 + (r + 1) as f64 + omega * omega
    }
}

/// Capytaine's exciting force (its convention) at frequency index `k` (of the finite ones),
/// heading `h`, DOF `i`: `re = 1, im = 2` at (0, 0, 0).
fn excitation(k: usize, h: usize, i: usize) -> (f64, f64) {
    let shift = k as f64 + 10.0 * h as f64 + 100.0 * i as f64;
    (1.0 + shift, 2.0 + shift)
}

fn stiffness(i: usize, r: usize) -> f64 {
    1000.0 * (i + 1) as f64 + r as f64
}

fn temp_path(tag: &str) -> PathBuf {
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    std::env::temp_dir().join(format!(
        "hydrofmu-capytaine-{}-{}-{tag}",
        std::process::id(),
        COUNT.fetch_add(1, Ordering::Relaxed)
    ))
}

/// Character array of `names`, padded with NULs to `width`.
fn chars(names: &[&str], width: usize) -> Vec<u8> {
    let mut out = Vec::with_capacity(names.len() * width);
    for name in names {
        let mut bytes = name.as_bytes().to_vec();
        bytes.resize(width, 0);
        out.extend(bytes);
    }
    out
}

/// A dimension's index (or size) by name.
type ByName<'a> = &'a dyn Fn(&str) -> usize;

/// Row-major values of a variable over `dims` (names), from a function of each dimension's
/// index by name.
fn fill(dims: &[&str], sizes: ByName, value: &dyn Fn(ByName) -> f64) -> Vec<f64> {
    let shape: Vec<usize> = dims.iter().map(|d| sizes(d)).collect();
    let total: usize = shape.iter().product();
    (0..total)
        .map(|flat| {
            let mut index = vec![0; dims.len()];
            let mut rest = flat;
            for k in (0..dims.len()).rev() {
                index[k] = rest % shape[k];
                rest /= shape[k];
            }
            let at = |name: &str| index[dims.iter().position(|d| *d == name).unwrap()];
            value(&at)
        })
        .collect()
}

/// The file's bytes.
fn write(spec: &Spec) -> Vec<u8> {
    let n = spec.influenced.len();
    let width = 16;
    let mut ds = DataSet::new();
    let dims = [
        ("omega", spec.omega.len()),
        ("influenced_dof", n),
        ("radiating_dof", spec.radiating.len()),
        ("wave_direction", spec.directions.len()),
        ("complex", 2),
        ("string16", width),
        ("string2", 2),
    ];
    for (name, size) in dims {
        ds.add_fixed_dim(name, size).unwrap();
    }
    let sizes = |d: &str| dims.iter().find(|(n, _)| *n == d).unwrap().1;
    let mut vars: Vec<(&str, Vec<f64>)> = Vec::new();
    let mut char_vars: Vec<(&str, Vec<u8>)> = Vec::new();
    let finite_index = |k: usize| {
        spec.omega[..k]
            .iter()
            .filter(|w| w.is_finite() && **w > 0.0)
            .count()
    };
    let omega = |k: usize| spec.omega[k];
    let rad = spec.radiation_dims.to_vec();
    // The spec's radiating DOF r is influenced DOF `column(r)`: values are a function of the
    // (influenced, influenced) pair, so a reader ignoring the names gets them wrong.
    let column = |r: usize| {
        spec.influenced
            .iter()
            .position(|d| *d == spec.radiating[r])
            .unwrap_or(r)
    };
    vars.push((
        "added_mass",
        fill(&rad, &sizes, &|at| {
            added_mass(
                omega(at("omega")),
                at("influenced_dof"),
                column(at("radiating_dof")),
            )
        }),
    ));
    vars.push((
        "radiation_damping",
        fill(&rad, &sizes, &|at| {
            damping(
                omega(at("omega")),
                at("influenced_dof"),
                column(at("radiating_dof")),
            )
        }),
    ));
    let force = |scale: f64| {
        fill(&spec.force_dims, &sizes, &|at| {
            let k = at("omega");
            if !(spec.omega[k].is_finite() && spec.omega[k] > 0.0) {
                return f64::NAN;
            }
            let (re, im) = excitation(finite_index(k), at("wave_direction"), at("influenced_dof"));
            scale * if at("complex") == 0 { re } else { im }
        })
    };
    vars.push(("excitation_force", force(1.0)));
    vars.push(("Froude_Krylov_force", force(0.5)));
    vars.push((
        "hydrostatic_stiffness",
        fill(&["influenced_dof", "radiating_dof"], &sizes, &|at| {
            stiffness(at("influenced_dof"), column(at("radiating_dof")))
        }),
    ));
    vars.push(("omega", spec.omega.clone()));
    vars.push(("wave_direction", spec.directions.clone()));
    for (name, value) in [
        ("rho", spec.rho),
        ("g", spec.g),
        ("forward_speed", spec.forward_speed),
        ("water_depth", spec.water_depth),
    ] {
        vars.push((name, vec![value]));
    }
    char_vars.push(("influenced_dof", chars(&spec.influenced, width)));
    char_vars.push(("radiating_dof", chars(&spec.radiating, width)));
    char_vars.push(("complex", chars(&["re", "im"], 2)));
    vars.retain(|(name, _)| !spec.omit.contains(name));
    char_vars.retain(|(name, _)| !spec.omit.contains(name));
    if let Some((name, index)) = spec.nan {
        let var = vars.iter_mut().find(|(v, _)| *v == name).unwrap();
        var.1[index] = f64::NAN;
    }
    for (name, _) in &vars {
        let var_dims: Vec<&str> = match *name {
            "added_mass" | "radiation_damping" => rad.clone(),
            "excitation_force" | "Froude_Krylov_force" => spec.force_dims.to_vec(),
            "hydrostatic_stiffness" => vec!["influenced_dof", "radiating_dof"],
            "omega" => vec!["omega"],
            "wave_direction" => vec!["wave_direction"],
            _ => vec![],
        };
        ds.add_var_f64(name, &var_dims).unwrap();
    }
    for (name, _) in &char_vars {
        let string = if *name == "complex" {
            "string2"
        } else {
            "string16"
        };
        ds.add_var_u8(name, &[*name, string]).unwrap();
    }
    ds.add_global_attr_string("capytaine_version", "3.0.0")
        .unwrap();
    let path = temp_path("write.nc");
    {
        let mut writer = FileWriter::open(&path).unwrap();
        writer.set_def(&ds, Version::Offset64Bit, 0).unwrap();
        for (name, data) in &vars {
            writer.write_var_f64(name, data).unwrap();
        }
        for (name, data) in &char_vars {
            writer.write_var_u8(name, data).unwrap();
        }
        writer.close().unwrap();
    }
    let bytes = std::fs::read(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    bytes
}

fn params(rho: f64, g: f64) -> WamitParams {
    WamitParams {
        rho,
        g,
        ..WamitParams::default()
    }
}

fn read(spec: &Spec, rho: f64) -> Result<ImportedCapytaine, String> {
    capytaine::read("test", write(spec), "test.nc", &params(rho, spec.g)).map_err(|e| e.to_string())
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1.0)
}

#[test]
fn a_dataset_maps_to_our_conventions() {
    let spec = Spec::new();
    let imported = read(&spec, 1025.0).unwrap();
    let db = &imported.database;
    let s = 1025.0 / 1000.0;
    assert!(imported.added_mass_inf_given);
    assert!(imported.has_excitation && imported.has_hydrostatics);
    assert_eq!(db.dof_names, ["heave", "pitch", "flex_mode_2"]);
    let units: Vec<(u8, bool)> = db
        .dof_units
        .iter()
        .map(|u| (u.length_exponent, u.is_angle))
        .collect();
    assert_eq!(units, [(0, false), (1, true), (0, false)]);
    assert!(
        db.notes
            .iter()
            .any(|n| n.contains("Flex-Mode 2 -> flex_mode_2") && n.contains("length exponent 0")),
        "{:?}",
        db.notes
    );
    assert!(db.notes.iter().any(|n| n.contains("rho = 1000")));
    assert_eq!(db.rho, 1025.0);
    assert_eq!(db.g, 9.81);
    // The limits are not frequencies.
    assert_eq!(db.omega, [0.5, 1.0, 1.5, 2.0]);
    assert_eq!(db.headings, [0.0, 90.0, 180.0]);
    for (k, &w) in db.omega.iter().enumerate() {
        for i in 0..3 {
            for j in 0..3 {
                let z = db.added_mass[k][(i, j)];
                let want = Complex64::new(added_mass(w, i, j), -damping(w, i, j) / w) * s;
                assert!(
                    close(z.re, want.re) && close(z.im, want.im),
                    "A~[{k}]({i},{j}) = {z}, want {want}"
                );
            }
        }
        for h in 0..3 {
            for i in 0..3 {
                let (re, im) = excitation(k, h, i);
                let want = Complex64::new(re, -im) * s;
                let z = db.excitation[k][(i, h)];
                assert!(close(z.re, want.re) && close(z.im, want.im));
                let fk = db.froude_krylov[k][(i, h)];
                assert!(close(fk.re, 0.5 * want.re) && close(fk.im, 0.5 * want.im));
            }
        }
    }
    // re = 1, im = 2 in Capytaine's exp(-i omega t) is 1 - 2i in ours (before rho).
    assert_eq!(db.excitation[0][(0, 0)] / s, Complex64::new(1.0, -2.0));
    for i in 0..3 {
        for j in 0..3 {
            assert!(close(
                db.added_mass_inf[(i, j)],
                added_mass(f64::INFINITY, i, j) * s
            ));
            assert!(close(db.stiffness_hydrostatic[(i, j)], stiffness(i, j) * s));
        }
    }
    // The long-wave limit is the heave column of the restoring, set by the import's checks.
    assert!(db.excitation_long_wave.is_none());
    let mut finished = db.clone();
    import::finish(&mut finished, true, &ImportParams::new()).unwrap();
    let long_wave = finished.excitation_long_wave.as_ref().unwrap();
    assert!(close(long_wave[1], stiffness(1, 0) * s));
}

#[test]
fn dimensions_are_found_by_name() {
    let mut spec = Spec::new();
    spec.radiation_dims = ["radiating_dof", "omega", "influenced_dof"];
    spec.force_dims = ["omega", "influenced_dof", "wave_direction", "complex"];
    spec.directions = vec![PI, -PI / 2.0];
    let db = read(&spec, 1000.0).unwrap().database;
    let reference = read(&Spec::new(), 1000.0).unwrap().database;
    assert_eq!(db.added_mass, reference.added_mass);
    assert_eq!(db.added_mass_inf, reference.added_mass_inf);
    // Headings sorted: -90 (file index 1), 180 (file index 0).
    assert_eq!(db.headings, [-90.0, 180.0]);
    let (re, im) = excitation(2, 0, 1);
    assert_eq!(db.excitation[2][(1, 1)], Complex64::new(re, -im));
    let (re, im) = excitation(2, 1, 1);
    assert_eq!(db.excitation[2][(1, 0)], Complex64::new(re, -im));
}

#[test]
fn gravity_differing_is_scaled_and_noted() {
    let spec = Spec::new();
    let imported = capytaine::read("test", write(&spec), "test.nc", &params(1000.0, 9.80665))
        .unwrap()
        .database;
    let s = 9.80665 / 9.81;
    let (re, im) = excitation(0, 0, 0);
    let z = imported.excitation[0][(0, 0)];
    assert!(close(z.re, re * s) && close(z.im, -im * s));
    assert!(close(
        imported.stiffness_hydrostatic[(0, 0)],
        stiffness(0, 0) * s
    ));
    assert!(close(
        imported.added_mass_inf[(0, 0)],
        added_mass(f64::INFINITY, 0, 0)
    ));
    assert!(imported.notes.iter().any(|n| n.contains("g = 9.81")));
}

#[test]
fn optional_parts_and_finite_depth() {
    let mut spec = Spec::new();
    spec.omit = vec!["hydrostatic_stiffness", "Froude_Krylov_force"];
    spec.omega = vec![0.5, 1.0, 1.5, 2.0];
    spec.water_depth = 30.0;
    let imported = read(&spec, 1000.0).unwrap();
    assert!(!imported.added_mass_inf_given && !imported.has_hydrostatics);
    let db = &imported.database;
    assert!(db.froude_krylov.is_empty());
    assert!(db
        .warnings
        .iter()
        .any(|w| w.contains("hydrostatic_stiffness")));
    assert!(db
        .notes
        .iter()
        .any(|n| n.contains("finite water depth 30 m")));
    assert!(db.excitation_long_wave.is_none());

    let mut spec = Spec::new();
    spec.omit = vec!["excitation_force"];
    let imported = read(&spec, 1000.0).unwrap();
    assert!(!imported.has_excitation);
    assert!(imported.database.excitation.is_empty() && imported.database.headings.is_empty());
    assert!(imported
        .database
        .warnings
        .iter()
        .any(|w| w.contains("no excitation_force")));
}

#[test]
fn import_reads_nc_files_through_finish() {
    assert!(import::is_database_path(Path::new("a/box.nc")));
    assert!(import::is_database_path(Path::new("BOX.NC")));
    assert!(import::is_database_path(Path::new("box.1")));
    assert!(!import::is_database_path(Path::new("box.3")));
    let path = temp_path("box.nc");
    std::fs::write(&path, write(&Spec::new())).unwrap();
    let mut params = ImportParams::new();
    params.wamit.rho = 1000.0;
    let db = import::import(&path, &params);
    std::fs::remove_file(&path).unwrap();
    let db = db.unwrap();
    // finish() made A~ symmetric.
    for a in &db.added_mass {
        assert!((a - a.transpose()).norm() <= 1e-9 * a.norm());
    }
    assert_eq!(db.dof_names.len(), 3);
    assert!(db.source.contains("Capytaine"));
}

fn refused(spec: &Spec) -> String {
    match read(spec, 1025.0) {
        Ok(_) => panic!("accepted"),
        Err(e) => e,
    }
}

#[test]
fn hdf5_and_foreign_files_are_refused() {
    let mut hdf5 = b"\x89HDF\r\n\x1a\n".to_vec();
    hdf5.resize(2048, 0);
    let e = capytaine::read("x", hdf5, "x.nc", &WamitParams::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("NetCDF-4") && e.contains("engine=\"scipy\"") && e.contains("separate_complex"),
        "{e}"
    );
    let e = capytaine::read(
        "x",
        b"CDF\x05rest".to_vec(),
        "x.nc",
        &WamitParams::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("CDF-5"), "{e}");
    let e = capytaine::read("x", b"hello".to_vec(), "x.nc", &WamitParams::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("not a NetCDF file"), "{e}");
    // WAMIT-only options do not apply.
    let mut p = WamitParams {
        length_scale: 2.0,
        ..WamitParams::default()
    };
    let e = capytaine::read("x", write(&Spec::new()), "x.nc", &p).unwrap_err();
    assert!(e.message.contains("length scale"), "{e}");
    p.length_scale = 1.0;
    p.conjugate = true;
    assert!(capytaine::read("x", write(&Spec::new()), "x.nc", &p).is_err());
}

#[test]
fn missing_variables_are_named() {
    for var in [
        "added_mass",
        "radiation_damping",
        "omega",
        "influenced_dof",
        "rho",
        "g",
        "forward_speed",
    ] {
        let mut spec = Spec::new();
        spec.omit = vec![var];
        let e = refused(&spec);
        assert!(e.contains(&format!("no variable {var}")), "{var}: {e}");
    }
    let mut spec = Spec::new();
    spec.omit = vec!["wave_direction"];
    assert!(refused(&spec).contains("no variable wave_direction"));
}

#[test]
fn nan_inside_is_named() {
    // added_mass (omega, influenced, radiating) 6 x 3 x 3: omega index 2 (1 rad/s), (1, 0).
    let mut spec = Spec::new();
    spec.nan = Some(("added_mass", 2 * 9 + 3));
    let e = refused(&spec);
    assert!(
        e.contains(
            "added_mass[omega = 1 (2), influenced_dof = Pitch (1), radiating_dof = Pitch (0)] \
             is NaN"
        ),
        "{e}"
    );
    // In the inf row: A_inf is needed.
    let mut spec = Spec::new();
    spec.nan = Some(("added_mass", 5 * 9));
    assert!(refused(&spec).contains("omega = inf (5)"));
    // In the zero row: not used.
    let mut spec = Spec::new();
    spec.nan = Some(("added_mass", 0));
    assert!(read(&spec, 1025.0).is_ok());
    // The exciting force at a finite frequency (complex 1 = im, omega 3, heading 0, DOF 2).
    let mut spec = Spec::new();
    spec.nan = Some(("excitation_force", 6 * 3 * 3 + 3 * 9 + 2));
    let e = refused(&spec);
    assert!(
        e.contains(
            "excitation_force[complex = im, omega = 1.5 (3), wave_direction = 0 (0), \
             influenced_dof = Flex-Mode 2 (2)] is NaN"
        ),
        "{e}"
    );
    let mut spec = Spec::new();
    spec.nan = Some(("hydrostatic_stiffness", 4));
    assert!(refused(&spec).contains("hydrostatic_stiffness["));
}

#[test]
fn inconsistent_datasets_are_refused() {
    let mut spec = Spec::new();
    spec.forward_speed = 1.5;
    assert!(refused(&spec).contains("forward_speed = 1.5"));
    let mut spec = Spec::new();
    spec.radiating = vec!["Pitch", "Heave", "Roll"];
    assert!(refused(&spec).contains("radiating_dof 'Roll'"));
    let mut spec = Spec::new();
    spec.influenced = vec!["Heave", "HEAVE", "Flex-Mode 2"];
    spec.radiating = spec.influenced.clone();
    assert!(refused(&spec).contains("are both DOF heave"));
    let mut spec = Spec::new();
    spec.omega = vec![0.5, 1.0, 1.0 + 1e-9, 2.0];
    assert!(refused(&spec).contains("written twice"));
    let mut spec = Spec::new();
    spec.omega = vec![0.5, -1.0, 1.5, 2.0];
    assert!(refused(&spec).contains("omega[1] = -1"));
    let mut spec = Spec::new();
    spec.directions = vec![0.0, 2.0 * PI / 4.0, PI / 2.0];
    assert!(refused(&spec).contains("are both 90 deg"));
    let mut spec = Spec::new();
    spec.rho = -1.0;
    assert!(refused(&spec).contains("rho = -1"));
}

#[test]
fn sizes_past_the_limits_are_refused() {
    // More headings than the FMU's table holds.
    let mut spec = Spec::new();
    spec.directions = (0..=hydrofmu::database::MAX_HEADINGS)
        .map(|h| h as f64 * 0.1)
        .collect();
    assert!(refused(&spec).contains("wave directions"));
    // More DOFs than the limit, and a frequency x DOF^2 count past MAX_ENTRIES: the variables
    // are declared scalars so that the file stays small; the sizes come from the dimensions.
    let header_only = |n_dofs: usize, n_omega: usize| {
        let mut ds = DataSet::new();
        ds.add_fixed_dim("omega", n_omega).unwrap();
        ds.add_fixed_dim("influenced_dof", n_dofs).unwrap();
        ds.add_fixed_dim("radiating_dof", n_dofs).unwrap();
        ds.add_fixed_dim("string4", 4).unwrap();
        for var in [
            "added_mass",
            "radiation_damping",
            "rho",
            "g",
            "forward_speed",
        ] {
            ds.add_var_f64::<&str>(var, &[]).unwrap();
        }
        ds.add_var_f64("omega", &["omega"]).unwrap();
        ds.add_var_u8("influenced_dof", &["influenced_dof", "string4"])
            .unwrap();
        ds.add_var_u8("radiating_dof", &["radiating_dof", "string4"])
            .unwrap();
        let path = temp_path("big.nc");
        let mut writer = FileWriter::open(&path).unwrap();
        writer.set_def(&ds, Version::Classic, 0).unwrap();
        writer.close().unwrap();
        let bytes = std::fs::read(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        capytaine::read("big", bytes, "big.nc", &WamitParams::default())
            .unwrap_err()
            .to_string()
    };
    let e = header_only(wamit::MAX_MODE_INDEX + 1, 10);
    assert!(e.contains("601 DOFs"), "{e}");
    let e = header_only(wamit::MAX_MODE_INDEX, 200);
    assert!(e.contains("exceed 50000000 entries"), "{e}");

    // A variable declared larger than the file: refused by the header walk.
    let mut bytes = write(&Spec::new());
    let at = find(&bytes, b"omega\0\0\0\0\0\0\x06").expect("the omega dimension");
    bytes[at + 8..at + 12].copy_from_slice(&0x7fff_ffffu32.to_be_bytes());
    let e = capytaine::read("x", bytes, "x.nc", &params(1025.0, 9.81))
        .unwrap_err()
        .to_string();
    assert!(e.contains("do not fit in the file"), "{e}");
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

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

#[test]
fn mutated_files_never_panic() {
    let seed = write(&Spec::new());
    let mut rng = Rng(7);
    let words: [u32; 6] = [0, 1, 0x7fff_ffff, 0xffff_ffff, 0x8000_0000, 0x0a];
    let cases: usize = std::env::var("HYDROFMU_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3000);
    let mut accepted = 0;
    for case in 0..cases {
        let mut bytes = seed.clone();
        match case % 4 {
            0 => {
                let at = rng.below(bytes.len());
                bytes[at] ^= 1 << rng.below(8);
            }
            1 => {
                // Header words replaced by extreme counts and sizes.
                let at = rng.below(1200.min(bytes.len() - 4)) & !3;
                let word = words[rng.below(words.len())];
                bytes[at..at + 4].copy_from_slice(&word.to_be_bytes());
            }
            2 => {
                let len = rng.below(bytes.len());
                bytes.truncate(len);
            }
            _ => {
                for _ in 0..4 {
                    let at = rng.below(bytes.len());
                    bytes[at] = rng.next() as u8;
                }
            }
        }
        let result = std::panic::catch_unwind(|| {
            capytaine::read("x", bytes.clone(), "x.nc", &params(1025.0, 9.81))
        });
        match result {
            Ok(Ok(imported)) => {
                accepted += 1;
                let db = imported.database;
                assert!(db.omega.iter().all(|w| w.is_finite() && *w > 0.0));
                assert!(db
                    .added_mass
                    .iter()
                    .all(|a| a.iter().all(|z| z.re.is_finite() && z.im.is_finite())));
            }
            Ok(Err(_)) => {}
            Err(_) => {
                let path = temp_path(&format!("panic-{case}.nc"));
                std::fs::write(&path, &bytes).unwrap();
                panic!("case {case} panicked: input in {}", path.display());
            }
        }
    }
    assert!(accepted > 0);
}

/// Manual check against a Capytaine run (see the module docs). Ignored by default: it needs
/// Capytaine's output, which the Python suite makes and compares the same way
/// (tests/python/test_database_capytaine.py).
#[test]
#[ignore = "needs HYDROFMU_CAPYTAINE_BOX=DIR, a Capytaine run; the Python suite runs the same comparison"]
fn box_barge_matches_the_wamit_export() {
    let dir = std::env::var_os("HYDROFMU_CAPYTAINE_BOX").expect(
        "HYDROFMU_CAPYTAINE_BOX=DIR, the output of examples/databases/capytaine_box_barge.py",
    );
    let dir = PathBuf::from(dir);
    let mut params = ImportParams::new();
    params.spikes = None;
    let nc = import::import(&dir.join("box.nc"), &params).unwrap();
    let wamit = import::import(&dir.join("box.1"), &params).unwrap();
    assert_eq!(nc.dof_names, wamit.dof_names);
    assert_eq!(nc.headings, wamit.headings);
    assert_eq!(nc.omega.len(), wamit.omega.len());
    let n = nc.dof_names.len();
    let mut worst = [0.0f64; 4];
    for (k, (w1, w2)) in nc.omega.iter().zip(&wamit.omega).enumerate() {
        assert!((w1 - w2).abs() <= 1e-6 * w1, "{w1} {w2}");
        let a = &nc.added_mass[k];
        let b = &wamit.added_mass[k];
        for i in 0..n {
            for j in 0..n {
                let scale = (a[(i, i)].norm() * a[(j, j)].norm()).sqrt();
                worst[0] = worst[0].max((a[(i, j)].re - b[(i, j)].re).abs() / scale);
                worst[1] = worst[1].max((a[(i, j)].im - b[(i, j)].im).abs() / scale);
            }
            let x = &nc.excitation[k];
            let y = &wamit.excitation[k];
            let scale = (0..x.ncols()).map(|h| x[(i, h)].norm()).fold(0.0, f64::max);
            for h in 0..x.ncols() {
                worst[2] = worst[2].max((x[(i, h)] - y[(i, h)]).norm() / scale);
            }
        }
    }
    for i in 0..n {
        for j in 0..n {
            let scale = (nc.added_mass_inf[(i, i)] * nc.added_mass_inf[(j, j)])
                .abs()
                .sqrt();
            worst[3] = worst[3]
                .max((nc.added_mass_inf[(i, j)] - wamit.added_mass_inf[(i, j)]).abs() / scale);
        }
    }
    let c = (&nc.stiffness_hydrostatic - &wamit.stiffness_hydrostatic).amax()
        / nc.stiffness_hydrostatic.amax();
    eprintln!(
        "box barge, .nc against .1/.3/.hst: added mass {:.2e}, damping/omega {:.2e}, \
         excitation {:.2e}, A_inf {:.2e} (relative to sqrt(A_ii A_jj) or the DOF's largest \
         force), restoring {c:.2e} of the largest",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(worst.iter().all(|w| *w < 1e-5), "{worst:?}");
    assert!(c < 1e-5);

    // Before finish() symmetrizes: Capytaine's .1 holds (radiating, influenced) pairs, the
    // transpose of ours, so the raw WAMIT reading is the raw NetCDF one transposed.
    let bytes = std::fs::read(dir.join("box.nc")).unwrap();
    let raw = capytaine::read("box", bytes, "box.nc", &params.wamit)
        .unwrap()
        .database;
    let text = |ext: &str| std::fs::read_to_string(dir.join(format!("box.{ext}"))).unwrap();
    let (t1, t3, thst) = (text("1"), text("3"), text("hst"));
    let source = |name, text| wamit::Source { name, text };
    let texts = wamit::WamitTexts {
        radiation: source("box.1", &t1),
        excitation: Some(source("box.3", &t3)),
        hydrostatics: Some(source("box.hst", &thst)),
    };
    let raw_wamit = wamit::read("box", texts, &params.wamit).unwrap().database;
    let (mut transposed, mut straight, mut asymmetry) = (0.0f64, 0.0f64, 0.0f64);
    for (a, b) in raw.added_mass.iter().zip(&raw_wamit.added_mass) {
        for i in 0..n {
            for j in 0..n {
                let scale = (a[(i, i)].norm() * a[(j, j)].norm()).sqrt();
                transposed = transposed.max((a[(i, j)] - b[(j, i)]).norm() / scale);
                straight = straight.max((a[(i, j)] - b[(i, j)]).norm() / scale);
                asymmetry = asymmetry.max((a[(i, j)] - a[(j, i)]).norm() / scale);
            }
        }
    }
    eprintln!(
        "raw A~: .nc against the .1 transposed {transposed:.2e}, not transposed {straight:.2e}; \
         the .nc's own asymmetry {asymmetry:.2e}"
    );
    assert!(transposed < 1e-5);
}

/// Directions equal modulo 2 pi (0 and 2 pi; -pi/2 and 3 pi/2) would be one column of the
/// FMU's table twice: the reader refuses them, naming both.
#[test]
fn wave_directions_equal_modulo_360_degrees_are_refused() {
    let mut spec = Spec::new();
    spec.directions = vec![0.0, PI, 2.0 * PI];
    let e = refused(&spec);
    assert!(
        e.contains("wave_direction[0] and wave_direction[2]")
            && e.contains("headings 0 and 360 are the same direction (equal modulo 360 degrees)"),
        "{e}"
    );
    spec.directions = vec![-PI / 2.0, 0.0, 1.5 * PI];
    let e = refused(&spec);
    assert!(
        e.contains("headings -90 and 270 are the same direction"),
        "{e}"
    );
    spec.directions = vec![0.0, PI, 1.5 * PI];
    assert!(read(&spec, 1025.0).is_ok());
}
