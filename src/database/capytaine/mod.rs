//! Capytaine's NetCDF datasets: what `cpt.assemble_dataset` returns, written as NetCDF-3 by
//!
//! ```python
//! cpt.io.xarray.separate_complex_values(ds).to_netcdf(path, engine="scipy")
//! ```
//!
//! (plain pip Capytaine has no NetCDF-4 library; `format="NETCDF3_64BIT"` or the classic
//! format both read). The variables used, each found by its dimensions' NAMES (their order
//! may differ from file to file; any other dimension of a variable must have size 1):
//!
//! ```text
//! added_mass, radiation_damping    (omega, influenced_dof, radiating_dof)        float
//! excitation_force                 (complex, omega, wave_direction, influenced_dof)
//! Froude_Krylov_force              (complex, omega, wave_direction, influenced_dof)
//! hydrostatic_stiffness            (influenced_dof, radiating_dof)
//! omega (rad/s), wave_direction (rad), influenced_dof, radiating_dof (names), complex
//! ("re", "im"); rho, g, forward_speed, water_depth (scalars)
//! ```
//!
//! `excitation_force` (with `wave_direction`), `Froude_Krylov_force` and
//! `hydrostatic_stiffness` may be absent (the database then has no exciting force, or a zero
//! restoring, with a warning); every other variable above must be there.
//!
//! Conventions. Capytaine's time factor is `exp(-i omega t)`, ours `exp(+i omega t)`
//! (docs/DESIGN.md); its added mass `a` and damping `b` are real, its exciting force `X_c` is per
//! unit wave amplitude, all in SI at the file's `rho_f`, `g_f`. With the caller's `rho`, `g`
//! ([`WamitParams::rho`], [`WamitParams::g`]):
//!
//! `A~_ij(omega) = (rho / rho_f) (a_ij(omega) - i b_ij(omega) / omega)`,
//! `A_inf,ij = (rho / rho_f) a_ij(inf)`,
//! `X_j(omega, beta) = (rho g / (rho_f g_f)) conj(X_c,j(omega, beta))`,
//! `C_ij = (rho g / (rho_f g_f)) C_f,ij`,
//!
//! with `i` the influenced DOF (the force) and `j` the radiating one (the motion), and `beta`
//! = `wave_direction` in degrees (0 = waves travelling towards +x, as ours). A BEM solution at
//! fixed `omega` is linear in `rho`; a change of `g` changes the wave number and is only
//! approximated by the scaling above (noted when `g / g_f` differs from 1 by more than 1e-9).
//!
//! Frequencies: `omega = inf` gives `A_inf` (its damping is ignored), `omega = 0` is skipped
//! (`A(0)` is not used), the exciting force is NaN at both and is not read there. The DOF
//! names `Surge`, `Sway`, `Heave`, `Roll`, `Pitch`, `Yaw` (any case) become `surge` .. `yaw`
//! (the rotations: length exponent 1, angles); any other name (a generalized or flexible DOF)
//! is lowercased, every character outside `[a-z0-9_]` replaced by `_` (prefixed `dof_` when
//! it does not start with a letter), with length exponent 0, and a note says so.
//!
//! Refused, naming the variable (and the index for a value): a NetCDF-4/HDF5 file (with how
//! to write NetCDF-3), a CDF-5 file, a malformed header, a record (unlimited) dimension, a
//! missing variable, a non-numeric or non-finite coordinate, a NaN or infinite coefficient at
//! a finite frequency (or in `A_inf`) or one beyond the floating-point range once scaled,
//! `forward_speed != 0`, `influenced_dof` and `radiating_dof` naming different DOFs, two DOFs
//! with one name, two frequencies within 1e-6 or two equal headings, and every size beyond
//! the limits ([`wamit::MAX_FILE_BYTES`], [`MAX_HEADER_BYTES`], [`wamit::MAX_MODE_INDEX`]
//! DOFs, [`wamit::MAX_ENTRIES`] matrix entries, [`super::MAX_HEADINGS`] headings), before
//! allocating. A finite `water_depth` is accepted and noted.
//!
//! The file's header is walked first (`header.rs`) with every count and offset bounded by the
//! file's size before the `netcdf3` crate parses it (the crate trusts the counts it reads);
//! `variables.rs` reads the variables by name, `writer.rs` writes a dataset.

mod header;
mod variables;
mod writer;

