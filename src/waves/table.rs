//! The excitation table written by `fmu-pack sweep HULL --excitation FILE` (docs/DESIGN.md), read
//! by a strict, bounded parser, and its interpolation in `kR`.
//!
//! ```text
//! # modes: sway heave roll ...          (required)
//! # convention: exp(+i omega t)         (required, exactly)
//! # R: 1 m                              (required: the reference radius)
//! # length exponents: 0 0 1 ...         (required: e_j per mode)
//! # depth: inf                         (optional: h/R, or `inf`; absent: deep water)
//! # hull: ..., # H/R: ..., other '#' lines: kept (hull) or ignored
//! kR,j,heading,re,im
//! ```
//!
//! `re + i im = X_j / (rho g a R^(1 + e_j))`; in SI `X_j = (re + i im) rho g R^(1 + e_j)` at
//! `omega = sqrt(kR g / R)`. `kR = 0` rows are the long-wave limit. Every (kR, heading) must
//! hold each `j` exactly once.
//!
//! One writer of the rows ([`write_excitation_rows`]) serves a section's sweep and a
//! whole-body database.
//!
//! Interpolation: cubic Hermite in `ln kR` over the positive `kR` (each node's slope from the
//! polynomial through the five nodes around it; linear with two nodes); below
//! the band, linear in `kR` towards the `kR = 0` rows when the table has them.

use super::WaveError;
use crate::units::WaterDepth;
use nalgebra::DMatrix;
use num_complex::Complex64;
use std::io::Write;

/// Largest table accepted, in bytes of text (64 MiB).
pub const MAX_TABLE_BYTES: usize = 64 << 20;
/// Largest number of data rows accepted.
pub const MAX_ROWS: usize = 2_000_000;
/// Largest number of distinct `kR` values accepted.
pub const MAX_WAVE_FREQUENCIES: usize = 100_000;
/// Largest number of modes accepted.
pub const MAX_MODES: usize = 1000;
/// Largest number of distinct headings accepted.
pub const MAX_HEADINGS: usize = 16;
/// Largest length exponent accepted (exponents are integers 0..=4).
const MAX_LENGTH_EXPONENT: i32 = 4;
/// Relative slack on the band's ends (rounding of `kR = omega^2 R / g`).
const BAND_SLACK: f64 = 1e-12;
const CONVENTION: &str = "exp(+i omega t)";
const COLUMNS: &str = "kR,j,heading,re,im";

/// Writes the column line and the rows of an excitation table: the long-wave `kR = 0` rows
/// first (every heading, `long_wave[j] / scale[j]`, imaginary part 0), then for each
/// `(kR, X)` of `rows` every heading and mode, `X[(j, h)] / scale[j]` (`X` one column per
/// heading of `headings`). A zero long-wave value prints as 0, not -0.
pub(crate) fn write_excitation_rows<'a>(
    out: &mut dyn Write,
    headings: &[f64],
    long_wave: Option<&[f64]>,
    scale: &[f64],
    rows: impl Iterator<Item = (f64, &'a DMatrix<Complex64>)>,
) -> std::io::Result<()> {
    writeln!(out, "{COLUMNS}")?;
    if let Some(long_wave) = long_wave {
        for heading in headings {
            for (j, value) in long_wave.iter().enumerate() {
                writeln!(out, "0,{},{heading},{:e},0", j + 1, value / scale[j] + 0.0)?;
            }
        }
    }
    for (kr, forces) in rows {
        for (h, heading) in headings.iter().enumerate() {
            for j in 0..forces.nrows() {
                let z = forces[(j, h)] / scale[j];
                writeln!(out, "{kr:e},{},{heading},{:e},{:e}", j + 1, z.re, z.im)?;
            }
        }
    }
    Ok(())
}

