//! State bytes: the explicit state of a component, self-describing and checked.
//!
//! Layout (little-endian): `HYDROFMU`, format version (u32), the owner's tag byte, the GUID
//! (u32 length + UTF-8), DOFs n and states (u32 each), keep_inf_mass (u8), rho, g, time,
//! time anchor, last step (f64 each), steps since the anchor (u64), then z, v, v', a, a'
//! (f64 each), the wave parameters (kind, seed, components, height, period, heading, gamma, ramp:
//! `write_waves`), the start time and the stop time (f64 each, +inf: none), `wave.drift`
//! (i32; only in the states of an FMU packed with a drift table, so the bytes of every other
//! FMU are unchanged), `current.speed` and `current.heading` (f64 each; only in the states of
//! an FMU packed with viscous damping), then an FNV-1a 64 checksum of everything before it.
//!
//! The bytes are untrusted input. Every size they decide is bounded before anything is
//! allocated (the GUID at 1024 bytes, the vectors at this component's dimensions, which
//! must match). A state is accepted only by a component with the same GUID and dimensions,
//! and only if it meets every rule of `validate` (finite values within their limits, a
//! time consistent with its anchor and step count, finite outputs): the checksum alone
//! would accept any change made with the checksum recomputed.

use super::{Model, ModelError, ModelState};
use crate::waves::{DriftMode, WaveKind, WaveParams};
use nalgebra::DVector;

const MAGIC: &[u8; 8] = b"HYDROFMU";
/// 3: the stop time after the start time; 4: the current of an FMU with viscous damping.
const FORMAT_VERSION: u32 = 4;

/// The state bytes' checksum (FNV-1a 64).
#[cfg(test)]
pub(super) fn checksum(bytes: &[u8]) -> u64 {
    fnv1a(bytes)
}

fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf29ce484222325u64, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x100000001b3)
    })
}

struct ByteReader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl ByteReader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], ModelError> {
        let end = self.at.checked_add(n).filter(|e| *e <= self.bytes.len());
        let end = end.ok_or_else(|| ModelError::State("the bytes end too early".into()))?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8, ModelError> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, ModelError> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn u64(&mut self) -> Result<u64, ModelError> {
        let mut a = [0u8; 8];
        a.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(a))
    }
    fn f64(&mut self) -> Result<f64, ModelError> {
        Ok(f64::from_bits(self.u64()?))
    }
    fn vector(&mut self, n: usize) -> Result<DVector<f64>, ModelError> {
        let mut v = DVector::zeros(n);
        for x in v.iter_mut() {
            *x = self.f64()?;
        }
        Ok(v)
    }
}

/// Bytes before the GUID: magic, format version, tag, GUID length.
const HEADER_BYTES: usize = 8 + 4 + 1 + 4;

/// Bytes from the GUID to the vectors: n, states, keep_inf_mass, five f64, the step count.
const FIXED_BYTES: usize = 4 + 4 + 1 + 5 * 8 + 8;

/// Bytes of the wave parameters, the start time and the stop time in the state.
const WAVE_AND_RUN_BYTES: usize = 4 + 4 + 4 + 5 * 8 + 8 + 8;

/// The wave parameters: kind (i32), seed (i32), components (u32), height, period, heading,
/// gamma, ramp (f64).
fn write_waves(b: &mut Vec<u8>, w: &WaveParams) {
    b.extend_from_slice(&w.kind.code().to_le_bytes());
    b.extend_from_slice(&w.seed.to_le_bytes());
    // Validated parameters have at most MAX_COMPONENTS components.
    b.extend_from_slice(&(w.components as u32).to_le_bytes());
    for x in [w.height, w.period, w.heading, w.gamma, w.ramp] {
        b.extend_from_slice(&x.to_le_bytes());
    }
}

/// Reads and validates what `write_waves` wrote.
fn read_waves(r: &mut ByteReader<'_>) -> Result<WaveParams, ModelError> {
    let invalid = |e: crate::waves::WaveError| ModelError::State(format!("wave parameters: {e}"));
    let kind = WaveKind::from_code(r.u32()? as i32).map_err(invalid)?;
    let seed = r.u32()? as i32;
    let components = r.u32()? as usize;
    let waves = WaveParams {
        kind,
        seed,
        components,
        height: r.f64()?,
        period: r.f64()?,
        heading: r.f64()?,
        gamma: r.f64()?,
        ramp: r.f64()?,
        drift: DriftMode::Off,
    };
    waves.validate().map_err(invalid)?;
    Ok(waves)
}

impl Model {
    /// The state as self-describing bytes; `tag` is kept for the owner (the FMI layer
    /// stores its phase there).
    pub fn serialize(&self, tag: u8) -> Vec<u8> {
        self.serialize_state(&self.state, tag)
    }

