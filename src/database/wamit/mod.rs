//! WAMIT numeric output files: `NAME.1` (added mass and damping), `NAME.3` (exciting force per
//! heading), `NAME.hst` (hydrostatic restoring), as written by WAMIT, by Capytaine's
//! `export_to_wamit`, by BEMRosetta and by HAMS.
//!
//! ```text
//! NAME.1    PER  I  J  Abar  Bbar        (PER = -1: omega = 0; PER = 0: omega = inf; no Bbar)
//! NAME.3    PER  BETA  I  Mod  Pha  Re  Im       (Pha in degrees)
//! NAME.hst  I  J  Cbar
//! ```
//!
//! Dimensional values, with `L` the length scale ULEN and `e_i` = 1 for the rotations 4..6,
//! 0 otherwise (surge, sway, heave, generalized modes):
//!
//! `A_ij = Abar rho L^(3 + e_i + e_j)`, `B_ij = Bbar rho omega L^(3 + e_i + e_j)`,
//! `X_i = Xbar rho g a L^(2 + e_i)`, `C_ij = Cbar rho g L^(2 + e_i + e_j)`.
//!
//! WAMIT's time factor is `exp(+i omega t)`, ours: `A~ = A - i B / omega` and `X = Re + i Im`
//! as written; a file in `exp(-i omega t)` (older HAMS builds) is read with
//! [`WamitParams::conjugate`]. `A_ij` is the force in mode I from motion in mode J.
//! BETA is the direction the waves travel to, from +x (0 = towards +x), as our heading.
//!
//! What real files do and the reader accepts: header lines (skipped while no number row has
//! been seen), tabs or spaces, `E` or Fortran `D` exponents, any row order, `.1` entries left
//! out (zero by a symmetry plane, or a mode switched off): missing pairs are zero as long as
//! every frequency leaves out the same ones. What it refuses, naming file, line and field:
//! a non-finite or unparsable number, a short row, a duplicated entry, two frequencies
//! within 1e-6 of each other, a frequency block with fewer entries than the others (a
//! truncated file), a `.3` row whose modulus and phase disagree with its real and imaginary
//! parts, and every size beyond the limits below, before allocating.

mod drift;
mod rows;
mod writer;

pub use drift::read_drift;
pub use writer::{write, WamitFiles};

use super::{Database, DatabaseError};
use crate::fmu::DofUnit;
use nalgebra::DMatrix;
use num_complex::Complex64;
use rows::Rows;
use std::collections::{BTreeMap, BTreeSet};

/// Largest file read, in bytes (256 MiB).
pub const MAX_FILE_BYTES: u64 = 256 << 20;
/// Largest number of data rows in one file.
pub(crate) const MAX_ROWS: usize = 5_000_000;
/// Largest mode index (100 bodies of 6 DOFs, or generalized modes).
pub const MAX_MODE_INDEX: usize = 600;
/// Largest number of matrix entries kept (frequencies x modes^2): 800 MB of complex numbers.
pub const MAX_ENTRIES: usize = 50_000_000;
/// Largest number of leading header lines skipped.
const MAX_HEADER_LINES: usize = 100;
/// Two frequencies closer than this (relative) are one frequency written twice.
pub(super) const SAME_FREQUENCY: f64 = 1e-6;
/// A `.3` frequency matches a `.1` one within this (relative): the files' 7 digits.
const MATCHING_FREQUENCY: f64 = 1e-4;
/// Modulus and phase must agree with Re and Im within these (the files' digits).
const MODULUS_AGREEMENT: f64 = 1e-4;
const PHASE_AGREEMENT_DEG: f64 = 0.05;

/// Names of the rigid modes 1..6.
pub const RIGID_MODES: [&str; 6] = ["surge", "sway", "heave", "roll", "pitch", "yaw"];

/// What the first column of `.1` and `.3` holds (WAMIT's `IPEROUT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrequencyColumn {
    /// Period T in s (WAMIT's default, IPEROUT = 1); limits PER = -1 (omega = 0) and
    /// PER = 0 (omega = inf).
    Period,
    /// Circular frequency omega in rad/s (IPEROUT = 2); limits as HAMS writes them: 0 is
    /// omega = 0, -1 is omega = inf.
    RadPerSecond,
    /// Frequency in Hz; limits as [`FrequencyColumn::RadPerSecond`].
    Hertz,
}

