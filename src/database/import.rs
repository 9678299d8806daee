//! From files on disk to a [`Database`] ready to fit: a WAMIT file set (`NAME.1` and the
//! companions found beside it, [`super::wamit`]) or a Capytaine NetCDF-3 dataset (`NAME.nc`,
//! [`super::capytaine`]); then, whatever the format, reciprocity (symmetrized, the asymmetry
//! reported), irregular-frequency spikes removed ([`super::irregular`]), `A_inf` estimated
//! when the files give none ([`super::added_mass_inf`]), and sanity checks of units.

use super::added_mass_inf;
use super::capytaine;
use super::irregular::{self, SpikeParams};
use super::wamit::{self, Source, WamitParams, WamitTexts};
use super::{Database, DatabaseError};
use crate::units::WaterDepth;
use nalgebra::DMatrix;
use std::path::{Path, PathBuf};

/// How to import, with documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportParams {
    /// How to read WAMIT files.
    pub wamit: WamitParams,
    /// The spike search; `None` keeps every frequency.
    pub spikes: Option<SpikeParams>,
    /// Take the first column's meaning from WAMIT's `NAME.cfg` beside the files when it
    /// declares one (`IPEROUT`), over [`WamitParams::frequency_column`]. Default true.
    pub read_cfg: bool,
    /// The water depth the user gives (`--water-depth`): the depth of WAMIT files, which do
    /// not state it (deep water without it); a Capytaine dataset's own `water_depth` must
    /// agree with it. Default `None`.
    pub depth: Option<WaterDepth>,
}

impl Default for ImportParams {
    fn default() -> Self {
        ImportParams::new()
    }
}

impl ImportParams {
    /// The defaults: WAMIT's, the spike search on, `NAME.cfg` read.
    pub fn new() -> ImportParams {
        ImportParams {
            wamit: WamitParams::default(),
            spikes: Some(SpikeParams::default()),
            read_cfg: true,
            depth: None,
        }
    }
}

/// Whether `path` names a database file this module reads (by its extension: `.1`, or `.nc`
/// in any case).
pub fn is_database_path(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e == "1" || e.eq_ignore_ascii_case("nc"))
}

/// Whether `path` names a Capytaine NetCDF dataset (`.nc`).
fn is_netcdf_path(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("nc"))
}

/// The bytes of a regular file of at most [`wamit::MAX_FILE_BYTES`]
/// ([`crate::input::read_bounded`]).
fn read_bounded_bytes(path: &Path) -> Result<Vec<u8>, DatabaseError> {
    crate::input::read_bounded(path, wamit::MAX_FILE_BYTES, "MAX_FILE_BYTES")
        .map_err(|cause| DatabaseError::unreadable(&path.display().to_string(), cause))
}

/// As [`read_bounded_bytes`], for text.
fn read_bounded(path: &Path) -> Result<String, DatabaseError> {
    crate::input::read_bounded_text(path, wamit::MAX_FILE_BYTES, "MAX_FILE_BYTES")
        .map_err(|cause| DatabaseError::unreadable(&path.display().to_string(), cause))
}

/// The companion `stem.ext` of `path` when it exists (also in upper case).
fn companion(path: &Path, ext: &str) -> Option<PathBuf> {
    [ext.to_string(), ext.to_uppercase()]
        .iter()
        .map(|e| path.with_extension(e))
        .find(|p| p.is_file())
}