pub use writer::{write, write_with, Attribute, WriteError};

use super::wamit::{self, FrequencyColumn, WamitParams};
use super::{Database, DatabaseError};
use crate::fmu::DofUnit;
use crate::units::WaterDepth;
use header::check_header;
use nalgebra::DMatrix;
use netcdf3::FileReader;
use num_complex::Complex64;
use variables::{Array, Nc};

/// Largest NetCDF header read, in bytes (Capytaine's are a few kB).
pub const MAX_HEADER_BYTES: usize = 256 << 10;

/// How to write a file this reader takes, for the messages.
const HOW_TO_WRITE: &str = "write it as NetCDF-3 with \
    `cpt.io.xarray.separate_complex_values(ds).to_netcdf(path, engine=\"scipy\")`";

/// What [`read`] gives: the database and what the file held.
#[derive(Clone, Debug)]
pub struct ImportedCapytaine {
    /// The SI database, at the caller's `rho` and `g`.
    pub database: Database,
    /// Whether the file has an `omega = inf` row (`A_inf`); when not, `A_inf` is zero and
    /// [`super::import::finish`] estimates it.
    pub added_mass_inf_given: bool,
    /// Whether `excitation_force` was read.
    pub has_excitation: bool,
    /// Whether `hydrostatic_stiffness` was read.
    pub has_hydrostatics: bool,
}

/// Reads a Capytaine NetCDF-3 dataset (the bytes of `file`) into SI ([`Database`]) at
/// `params.rho` and `params.g`; `name` is the body's name. `A_inf` is the `omega = inf`
/// row's; no spike is removed and nothing is symmetrized here ([`super::import::finish`]).
///
/// # Errors
/// Every refused input of the module's documentation, naming `file`, the variable and, for a
/// value, its index.
pub fn read(
    name: &str,
    bytes: Vec<u8>,
    file: &str,
    params: &WamitParams,
) -> Result<ImportedCapytaine, DatabaseError> {
    let error = |message: String| DatabaseError::file(file, message);
    check_params(params).map_err(error)?;
    if bytes.len() as u64 > wamit::MAX_FILE_BYTES {
        return Err(error(format!(
            "{} bytes, more than the {} accepted",
            bytes.len(),
            wamit::MAX_FILE_BYTES
        )));
    }
    check_header(&bytes).map_err(error)?;
    let reader = FileReader::open_seek_read(file, Box::new(std::io::Cursor::new(bytes)))
        .map_err(|e| error(format!("not a readable NetCDF-3 file: {e}")))?;
    let mut nc = Nc { reader, file };
    convert(name, &mut nc, params)
}

fn check_params(params: &WamitParams) -> Result<(), String> {
    if params.length_scale != 1.0 {
        return Err(format!(
            "a length scale of {} m: it applies to WAMIT's nondimensional files; a Capytaine \
             dataset is in SI",
            params.length_scale
        ));
    }
    if params.conjugate {
        return Err(
            "conjugation asked: a Capytaine dataset's convention is known \
                    (exp(-i omega t)) and its exciting force is always conjugated"
                .to_string(),
        );
    }
    if params.frequency_column != FrequencyColumn::Period {
        return Err(
            "a frequency column asked: it applies to WAMIT files; a Capytaine dataset has \
                    its omega coordinate"
                .to_string(),
        );
    }
    for (what, value) in [("rho", params.rho), ("g", params.g)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(format!("{what} = {value}: it must be finite and > 0"));
        }
    }
    Ok(())
}