/// The first column WAMIT's configuration file `NAME.cfg` declares (`IPEROUT=n`, or `IPERIO=n`
/// for input and output alike): `None` when it declares none (WAMIT's default, the period).
///
/// # Errors
/// A declared column this reader does not take (3 and 4: nondimensional wavenumbers), or an
/// unreadable value, naming the line.
pub(crate) fn frequency_column_of_cfg(
    source: Source,
) -> Result<Option<FrequencyColumn>, DatabaseError> {
    let mut found = None;
    for (index, line) in source.text.lines().enumerate() {
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        let key = key.trim().to_ascii_uppercase();
        if key != "IPEROUT" && key != "IPERIO" {
            continue;
        }
        let token = value.split_whitespace().next().unwrap_or("");
        let column = match token {
            "1" => FrequencyColumn::Period,
            "2" => FrequencyColumn::RadPerSecond,
            "3" | "4" => {
                return Err(DatabaseError::at(
                    source.name,
                    index + 1,
                    format!(
                        "{key}={token}: the first column is a nondimensional wavenumber, which \
                         this reader does not take; rerun WAMIT with {key}=1 (period) or 2 (rad/s)"
                    ),
                ))
            }
            _ => {
                return Err(DatabaseError::at(
                    source.name,
                    index + 1,
                    format!("{key}='{token}': expected 1 (period) or 2 (rad/s)"),
                ))
            }
        };
        // IPEROUT wins over IPERIO.
        if key == "IPEROUT" || found.is_none() {
            found = Some(column);
        }
    }
    Ok(found)
}

/// How to read a WAMIT file set, with documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct WamitParams {
    /// ULEN, the length scale of the nondimensional values, m. Default 1 (Capytaine,
    /// BEMRosetta and most WAMIT runs).
    pub length_scale: f64,
    /// Water density the SI values are given for, kg/m^3 (the files do not depend on it).
    pub rho: f64,
    /// Gravity, m/s^2.
    pub g: f64,
    /// The first column. Default [`FrequencyColumn::Period`].
    pub frequency_column: FrequencyColumn,
    /// The files are in `exp(-i omega t)`: conjugate the exciting force. Default false.
    pub conjugate: bool,
}

impl Default for WamitParams {
    fn default() -> Self {
        WamitParams {
            length_scale: 1.0,
            rho: crate::fmu::description::DEFAULT_RHO,
            g: crate::fmu::description::DEFAULT_G,
            frequency_column: FrequencyColumn::Period,
            conjugate: false,
        }
    }
}

/// One file's text and the name errors use.
#[derive(Clone, Copy, Debug)]
pub struct Source<'a> {
    /// File name as the user gave it.
    pub name: &'a str,
    /// Its text.
    pub text: &'a str,
}

/// The three files' contents (`.3`, `.hst` optional).
#[derive(Clone, Copy, Debug)]
pub struct WamitTexts<'a> {
    /// `NAME.1`.
    pub radiation: Source<'a>,
    /// `NAME.3`.
    pub excitation: Option<Source<'a>>,
    /// `NAME.hst`.
    pub hydrostatics: Option<Source<'a>>,
}

/// A frequency of the first column: zero, infinite or finite (rad/s).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Frequency {
    Zero,
    Infinite,
    Finite(f64),
}

/// A number as the files write it (`1.5E+02`, `0.15E+03`, Fortran `1.5D+02`).
fn parse_number(token: &str) -> Option<f64> {
    if token.len() > 64 {
        return None;
    }
    let value = token
        .parse::<f64>()
        .ok()
        .or_else(|| token.replace(['D', 'd'], "E").parse::<f64>().ok())?;
    // Rust accepts "inf" and "nan"; the files never write them.
    let alphabetic = token
        .chars()
        .any(|c| c.is_ascii_alphabetic() && !matches!(c, 'e' | 'E' | 'd' | 'D'));
    (!alphabetic).then_some(value)
}

/// Mode names a header line gives as `modes: 3=heave 5=pitch 7=vb1` (what [`write`] puts
/// there; WAMIT itself names none). Only names of identifier form are taken.
fn header_names(header: &[&str]) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for line in header {
        let Some((_, list)) = line.split_once("modes:") else {
            continue;
        };
        for pair in list.split_whitespace() {
            let Some((index, name)) = pair.split_once('=') else {
                continue;
            };
            let identifier = name.len() <= 64
                && name.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if let (Ok(index), true) = (index.parse::<usize>(), identifier) {
                out.push((index, name.to_string()));
            }
        }
    }
    out
}

