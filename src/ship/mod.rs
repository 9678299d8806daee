//! Ships by zero-speed strip theory: stations along the ship, each with a 2D section, and the
//! ship's generalized DOFs as motions of every section.
//!
//! # Axes and DOFs (docs/DESIGN.md, "Ships")
//! x forward, y to port, z up, origin on the mean free surface. A section's 2D frame is the
//! ship's (y, z) plane seen from the bow: 2D x = ship y, 2D y = ship z, 2D roll = ship roll
//! about +x. The ship's DOF `r` moves the section at station `x` by a sway `v_r(x)` (+y), a
//! heave `w_r(x)` (+z), a roll `theta_r(x)` (about +x, through the centreline on the free
//! surface) and, for a section with elastic DOFs of its own, by their amplitudes:
//!
//! ```text
//! sway:  v = 1          heave: w = 1          roll: theta = 1
//! pitch: w = -x         yaw:   v = x          (bow down and bow to port positive)
//! elastic (hull-girder) modes: v(x), w(x), theta(x) given per station (ship file), or
//!                              computed from the stations' structure (`girder.rs`)
//! ```
//!
//! Surge is left out: a slender section has no sectional force along x.
//!
//! # Strip integration
//! With `T(x)` the section coordinates of every ship DOF at `x` (one column per ship DOF: the
//! section's sway, heave, roll and elastic amplitudes) and the sectional complex added mass
//! `A~_s(x, omega)` (per unit length),
//!
//! ```text
//! A~_rs(omega) = integral T_r(x)^T A~_s(x, omega) T_s(x) dx,
//! X_r(omega, beta) = integral T_r(x)^T X_s(x, omega, beta) e^{-i k x cos beta} dx,
//! C_rs = integral T_r(x)^T C_s(x) T_s(x) dx  (+ rho g V z_B in rigid pitch),
//! ```
//!
//! between the first and the last station (`strip.rs`). Between two stations the sectional
//! quantities vary linearly (each end's section weighted by its distance) and the motions
//! `v, w, theta` and amplitudes linearly; 8-point Gauss-Legendre per interval integrates the
//! products, exactly for the rigid motions of a prismatic ship. A station without a section
//! (a pointed end) contributes nothing.
//!
//! # Where things are
//! * `file.rs`: ship files (`docs/SHIPS.md`);
//! * `pdstrip.rs`: PDStrip offset files (the stations of a ship file's `<offsets>`);
//! * `girder.rs`: free-free hull-girder modes from mass and stiffness distributions;
//! * `strip.rs`: the sweep of every distinct section and the strip integration;
//! * `drift.rs`: the fixed ship's mean wave drift by strip theory.

pub mod drift;
mod file;
pub mod girder;
mod pdstrip;
pub mod strip;

pub use strip::ShipSweepParams;

use crate::hull::Hull;

/// Most stations of a ship: each may be its own section, swept over every frequency.
pub(crate) const MAX_STATIONS: usize = 1000;

/// Most elastic modes of a ship (a ship has at most [`crate::hull::MAX_DOFS`] DOFs in all).
pub(crate) const MAX_ELASTIC_MODES: usize = crate::hull::MAX_DOFS - RIGID_DOFS.len();

/// The rigid DOFs of a ship, in order (surge is left out, see the module docs).
pub const RIGID_DOFS: [&str; 5] = ["sway", "heave", "roll", "pitch", "yaw"];

/// Why a ship could not be built: the file (or description), the line when known, and the
/// problem.
pub type ShipError = crate::input::FileError;

/// A section's motion at one station for one ship DOF.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionMotion {
    /// Sway `v` (m per unit coordinate), along +y.
    pub sway: f64,
    /// Heave `w` (m per unit coordinate), along +z.
    pub heave: f64,
    /// Roll `theta` (rad per unit coordinate), about +x.
    pub roll: f64,
    /// Amplitudes of the section's own elastic DOFs, by name.
    pub amplitudes: Vec<(String, f64)>,
}

/// A station: its position and its section (`None`: no wetted section, a pointed end).
#[derive(Clone, Debug)]
pub struct Station {
    /// Position along the ship, m (x forward).
    pub x: f64,
    /// Index into [`Ship::sections`].
    pub section: Option<usize>,
}

