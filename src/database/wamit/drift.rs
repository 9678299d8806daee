//! WAMIT mean drift files beside `NAME.1`: `NAME.8` (momentum conservation: the horizontal
//! force and the yaw moment) and `NAME.9` (pressure integration: every mode).
//!
//! ```text
//! NAME.8, NAME.9    PER  BETA1  BETA2  I  Mod  Pha  Re  Im     (Pha in degrees)
//! ```
//!
//! `D_i = Dbar rho g L^(1 + e_i)` per unit wave amplitude squared (`L` = ULEN, `e_i` = 1 for
//! the rotations 4..6), `a^2 D_i` the mean force of a regular wave of amplitude `a`. A mean
//! drift is real: `Re` is the value, `Im` must be zero to the files' digits. Only the rows of
//! one wave direction (`BETA1 = BETA2`) are mean drift; bidirectional rows and body-fixed
//! moments (negative mode index) are left out, each said in a note. With both files, `.8`
//! gives the modes it has (the far field is the more accurate) and `.9` the others.
//!
//! Refused, naming file, line and field: a short or long row, a number that is not finite, a
//! limit frequency, a mode index out of range, a row written twice, a value with an
//! imaginary part, more headings than the FMU's table holds. A drift file that does not
//! cover every frequency and heading of the data for its modes is left out with a note: the
//! database keeps its first-order coefficients.

use super::rows::Rows;
use super::MODULUS_AGREEMENT;
use super::{length_exponent, mode_name, DatabaseError, Frequency, Source, WamitParams};
use crate::database::Database;
use nalgebra::DMatrix;
use std::collections::{BTreeMap, BTreeSet};

/// One drift file read: its headings (ascending) and, per mode it holds, `D` at every
/// frequency of the database and heading (SI).
struct DriftFile {
    headings: Vec<f64>,
    values: BTreeMap<usize, DMatrix<f64>>,
}

/// Reads the mean drift of `NAME.8` (`momentum`) and `NAME.9` (`pressure`) into `database`
/// (its frequencies, the WAMIT modes `modes` of its DOFs in order), with notes of what was
/// left out. Without either file the database stays without drift.
///
/// # Errors
/// A malformed row (module docs).
pub fn read_drift(
    database: &mut Database,
    modes: &[usize],
    momentum: Option<Source>,
    pressure: Option<Source>,
    params: &WamitParams,
) -> Result<(), DatabaseError> {
    let mut notes = Vec::new();
    let read = |source: Option<Source>, notes: &mut Vec<String>| {
        source
            .map(|s| read_file(s, &database.omega, modes, params, notes))
            .transpose()
    };
    let momentum_file = read(momentum, &mut notes)?.flatten();
    let pressure_file = read(pressure, &mut notes)?.flatten();
    let names = [momentum, pressure].map(|s| s.map(|s| s.name).unwrap_or_default());
    let (headings, values) = match (momentum_file, pressure_file) {
        (None, None) => {
            database.notes.extend(notes);
            return Ok(());
        }
        (Some(one), None) | (None, Some(one)) => (one.headings, one.values),
        (Some(momentum), Some(pressure)) => {
            if momentum.headings != pressure.headings {
                notes.push(format!(
                    "{}: headings {:?} differ from {}'s {:?}: the pressure file alone is used",
                    names[0], momentum.headings, names[1], pressure.headings
                ));
                (pressure.headings, pressure.values)
            } else {
                let mut values = pressure.values;
                values.extend(momentum.values);
                (momentum.headings, values)
            }
        }
    };
    let n = modes.len();
    let missing: Vec<String> = modes
        .iter()
        .filter(|m| !values.contains_key(m))
        .map(|&m| mode_name(m))
        .collect();
    if !missing.is_empty() {
        notes.push(format!(
            "no mean drift for {} in the drift files: zero",
            missing.join(", ")
        ));
    }
    let h = headings.len();
    database.drift = (0..database.omega.len())
        .map(|k| {
            DMatrix::from_fn(n, h, |p, b| {
                values.get(&modes[p]).map_or(0.0, |m| m[(k, b)])
            })
        })
        .collect();
    database.drift_headings = headings;
    database.notes.extend(notes);
    Ok(())
}