/// WAMIT mode indices of DOF names: `surge` .. `yaw` are 1..6, every other DOF (an elastic or
/// generalized mode) 7, 8, ... in its order.
pub fn mode_indices(names: &[String]) -> Vec<usize> {
    let mut next = 7;
    names
        .iter()
        .map(|name| match RIGID_MODES.iter().position(|r| r == name) {
            Some(k) => k + 1,
            None => {
                next += 1;
                next - 1
            }
        })
        .collect()
}

/// `e_i`: 1 for the rotations 4..6, 0 for the translations and the generalized modes.
pub(crate) fn length_exponent(mode: usize) -> u8 {
    u8::from((4..=6).contains(&mode))
}

/// The DOF name of mode index `mode` (1-based): `surge` .. `yaw`, then `mode7`, `mode8`, ...
pub(crate) fn mode_name(mode: usize) -> String {
    match RIGID_MODES.get(mode.wrapping_sub(1)) {
        Some(name) => (*name).to_string(),
        None => format!("mode{mode}"),
    }
}

/// An entry key: the frequency's bits (finite ones) and the pair.
type PairKey = (usize, usize);

struct RadiationRows {
    /// Finite frequencies (rad/s, as read) with their entries (pair -> (A, B, line)).
    finite: BTreeMap<u64, BTreeMap<PairKey, (f64, f64, usize)>>,
    infinite: BTreeMap<PairKey, (f64, usize)>,
    zero: BTreeMap<PairKey, (f64, usize)>,
    modes: BTreeSet<usize>,
}

fn read_radiation(rows: &Rows, params: &WamitParams) -> Result<RadiationRows, DatabaseError> {
    let mut out = RadiationRows {
        finite: BTreeMap::new(),
        infinite: BTreeMap::new(),
        zero: BTreeMap::new(),
        modes: BTreeSet::new(),
    };
    for (line, fields) in &rows.rows {
        let line = *line;
        rows.columns(line, fields, &[4, 5], "PER I J A [B]")?;
        let per = rows.number(line, fields, 0, "PER")?;
        let frequency = rows.frequency(line, per, params.frequency_column)?;
        let i = rows.mode(line, fields, 1, "I")?;
        let j = rows.mode(line, fields, 2, "J")?;
        let a = rows.number(line, fields, 3, "A")?;
        out.modes.insert(i);
        out.modes.insert(j);
        let duplicate = |previous: usize| {
            rows.error(
                line,
                format!(
                    "entry ({i},{j}) at PER {per} is written twice (lines {previous} and {line})"
                ),
            )
        };
        match frequency {
            Frequency::Zero | Frequency::Infinite => {
                let map = if frequency == Frequency::Zero {
                    &mut out.zero
                } else {
                    &mut out.infinite
                };
                if let Some((_, previous)) = map.insert((i, j), (a, line)) {
                    return Err(duplicate(previous));
                }
            }
            Frequency::Finite(omega) => {
                if fields.len() != 5 {
                    return Err(rows.error(
                        line,
                        format!("4 fields at PER {per}: a finite frequency needs A and B"),
                    ));
                }
                let b = rows.number(line, fields, 4, "B")?;
                let block = out.finite.entry(omega.to_bits()).or_default();
                if let Some((_, _, previous)) = block.insert((i, j), (a, b, line)) {
                    return Err(duplicate(previous));
                }
            }
        }
    }
    Ok(out)
}

/// The first line of a block, for messages.
fn first_line<V>(block: &BTreeMap<PairKey, V>, line: impl Fn(&V) -> usize) -> usize {
    block.values().map(line).min().unwrap_or(0)
}