/// Our name and unit of a Capytaine DOF name; `true` when it is a rigid-body DOF.
fn dof(name: &str) -> (String, DofUnit, bool) {
    let lower = name.to_ascii_lowercase();
    if let Some(mode) = wamit::RIGID_MODES.iter().position(|m| *m == lower) {
        let rotation = mode >= 3;
        return (
            lower.clone(),
            DofUnit::new(&lower, u8::from(rotation), rotation),
            true,
        );
    }
    let mut ours: String = lower
        .chars()
        .map(|c| {
            if c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if !ours.starts_with(|c: char| c.is_ascii_lowercase()) {
        ours = format!("dof_{ours}");
    }
    let unit = DofUnit::new(&ours, 0, false);
    (ours, unit, false)
}

/// A frequency of the omega coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Frequency {
    Zero,
    Infinite,
    Finite(f64),
}

fn convert(
    name: &str,
    nc: &mut Nc,
    params: &WamitParams,
) -> Result<ImportedCapytaine, DatabaseError> {
    let file = nc.file.to_string();
    let error = |message: String| DatabaseError::file(&file, message);
    for (var, what) in [
        ("added_mass", "the added mass"),
        ("radiation_damping", "the radiation damping"),
        ("omega", "the frequencies"),
        ("influenced_dof", "the DOFs"),
        ("radiating_dof", "the DOFs"),
        ("rho", "the water density"),
        ("g", "gravity"),
        ("forward_speed", "the forward speed"),
    ] {
        if !nc.has(var) {
            return Err(nc.missing(var, what));
        }
    }
    let mut notes = Vec::new();
    let mut warnings = Vec::new();

    // Sizes first, from the header: nothing large is read before they are bounded.
    let n_omega = nc.dim("omega")?;
    let n = nc.dim("influenced_dof")?;
    if n == 0 || n > wamit::MAX_MODE_INDEX {
        return Err(error(format!(
            "{n} DOFs (influenced_dof): 1..{} are read",
            wamit::MAX_MODE_INDEX
        )));
    }
    if nc.dim("radiating_dof")? != n {
        return Err(error(format!(
            "{} radiating DOFs and {n} influenced ones: the same DOFs must be both",
            nc.dim("radiating_dof")?
        )));
    }
    if n.saturating_mul(n).saturating_mul(n_omega) > wamit::MAX_ENTRIES {
        return Err(error(format!(
            "{n_omega} frequencies x {n} DOFs^2 exceed {} entries",
            wamit::MAX_ENTRIES
        )));
    }
    let has_excitation = nc.has("excitation_force");
    let n_headings = if has_excitation {
        if !nc.has("wave_direction") {
            return Err(nc.missing("wave_direction", "the headings of excitation_force"));
        }
        let h = nc.dim("wave_direction")?;
        if h == 0 || h > super::MAX_HEADINGS {
            return Err(error(format!(
                "{h} wave directions: 1..{} are read (the FMU's table holds at most {})",
                super::MAX_HEADINGS,
                super::MAX_HEADINGS
            )));
        }
        if n.saturating_mul(h).saturating_mul(n_omega) > wamit::MAX_ENTRIES {
            return Err(error(format!(
                "{n_omega} frequencies x {h} headings x {n} DOFs exceed {} entries",
                wamit::MAX_ENTRIES
            )));
        }
        h
    } else {
        0
    };

    // Scalars.
    let rho_file = nc.scalar("rho", "the water density")?;
    let g_file = nc.scalar("g", "gravity")?;
    for (var, value) in [("rho", rho_file), ("g", g_file)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(error(format!(
                "variable {var} = {value}: it must be finite and > 0"
            )));
        }
    }
    let speed = nc.scalar("forward_speed", "the forward speed")?;
    if speed != 0.0 {
        return Err(error(format!(
            "variable forward_speed = {speed} m/s: only zero-speed databases are read"
        )));
    }
    let depth = if nc.has("water_depth") {
        let depth = nc.scalar("water_depth", "the water depth")?;
        let depth = WaterDepth::new(depth).map_err(|_| {
            error(format!(
                "variable water_depth = {depth}: it must be > 0 (inf for deep water)"
            ))
        })?;
        if let WaterDepth::Finite(h) = depth {
            notes.push(format!(
                "{file}: finite water depth {h} m (the coefficients are for that depth; the \
                 FMU's parameter depth)"
            ));
        }
        depth
    } else {
        notes.push(format!(
            "{file}: no water_depth variable: the depth is unknown (taken as deep water)"
        ));
        WaterDepth::Infinite
    };
    let rho = params.rho;
    let g = params.g;
    let radiation_scale = rho / rho_file;
    let force_scale = radiation_scale * g / g_file;
    if rho != rho_file {
        notes.push(format!(
            "{file}: computed for rho = {rho_file} kg/m^3: every coefficient scaled by {rho} / \
             {rho_file}"
        ));
    }
    if (g / g_file - 1.0).abs() > 1e-9 {
        notes.push(format!(
            "{file}: computed for g = {g_file} m/s^2: the exciting force and the restoring scaled \
             by {g} / {g_file}; the radiation coefficients are the file's (the wave number \
             omega^2 / g differs: an approximation)"
        ));
    }

    // DOFs.
    let influenced = nc.strings("influenced_dof", "the influenced DOFs")?;
    let radiating = nc.strings("radiating_dof", "the radiating DOFs")?;
    let mut dof_names = Vec::with_capacity(n);
    let mut dof_units = Vec::with_capacity(n);
    let mut generalized = Vec::new();
    for original in &influenced {
        let (ours, unit, rigid) = dof(original);
        if let Some(k) = dof_names.iter().position(|d| *d == ours) {
            return Err(error(format!(
                "influenced_dof: '{}' and '{original}' are both DOF {ours}",
                influenced[k]
            )));
        }
        if !rigid {
            generalized.push(format!("{original} -> {ours}"));
        }
        dof_names.push(ours);
        dof_units.push(unit);
    }
    if !generalized.is_empty() {
        notes.push(format!(
            "{file}: DOFs that are no rigid-body motion taken as lengths (length exponent 0): {}",
            generalized.join(", ")
        ));
    }
    // radiating_dof[k] is DOF column[k] of ours.
    let column: Vec<usize> = radiating
        .iter()
        .map(|r| {
            let ours = dof(r).0;
            dof_names.iter().position(|d| *d == ours).ok_or_else(|| {
                error(format!(
                    "radiating_dof '{r}' is no influenced_dof ({}): the same DOFs must be both",
                    influenced.join(", ")
                ))
            })
        })
        .collect::<Result<_, _>>()?;
    {
        let mut seen = column.clone();
        seen.sort_unstable();
        seen.dedup();
        if seen.len() != n {
            return Err(error(
                "radiating_dof names one DOF twice: the same DOFs must be both".to_string(),
            ));
        }
    }

    // Frequencies.
    let omega_values = nc.coordinate("omega", "the frequencies")?;
    let mut zero = None;
    let mut infinite = None;
    let mut finite: Vec<(f64, usize)> = Vec::with_capacity(n_omega);
    for (k, &w) in omega_values.iter().enumerate() {
        let frequency = if w == 0.0 {
            Frequency::Zero
        } else if w == f64::INFINITY {
            Frequency::Infinite
        } else if w.is_finite() && w > 0.0 {
            Frequency::Finite(w)
        } else {
            return Err(error(format!(
                "omega[{k}] = {w}: no frequency (0, inf or finite > 0 rad/s)"
            )));
        };
        let twice = |previous: usize| {
            error(format!(
                "omega[{previous}] and omega[{k}] are both {w}: a frequency written twice"
            ))
        };
        match frequency {
            Frequency::Zero => {
                if let Some(previous) = zero.replace(k) {
                    return Err(twice(previous));
                }
            }
            Frequency::Infinite => {
                if let Some(previous) = infinite.replace(k) {
                    return Err(twice(previous));
                }
            }
            Frequency::Finite(w) => finite.push((w, k)),
        }
    }
    finite.sort_by(|a, b| a.0.total_cmp(&b.0));
    for pair in finite.windows(2) {
        if pair[1].0 - pair[0].0 <= wamit::SAME_FREQUENCY * pair[1].0 {
            return Err(error(format!(
                "omega[{}] = {} and omega[{}] = {} rad/s are the same to 1e-6: a frequency \
                 written twice",
                pair[0].1, pair[0].0, pair[1].1, pair[1].0
            )));
        }
    }
    if finite.is_empty() {
        return Err(error(
            "no finite frequency in omega (only the limits)".to_string(),
        ));
    }

    // Radiation.
    let radiation_axes = [
        ("omega", n_omega),
        ("influenced_dof", n),
        ("radiating_dof", n),
    ];
    let a = nc.floats("added_mass", "the added mass")?;
    let a_strides = a.strides(&radiation_axes).map_err(&error)?;
    let b = nc.floats("radiation_damping", "the radiation damping")?;
    let b_strides = b.strides(&radiation_axes).map_err(&error)?;
    let value = |array: &Array, strides: &[Option<usize>], k: usize, i: usize, r: usize| {
        let x = array.at(strides, &[k, i, r]);
        if x.is_finite() {
            Ok(x)
        } else {
            Err(error(format!(
                "{}[omega = {} ({k}), influenced_dof = {} ({i}), radiating_dof = {} ({r})] is \
                 {x}",
                array.name, omega_values[k], influenced[i], radiating[r]
            )))
        }
    };
    let out_of_range = |k: usize, i: usize, r: usize| {
        error(format!(
            "added_mass or radiation_damping at [omega = {} ({k}), influenced_dof = {} ({i}), \
             radiating_dof = {} ({r})]: beyond the floating-point range once scaled",
            omega_values[k], influenced[i], radiating[r]
        ))
    };
    let mut added_mass = Vec::with_capacity(finite.len());
    for &(w, k) in &finite {
        let mut m = DMatrix::<Complex64>::zeros(n, n);
        for i in 0..n {
            for (r, &j) in column.iter().enumerate() {
                let am = value(&a, &a_strides, k, i, r)?;
                let damping = value(&b, &b_strides, k, i, r)?;
                let z = Complex64::new(am, -damping / w) * radiation_scale;
                if !(z.re.is_finite() && z.im.is_finite()) {
                    return Err(out_of_range(k, i, r));
                }
                m[(i, j)] = z;
            }
        }
        added_mass.push(m);
    }
    let added_mass_inf = match infinite {
        Some(k) => {
            let mut m = DMatrix::<f64>::zeros(n, n);
            for i in 0..n {
                for (r, &j) in column.iter().enumerate() {
                    m[(i, j)] = value(&a, &a_strides, k, i, r)? * radiation_scale;
                    if !m[(i, j)].is_finite() {
                        return Err(out_of_range(k, i, r));
                    }
                }
            }
            Some(m)
        }
        None => None,
    };
    drop((a, b));

    // Hydrostatics.
    let has_hydrostatics = nc.has("hydrostatic_stiffness");
    let stiffness = if has_hydrostatics {
        let c = nc.floats("hydrostatic_stiffness", "the hydrostatic restoring")?;
        let strides = c
            .strides(&[("influenced_dof", n), ("radiating_dof", n)])
            .map_err(&error)?;
        let mut m = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for (r, &j) in column.iter().enumerate() {
                let x = c.at(&strides, &[i, r]);
                if !x.is_finite() {
                    return Err(error(format!(
                        "hydrostatic_stiffness[influenced_dof = {} ({i}), radiating_dof = {} \
                         ({r})] is {x}",
                        influenced[i], radiating[r]
                    )));
                }
                m[(i, j)] = x * force_scale;
                if !m[(i, j)].is_finite() {
                    return Err(error(format!(
                        "hydrostatic_stiffness[influenced_dof = {} ({i}), radiating_dof = {} \
                         ({r})] = {x}: beyond the floating-point range once scaled",
                        influenced[i], radiating[r]
                    )));
                }
            }
        }
        m
    } else {
        warnings.push(format!(
            "{file}: no hydrostatic_stiffness variable: the hydrostatic restoring is zero"
        ));
        DMatrix::zeros(n, n)
    };

    // Excitation.
    let (headings, excitation, froude_krylov) = if has_excitation {
        let directions = nc.coordinate("wave_direction", "the headings")?;
        let mut order: Vec<(f64, usize)> = Vec::with_capacity(n_headings);
        for (h, &beta) in directions.iter().enumerate() {
            if !beta.is_finite() {
                return Err(error(format!("wave_direction[{h}] = {beta}")));
            }
            order.push((degrees(beta), h));
        }
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let Some(pair) = order.windows(2).find(|p| p[0].0 == p[1].0) {
            return Err(error(format!(
                "wave_direction[{}] and wave_direction[{}] are both {} deg",
                pair[0].1, pair[1].1, pair[0].0
            )));
        }
        // Directions: two equal modulo 360 degrees would be one table column twice.
        for (k, &(a, first)) in order.iter().enumerate() {
            let same = |(b, _): &&(f64, usize)| crate::waves::same_direction(a, *b);
            if let Some(&(b, second)) = order[k + 1..].iter().find(same) {
                return Err(error(format!(
                    "wave_direction[{first}] and wave_direction[{second}]: headings {a} and {b} \
                     are the same direction (equal modulo 360 degrees)"
                )));
            }
        }
        let (re, im) = complex_parts(nc, &mut notes)?;
        let has_froude_krylov = nc.has("Froude_Krylov_force");
        let mut forces = |var: &str| -> Result<Vec<DMatrix<Complex64>>, DatabaseError> {
            let x = nc.floats(var, "an exciting force")?;
            let strides = x
                .strides(&[
                    ("complex", 2),
                    ("omega", n_omega),
                    ("wave_direction", n_headings),
                    ("influenced_dof", n),
                ])
                .map_err(|m| {
                    error(format!(
                        "{m} (complex values must be split: \
                         cpt.io.xarray.separate_complex_values)"
                    ))
                })?;
            let mut out = Vec::with_capacity(finite.len());
            for &(_, k) in &finite {
                let mut m = DMatrix::<Complex64>::zeros(n, n_headings);
                for (slot, &(_, h)) in order.iter().enumerate() {
                    for i in 0..n {
                        let part = |c: usize, what: &str| {
                            let v = x.at(&strides, &[c, k, h, i]);
                            if v.is_finite() {
                                Ok(v)
                            } else {
                                Err(error(format!(
                                    "{var}[complex = {what}, omega = {} ({k}), wave_direction = \
                                     {} ({h}), influenced_dof = {} ({i})] is {v}",
                                    omega_values[k], directions[h], influenced[i]
                                )))
                            }
                        };
                        // exp(-i omega t) to exp(+i omega t): the conjugate.
                        let z = Complex64::new(part(re, "re")?, -part(im, "im")?) * force_scale;
                        if !(z.re.is_finite() && z.im.is_finite()) {
                            return Err(error(format!(
                                "{var}[omega = {} ({k}), wave_direction = {} ({h}), \
                                 influenced_dof = {} ({i})]: beyond the floating-point range \
                                 once scaled",
                                omega_values[k], directions[h], influenced[i]
                            )));
                        }
                        m[(i, slot)] = z;
                    }
                }
                out.push(m);
            }
            Ok(out)
        };
        let excitation = forces("excitation_force")?;
        let froude_krylov = if has_froude_krylov {
            forces("Froude_Krylov_force")?
        } else {
            Vec::new()
        };
        let headings: Vec<f64> = order.iter().map(|(d, _)| *d).collect();
        (headings, excitation, froude_krylov)
    } else {
        warnings.push(format!(
            "{file}: no excitation_force variable: no exciting force (the FMU's wave.kind must \
             stay 0)"
        ));
        (Vec::new(), Vec::new(), Vec::new())
    };

    let database = Database {
        name: name.to_string(),
        source: format!("imported from a Capytaine dataset ({file})"),
        dof_names,
        dof_units,
        rho,
        g,
        omega: finite.iter().map(|(w, _)| *w).collect(),
        added_mass,
        added_mass_inf: added_mass_inf
            .clone()
            .unwrap_or_else(|| DMatrix::zeros(n, n)),
        headings,
        excitation,
        froude_krylov,
        // Set from the restoring by import::finish.
        excitation_long_wave: None,
        stiffness_hydrostatic: stiffness,
        reference_length: 1.0,
        failures: Vec::new(),
        warnings,
        notes,
        noise: DMatrix::zeros(n, n),
        body_panels: Vec::new(),
        drift: Vec::new(),
        drift_headings: Vec::new(),
        depth,
    };
    Ok(ImportedCapytaine {
        database,
        added_mass_inf_given: added_mass_inf.is_some(),
        has_excitation,
        has_hydrostatics,
    })
}

/// Radians to degrees, with the round-off of `np.radians` removed (`90.00000000000001`).
fn degrees(radians: f64) -> f64 {
    let d = radians.to_degrees();
    let rounded = (d * 1e6).round() / 1e6;
    if (d - rounded).abs() <= 1e-9 * d.abs().max(1.0) {
        rounded + 0.0
    } else {
        d
    }
}

/// The indices of the real and imaginary parts along `complex` (its coordinate's order, or
/// re, im when the file has none).
fn complex_parts(nc: &mut Nc, notes: &mut Vec<String>) -> Result<(usize, usize), DatabaseError> {
    if !nc.has("complex") {
        notes.push(format!(
            "{}: no complex coordinate: its order taken as (re, im), as \
             separate_complex_values writes it",
            nc.file
        ));
        return Ok((0, 1));
    }
    let parts = nc.strings("complex", "the real and imaginary parts")?;
    let re = parts.iter().position(|p| p == "re");
    let im = parts.iter().position(|p| p == "im");
    match (re, im, parts.len()) {
        (Some(re), Some(im), 2) => Ok((re, im)),
        _ => Err(nc.error(format!(
            "variable complex is ({}) where (re, im) belongs",
            parts.join(", ")
        ))),
    }
}
