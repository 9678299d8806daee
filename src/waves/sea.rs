//! One realization of a sea ([`Sea`]) and its evaluation in time with cached phasors
//! ([`SeaScratch`]).
//!
//! `eta(t) = r(t) sum_n Re[e_n z_n]`, `F_j(t) = r(t) sum_n Re[c_nj z_n]`, with
//! `e_n = a_n e^{i eps_n}`, `c_nj = a_n X_j(omega_n) e^{i eps_n}` and the phasors
//! `z_n = e^{i omega_n t}`. When the time advances by the step of the previous call, the
//! phasors advance by one multiplication with the cached `w_n = e^{i omega_n h}`; a step
//! that differs from `h` by at most `1e-3 h` (and `omega_max |delta| <= 1e-4`) is corrected
//! by the third-order Taylor factor of `e^{i omega_n delta}` (neglected term below 5e-18). A
//! new step size computes `w_n` once it repeats; any other time (a restored state, a jump)
//! and every [`RESYNC_INTERVAL`] steps resynchronize `z_n = e^{i omega_n t}` directly. Each
//! multiplication adds at most about `1.3e-15` (complex product and `w_n` rounding), so the
//! recurrence stays within `RESYNC_INTERVAL * 1.3e-15 = 6.7e-13` of `sum_n |c_nj|` from the
//! direct sum (the direct sum's own phase rounding, `eps omega_n t`, is of the same order).

use super::spectrum::{self, Components};
use super::{
    heading_direction, DriftMode, DriftTable, ExcitationTable, WaveError, WaveKind, WaveParams,
    HEADING_TOLERANCE,
};
use crate::units;
use num_complex::Complex64;
use std::f64::consts::PI;

/// Steps between two direct resynchronizations of the phasors.
pub(crate) const RESYNC_INTERVAL: usize = 512;

/// Lanes of the sums (arrays are padded with zero components to a multiple).
const LANES: usize = 4;

/// Relative slack on the table's band for a regular wave (rounding of `kR`).
const BAND_SLACK: f64 = 1e-12;

/// One realization of a sea: its components and, per DOF, the complex force amplitudes
/// (module docs). Fixed by the parameters, the table, `rho`, `g` and the start time.
#[derive(Clone, Debug)]
pub struct Sea {
    kind: WaveKind,
    count: usize,
    dofs: usize,
    /// Padded to a multiple of `LANES` with zero components (omega 0, amplitude 0).
    padded: usize,
    omega: Vec<f64>,
    amplitude: Vec<f64>,
    phase: Vec<f64>,
    elevation_re: Vec<f64>,
    elevation_im: Vec<f64>,
    /// `[j * padded + n]`.
    force_re: Vec<f64>,
    force_im: Vec<f64>,
    omega_max: f64,
    ramp: f64,
    start_time: f64,
    target_variance: f64,
    spectrum_m0: f64,
    notes: Vec<String>,
    /// The drift forces ([`Sea::with_drift`]); `None`: no drift.
    drift: Option<SeaDrift>,
}

/// The drift coefficients of a sea (module docs of [`crate::waves`]): per DOF `j` with a
/// nonzero drift, `d_nj = D_j(omega_n)` in SI.
#[derive(Clone, Debug)]
struct SeaDrift {
    mode: DriftMode,
    /// The table's mode count (DOFs of the output).
    dofs: usize,
    /// The DOFs whose drift is not zero at every frequency of the heading.
    active: Vec<usize>,
    /// Per active DOF, `sum_n a_n^2 d_nj`.
    mean: Vec<f64>,
    /// Per active DOF, `d_nj`: `[active * padded + n]` (zero in the padding).
    coefficient: Vec<f64>,
}