/// Reads a WAMIT file set into SI ([`Database`]) for `params`. `A_inf` is the `omega = inf`
/// rows' (zero when the file has none: [`Database::notes`] then says so and the caller
/// estimates it); no spike is removed here.
///
/// # Errors
/// Every malformed, truncated, inconsistent or oversized input, naming file, line and field.
pub fn read(
    name: &str,
    texts: WamitTexts,
    params: &WamitParams,
) -> Result<ImportedWamit, DatabaseError> {
    let radiation_file = texts.radiation.name;
    if !(params.length_scale.is_finite() && params.length_scale > 0.0) {
        return Err(DatabaseError::file(
            radiation_file,
            format!(
                "length scale {} m: it must be finite and > 0",
                params.length_scale
            ),
        ));
    }
    let rows = Rows::read(texts.radiation)?;
    let radiation = read_radiation(&rows, params)?;
    if radiation.finite.is_empty() {
        return Err(DatabaseError::file(
            radiation_file,
            "no row at a finite frequency (only the limits)".to_string(),
        ));
    }
    let modes: Vec<usize> = radiation.modes.iter().copied().collect();
    if modes.iter().any(|&m| m > 6) && params.length_scale != 1.0 {
        return Err(DatabaseError::file(
            radiation_file,
            format!(
                "modes beyond 6 (generalized modes or further bodies) with a length scale of {} m: \
                 the WAMIT format does not fix their length exponents; use files written with \
                 ULEN = 1",
                params.length_scale
            ),
        ));
    }
    let n = modes.len();
    let count = radiation.finite.len();
    if n.saturating_mul(n).saturating_mul(count + 2) > MAX_ENTRIES {
        return Err(DatabaseError::file(
            radiation_file,
            format!("{count} frequencies x {n} modes^2 exceed {MAX_ENTRIES} entries"),
        ));
    }
    // Frequencies ascending; near-duplicates refused.
    let mut omegas: Vec<(f64, u64)> = radiation
        .finite
        .keys()
        .map(|&bits| (f64::from_bits(bits), bits))
        .collect();
    omegas.sort_by(|a, b| a.0.total_cmp(&b.0));
    for pair in omegas.windows(2) {
        if (pair[1].0 - pair[0].0) <= SAME_FREQUENCY * pair[1].0 {
            let line_of = |bits: u64| first_line(&radiation.finite[&bits], |v| v.2);
            return Err(DatabaseError::at(
                radiation_file,
                line_of(pair[1].1),
                format!(
                    "frequencies {} and {} rad/s (lines {} and {}) are the same to 1e-6: a \
                     frequency written twice",
                    pair[0].0,
                    pair[1].0,
                    line_of(pair[0].1),
                    line_of(pair[1].1)
                ),
            ));
        }
    }
    // Every finite block must hold the same pairs (left-out pairs are symmetry zeros).
    let all_pairs: BTreeSet<PairKey> = radiation
        .finite
        .values()
        .flat_map(|block| block.keys().copied())
        .collect();
    for (omega, bits) in &omegas {
        let block = &radiation.finite[bits];
        if block.len() != all_pairs.len() {
            let missing = all_pairs.iter().find(|p| !block.contains_key(p)).copied();
            let (i, j) = missing.unwrap_or((0, 0));
            return Err(DatabaseError::at(
                radiation_file,
                first_line(block, |v| v.2),
                format!(
                    "the block at omega = {omega} rad/s has {} entries where the file's blocks \
                     together have {} (entry ({i},{j}) missing): a truncated or incomplete file",
                    block.len(),
                    all_pairs.len()
                ),
            ));
        }
    }
    let position: BTreeMap<usize, usize> = modes.iter().enumerate().map(|(k, &m)| (m, k)).collect();
    let l = params.length_scale;
    let exponent =
        |i: usize, j: usize| 3 + i32::from(length_exponent(i)) + i32::from(length_exponent(j));
    let rho = params.rho;
    let mut notes = Vec::new();
    let mut added_mass = Vec::with_capacity(count);
    for (_, bits) in &omegas {
        let mut a = DMatrix::<Complex64>::zeros(n, n);
        for (&(i, j), &(abar, bbar, _)) in &radiation.finite[bits] {
            let scale = rho * l.powi(exponent(i, j));
            // A~ = A - i B / omega with B = Bbar rho omega L^k.
            a[(position[&i], position[&j])] = Complex64::new(abar * scale, -bbar * scale);
        }
        added_mass.push(a);
    }
    let limit = |map: &BTreeMap<PairKey, (f64, usize)>| {
        let mut m = DMatrix::<f64>::zeros(n, n);
        for (&(i, j), &(abar, _)) in map {
            m[(position[&i], position[&j])] = abar * rho * l.powi(exponent(i, j));
        }
        m
    };
    let added_mass_inf = if radiation.infinite.is_empty() {
        None
    } else {
        Some(limit(&radiation.infinite))
    };
    let added_mass_zero = (!radiation.zero.is_empty()).then(|| limit(&radiation.zero));
    let omega: Vec<f64> = omegas.iter().map(|(w, _)| *w).collect();

    let named = header_names(&rows.header);
    let dof_names: Vec<String> = modes
        .iter()
        .map(|&m| {
            let given = named.iter().find(|(k, _)| *k == m && m > 6);
            match given {
                // A rigid mode's name would make the generalized mode rigid downstream.
                Some((_, name)) if RIGID_MODES.contains(&name.as_str()) => {
                    notes.push(format!(
                        "{radiation_file}: the header names generalized mode {m} '{name}', a \
                         rigid mode's name: kept as '{}'",
                        mode_name(m)
                    ));
                    mode_name(m)
                }
                Some((_, name)) => name.clone(),
                None => mode_name(m),
            }
        })
        .collect();
    if let Some(k) = (1..dof_names.len()).find(|&k| dof_names[..k].contains(&dof_names[k])) {
        return Err(DatabaseError::file(
            radiation_file,
            format!("the header names two modes '{}'", dof_names[k]),
        ));
    }
    let dof_units: Vec<DofUnit> = modes
        .iter()
        .zip(&dof_names)
        .map(|(&m, name)| DofUnit::new(name, length_exponent(m), (4..=6).contains(&m)))
        .collect();

    let stiffness = match texts.hydrostatics {
        Some(source) => Some(read_hydrostatics(source, &position, params, &mut notes)?),
        None => None,
    };
    let (headings, excitation, kept) = match texts.excitation {
        Some(source) => read_excitation(source, &omega, &position, params, &mut notes)?,
        None => (Vec::new(), Vec::new(), vec![true; omega.len()]),
    };
    let mut omega = omega;
    let mut excitation = excitation;
    super::retain_flagged(&mut omega, &kept);
    super::retain_flagged(&mut added_mass, &kept);
    super::retain_flagged(&mut excitation, &kept);
    let database = Database {
        name: name.to_string(),
        source: format!("imported from WAMIT files ({radiation_file})"),
        dof_names,
        dof_units,
        rho,
        g: params.g,
        omega,
        added_mass,
        added_mass_inf: added_mass_inf
            .clone()
            .unwrap_or_else(|| DMatrix::zeros(n, n)),
        headings,
        excitation,
        froude_krylov: Vec::new(),
        // Set from the restoring by import::finish.
        excitation_long_wave: None,
        stiffness_hydrostatic: stiffness.unwrap_or_else(|| DMatrix::zeros(n, n)),
        reference_length: l,
        failures: Vec::new(),
        warnings: Vec::new(),
        notes,
        noise: DMatrix::zeros(n, n),
        body_panels: Vec::new(),
        drift: Vec::new(),
        drift_headings: Vec::new(),
        // WAMIT's files do not state the depth: deep unless the user says otherwise.
        depth: crate::units::WaterDepth::Infinite,
    };
    if let Some(what) = database.first_non_finite() {
        return Err(DatabaseError::file(
            radiation_file,
            format!("{what} is not finite in SI (a value too large for its scale)"),
        ));
    }
    Ok(ImportedWamit {
        database,
        added_mass_inf_given: added_mass_inf.is_some(),
        added_mass_zero,
        has_excitation: texts.excitation.is_some(),
        has_hydrostatics: texts.hydrostatics.is_some(),
        modes,
    })
}