/// A parsed excitation table: nondimensional `X_j / (rho g a R^(1 + e_j))` on a rectangular
/// set of `kR` x heading x mode.
#[derive(Clone, Debug, PartialEq)]
pub struct ExcitationTable {
    hull: Option<String>,
    modes: Vec<String>,
    radius: f64,
    length_exponents: Vec<i32>,
    kr: Vec<f64>,
    headings: Vec<f64>,
    /// `[(heading * modes + j) * kr.len() + k]`.
    values: Vec<Complex64>,
    depth: WaterDepth,
}

struct Row {
    kr: f64,
    heading: usize,
    mode: usize,
    value: Complex64,
    line: usize,
}

impl ExcitationTable {
    /// Parses the table text; `source_name` (the file name) starts every error message.
    ///
    /// # Errors
    /// Text over [`MAX_TABLE_BYTES`]; a missing, repeated or malformed header line; a row
    /// with a wrong field count, a bad or non-finite number, `j` out of range, a negative
    /// `kR`; duplicated or missing rows; more than [`MAX_ROWS`] rows, [`MAX_WAVE_FREQUENCIES`]
    /// `kR`, [`MAX_MODES`] modes or [`MAX_HEADINGS`] headings; fewer than two positive `kR`.
    pub fn from_csv_str(text: &str, source_name: &str) -> Result<ExcitationTable, WaveError> {
        let grid = Grid::parse(text, source_name, COLUMNS)?;
        Ok(ExcitationTable {
            hull: grid.hull,
            modes: grid.modes,
            radius: grid.radius,
            length_exponents: grid.length_exponents,
            kr: grid.kr,
            headings: grid.headings,
            values: grid.values,
            depth: grid.depth,
        })
    }

    /// The water depth the table is for (`# depth:`; deep water without that line).
    pub fn depth(&self) -> WaterDepth {
        self.depth
    }

    /// The hull's name from the `# hull:` line, when present.
    pub fn hull(&self) -> Option<&str> {
        self.hull.as_deref()
    }

    /// The DOF names (`# modes:`), in the order of `j`.
    pub fn modes(&self) -> &[String] {
        &self.modes
    }

    /// The reference radius `R` (m).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The length exponents `e_j` (`# length exponents:`).
    pub fn length_exponents(&self) -> &[i32] {
        &self.length_exponents
    }

    /// The distinct `kR`, ascending (a leading 0 when the table has long-wave rows).
    pub fn kr(&self) -> &[f64] {
        &self.kr
    }

    /// The distinct headings in degrees, in `[0, 360)`, ascending.
    pub fn headings(&self) -> &[f64] {
        &self.headings
    }

    /// The index of `heading` (degrees, modulo 360, within 1e-9) in [`Self::headings`].
    pub fn heading_index(&self, heading: f64) -> Option<usize> {
        let reduced = normalize_heading(heading)?;
        self.headings
            .iter()
            .position(|&h| super::same_direction(h, reduced))
    }

    /// The tabulated `X_j / (rho g a R^(1 + e_j))` of mode `mode` (0-based), heading
    /// `heading` and `kR` at the given indices; `None` when an index is out of range.
    pub fn value(&self, mode: usize, heading: usize, kr: usize) -> Option<Complex64> {
        if mode >= self.modes.len() || heading >= self.headings.len() || kr >= self.kr.len() {
            return None;
        }
        Some(self.values[(heading * self.modes.len() + mode) * self.kr.len() + kr])
    }

    /// Whether the table has `kR = 0` (long-wave limit) rows.
    pub fn has_long_wave_rows(&self) -> bool {
        self.kr[0] == 0.0
    }

    /// The band `(smallest positive kR, largest kR)` interpolated in.
    pub fn band(&self) -> (f64, f64) {
        let first = usize::from(self.has_long_wave_rows());
        (self.kr[first], self.kr[self.kr.len() - 1])
    }

    /// `rho g R^(1 + e_j)`: multiplies the table's numbers to give `X_j` in SI (N/m per metre
    /// of wave amplitude, or N m/m for DOFs in rad); `None` for a mode out of range.
    pub fn force_scale(&self, mode: usize, rho: f64, g: f64) -> Option<f64> {
        let exponent = *self.length_exponents.get(mode)?;
        Some(rho * g * self.radius.powi(1 + exponent))
    }