impl Sea {
    /// Builds the sea of `params` with the exciting forces of `table` (one per mode; none
    /// without a table: the elevation only) for water density `rho` (kg/m^3) and gravity
    /// `g` (m/s^2); the ramp starts at `start_time` (s). Calm water has no components.
    ///
    /// # Errors
    /// A parameter out of range ([`WaveParams::validate`]), `rho` or `g` not finite and
    /// positive, a non-finite start time; with a table: a heading it lacks, a regular wave
    /// above its band or below it without `kR = 0` rows, a JONSWAP range outside its band.
    pub fn new(
        params: &WaveParams,
        table: Option<&ExcitationTable>,
        rho: f64,
        g: f64,
        start_time: f64,
    ) -> Result<Sea, WaveError> {
        for (name, value) in [("rho", rho), ("g", g)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(WaveError::parameter(name, value, "must be finite and > 0"));
            }
        }
        if !start_time.is_finite() {
            return Err(WaveError::parameter(
                "start time",
                start_time,
                "must be finite (s)",
            ));
        }
        let mut notes = params.validate()?;
        let heading = heading_direction(params.heading)?;
        let active_table = table.filter(|_| params.kind != WaveKind::Calm);
        let heading_index = match active_table {
            Some(t) => Some(t.heading_index(heading).ok_or_else(|| WaveError::Band {
                message: format!(
                    "wave.heading = {heading} deg: the excitation table has no such heading \
                     (it has {:?}; within {HEADING_TOLERANCE} deg, modulo 360)",
                    t.headings()
                ),
            })?),
            None => None,
        };
        if active_table.is_none() && params.kind != WaveKind::Calm {
            notes.push(
                "no excitation table: the sea gives the elevation only, no exciting force"
                    .to_string(),
            );
        }
        let components = match params.kind {
            WaveKind::Calm => Components {
                omega: Vec::new(),
                amplitude: Vec::new(),
                phase: Vec::new(),
                represented_m0: 0.0,
                spectrum_m0: 0.0,
                notes: Vec::new(),
            },
            WaveKind::Regular => regular(params, active_table, g, &mut notes)?,
            WaveKind::Jonswap => {
                let band = active_table.map(|t| {
                    let (low, high) = t.band();
                    let radius = t.radius();
                    (
                        units::omega_from_kr(low, radius, g),
                        units::omega_from_kr(high, radius, g),
                    )
                });
                spectrum::discretize(params, band)?
            }
        };
        notes.extend(components.notes.iter().cloned());
        let count = components.omega.len();
        let padded = count.div_ceil(LANES) * LANES;
        let dofs = table.map_or(0, |t| t.modes().len());
        let mut sea = Sea {
            kind: params.kind,
            count,
            dofs,
            padded,
            omega: vec![0.0; padded],
            amplitude: components.amplitude,
            phase: components.phase,
            elevation_re: vec![0.0; padded],
            elevation_im: vec![0.0; padded],
            force_re: vec![0.0; dofs * padded],
            force_im: vec![0.0; dofs * padded],
            omega_max: components.omega.iter().fold(0.0, |m: f64, &w| m.max(w)),
            ramp: params.ramp,
            start_time,
            target_variance: components.represented_m0,
            spectrum_m0: components.spectrum_m0,
            notes,
            drift: None,
        };
        sea.omega[..count].copy_from_slice(&components.omega);
        let mut excitation = vec![Complex64::new(0.0, 0.0); dofs];
        for n in 0..count {
            let coefficient = Complex64::from_polar(sea.amplitude[n], sea.phase[n]);
            sea.elevation_re[n] = coefficient.re;
            sea.elevation_im[n] = coefficient.im;
            if let (Some(t), Some(heading)) = (active_table, heading_index) {
                let kr = units::kr_from_omega(sea.omega[n], t.radius(), g);
                t.interpolate_all(heading, kr, &mut excitation)
                    .ok_or_else(|| WaveError::Band {
                        message: format!(
                            "wave component omega = {} rad/s (kR = {kr}) is outside the \
                             excitation table's band",
                            sea.omega[n]
                        ),
                    })?;
                for (j, x) in excitation.iter().enumerate() {
                    let scale = t.force_scale(j, rho, g).unwrap_or(f64::NAN);
                    let c = coefficient * x * scale;
                    sea.force_re[j * padded + n] = c.re;
                    sea.force_im[j * padded + n] = c.im;
                }
            }
        }
        Ok(sea)
    }

    /// This sea with the drift forces of `table` in `mode` (module docs of [`crate::waves`]),
    /// at the heading of `params` (the parameters the sea was built with), for `rho` and `g`.
    /// [`DriftMode::Off`] or calm water: no drift force.
    ///
    /// # Errors
    /// A heading the table lacks; a component above the table's highest `kR`.
    pub fn with_drift(
        mut self,
        params: &WaveParams,
        table: &DriftTable,
        mode: DriftMode,
        rho: f64,
        g: f64,
    ) -> Result<Sea, WaveError> {
        if mode == DriftMode::Off || self.count == 0 {
            self.drift = None;
            return Ok(self);
        }
        let heading = table
            .heading_index(params.heading)
            .ok_or_else(|| WaveError::Band {
                message: format!(
                    "wave.heading = {} deg: the drift table has no such heading (it has {:?})",
                    params.heading,
                    table.headings()
                ),
            })?;
        let dofs = table.modes().len();
        let active: Vec<usize> = (0..dofs).filter(|&j| !table.is_zero(j, heading)).collect();
        let padded = self.padded;
        let mut drift = SeaDrift {
            mode,
            dofs,
            mean: vec![0.0; active.len()],
            coefficient: vec![0.0; active.len() * padded],
            active,
        };
        for n in 0..self.count {
            let kr = units::kr_from_omega(self.omega[n], table.radius(), g);
            if kr > table.highest_kr() * (1.0 + BAND_SLACK) {
                return Err(WaveError::Band {
                    message: format!(
                        "wave component omega = {} rad/s (kR = {kr}) is above the drift \
                         table's highest kR {}",
                        self.omega[n],
                        table.highest_kr()
                    ),
                });
            }
            let amplitude = self.amplitude[n];
            for (a, &j) in drift.active.iter().enumerate() {
                let value = table.interpolate(j, heading, kr).unwrap_or(f64::NAN);
                let d = value * table.force_scale(j, rho, g).unwrap_or(f64::NAN);
                drift.mean[a] += amplitude * amplitude * d;
                drift.coefficient[a * padded + n] = d;
            }
        }
        self.drift = Some(drift);
        Ok(self)
    }

    /// The drift mode in use ([`DriftMode::Off`] without drift).
    pub fn drift_mode(&self) -> DriftMode {
        self.drift.as_ref().map_or(DriftMode::Off, |d| d.mode)
    }

    /// The mean drift force `sum_n a_n^2 d_nj` (SI) of DOF `j` after the ramp; 0 without
    /// drift or for a DOF whose drift is zero.
    pub fn mean_drift(&self, j: usize) -> f64 {
        self.drift.as_ref().map_or(0.0, |d| {
            d.active
                .iter()
                .position(|&a| a == j)
                .map_or(0.0, |a| d.mean[a])
        })
    }

    /// Writes the drift force of DOF `j` at `time` to `forces[j]` (`j` below the drift
    /// table's mode count; zeros elsewhere and without drift): mean, `r^2 sum_n a_n^2 d_nj`;
    /// Newman, `r^2 Re[P_j conj(Q)]` from `scratch`'s phasors (advanced to `time` as
    /// [`Self::evaluate`] does, no work when it is already there).
    pub fn evaluate_drift(&self, time: f64, scratch: &mut SeaScratch, forces: &mut [f64]) {
        forces.fill(0.0);
        let Some(drift) = &self.drift else {
            return;
        };
        let ramp = self.ramp_factor(time);
        let ramp2 = ramp * ramp;
        match drift.mode {
            DriftMode::Off => {}
            DriftMode::Mean => {
                for (&j, mean) in drift.active.iter().zip(&drift.mean) {
                    if let Some(force) = forces.get_mut(j) {
                        *force = ramp2 * mean;
                    }
                }
            }
            DriftMode::Newman => {
                if scratch.z_re.len() != self.padded {
                    *scratch = self.scratch();
                }
                // The phasors the exciting force used at this time, when it came first.
                if scratch.reached != time {
                    scratch.advance(&self.omega, self.omega_max, time);
                }
                // F_j = Re[P_j conj Q] = sum_n d_nj u_n, u_n = Re[w_n conj Q], w_n = e_n z_n.
                let weights = &mut scratch.drift_weight;
                let (q_re, q_im) = elevation_terms(
                    &self.elevation_re,
                    &self.elevation_im,
                    &scratch.z_re,
                    &scratch.z_im,
                    weights,
                );
                let (w_re, w_im) = weights.split_at_mut(self.padded);
                for (re, im) in w_re.iter_mut().zip(w_im.iter()) {
                    *re = *re * q_re + im * q_im;
                }
                for (a, &j) in drift.active.iter().enumerate() {
                    let Some(force) = forces.get_mut(j) else {
                        continue;
                    };
                    let range = a * self.padded..(a + 1) * self.padded;
                    *force = ramp2 * dot_real(&drift.coefficient[range], w_re);
                }
            }
        }
    }

    /// The time derivative of [`Self::evaluate_drift`] at `time`, by the direct sum:
    /// mean, `2 r r' M_j`; Newman, `2 r r' Re[P conj Q] + r^2 Re[P' conj Q + P conj Q']` with
    /// `P' = sum_n i omega_n (...)`.
    pub fn evaluate_drift_rate(&self, time: f64, forces_rate: &mut [f64]) {
        forces_rate.fill(0.0);
        let Some(drift) = &self.drift else {
            return;
        };
        let (ramp, ramp_rate) = (self.ramp_factor(time), self.ramp_rate(time));
        let (mut q, mut q_rate) = (Complex64::new(0.0, 0.0), Complex64::new(0.0, 0.0));
        let mut phasors = Vec::with_capacity(self.count);
        for n in 0..self.count {
            let z = Complex64::cis(self.omega[n] * time);
            let term = Complex64::new(self.elevation_re[n], self.elevation_im[n]) * z;
            q += term;
            q_rate += Complex64::i() * self.omega[n] * term;
            phasors.push(z);
        }
        for (a, &j) in drift.active.iter().enumerate() {
            let Some(rate) = forces_rate.get_mut(j) else {
                continue;
            };
            *rate = match drift.mode {
                DriftMode::Off => 0.0,
                DriftMode::Mean => 2.0 * ramp * ramp_rate * drift.mean[a],
                DriftMode::Newman => {
                    let (mut p, mut p_rate) = (Complex64::new(0.0, 0.0), Complex64::new(0.0, 0.0));
                    for (n, z) in phasors.iter().enumerate() {
                        let e = Complex64::new(self.elevation_re[n], self.elevation_im[n]);
                        let term = e * z * drift.coefficient[a * self.padded + n];
                        p += term;
                        p_rate += Complex64::i() * self.omega[n] * term;
                    }
                    2.0 * ramp * ramp_rate * (p * q.conj()).re
                        + ramp * ramp * (p_rate * q.conj() + p * q_rate.conj()).re
                }
            };
        }
    }

    /// Number of DOFs with a drift output (the drift table's modes; 0 without drift).
    pub fn drift_dof_count(&self) -> usize {
        self.drift.as_ref().map_or(0, |d| d.dofs)
    }

    /// Fallbacks taken and warnings (band cuts, long-wave interpolation, gamma outside 1..7,
    /// no table).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// The kind of sea.
    pub fn kind(&self) -> WaveKind {
        self.kind
    }

    /// Number of components (0 calm, 1 regular, N JONSWAP).
    pub fn component_count(&self) -> usize {
        self.count
    }

    /// Number of DOFs with an exciting force (the table's modes; 0 without a table).
    pub fn dof_count(&self) -> usize {
        self.dofs
    }

    /// The component frequencies `omega_n` (rad/s).
    pub fn frequencies(&self) -> &[f64] {
        &self.omega[..self.count]
    }

    /// The component amplitudes `a_n` (m).
    pub fn amplitudes(&self) -> &[f64] {
        &self.amplitude
    }

    /// The component phases `eps_n` (rad).
    pub fn phases(&self) -> &[f64] {
        &self.phase
    }

    /// The force amplitude `c_nj = a_n X_j(omega_n) e^{i eps_n}` (SI) of component `n` in
    /// DOF `j`; `None` out of range.
    pub fn force_amplitude(&self, n: usize, j: usize) -> Option<Complex64> {
        if n >= self.count || j >= self.dofs {
            return None;
        }
        let slot = j * self.padded + n;
        Some(Complex64::new(self.force_re[slot], self.force_im[slot]))
    }

    /// `sum_n a_n^2 / 2`: this realization's elevation variance (m^2).
    pub fn spectral_variance(&self) -> f64 {
        self.amplitude.iter().map(|a| a * a / 2.0).sum()
    }

    /// The spectrum's integral over the frequencies represented (m^2): the expected value
    /// of [`Self::spectral_variance`] over seeds (regular: `a^2 / 2`).
    pub fn target_variance(&self) -> f64 {
        self.target_variance
    }

    /// The spectrum's integral over all frequencies, m0 (m^2; regular: `a^2 / 2`).
    pub fn spectrum_m0(&self) -> f64 {
        self.spectrum_m0
    }

    /// The ramp factor `r(t)` (module docs of [`crate::waves`]).
    pub fn ramp_factor(&self, time: f64) -> f64 {
        let elapsed = time - self.start_time;
        if self.ramp <= 0.0 || elapsed >= self.ramp {
            1.0
        } else if elapsed <= 0.0 {
            0.0
        } else {
            0.5 * (1.0 - (PI * elapsed / self.ramp).cos())
        }
    }

    /// `dr/dt` of [`Self::ramp_factor`]: `pi / (2 T_ramp) sin(pi (t - t0) / T_ramp)` inside
    /// the ramp, 0 outside.
    pub fn ramp_rate(&self, time: f64) -> f64 {
        let elapsed = time - self.start_time;
        if self.ramp <= 0.0 || elapsed >= self.ramp || elapsed <= 0.0 {
            0.0
        } else {
            0.5 * PI / self.ramp * (PI * elapsed / self.ramp).sin()
        }
    }

    /// Time derivatives of the elevation (returned) and of the exciting forces (written into
    /// `forces_rate`, as [`Self::evaluate`]), by the direct sum:
    ///
    /// ```text
    /// d/dt r Re[c e^{i omega t}] = r' Re[c e^{i omega t}] - r omega Im[c e^{i omega t}]
    /// ```
    pub fn evaluate_rate(&self, time: f64, forces_rate: &mut [f64]) -> f64 {
        let written = forces_rate.len().min(self.dofs);
        forces_rate.fill(0.0);
        let (ramp, ramp_rate) = (self.ramp_factor(time), self.ramp_rate(time));
        // d/dt of Re[c z] with z = cos + i sin: (r' Re - r omega Im)[c z].
        let rate = |c_re: f64, c_im: f64, omega: f64, sin: f64, cos: f64| {
            let (re, im) = (c_re * cos - c_im * sin, c_re * sin + c_im * cos);
            ramp_rate * re - ramp * omega * im
        };
        let mut elevation = 0.0;
        for n in 0..self.count {
            let omega = self.omega[n];
            let (sin, cos) = (omega * time).sin_cos();
            elevation += rate(self.elevation_re[n], self.elevation_im[n], omega, sin, cos);
            for (j, force) in forces_rate[..written].iter_mut().enumerate() {
                let slot = j * self.padded + n;
                *force += rate(self.force_re[slot], self.force_im[slot], omega, sin, cos);
            }
        }
        elevation
    }

    /// A scratch sized for this sea, not yet synchronized.
    pub fn scratch(&self) -> SeaScratch {
        SeaScratch::sized(self.padded)
    }

    /// The elevation `eta(t)` at x = 0 (m); writes the exciting force `F_j(t)` of DOF `j` to
    /// `forces[j]` for `j < min(forces.len(), dof_count())` and zeros the rest of `forces`.
    /// Advances `scratch`'s phasors (module docs); a scratch of another sea is resized. A
    /// non-finite time gives NaN.
    pub fn evaluate(&self, time: f64, scratch: &mut SeaScratch, forces: &mut [f64]) -> f64 {
        let written = forces.len().min(self.dofs);
        forces[written..].fill(0.0);
        if self.count == 0 {
            forces.fill(0.0);
            return 0.0;
        }
        if scratch.z_re.len() != self.padded {
            *scratch = self.scratch();
        }
        scratch.advance(&self.omega, self.omega_max, time);
        let ramp = self.ramp_factor(time);
        let (z_re, z_im) = (&scratch.z_re, &scratch.z_im);
        for (j, force) in forces[..written].iter_mut().enumerate() {
            let range = j * self.padded..(j + 1) * self.padded;
            *force = ramp
                * dot(
                    &self.force_re[range.clone()],
                    &self.force_im[range],
                    z_re,
                    z_im,
                );
        }
        ramp * dot(&self.elevation_re, &self.elevation_im, z_re, z_im)
    }

    /// [`Self::evaluate`] by the direct sum (one `sin_cos` per component), without a
    /// scratch: the reference of the phasor recurrence, and the cheaper choice for isolated
    /// times.
    pub fn evaluate_direct(&self, time: f64, forces: &mut [f64]) -> f64 {
        let written = forces.len().min(self.dofs);
        forces.fill(0.0);
        let ramp = self.ramp_factor(time);
        let mut elevation = 0.0;
        for n in 0..self.count {
            let (sin, cos) = (self.omega[n] * time).sin_cos();
            elevation += self.elevation_re[n] * cos - self.elevation_im[n] * sin;
            for (j, force) in forces[..written].iter_mut().enumerate() {
                let slot = j * self.padded + n;
                *force += self.force_re[slot] * cos - self.force_im[slot] * sin;
            }
        }
        for force in &mut forces[..written] {
            *force *= ramp;
        }
        ramp * elevation
    }
}