/// What [`read`] gives: the database and what the files held.
#[derive(Clone, Debug)]
pub struct ImportedWamit {
    /// The SI database (`A_inf` zero when not given).
    pub database: Database,
    /// Whether the `.1` file had `omega = inf` rows.
    pub added_mass_inf_given: bool,
    /// The `omega = 0` rows, when given (SI).
    pub added_mass_zero: Option<DMatrix<f64>>,
    /// Whether a `.3` file was read.
    pub has_excitation: bool,
    /// Whether a `.hst` file was read.
    pub has_hydrostatics: bool,
    /// The WAMIT mode index of each DOF, in order.
    pub modes: Vec<usize>,
}

fn read_hydrostatics(
    source: Source,
    position: &BTreeMap<usize, usize>,
    params: &WamitParams,
    notes: &mut Vec<String>,
) -> Result<DMatrix<f64>, DatabaseError> {
    let rows = Rows::read(source)?;
    let n = position.len();
    let mut c = DMatrix::<f64>::zeros(n, n);
    let mut seen: BTreeMap<PairKey, usize> = BTreeMap::new();
    let mut dropped = BTreeSet::new();
    let l = params.length_scale;
    for (line, fields) in &rows.rows {
        let line = *line;
        rows.columns(line, fields, &[3], "I J C")?;
        let i = rows.mode(line, fields, 0, "I")?;
        let j = rows.mode(line, fields, 1, "J")?;
        let value = rows.number(line, fields, 2, "C")?;
        if let Some(previous) = seen.insert((i, j), line) {
            return Err(rows.error(
                line,
                format!("entry ({i},{j}) is written twice (lines {previous} and {line})"),
            ));
        }
        match (position.get(&i), position.get(&j)) {
            (Some(&p), Some(&q)) => {
                let k = 2 + i32::from(length_exponent(i)) + i32::from(length_exponent(j));
                c[(p, q)] = value * params.rho * params.g * l.powi(k);
            }
            _ if value != 0.0 => {
                dropped.insert(if position.contains_key(&i) { j } else { i });
            }
            _ => {}
        }
    }
    if !dropped.is_empty() {
        let list: Vec<String> = dropped.iter().map(|m| mode_name(*m)).collect();
        notes.push(format!(
            "{}: the restoring of {} is left out: the radiation file has no such mode",
            source.name,
            list.join(", ")
        ));
    }
    Ok(c)
}