/// A ship DOF: rigid (one of [`RIGID_DOFS`]) or elastic with a motion per station.
#[derive(Clone, Debug)]
pub struct ShipDof {
    /// Name (`sway`, ..., or the mode's).
    pub name: String,
    /// `None` for a rigid DOF (its motion follows from its name and x); else one motion per
    /// station.
    pub motions: Option<Vec<SectionMotion>>,
}

/// A ship: stations in increasing x, its distinct sections, its DOFs.
#[derive(Clone, Debug)]
pub struct Ship {
    name: String,
    stations: Vec<Station>,
    sections: Vec<Hull>,
    dofs: Vec<ShipDof>,
    girder_modes: Vec<(String, girder::GirderMode)>,
    /// The water depth of the ship file's `depth` attribute (deep water without it).
    depth: crate::units::WaterDepth,
}

impl Ship {
    /// Builds a ship from stations (strictly increasing x, at least two, at least one with a
    /// section), its distinct sections and its DOFs, checked as a file is
    /// (`source` names the description in errors).
    ///
    /// # Errors
    /// Stations out of order or repeated, sections that do not pierce the free surface, a
    /// station pointing at no section, motions of the wrong length or non-finite, amplitudes
    /// of DOFs the station's section does not have.
    pub fn new(
        name: &str,
        stations: Vec<Station>,
        sections: Vec<Hull>,
        dofs: Vec<ShipDof>,
        source: &str,
    ) -> Result<Ship, ShipError> {
        let error = |m: String| ShipError::new(source, None, m);
        if stations.len() < 2 {
            return Err(error(format!(
                "a ship needs at least 2 stations, got {}",
                stations.len()
            )));
        }
        if stations.len() > MAX_STATIONS {
            return Err(error(format!(
                "{} stations; at most {MAX_STATIONS}",
                stations.len()
            )));
        }
        for (i, station) in stations.iter().enumerate() {
            if !station.x.is_finite() || station.x.abs() > crate::hull::MAX_LENGTH {
                return Err(error(format!(
                    "station {} : x = {} is not a finite position within {} m",
                    i + 1,
                    station.x,
                    crate::hull::MAX_LENGTH
                )));
            }
            if i > 0 && station.x <= stations[i - 1].x {
                return Err(error(format!(
                    "station {} at x = {} m is not after station {} at x = {} m: stations go \
                     from stern to bow in increasing x, each once",
                    i + 1,
                    station.x,
                    i,
                    stations[i - 1].x
                )));
            }
            if let Some(k) = station.section {
                let Some(hull) = sections.get(k) else {
                    return Err(error(format!("station {} has no section {k}", i + 1)));
                };
                if hull.is_closed() {
                    return Err(error(format!(
                        "station {} at x = {} m: the section is fully submerged; a ship's \
                         sections pierce the free surface",
                        i + 1,
                        station.x
                    )));
                }
            }
        }
        if stations.iter().all(|s| s.section.is_none()) {
            return Err(error("no station has a section".to_string()));
        }
        for (k, dof) in dofs.iter().enumerate() {
            if dofs[..k].iter().any(|d| d.name == dof.name) {
                return Err(error(format!("DOF '{}' is defined twice", dof.name)));
            }
            match &dof.motions {
                None if !RIGID_DOFS.contains(&dof.name.as_str()) => {
                    return Err(error(format!(
                        "DOF '{}' is neither rigid ({}) nor given by its motions",
                        dof.name,
                        RIGID_DOFS.join(" ")
                    )))
                }
                None => {}
                Some(motions) => {
                    check_motions(&dof.name, motions, &stations, &sections).map_err(error)?
                }
            }
        }
        if dofs.is_empty() {
            return Err(error("the ship has no DOFs".to_string()));
        }
        if dofs.len() > crate::hull::MAX_DOFS {
            return Err(error(format!(
                "{} DOFs; at most {}",
                dofs.len(),
                crate::hull::MAX_DOFS
            )));
        }
        Ok(Ship {
            name: name.to_string(),
            stations,
            sections,
            dofs,
            girder_modes: Vec::new(),
            depth: crate::units::WaterDepth::Infinite,
        })
    }

    /// The water depth the file gives (`<ship depth="H">`, m; deep water without it), the
    /// default of [`ShipSweepParams::for_ship`].
    pub fn depth(&self) -> crate::units::WaterDepth {
        self.depth
    }

    /// This ship in water depth `depth`.
    pub fn with_depth(mut self, depth: crate::units::WaterDepth) -> Ship {
        self.depth = depth;
        self
    }