/// The component of a regular wave, with its band check.
fn regular(
    params: &WaveParams,
    table: Option<&ExcitationTable>,
    g: f64,
    notes: &mut Vec<String>,
) -> Result<Components, WaveError> {
    let amplitude = params.height / 2.0;
    let omega = 2.0 * PI / params.period;
    if let Some(t) = table {
        let kr = units::kr_from_omega(omega, t.radius(), g);
        let (low, high) = t.band();
        let describe = || {
            format!(
                "regular wave T = {} s (omega = {omega:.6} rad/s, kR = {kr:.6e}) is {} the \
                 excitation table's band kR {low:e}..{high:e} (omega {:.6}..{:.6} rad/s)",
                params.period,
                if kr > high { "above" } else { "below" },
                units::omega_from_kr(low, t.radius(), g),
                units::omega_from_kr(high, t.radius(), g)
            )
        };
        if kr > high * (1.0 + BAND_SLACK) {
            return Err(WaveError::Band {
                message: describe(),
            });
        }
        if kr < low * (1.0 - BAND_SLACK) {
            if !t.has_long_wave_rows() {
                return Err(WaveError::Band {
                    message: format!("{} and the table has no kR = 0 rows", describe()),
                });
            }
            notes.push(format!(
                "{}: X interpolated linearly in kR towards the table's kR = 0 long-wave rows",
                describe()
            ));
        }
    }
    let variance = amplitude * amplitude / 2.0;
    Ok(Components {
        omega: vec![omega],
        amplitude: vec![amplitude],
        phase: vec![0.0],
        represented_m0: variance,
        spectrum_m0: variance,
        notes: Vec::new(),
    })
}