/// The excitation rows on the radiation file's frequencies: headings (ascending), one matrix
/// (modes x headings) per frequency, and which frequencies have every entry.
/// The index of the radiation file's frequency `w` matches within the files' digits
/// ([`MATCHING_FREQUENCY`]); `omega` ascending.
fn matching_frequency(omega: &[f64], w: f64) -> Option<usize> {
    let k = omega.partition_point(|x| *x < w * (1.0 - MATCHING_FREQUENCY));
    (k < omega.len() && (omega[k] - w).abs() <= MATCHING_FREQUENCY * w).then_some(k)
}

/// Notes of the rows a companion file (`.3`, `.8`, `.9`) of `file` holds that the radiation
/// file has no place for: modes it lacks (`what` of them left out) and periods it lacks (their
/// bits).
fn note_left_out(
    notes: &mut Vec<String>,
    file: &str,
    what: &str,
    foreign_modes: &BTreeSet<usize>,
    unmatched_periods: &BTreeSet<u64>,
) {
    if !foreign_modes.is_empty() {
        let list: Vec<String> = foreign_modes.iter().map(|m| mode_name(*m)).collect();
        notes.push(format!(
            "{file}: {what} of {} is left out: the radiation file has no such mode",
            list.join(", ")
        ));
    }
    if !unmatched_periods.is_empty() {
        let list: Vec<String> = unmatched_periods
            .iter()
            .map(|b| f64::from_bits(*b).to_string())
            .collect();
        notes.push(format!(
            "{file}: rows at PER {} left out: the radiation file has no such frequency",
            list.join(", ")
        ));
    }
}