    /// The nondimensional `X_j` interpolated at `kr`: cubic Hermite in `ln kR` inside
    /// [`Self::band`] (with 1e-12 relative slack at its ends), linear in `kR` between the
    /// `kR = 0` rows and the band's lower end when the table has them; `None` elsewhere or
    /// for an index out of range.
    pub fn interpolate(&self, mode: usize, heading: usize, kr: f64) -> Option<Complex64> {
        let mut out = [Complex64::new(0.0, 0.0)];
        if mode >= self.modes.len() {
            return None;
        }
        self.interpolate_range(mode..mode + 1, heading, kr, &mut out)?;
        Some(out[0])
    }

    /// [`Self::interpolate`] for every mode at once into `out` (`out.len()` = mode count).
    pub(crate) fn interpolate_all(
        &self,
        heading: usize,
        kr: f64,
        out: &mut [Complex64],
    ) -> Option<()> {
        if out.len() != self.modes.len() {
            return None;
        }
        self.interpolate_range(0..self.modes.len(), heading, kr, out)
    }

    fn interpolate_range(
        &self,
        modes: std::ops::Range<usize>,
        heading: usize,
        kr: f64,
        out: &mut [Complex64],
    ) -> Option<()> {
        if heading >= self.headings.len() || !kr.is_finite() || kr < 0.0 {
            return None;
        }
        let (low, high) = self.band();
        let n = self.kr.len();
        let series = |mode: usize| {
            let start = (heading * self.modes.len() + mode) * n;
            &self.values[start..start + n]
        };
        if kr < low * (1.0 - BAND_SLACK) {
            if !self.has_long_wave_rows() {
                return None;
            }
            let t = kr / low;
            for (slot, mode) in out.iter_mut().zip(modes) {
                let y = series(mode);
                *slot = y[0] + (y[1] - y[0]) * t;
            }
            return Some(());
        }
        if kr > high * (1.0 + BAND_SLACK) {
            return None;
        }
        let first = usize::from(self.has_long_wave_rows());
        let nodes = &self.kr[first..];
        let position = ln(kr.clamp(low, high));
        // Interval i: nodes[i] <= kr <= nodes[i + 1].
        let upper = nodes
            .partition_point(|&k| k <= kr)
            .clamp(1, nodes.len() - 1);
        let i = upper - 1;
        let stencil = Stencil::new(nodes, i, position);
        for (slot, mode) in out.iter_mut().zip(modes) {
            *slot = stencil.apply(&series(mode)[first..]);
        }
        Some(())
    }
}

/// The rows of a table on its rectangular set of `kR` x heading x mode, with its header: what
/// the excitation and drift tables share (a drift value is the real part).
pub(super) struct Grid {
    pub(super) hull: Option<String>,
    pub(super) modes: Vec<String>,
    pub(super) radius: f64,
    pub(super) length_exponents: Vec<i32>,
    pub(super) kr: Vec<f64>,
    pub(super) headings: Vec<f64>,
    /// `[(heading * modes + j) * kr.len() + k]`.
    pub(super) values: Vec<Complex64>,
    /// `# depth:` (deep water without that line).
    pub(super) depth: WaterDepth,
}