/// Imports the database of `path`: a Capytaine dataset (`NAME.nc`, [`capytaine::read`]) or
/// the WAMIT file set (`NAME.1`, with `NAME.3` and `NAME.hst` beside it when present), then
/// [`finish`].
///
/// # Errors
/// Missing or malformed files ([`wamit::read`], [`capytaine::read`]), or data left unusable
/// after the checks.
pub fn import(path: &Path, params: &ImportParams) -> Result<Database, DatabaseError> {
    if is_netcdf_path(path) {
        return import_netcdf(path, params);
    }
    let radiation_text = read_bounded(path)?;
    let excitation_path = companion(path, "3");
    let hydrostatics_path = companion(path, "hst");
    let excitation_text = excitation_path.as_deref().map(read_bounded).transpose()?;
    let hydrostatics_text = hydrostatics_path.as_deref().map(read_bounded).transpose()?;
    let names = [
        path.display().to_string(),
        excitation_path
            .map(|p| p.display().to_string())
            .unwrap_or_default(),
        hydrostatics_path
            .map(|p| p.display().to_string())
            .unwrap_or_default(),
    ];
    let texts = WamitTexts {
        radiation: Source {
            name: &names[0],
            text: &radiation_text,
        },
        excitation: excitation_text.as_deref().map(|text| Source {
            name: &names[1],
            text,
        }),
        hydrostatics: hydrostatics_text.as_deref().map(|text| Source {
            name: &names[2],
            text,
        }),
    };
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "body".to_string());
    let mut wamit_params = params.wamit.clone();
    let mut cfg_note = None;
    if params.read_cfg {
        if let Some(cfg) = companion(path, "cfg") {
            let name = cfg.display().to_string();
            let text = read_bounded(&cfg)?;
            if let Some(column) = wamit::frequency_column_of_cfg(Source {
                name: &name,
                text: &text,
            })? {
                wamit_params.frequency_column = column;
                cfg_note = Some(format!(
                    "{name} declares the first column: {}",
                    match column {
                        wamit::FrequencyColumn::Period => "the period (s)",
                        wamit::FrequencyColumn::RadPerSecond => "omega (rad/s)",
                        wamit::FrequencyColumn::Hertz => "the frequency (Hz)",
                    }
                ));
            }
        }
    }
    let imported = wamit::read(&stem, texts, &wamit_params)?;
    let mut database = imported.database;
    database.notes.extend(cfg_note);
    if let Some(depth) = params.depth {
        database.depth = depth;
        database.notes.push(format!(
            "water depth {depth} (given: WAMIT files do not state it)"
        ));
    }
    // The mean drift beside it: NAME.8 (momentum) and NAME.9 (pressure).
    let drift_files: Vec<(String, String)> = ["8", "9"]
        .iter()
        .filter_map(|ext| companion(path, ext))
        .map(|p| Ok((p.display().to_string(), read_bounded(&p)?)))
        .collect::<Result<_, DatabaseError>>()?;
    let drift_source = |ext: &str| {
        drift_files
            .iter()
            .find(|(name, _)| Path::new(name).extension().is_some_and(|e| e == ext))
            .map(|(name, text)| Source { name, text })
    };
    wamit::read_drift(
        &mut database,
        &imported.modes,
        drift_source("8"),
        drift_source("9"),
        &wamit_params,
    )?;
    if !imported.has_excitation {
        database.warnings.push(format!(
            "no {} beside {}: no exciting force (the FMU's wave.kind must stay 0)",
            path.with_extension("3").display(),
            names[0]
        ));
    }
    if !imported.has_hydrostatics {
        database.warnings.push(format!(
            "no {} beside {}: the hydrostatic restoring is zero",
            path.with_extension("hst").display(),
            names[0]
        ));
    }
    finish(&mut database, imported.added_mass_inf_given, params)?;
    // Archives carry the source: the file's name, not the machine's folders.
    database.source = format!("imported from WAMIT files ({})", file_name(path));
    Ok(database)
}

/// The last component of `path` (what a database written elsewhere names as its source).
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// Imports a Capytaine NetCDF-3 dataset.
fn import_netcdf(path: &Path, params: &ImportParams) -> Result<Database, DatabaseError> {
    let bytes = read_bounded_bytes(path)?;
    let name = path.display().to_string();
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "body".to_string());
    let imported = capytaine::read(&stem, bytes, &name, &params.wamit)?;
    let mut database = imported.database;
    if let Some(given) = params.depth {
        if given != database.depth {
            return Err(DatabaseError::file(
                &name,
                format!(
                    "the dataset's water_depth is {} but the depth given is {given}: the \
                     coefficients are for the dataset's depth",
                    database.depth
                ),
            ));
        }
    }
    finish(&mut database, imported.added_mass_inf_given, params)?;
    database.source = format!("imported from a Capytaine dataset ({})", file_name(path));
    Ok(database)
}

/// The checks every imported database goes through (any format): reciprocity, spikes,
/// `A_inf`, units.
///
/// # Errors
/// When the spikes leave fewer than 3 frequencies or `A_inf` cannot be estimated.
pub fn finish(
    database: &mut Database,
    added_mass_inf_given: bool,
    params: &ImportParams,
) -> Result<(), DatabaseError> {
    let file = database.source.clone();
    let mut gaps = symmetrize(database);
    if let Some(spike_params) = &params.spikes {
        let spikes = irregular::find(
            &database.omega,
            &database.added_mass,
            &database.dof_names,
            spike_params,
        );
        let mut drop = vec![false; database.omega.len()];
        for spike in &spikes {
            drop[spike.index] = true;
            database.failures.push((
                database.omega[spike.index],
                format!("irregular-frequency spike, kept out: {}", spike.reason),
            ));
        }
        database.failures.sort_by(|a, b| a.0.total_cmp(&b.0));
        let keep: Vec<bool> = drop.iter().map(|d| !d).collect();
        super::retain_flagged(&mut database.added_mass, &keep);
        super::retain_flagged(&mut database.excitation, &keep);
        super::retain_flagged(&mut database.froude_krylov, &keep);
        super::retain_flagged(&mut database.drift, &keep);
        super::retain_flagged(&mut database.omega, &keep);
        super::retain_flagged(&mut gaps, &keep);
    }
    database.noise = largest_gap(&gaps, database.dof_names.len());
    if database.omega.len() < 3 {
        return Err(DatabaseError::file(
            &file,
            format!(
                "{} usable frequencies; at least 3 are needed",
                database.omega.len()
            ),
        ));
    }
    if !added_mass_inf_given {
        let estimate = added_mass_inf::estimate(&database.omega, &database.added_mass)
            .ok_or_else(|| DatabaseError::file(&file, "A_inf cannot be estimated".to_string()))?;
        let n = database.dof_names.len();
        let per_dof: Vec<String> = (0..n)
            .map(|i| {
                let scale = estimate.added_mass_inf[(i, i)].abs().max(f64::MIN_POSITIVE);
                format!(
                    "{} {:.1} %",
                    database.dof_names[i],
                    100.0 * estimate.spread[(i, i)] / scale
                )
            })
            .collect();
        database.notes.push(format!(
            "A_inf estimated (no omega = inf rows) by the Kramers-Kronig relation from the \
             damping, the median over {} frequencies; uncertain by {} (the estimates' \
             spread plus the share of the damping beyond the last frequency)",
            estimate.frequencies_used,
            per_dof.join(", ")
        ));
        database.added_mass_inf = estimate.added_mass_inf;
    }
    let heave = database.dof_names.iter().position(|d| d == "heave");
    if let (Some(h), false) = (heave, database.excitation.is_empty()) {
        // A crest of height a lifts the pressure by rho g a everywhere: the force of the body
        // moved down by a, -C_j3 (-a) (docs/DESIGN.md, "Waves and hydrostatics"); exact for rigid
        // modes. Without a restoring (C_33 = 0) the long-wave limit stays unknown.
        let c = &database.stiffness_hydrostatic;
        if c[(h, h)] > 0.0 {
            database.excitation_long_wave = Some((0..c.nrows()).map(|j| c[(j, h)]).collect());
        }
    }
    if let Some(what) = database.first_non_finite() {
        return Err(DatabaseError::file(
            &file,
            format!("{what} is not finite after the checks (values too large for their scale)"),
        ));
    }
    check_units(database);
    Ok(())
}