    /// Like [`Model::serialize`], for a state saved earlier (same dimensions).
    pub fn serialize_state(&self, s: &ModelState, tag: u8) -> Vec<u8> {
        let mut b = Vec::with_capacity(self.serialized_size());
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        b.push(tag);
        b.extend_from_slice(&(self.guid.len() as u32).to_le_bytes());
        b.extend_from_slice(self.guid.as_bytes());
        b.extend_from_slice(&(self.dof_count() as u32).to_le_bytes());
        b.extend_from_slice(&(self.system.state_size() as u32).to_le_bytes());
        b.push(u8::from(self.system.keep_inf_mass));
        for x in [s.rho, s.g, s.time, s.time_anchor, s.last_step] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        b.extend_from_slice(&s.steps_since_anchor.to_le_bytes());
        for v in s.vectors() {
            for x in v.iter() {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        write_waves(&mut b, &s.waves);
        b.extend_from_slice(&s.start_time.to_le_bytes());
        let stop = s.stop_time.unwrap_or(f64::INFINITY);
        b.extend_from_slice(&stop.to_le_bytes());
        if self.drift.is_some() {
            b.extend_from_slice(&s.waves.drift.code().to_le_bytes());
        }
        if self.viscous.is_some() {
            for x in s.current {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        let sum = fnv1a(&b);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// Length of [`Model::serialize`]'s output.
    pub fn serialized_size(&self) -> usize {
        let n = self.dof_count();
        let ns = self.system.state_size();
        let drift = if self.drift.is_some() { 4 } else { 0 };
        let current = if self.viscous.is_some() { 16 } else { 0 };
        HEADER_BYTES
            + self.guid.len()
            + FIXED_BYTES
            + 8 * (ns + 4 * n)
            + WAVE_AND_RUN_BYTES
            + drift
            + current
            + 8
    }

    /// Reads state bytes written by [`Model::serialize`] of an FMU with the same GUID, and
    /// checks the state as [`Model::set_state`] does, and its outputs finite (module docs).
    /// Returns the state and the owner's tag; does not change the model.
    pub fn deserialize(&self, bytes: &[u8]) -> Result<(ModelState, u8), ModelError> {
        if bytes.len() < 8 + 4 + 8 || &bytes[..8] != MAGIC {
            return Err(ModelError::State(
                "not a hydrofmu state (wrong magic bytes)".into(),
            ));
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        let mut r = ByteReader { bytes: body, at: 8 };
        let version = r.u32()?;
        if version != FORMAT_VERSION {
            return Err(ModelError::State(format!(
                "format version {version}, this FMU reads {FORMAT_VERSION}"
            )));
        }
        let mut s = [0u8; 8];
        s.copy_from_slice(sum);
        if u64::from_le_bytes(s) != fnv1a(body) {
            return Err(ModelError::State(
                "checksum mismatch (corrupt bytes)".into(),
            ));
        }
        let tag = r.u8()?;
        let guid_len = r.u32()? as usize;
        if guid_len > 1024 {
            return Err(ModelError::State("GUID too long".into()));
        }
        let guid = String::from_utf8_lossy(r.take(guid_len)?).into_owned();
        if guid != self.guid {
            return Err(ModelError::State(format!(
                "state of FMU {guid}, this FMU is {}",
                self.guid
            )));
        }
        let n = r.u32()? as usize;
        let ns = r.u32()? as usize;
        let keep = r.u8()? != 0;
        if n != self.dof_count()
            || ns != self.system.state_size()
            || keep != self.system.keep_inf_mass
        {
            return Err(ModelError::State(format!(
                "dimensions {n} DOFs, {ns} states do not match this FMU"
            )));
        }
        let mut state = ModelState {
            rho: r.f64()?,
            g: r.f64()?,
            time: r.f64()?,
            time_anchor: r.f64()?,
            last_step: r.f64()?,
            steps_since_anchor: r.u64()?,
            network: r.vector(ns)?,
            velocity: r.vector(n)?,
            velocity_derivative: r.vector(n)?,
            acceleration: r.vector(n)?,
            acceleration_derivative: r.vector(n)?,
            waves: read_waves(&mut r)?,
            start_time: r.f64()?,
            // +inf: no stop time; anything else must pass the checks below.
            stop_time: Some(r.f64()?).filter(|t| *t != f64::INFINITY),
            current: [0.0; 2],
        };
        if self.drift.is_some() {
            state.waves.drift = DriftMode::from_code(r.u32()? as i32)
                .map_err(|e| ModelError::State(format!("wave parameters: {e}")))?;
        }
        if self.viscous.is_some() {
            state.current = [r.f64()?, r.f64()?];
        }
        if r.at != body.len() {
            return Err(ModelError::State("trailing bytes".into()));
        }
        let realized = self.check_state(&state)?;
        self.check_outputs(&state, realized.as_ref().unwrap_or(&self.system))?;
        Ok((state, tag))
    }
}

#[cfg(test)]
mod fuzz;
#[cfg(test)]
pub(crate) mod tests;