impl Grid {
    /// Parses the text of a table whose column line is `columns` (`kR,j,heading,` and one
    /// field `value` or two `re,im`); `source_name` (the file name) starts every error message.
    pub(super) fn parse(text: &str, source_name: &str, columns: &str) -> Result<Grid, WaveError> {
        let error = |line: Option<usize>, message: String| WaveError::Table {
            source: source_name.to_string(),
            line,
            message,
        };
        if text.len() > MAX_TABLE_BYTES {
            return Err(error(
                None,
                format!(
                    "{} bytes: the limit is {MAX_TABLE_BYTES} bytes (64 MiB)",
                    text.len()
                ),
            ));
        }
        let mut header = Header::default();
        let mut columns_seen = false;
        let mut rows: Vec<Row> = Vec::new();
        let mut headings: Vec<f64> = Vec::new();
        for (index, raw) in text.lines().enumerate() {
            let line = index + 1;
            let trimmed = raw.trim();
            if trimmed.is_empty() {
                continue;
            }
            if let Some(comment) = trimmed.strip_prefix('#') {
                if columns_seen && header.is_key_line(comment) {
                    return Err(error(
                        Some(line),
                        format!("header line after the column line `{columns}`"),
                    ));
                }
                header
                    .read(comment, line)
                    .map_err(|m| error(Some(line), m))?;
                continue;
            }
            if !columns_seen {
                if trimmed != columns {
                    return Err(error(
                        Some(line),
                        format!("expected the column line `{columns}`, found `{trimmed}`"),
                    ));
                }
                header.complete().map_err(|m| error(Some(line), m))?;
                columns_seen = true;
                continue;
            }
            if rows.len() == MAX_ROWS {
                return Err(error(Some(line), format!("more than {MAX_ROWS} data rows")));
            }
            let row = parse_row(trimmed, columns, line, header.modes.len(), &mut headings)
                .map_err(|m| error(Some(line), m))?;
            rows.push(row);
        }
        if !columns_seen {
            header.complete().map_err(|m| error(None, m))?;
            return Err(error(
                None,
                format!("no column line `{columns}` (and so no data)"),
            ));
        }
        let depth = match &header.depth {
            None => WaterDepth::Infinite,
            Some((value, line)) => {
                WaterDepth::from_table_value(value, header.radius.unwrap_or(f64::NAN))
                    .map_err(|m| error(Some(*line), m))?
            }
        };
        let mut grid = Self::assemble(header, headings, rows, &error)?;
        grid.depth = depth;
        Ok(grid)
    }

    fn assemble(
        header: Header,
        headings: Vec<f64>,
        mut rows: Vec<Row>,
        error: &dyn Fn(Option<usize>, String) -> WaveError,
    ) -> Result<Grid, WaveError> {
        let modes = header.modes;
        if rows.is_empty() {
            return Err(error(None, "no data rows".to_string()));
        }
        // Headings in ascending order; rows renumbered.
        let mut order: Vec<usize> = (0..headings.len()).collect();
        order.sort_by(|&a, &b| headings[a].total_cmp(&headings[b]));
        let mut rank = vec![0; headings.len()];
        for (position, &original) in order.iter().enumerate() {
            rank[original] = position;
        }
        let headings: Vec<f64> = order.iter().map(|&i| headings[i]).collect();
        for row in &mut rows {
            row.heading = rank[row.heading];
        }
        rows.sort_by(|a, b| {
            a.kr.total_cmp(&b.kr)
                .then(a.heading.cmp(&b.heading))
                .then(a.mode.cmp(&b.mode))
                .then(a.line.cmp(&b.line))
        });
        let mut kr: Vec<f64> = Vec::new();
        for row in &rows {
            if kr.last() != Some(&row.kr) {
                if kr.len() == MAX_WAVE_FREQUENCIES {
                    return Err(error(
                        Some(row.line),
                        format!("more than {MAX_WAVE_FREQUENCIES} distinct kR"),
                    ));
                }
                kr.push(row.kr);
            }
        }
        if kr.iter().filter(|&&k| k > 0.0).count() < 2 {
            return Err(error(
                None,
                "fewer than two positive kR: no band to interpolate in".to_string(),
            ));
        }
        let expected = kr.len() * headings.len() * modes.len();
        if rows.len() > expected {
            // Some key appears twice: find it.
            for pair in rows.windows(2) {
                if pair[0].kr == pair[1].kr
                    && pair[0].heading == pair[1].heading
                    && pair[0].mode == pair[1].mode
                {
                    return Err(error(
                        Some(pair[1].line),
                        format!(
                            "duplicated row kR = {}, heading = {}, j = {} ({}): first on line {}",
                            pair[1].kr,
                            headings[pair[1].heading],
                            pair[1].mode + 1,
                            modes[pair[1].mode],
                            pair[0].line
                        ),
                    ));
                }
            }
        }
        let mut values = vec![Complex64::new(f64::NAN, f64::NAN); expected];
        let mut filled = vec![false; expected];
        let mut k = 0;
        for row in &rows {
            while kr[k] != row.kr {
                k += 1;
            }
            let slot = (row.heading * modes.len() + row.mode) * kr.len() + k;
            if filled[slot] {
                return Err(error(
                    Some(row.line),
                    format!(
                        "duplicated row kR = {}, heading = {}, j = {} ({})",
                        row.kr,
                        headings[row.heading],
                        row.mode + 1,
                        modes[row.mode]
                    ),
                ));
            }
            filled[slot] = true;
            values[slot] = row.value;
        }
        if let Some(slot) = filled.iter().position(|&f| !f) {
            let k = slot % kr.len();
            let mode = (slot / kr.len()) % modes.len();
            let heading = slot / (kr.len() * modes.len());
            return Err(error(
                None,
                format!(
                    "missing row kR = {}, heading = {}, j = {} ({}): every kR and heading \
                     needs all {} modes",
                    kr[k],
                    headings[heading],
                    mode + 1,
                    modes[mode],
                    modes.len()
                ),
            ));
        }
        Ok(Grid {
            hull: header.hull,
            modes,
            radius: header.radius.unwrap_or(f64::NAN),
            length_exponents: header.length_exponents,
            kr,
            headings,
            values,
            depth: WaterDepth::Infinite,
        })
    }
}