/// The entrywise largest of `gaps` (n x n zeros if there are none).
pub(super) fn largest_gap(gaps: &[DMatrix<f64>], n: usize) -> DMatrix<f64> {
    gaps.iter()
        .fold(DMatrix::zeros(n, n), |acc, g| acc.zip_map(g, f64::max))
}

/// `A~` and `A_inf` made symmetric (reciprocity), the largest asymmetry noted; per frequency
/// the gaps `|A~_ij - A~_ji| / 2` (SI, symmetric).
pub(super) fn symmetrize(database: &mut Database) -> Vec<DMatrix<f64>> {
    let n = database.dof_names.len();
    let mut worst: (f64, usize, usize, f64) = (0.0, 0, 0, 0.0);
    let mut gaps = Vec::with_capacity(database.omega.len());
    for (a, omega) in database.added_mass.iter_mut().zip(&database.omega) {
        let mut gaps_here = DMatrix::zeros(n, n);
        for i in 0..n {
            for j in i + 1..n {
                let scale = (a[(i, i)].norm() * a[(j, j)].norm()).sqrt();
                let gap = (a[(i, j)] - a[(j, i)]).norm() / 2.0;
                gaps_here[(i, j)] = gap;
                gaps_here[(j, i)] = gap;
                if scale > 0.0 && gap / scale > worst.0 {
                    worst = (gap / scale, i, j, *omega);
                }
                let mean = (a[(i, j)] + a[(j, i)]) / 2.0;
                a[(i, j)] = mean;
                a[(j, i)] = mean;
            }
        }
        gaps.push(gaps_here);
    }
    let inf = &database.added_mass_inf;
    database.added_mass_inf = (inf + inf.transpose()) / 2.0;
    if worst.0 > 1e-3 {
        database.notes.push(format!(
            "A~ made symmetric (reciprocity): the largest asymmetry, {:.2} % of sqrt(|A~_ii \
             A~_jj|), is {}-{} at omega = {:.4} rad/s (a coarse mesh's)",
            100.0 * worst.0,
            database.dof_names[worst.1],
            database.dof_names[worst.2],
            worst.3
        ));
    }
    gaps
}

/// Mixed units show in long waves: the heave exciting force of the lowest frequency tends
/// to the restoring `C_33` (the crest's hydrostatic pressure). Warns when they are a factor
/// 2 apart while the waves are long (`k sqrt(A_wp) < 0.3`, `A_wp` from the smaller of the two
/// over `rho g`).
fn check_units(database: &mut Database) {
    let Some(h) = database.dof_names.iter().position(|d| d == "heave") else {
        return;
    };
    let c33 = database.stiffness_hydrostatic[(h, h)];
    let (Some(x), Some(&omega)) = (database.excitation.first(), database.omega.first()) else {
        return;
    };
    if c33 <= 0.0 {
        return;
    }
    let largest = (0..x.ncols()).map(|b| x[(h, b)].norm()).fold(0.0, f64::max);
    // The waterplane's size from the smaller of the two (either may be the wrong one).
    let k = omega * omega / database.g;
    let breadth = (c33.min(largest) / (database.rho * database.g)).sqrt();
    if k * breadth >= 0.3 {
        return;
    }
    let ratio = largest / c33;
    if !(0.5..=2.0).contains(&ratio) {
        database.warnings.push(format!(
            "the heave exciting force at omega = {omega:.4} rad/s is {ratio:.3} times the \
             restoring C33 where long waves make them nearly equal: files of different runs or \
             length scales (--length-scale)?"
        ));
    }
}