/// One file's mean drift (module docs); `None` (with a note) when it does not cover every
/// frequency of the data for every heading of a mode it holds.
fn read_file(
    source: Source,
    omega: &[f64],
    modes: &[usize],
    params: &WamitParams,
    notes: &mut Vec<String>,
) -> Result<Option<DriftFile>, DatabaseError> {
    let rows = Rows::read(source)?;
    let mut headings: Vec<f64> = Vec::new();
    let mut parsed = Vec::new();
    let (mut bidirectional, mut body_fixed) = (0usize, 0usize);
    for (line, fields) in &rows.rows {
        let line = *line;
        rows.columns(line, fields, &[8], "PER BETA1 BETA2 I Mod Pha Re Im")?;
        let per = rows.number(line, fields, 0, "PER")?;
        let Frequency::Finite(w) = rows.frequency(line, per, params.frequency_column)? else {
            return Err(rows.error(
                line,
                format!("field PER (column 1): {per} is a limit; the mean drift has none"),
            ));
        };
        let beta1 = rows.number(line, fields, 1, "BETA1")?;
        let beta2 = rows.number(line, fields, 2, "BETA2")?;
        if fields[3].starts_with('-') {
            body_fixed += 1;
            continue;
        }
        let mode = rows.mode(line, fields, 3, "I")?;
        let modulus = rows.number(line, fields, 4, "Mod")?;
        rows.number(line, fields, 5, "Pha")?;
        let re = rows.number(line, fields, 6, "Re")?;
        let im = rows.number(line, fields, 7, "Im")?;
        if beta1 != beta2 {
            bidirectional += 1;
            continue;
        }
        let scale = modulus.abs().max(re.abs());
        if im.abs() > MODULUS_AGREEMENT * scale + 1e-30 {
            return Err(rows.error(
                line,
                format!(
                    "field Im (column 8): {im} where a mean drift is real (Re {re}): a \
                     difference-frequency (QTF) file?"
                ),
            ));
        }
        if (modulus - re.abs()).abs() > MODULUS_AGREEMENT * scale + 1e-30 {
            return Err(rows.error(
                line,
                format!(
                    "Mod {modulus} disagrees with |Re| = {}: a hand-edited row",
                    re.abs()
                ),
            ));
        }
        if !headings.contains(&beta1) {
            let same = |b: &&f64| crate::waves::same_direction(beta1, **b);
            if let Some(b) = headings.iter().find(same) {
                return Err(rows.error(
                    line,
                    format!(
                        "field BETA1: headings {b} and {beta1} are the same direction (equal \
                         modulo 360 degrees)"
                    ),
                ));
            }
            if headings.len() == super::super::MAX_HEADINGS {
                return Err(rows.error(
                    line,
                    format!(
                        "field BETA1: more than {} headings (the FMU's table holds at most as many)",
                        super::super::MAX_HEADINGS
                    ),
                ));
            }
            headings.push(beta1);
        }
        parsed.push((line, per, w, beta1, mode, re));
    }
    if body_fixed > 0 {
        notes.push(format!(
            "{}: {body_fixed} rows of body-fixed moments (negative mode index) left out: the \
             global ones are used",
            source.name
        ));
    }
    if bidirectional > 0 {
        notes.push(format!(
            "{}: {bidirectional} bidirectional rows (BETA1 != BETA2) left out: the mean drift of \
             one wave direction is used",
            source.name
        ));
    }
    headings.sort_by(f64::total_cmp);
    let h = headings.len();
    let l = params.length_scale;
    let scale = |mode: usize| params.rho * params.g * l.powi(1 + i32::from(length_exponent(mode)));
    let mut values: BTreeMap<usize, DMatrix<f64>> = BTreeMap::new();
    let mut seen: BTreeMap<(usize, usize, usize), usize> = BTreeMap::new();
    let (mut unmatched, mut foreign) = (BTreeSet::new(), BTreeSet::new());
    for (line, per, w, beta, mode, re) in parsed {
        let Some(k) = super::matching_frequency(omega, w) else {
            unmatched.insert(per.to_bits());
            continue;
        };
        if !modes.contains(&mode) {
            foreign.insert(mode);
            continue;
        }
        let b = headings.iter().position(|x| *x == beta).unwrap_or(0);
        if let Some(previous) = seen.insert((k, b, mode), line) {
            return Err(rows.error(
                line,
                format!(
                    "mode {mode} at PER {per}, BETA {beta} is written twice (lines {previous} and \
                     {line})"
                ),
            ));
        }
        values
            .entry(mode)
            .or_insert_with(|| DMatrix::zeros(omega.len(), h))[(k, b)] = re * scale(mode);
    }
    super::note_left_out(notes, source.name, "the mean drift", &foreign, &unmatched);
    for &mode in values.keys() {
        let holes = (0..omega.len())
            .flat_map(|k| (0..h).map(move |b| (k, b)))
            .filter(|&(k, b)| !seen.contains_key(&(k, b, mode)))
            .count();
        if holes > 0 {
            notes.push(format!(
                "{}: mean drift left out: {} lacks {holes} of its {} values (frequencies of the \
                 radiation file x headings): files of different runs?",
                source.name,
                mode_name(mode),
                omega.len() * h
            ));
            return Ok(None);
        }
    }
    if values.is_empty() {
        notes.push(format!(
            "{}: no mean drift of one wave direction for the radiation file's modes",
            source.name
        ));
        return Ok(None);
    }
    Ok(Some(DriftFile { headings, values }))
}