fn ln(x: f64) -> f64 {
    x.ln()
}

/// Nodes of the slope stencils (five-point: fourth-order slopes).
const SLOPE_NODES: usize = 5;
/// Largest stencil of an interpolated value: the slopes' windows at both ends of an interval.
const STENCIL: usize = SLOPE_NODES + 1;

/// The cubic Hermite weights at a point of interval `i` (in `ln kR`), with each node's slope
/// the derivative of the polynomial through the `SLOPE_NODES` nodes around it (shifted
/// inwards at the ends; fewer when the table has fewer; linear with two nodes).
struct Stencil {
    first: usize,
    weights: [f64; STENCIL],
    count: usize,
}

impl Stencil {
    fn new(nodes: &[f64], i: usize, position: f64) -> Stencil {
        let x = |m: usize| ln(nodes[m]);
        let len = nodes.len();
        let h = x(i + 1) - x(i);
        let t = (position - x(i)) / h;
        if len == 2 {
            let mut weights = [0.0; STENCIL];
            weights[0] = 1.0 - t;
            weights[1] = t;
            return Stencil {
                first: 0,
                weights,
                count: 2,
            };
        }
        let window = SLOPE_NODES.min(len);
        let window_start = |m: usize| m.saturating_sub(window / 2).min(len - window);
        // Derivative at node m of the Lagrange basis on the window.
        let slope = |m: usize| -> (usize, [f64; SLOPE_NODES]) {
            let m0 = window_start(m);
            let p = x(m);
            let mut w = [0.0; SLOPE_NODES];
            for (k, wk) in w.iter_mut().enumerate().take(window) {
                let xk = x(m0 + k);
                let mut denominator = 1.0;
                for l in 0..window {
                    if l != k {
                        denominator *= xk - x(m0 + l);
                    }
                }
                let mut numerator = 0.0;
                for l in (0..window).filter(|&l| l != k) {
                    let mut product = 1.0;
                    for q in (0..window).filter(|&q| q != k && q != l) {
                        product *= p - x(m0 + q);
                    }
                    numerator += product;
                }
                *wk = numerator / denominator;
            }
            (m0, w)
        };
        let h00 = (1.0 + 2.0 * t) * (1.0 - t) * (1.0 - t);
        let h10 = t * (1.0 - t) * (1.0 - t);
        let h01 = t * t * (3.0 - 2.0 * t);
        let h11 = t * t * (t - 1.0);
        let first = window_start(i);
        let count = (window_start(i + 1) + window - first).min(STENCIL);
        let mut weights = [0.0; STENCIL];
        weights[i - first] += h00;
        weights[i + 1 - first] += h01;
        for (node, factor) in [(i, h10 * h), (i + 1, h11 * h)] {
            let (m0, w) = slope(node);
            for (offset, wk) in w.iter().enumerate().take(window) {
                weights[m0 + offset - first] += factor * wk;
            }
        }
        Stencil {
            first,
            weights,
            count,
        }
    }