#[allow(clippy::type_complexity)]
fn read_excitation(
    source: Source,
    omega: &[f64],
    position: &BTreeMap<usize, usize>,
    params: &WamitParams,
    notes: &mut Vec<String>,
) -> Result<(Vec<f64>, Vec<DMatrix<Complex64>>, Vec<bool>), DatabaseError> {
    let rows = Rows::read(source)?;
    let n = position.len();
    // Headings first (bounded), then the values.
    let mut headings: Vec<f64> = Vec::new();
    let mut parsed = Vec::with_capacity(rows.rows.len());
    for (line, fields) in &rows.rows {
        let line = *line;
        rows.columns(line, fields, &[7], "PER BETA I Mod Pha Re Im")?;
        let per = rows.number(line, fields, 0, "PER")?;
        let frequency = rows.frequency(line, per, params.frequency_column)?;
        let Frequency::Finite(w) = frequency else {
            return Err(rows.error(
                line,
                format!("field PER (column 1): {per} is a limit; the exciting force has none"),
            ));
        };
        let beta = rows.number(line, fields, 1, "BETA")?;
        let mode = rows.mode(line, fields, 2, "I")?;
        let modulus = rows.number(line, fields, 3, "Mod")?;
        let phase = rows.number(line, fields, 4, "Pha")?;
        let re = rows.number(line, fields, 5, "Re")?;
        let im = rows.number(line, fields, 6, "Im")?;
        let from_re_im = re.hypot(im);
        let scale = modulus.abs().max(from_re_im);
        let modulus_ok = (modulus - from_re_im).abs() <= MODULUS_AGREEMENT * scale + 1e-30;
        let phase_gap = {
            let d = (im.atan2(re).to_degrees() - phase).rem_euclid(360.0);
            d.min(360.0 - d)
        };
        // The phase of a zero entry is arbitrary (WAMIT writes 90).
        let phase_ok = from_re_im <= 1e-5 * scale.max(1e-300)
            || phase_gap <= PHASE_AGREEMENT_DEG
            || from_re_im == 0.0;
        if !(modulus_ok && phase_ok) {
            return Err(rows.error(
                line,
                format!(
                    "Mod {modulus} and Pha {phase} deg disagree with Re {re} and Im {im} (modulus \
                     {from_re_im}, phase {:.3} deg): a hand-edited or mixed row",
                    im.atan2(re).to_degrees()
                ),
            ));
        }
        if !headings.contains(&beta) {
            // Directions: two equal modulo 360 degrees would be one table column twice.
            let same = |b: &&f64| crate::waves::same_direction(beta, **b);
            if let Some(b) = headings.iter().find(same) {
                return Err(rows.error(
                    line,
                    format!(
                        "field BETA: headings {b} and {beta} are the same direction (equal \
                         modulo 360 degrees)"
                    ),
                ));
            }
            if headings.len() == super::MAX_HEADINGS {
                return Err(rows.error(
                    line,
                    format!(
                        "field BETA: more than {} headings (the FMU's table holds at most {})",
                        super::MAX_HEADINGS,
                        super::MAX_HEADINGS
                    ),
                ));
            }
            headings.push(beta);
        }
        parsed.push((line, per, w, beta, mode, Complex64::new(re, im)));
    }
    headings.sort_by(f64::total_cmp);
    let h = headings.len();
    let mut excitation = vec![DMatrix::<Complex64>::zeros(n, h); omega.len()];
    let mut seen: BTreeMap<(usize, usize, usize), usize> = BTreeMap::new();
    let mut unmatched = BTreeSet::new();
    let mut foreign_modes = BTreeSet::new();
    let l = params.length_scale;
    for (line, per, w, beta, mode, value) in parsed {
        // The radiation frequency this row belongs to, within the files' digits.
        let Some(k) = matching_frequency(omega, w) else {
            unmatched.insert(per.to_bits());
            continue;
        };
        let Some(&p) = position.get(&mode) else {
            foreign_modes.insert(mode);
            continue;
        };
        let b = headings.iter().position(|x| *x == beta).unwrap_or(0);
        if let Some(previous) = seen.insert((k, b, p), line) {
            return Err(rows.error(
                line,
                format!(
                    "mode {mode} at PER {per}, BETA {beta} is written twice (lines {previous} and \
                     {line})"
                ),
            ));
        }
        let value = if params.conjugate {
            value.conj()
        } else {
            value
        };
        excitation[k][(p, b)] =
            value * (params.rho * params.g * l.powi(2 + i32::from(length_exponent(mode))));
    }
    note_left_out(
        notes,
        source.name,
        "the exciting force",
        &foreign_modes,
        &unmatched,
    );
    let full = n * h;
    let kept: Vec<bool> = (0..omega.len())
        .map(|k| (0..h).all(|b| (0..n).all(|p| seen.contains_key(&(k, b, p)))))
        .collect();
    if kept.iter().all(|k| !k) {
        return Err(DatabaseError::file(
            source.name,
            format!(
                "no frequency of the radiation file has all {full} exciting forces ({n} modes x {h} \
                 headings): files of different runs?"
            ),
        ));
    }
    let missing: Vec<String> = omega
        .iter()
        .zip(&kept)
        .filter(|(_, k)| !**k)
        .map(|(w, _)| format!("{:.6}", w))
        .collect();
    if !missing.is_empty() {
        notes.push(format!(
            "{}: omega = {} rad/s left out: not every mode and heading has its exciting force there",
            source.name,
            missing.join(", ")
        ));
    }
    Ok((headings, excitation, kept))
}