    /// The girder modes computed from the stations' structural data (`<girder_modes>`), by
    /// DOF name, with their dry natural frequency and modal mass and stiffness: what a
    /// master's structural model of these modes needs.
    pub fn girder_modes(&self) -> &[(String, girder::GirderMode)] {
        &self.girder_modes
    }

    /// The ship's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Stations, in increasing x.
    pub fn stations(&self) -> &[Station] {
        &self.stations
    }

    /// The distinct sections.
    pub fn sections(&self) -> &[Hull] {
        &self.sections
    }

    /// The DOFs, in order.
    pub fn dofs(&self) -> &[ShipDof] {
        &self.dofs
    }

    /// DOF names, in order.
    pub fn dof_names(&self) -> Vec<&str> {
        self.dofs.iter().map(|d| d.name.as_str()).collect()
    }

    /// Length between the first and the last station, m.
    pub fn length(&self) -> f64 {
        self.stations[self.stations.len() - 1].x - self.stations[0].x
    }

    /// The motion of DOF `dof` at station `station` (rigid DOFs from their name and x).
    pub fn motion(&self, dof: usize, station: usize) -> SectionMotion {
        let d = &self.dofs[dof];
        if let Some(motions) = &d.motions {
            return motions[station].clone();
        }
        let x = self.stations[station].x;
        let (sway, heave, roll) = match d.name.as_str() {
            "sway" => (1.0, 0.0, 0.0),
            "heave" => (0.0, 1.0, 0.0),
            "roll" => (0.0, 0.0, 1.0),
            "pitch" => (0.0, -x, 0.0),
            "yaw" => (x, 0.0, 0.0),
            _ => unreachable!("checked in Ship::new"),
        };
        SectionMotion {
            sway,
            heave,
            roll,
            amplitudes: Vec::new(),
        }
    }

    /// Units of the DOFs: sway, heave (m); roll, pitch, yaw (rad); elastic modes
    /// dimensionless amplitudes (their motions carry the metres).
    pub fn dof_units(&self) -> Vec<crate::fmu::DofUnit> {
        self.dofs
            .iter()
            .map(|d| match d.name.as_str() {
                "sway" | "heave" if d.motions.is_none() => {
                    crate::fmu::DofUnit::new(&d.name, 0, false)
                }
                "roll" | "pitch" | "yaw" if d.motions.is_none() => {
                    crate::fmu::DofUnit::new(&d.name, 1, true)
                }
                _ => crate::fmu::DofUnit::new(&d.name, 1, false),
            })
            .collect()
    }
}

fn check_motions(
    name: &str,
    motions: &[SectionMotion],
    stations: &[Station],
    sections: &[Hull],
) -> Result<(), String> {
    if motions.len() != stations.len() {
        return Err(format!(
            "mode '{name}' has {} motions but the ship has {} stations (one per station, in \
             order)",
            motions.len(),
            stations.len()
        ));
    }
    let mut largest: f64 = 0.0;
    for (i, (motion, station)) in motions.iter().zip(stations).enumerate() {
        let fields = [
            ("v", motion.sway),
            ("w", motion.heave),
            ("theta", motion.roll),
        ];
        for (field, value) in fields
            .into_iter()
            .chain(motion.amplitudes.iter().map(|(n, a)| (n.as_str(), *a)))
        {
            if !value.is_finite() || value.abs() > crate::hull::MAX_LENGTH {
                return Err(format!(
                    "mode '{name}', station {} at x = {} m: {field} = {value} is not finite \
                     or beyond {} in magnitude",
                    i + 1,
                    station.x,
                    crate::hull::MAX_LENGTH
                ));
            }
            largest = largest.max(value.abs());
        }
        for (amplitude, _) in &motion.amplitudes {
            let has = station.section.is_some_and(|k| {
                sections[k].dof_names().iter().enumerate().any(|(j, n)| {
                    *n == amplitude
                        && !matches!(
                            sections[k].dof_kind(j),
                            Some(crate::hull::DofKind::Rigid { .. })
                        )
                })
            });
            if !has {
                return Err(format!(
                    "mode '{name}', station {} at x = {} m: the station's section has no \
                     elastic DOF '{amplitude}'",
                    i + 1,
                    station.x
                ));
            }
        }
    }
    if largest == 0.0 {
        return Err(format!("mode '{name}' is zero at every station"));
    }
    Ok(())
}

#[cfg(test)]
mod depth_tests;
#[cfg(test)]
mod tests;