    fn apply(&self, y: &[Complex64]) -> Complex64 {
        let mut sum = Complex64::new(0.0, 0.0);
        for m in 0..self.count {
            sum += y[self.first + m] * self.weights[m];
        }
        sum
    }
}

/// A heading in `[0, 360)`, 360 - 1e-9 and above folded to 0; `None` if not finite.
fn normalize_heading(heading: f64) -> Option<f64> {
    if !heading.is_finite() {
        return None;
    }
    let reduced = heading.rem_euclid(360.0);
    Some(if reduced >= 360.0 - super::HEADING_TOLERANCE {
        0.0
    } else {
        reduced
    })
}

#[derive(Default)]
struct Header {
    hull: Option<String>,
    modes: Vec<String>,
    modes_seen: bool,
    convention_seen: bool,
    radius: Option<f64>,
    length_exponents: Vec<i32>,
    exponents_seen: bool,
    /// The `# depth:` value and its line.
    depth: Option<(String, usize)>,
}

impl Header {
    fn is_key_line(&self, comment: &str) -> bool {
        ["modes:", "convention:", "R:", "length exponents:", "depth:"]
            .iter()
            .any(|key| comment.trim_start().starts_with(key))
    }

    /// Reads one comment line (without its '#'), line `line` of the text.
    fn read(&mut self, comment: &str, line: usize) -> Result<(), String> {
        let comment = comment.trim();
        if let Some(rest) = comment.strip_prefix("depth:") {
            if self.depth.is_some() {
                return Err("repeated `# depth:` line".to_string());
            }
            self.depth = Some((rest.trim().to_string(), line));
        } else if let Some(rest) = comment.strip_prefix("hull:") {
            if self.hull.is_some() {
                return Err("repeated `# hull:` line".to_string());
            }
            self.hull = Some(rest.trim().to_string());
        } else if let Some(rest) = comment.strip_prefix("modes:") {
            if self.modes_seen {
                return Err("repeated `# modes:` line".to_string());
            }
            self.modes_seen = true;
            let modes: Vec<&str> = rest.split_whitespace().collect();
            if modes.is_empty() {
                return Err("`# modes:` lists no mode".to_string());
            }
            if modes.len() > MAX_MODES {
                return Err(format!(
                    "`# modes:` lists {} modes: the limit is {MAX_MODES}",
                    modes.len()
                ));
            }
            for (i, name) in modes.iter().enumerate() {
                if modes[..i].contains(name) {
                    return Err(format!("`# modes:` names `{name}` twice"));
                }
            }
            self.modes = modes.into_iter().map(str::to_string).collect();
        } else if let Some(rest) = comment.strip_prefix("convention:") {
            if self.convention_seen {
                return Err("repeated `# convention:` line".to_string());
            }
            self.convention_seen = true;
            if rest.trim() != CONVENTION {
                return Err(format!(
                    "`# convention:` is `{}`: only `{CONVENTION}` is read",
                    rest.trim()
                ));
            }
        } else if let Some(rest) = comment.strip_prefix("R:") {
            if self.radius.is_some() {
                return Err("repeated `# R:` line".to_string());
            }
            let words: Vec<&str> = rest.split_whitespace().collect();
            let radius = match words.as_slice() {
                [value, "m"] => value.parse::<f64>().ok(),
                _ => None,
            };
            match radius {
                Some(r) if r.is_finite() && r > 0.0 => self.radius = Some(r),
                _ => {
                    return Err(format!(
                        "`# R:` is `{}`: expected `# R: <radius> m`, radius finite and > 0",
                        rest.trim()
                    ))
                }
            }
        } else if let Some(rest) = comment.strip_prefix("length exponents:") {
            if self.exponents_seen {
                return Err("repeated `# length exponents:` line".to_string());
            }
            self.exponents_seen = true;
            for word in rest.split_whitespace() {
                if self.length_exponents.len() == MAX_MODES {
                    return Err(format!(
                        "`# length exponents:` lists more than {MAX_MODES} values"
                    ));
                }
                match word.parse::<i32>() {
                    Ok(e) if (0..=MAX_LENGTH_EXPONENT).contains(&e) => {
                        self.length_exponents.push(e)
                    }
                    _ => {
                        return Err(format!(
                            "`# length exponents:` value `{word}`: expected an integer \
                             0..={MAX_LENGTH_EXPONENT}"
                        ))
                    }
                }
            }
        }
        Ok(())
    }