/// `sum_n Re[c_n z_n]` in `LANES` independent partial sums (vectorizable).
fn dot(c_re: &[f64], c_im: &[f64], z_re: &[f64], z_im: &[f64]) -> f64 {
    let mut acc = [0.0; LANES];
    for (((cr, ci), zr), zi) in c_re
        .chunks_exact(LANES)
        .zip(c_im.chunks_exact(LANES))
        .zip(z_re.chunks_exact(LANES))
        .zip(z_im.chunks_exact(LANES))
    {
        for l in 0..LANES {
            acc[l] += cr[l] * zr[l] - ci[l] * zi[l];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// The terms `w_n = c_n z_n` into `out` (real parts, then imaginary parts; `out.len()` twice
/// the others') and their sum, in `LANES` independent partial sums.
fn elevation_terms(
    c_re: &[f64],
    c_im: &[f64],
    z_re: &[f64],
    z_im: &[f64],
    out: &mut [f64],
) -> (f64, f64) {
    let (w_re, w_im) = out.split_at_mut(c_re.len());
    let (mut re, mut im) = ([0.0; LANES], [0.0; LANES]);
    for (((((cr, ci), zr), zi), wr), wi) in c_re
        .chunks_exact(LANES)
        .zip(c_im.chunks_exact(LANES))
        .zip(z_re.chunks_exact(LANES))
        .zip(z_im.chunks_exact(LANES))
        .zip(w_re.chunks_exact_mut(LANES))
        .zip(w_im.chunks_exact_mut(LANES))
    {
        for l in 0..LANES {
            wr[l] = cr[l] * zr[l] - ci[l] * zi[l];
            wi[l] = cr[l] * zi[l] + ci[l] * zr[l];
            re[l] += wr[l];
            im[l] += wi[l];
        }
    }
    (
        (re[0] + re[1]) + (re[2] + re[3]),
        (im[0] + im[1]) + (im[2] + im[3]),
    )
}

/// `sum_n a_n b_n` in `LANES` independent partial sums.
fn dot_real(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; LANES];
    for (a, b) in a.chunks_exact(LANES).zip(b.chunks_exact(LANES)) {
        for l in 0..LANES {
            acc[l] += a[l] * b[l];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// The cached phasors of one [`Sea`]: only a cache (any scratch gives the same values to the
/// bound in the module docs); clone it into a saved state for a bit-identical replay.
#[derive(Clone, Debug)]
pub struct SeaScratch {
    z_re: Vec<f64>,
    z_im: Vec<f64>,
    w_re: Vec<f64>,
    w_im: Vec<f64>,
    /// The phasors are `e^{i omega (base_time + steps * step)}`; NaN: not synchronized.
    base_time: f64,
    steps: u64,
    /// The step `w` holds (NaN: none yet).
    step: f64,
    /// The last time difference that was not `step` (NaN: none).
    candidate: f64,
    since_sync: usize,
    /// The slow drift's per-component terms (twice the padded length).
    drift_weight: Vec<f64>,
    /// The time of the last [`SeaScratch::advance`] (NaN: none): the phasors are there.
    reached: f64,
}

impl SeaScratch {
    fn sized(padded: usize) -> SeaScratch {
        SeaScratch {
            z_re: vec![1.0; padded],
            z_im: vec![0.0; padded],
            w_re: vec![1.0; padded],
            w_im: vec![0.0; padded],
            base_time: f64::NAN,
            steps: 0,
            step: f64::NAN,
            candidate: f64::NAN,
            since_sync: 0,
            drift_weight: vec![0.0; 2 * padded],
            reached: f64::NAN,
        }
    }

    fn time(&self) -> f64 {
        if self.steps == 0 {
            self.base_time
        } else {
            self.base_time + self.steps as f64 * self.step
        }
    }

    /// Brings the phasors to `time` (module docs).
    fn advance(&mut self, omega: &[f64], omega_max: f64, time: f64) {
        self.reached = time;
        if !(self.base_time.is_finite() && time.is_finite()) {
            self.resync(omega, time);
            return;
        }
        let now = self.time();
        if time == now {
            return;
        }
        let difference = time - now;
        if self.since_sync < RESYNC_INTERVAL {
            if self.step.is_finite() {
                let delta = difference - self.step;
                if delta.abs() <= 4.0 * f64::EPSILON * time.abs().max(self.step.abs()) {
                    self.multiply();
                    self.steps += 1;
                    self.since_sync += 1;
                    return;
                }
                if delta.abs() <= 1e-3 * self.step.abs() && omega_max * delta.abs() <= 1e-4 {
                    self.multiply_corrected(omega, delta);
                    self.base_time = time;
                    self.steps = 0;
                    self.since_sync += 1;
                    return;
                }
            }
            if (difference - self.candidate).abs() <= 1e-3 * self.candidate.abs() {
                for ((w_re, w_im), &w) in self.w_re.iter_mut().zip(&mut self.w_im).zip(omega) {
                    (*w_im, *w_re) = (w * difference).sin_cos();
                }
                self.step = difference;
                self.candidate = f64::NAN;
                self.multiply();
                self.base_time = time;
                self.steps = 0;
                self.since_sync += 1;
                return;
            }
        }
        self.candidate = difference;
        self.resync(omega, time);
    }

    fn resync(&mut self, omega: &[f64], time: f64) {
        for ((z_re, z_im), &w) in self.z_re.iter_mut().zip(&mut self.z_im).zip(omega) {
            (*z_im, *z_re) = (w * time).sin_cos();
        }
        self.base_time = time;
        self.steps = 0;
        self.since_sync = 0;
    }

    /// `z *= w`.
    fn multiply(&mut self) {
        for (((z_re, z_im), &w_re), &w_im) in self
            .z_re
            .iter_mut()
            .zip(&mut self.z_im)
            .zip(&self.w_re)
            .zip(&self.w_im)
        {
            let (a, b) = (*z_re, *z_im);
            *z_re = a * w_re - b * w_im;
            *z_im = a * w_im + b * w_re;
        }
    }

    /// `z *= w e^{i omega delta}`, the exponential by its third-order Taylor polynomial.
    fn multiply_corrected(&mut self, omega: &[f64], delta: f64) {
        for ((((z_re, z_im), &w_re), &w_im), &w) in self
            .z_re
            .iter_mut()
            .zip(&mut self.z_im)
            .zip(&self.w_re)
            .zip(&self.w_im)
            .zip(omega)
        {
            let x = w * delta;
            let (c, s) = (1.0 - 0.5 * x * x, x - x * x * x / 6.0);
            let (m_re, m_im) = (w_re * c - w_im * s, w_re * s + w_im * c);
            let (a, b) = (*z_re, *z_im);
            *z_re = a * m_re - b * m_im;
            *z_im = a * m_im + b * m_re;
        }
    }
}