    /// Checks that every required line was read.
    fn complete(&self) -> Result<(), String> {
        if !self.modes_seen {
            return Err("missing header line `# modes: ...`".to_string());
        }
        if !self.convention_seen {
            return Err(format!("missing header line `# convention: {CONVENTION}`"));
        }
        if self.radius.is_none() {
            return Err("missing header line `# R: <radius> m`".to_string());
        }
        if !self.exponents_seen {
            return Err("missing header line `# length exponents: ...`".to_string());
        }
        if self.length_exponents.len() != self.modes.len() {
            return Err(format!(
                "`# length exponents:` lists {} values for {} modes",
                self.length_exponents.len(),
                self.modes.len()
            ));
        }
        Ok(())
    }
}

/// One data row `kR,j,heading,re,im` (or `kR,j,heading,value`: the imaginary part 0); new
/// headings are appended to `headings`.
fn parse_row(
    text: &str,
    columns: &str,
    line: usize,
    modes: usize,
    headings: &mut Vec<f64>,
) -> Result<Row, String> {
    let fields: Vec<&str> = text.split(',').map(str::trim).collect();
    let expected = columns.split(',').count();
    if fields.len() != expected {
        return Err(format!(
            "{} fields: a row is `{columns}` ({expected} fields)",
            fields.len()
        ));
    }
    let number = |index: usize, name: &str| -> Result<f64, String> {
        let field = fields[index];
        let value: f64 = field
            .parse()
            .map_err(|_| format!("field `{name}`: `{field}` is not a number"))?;
        if !value.is_finite() {
            return Err(format!("field `{name}`: `{field}` is not finite"));
        }
        Ok(value)
    };
    let kr = number(0, "kR")?;
    if kr < 0.0 {
        return Err(format!("field `kR`: {kr} is negative"));
    }
    let mode: usize = fields[1]
        .parse()
        .map_err(|_| format!("field `j`: `{}` is not a positive integer", fields[1]))?;
    if mode == 0 || mode > modes {
        return Err(format!(
            "field `j`: {mode} is out of range 1..={modes} (the `# modes:` list)"
        ));
    }
    let heading_value = number(2, "heading")?;
    let heading_value = normalize_heading(heading_value).unwrap_or(heading_value);
    let heading = match headings
        .iter()
        .position(|&h| super::same_direction(h, heading_value))
    {
        Some(index) => index,
        None => {
            if headings.len() == MAX_HEADINGS {
                return Err(format!(
                    "field `heading`: {heading_value} is heading number {}: the limit is \
                     {MAX_HEADINGS}",
                    MAX_HEADINGS + 1
                ));
            }
            headings.push(heading_value);
            headings.len() - 1
        }
    };
    let (re, im) = if expected == 5 {
        (number(3, "re")?, number(4, "im")?)
    } else {
        (number(3, "value")?, 0.0)
    };
    Ok(Row {
        kr,
        heading,
        mode: mode - 1,
        value: Complex64::new(re, im),
        line,
    })
}
