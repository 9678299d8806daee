//! A floating section's rigid motion in regular waves (its RAOs) from its mass properties.
//!
//! Per unit length and per unit wave amplitude, the rigid DOFs (sway, heave, roll about the hull's
//! roll reference point `P`) move by `xi` solving
//!
//! ```text
//! [ -omega^2 (M + a(omega)) + i omega (b(omega) + B_ext) + C + C_G + K_ext ] xi = X(omega)
//! ```
//!
//! with `A~ = a - i b / omega` and `X` from the panel method, the hydrostatic restoring `C`
//! ([`crate::hydrostatics`], buoyancy only), the weight's restoring in roll
//! `C_G = -m g (y_G - y_P)`, and the rigid mass matrix of mass `m` (kg/m), centre of gravity `G`
//! and radius of gyration `k` about G:
//!
//! ```text
//! M = [ m             0             -m (y_G - y_P)          ]
//!     [ 0             m              m (x_G - x_P)          ]
//!     [ -m (y_G - y_P) m (x_G - x_P)  m (k^2 + |G - P|^2)    ]
//! ```
//!
//! `K_ext` and `B_ext` are the user's external (mooring) stiffness and damping over the rigid DOFs.
//! With [`Floating::with_viscous_roll`], `B_ext` gains in roll Ikeda's viscous damping
//! linearized at a roll amplitude `phi_a`, frequency by frequency:
//! `B_eq(omega) = B_l(omega, phi_a) + 8/(3 pi) omega phi_a B_q` ([`crate::viscous`]).
//! Elastic DOFs are held (`xi = 0`): their structural mass and stiffness are not in a hull file.
//! A section floats freely in equilibrium when `m = rho A` (the displaced mass) and `x_G = x_B`;
//! another mass is accepted (a mooring's pretension holds it) and noted by the caller.

use crate::hull::{DofKind, Hull, RigidKind};
use crate::hydrostatics::Hydrostatics;
use crate::sweep::SweepResult;
use crate::viscous::{equivalent_roll_damping, RollDampingParams};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use std::fmt;

/// A section's mass properties and its external (mooring) stiffness and damping.
#[derive(Clone, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass per unit length, kg/m (> 0).
    pub mass: f64,
    /// Centre of gravity (x, y), m, in the hull's frame (y up, free surface y = 0).
    pub centre_of_gravity: [f64; 2],
    /// Radius of gyration about the centre of gravity, m (>= 0).
    pub radius_of_gyration: f64,
    /// External stiffness over the hull's rigid DOFs (in the hull's order), SI per unit
    /// length; empty for none.
    pub stiffness: DMatrix<f64>,
    /// External damping over the hull's rigid DOFs, SI per unit length; empty for none.
    pub damping: DMatrix<f64>,
}

impl fmt::Display for MassProperties {
    /// One line: mass, centre of gravity, radius of gyration, and the external matrices'
    /// nonzero entries (`i,j=value`, 1-based over the rigid DOFs).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [x, y] = self.centre_of_gravity;
        write!(
            f,
            "mass {} kg/m, centre of gravity ({x}, {y}) m, radius of gyration {} m",
            self.mass, self.radius_of_gyration
        )?;
        for (name, matrix) in [("stiffness", &self.stiffness), ("damping", &self.damping)] {
            let entries: Vec<String> = (0..matrix.nrows())
                .flat_map(|i| (0..matrix.ncols()).map(move |j| (i, j)))
                .filter(|&(i, j)| matrix[(i, j)] != 0.0)
                .map(|(i, j)| format!("{},{}={}", i + 1, j + 1, matrix[(i, j)]))
                .collect();
            if !entries.is_empty() {
                write!(f, ", external {name} {}", entries.join(" "))?;
            }
        }
        Ok(())
    }
}

/// Why a motion cannot be computed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MotionError {
    /// A field is not finite or out of its range (named, with the reason).
    Field {
        /// The field, e.g. `mass`.
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The hull has no rigid DOF to move.
    NoRigidDof,
    /// The equation of motion is singular at this frequency (a DOF with neither inertia,
    /// restoring nor damping).
    Singular {
        /// Wave frequency, rad/s.
        omega: f64,
    },
    /// A sweep of another hull (DOF count), without its exciting forces, or (for the drift)
    /// without its drift.
    OtherSweep {
        /// The sweep's DOF count.
        dofs: usize,
        /// The hull's.
        expected: usize,
    },
}

impl fmt::Display for MotionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MotionError::Field { field, reason } => write!(f, "mass properties: {field} {reason}"),
            MotionError::NoRigidDof => f.write_str(
                "mass properties: the hull has no rigid DOF (sway, heave or roll) to move",
            ),
            MotionError::Singular { omega } => write!(
                f,
                "the equation of motion is singular at omega = {omega} rad/s (a DOF without \
                 inertia, restoring or damping)"
            ),
            MotionError::OtherSweep { dofs, expected } => write!(
                f,
                "the sweep has {dofs} DOFs and the floating hull {expected}, or the sweep has no \
                 exciting force (or no drift, for the drift): sweep this hull with its exciting \
                 forces (and --drift)"
            ),
        }
    }
}

impl std::error::Error for MotionError {}

/// A section that floats: the equation of motion's frequency-independent parts.
#[derive(Clone, Debug)]
pub struct Floating {
    /// The hull's DOF index of each rigid DOF.
    rigid: Vec<usize>,
    /// The hull's DOF count.
    dof_count: usize,
    /// Mass matrix over the rigid DOFs, per rho (m^2 ...).
    mass: DMatrix<f64>,
    /// Hydrostatic, weight and external restoring over the rigid DOFs, per rho.
    restoring: DMatrix<f64>,
    /// External damping over the rigid DOFs, per rho.
    damping: DMatrix<f64>,
    /// Gravity the restoring was made with (m/s^2).
    g: f64,
    /// The index among the rigid DOFs of the first roll.
    roll: Option<usize>,
    /// Ikeda's roll damping input and the roll amplitude (rad) it is linearized at.
    viscous_roll: Option<(RollDampingParams, f64)>,
}

fn check(field: &'static str, value: f64, lower: f64) -> Result<(), MotionError> {
    if value.is_finite() && value >= lower {
        Ok(())
    } else {
        Err(MotionError::Field {
            field,
            reason: format!("is {value}: expected a finite number >= {lower}"),
        })
    }
}

impl Floating {
    /// The rigid DOFs of `hull` with `properties`, in water of density `rho` and gravity `g`.
    ///
    /// # Errors
    /// A mass that is not finite and positive, a negative or non-finite radius of gyration, a
    /// centre of gravity farther than 100 half-beams from the origin, external matrices of the
    /// wrong size or not finite, or a hull without rigid DOFs.
    pub fn new(
        hull: &Hull,
        hydrostatics: &Hydrostatics,
        properties: &MassProperties,
        rho: f64,
        g: f64,
    ) -> Result<Floating, MotionError> {
        let p = properties;
        if !(p.mass.is_finite() && p.mass > 0.0) {
            return Err(MotionError::Field {
                field: "mass",
                reason: format!("is {}: expected a finite mass > 0 kg/m", p.mass),
            });
        }
        check("radius_of_gyration", p.radius_of_gyration, 0.0)?;
        let reach = 100.0 * hull.reference_half_beam();
        for (field, value) in [
            ("x_G", p.centre_of_gravity[0]),
            ("y_G", p.centre_of_gravity[1]),
        ] {
            if !(value.is_finite() && value.abs() <= reach) {
                return Err(MotionError::Field {
                    field,
                    reason: format!(
                        "is {value} m: expected within 100 half-beams ({reach} m) of the origin"
                    ),
                });
            }
        }
        let mut rigid = Vec::new();
        let mut kinds = Vec::new();
        for dof in 0..hull.dof_count() {
            if let Some(DofKind::Rigid { kind, reference }) = hull.dof_kind(dof) {
                rigid.push(dof);
                kinds.push((kind, reference));
            }
        }
        if rigid.is_empty() {
            return Err(MotionError::NoRigidDof);
        }
        let n = rigid.len();
        for (field, matrix) in [("stiffness", &p.stiffness), ("damping", &p.damping)] {
            let empty = matrix.nrows() == 0 && matrix.ncols() == 0;
            if !empty && (matrix.nrows() != n || matrix.ncols() != n) {
                return Err(MotionError::Field {
                    field,
                    reason: format!(
                        "is {}x{}: expected {n}x{n} (the hull's rigid DOFs)",
                        matrix.nrows(),
                        matrix.ncols()
                    ),
                });
            }
            if matrix.iter().any(|v| !v.is_finite()) {
                return Err(MotionError::Field {
                    field,
                    reason: "has an entry that is not finite".into(),
                });
            }
            if let Some(k) = (0..matrix.nrows()).find(|&k| matrix[(k, k)] < 0.0) {
                return Err(MotionError::Field {
                    field,
                    reason: format!(
                        "has the negative diagonal entry {} at DOF {}: a mooring stores or \
                         takes energy, it does not supply it",
                        matrix[(k, k)],
                        k + 1
                    ),
                });
            }
        }
        if !p.damping.is_empty() {
            let symmetric = (&p.damping + p.damping.transpose()) * 0.5;
            let scale = symmetric.amax();
            let lowest = symmetric.symmetric_eigenvalues().min();
            if lowest < -1e-12 * scale {
                return Err(MotionError::Field {
                    field: "damping",
                    reason: format!(
                        "has the negative eigenvalue {lowest:e} (its symmetric part): damping \
                         that would feed energy into the motion"
                    ),
                });
            }
        }
        let (m, [xg, yg], k) = (p.mass, p.centre_of_gravity, p.radius_of_gyration);
        let mut mass = DMatrix::zeros(n, n);
        let mut weight = DMatrix::zeros(n, n);
        // Displacement of G per unit DOF: sway (1, 0), heave (0, 1), roll about its own
        // reference point P (-(y_G - y_P), x_G - x_P).
        let motion = |kind: RigidKind, point: [f64; 2]| match kind {
            RigidKind::Sway => [1.0, 0.0],
            RigidKind::Heave => [0.0, 1.0],
            RigidKind::Roll => [-(yg - point[1]), xg - point[0]],
        };
        for (a, &(kind_a, point_a)) in kinds.iter().enumerate() {
            for (b, &(kind_b, point_b)) in kinds.iter().enumerate() {
                let (u, v) = (motion(kind_a, point_a), motion(kind_b, point_b));
                mass[(a, b)] = m * (u[0] * v[0] + u[1] * v[1]);
                if kind_a == RigidKind::Roll && kind_b == RigidKind::Roll {
                    mass[(a, b)] += m * k * k;
                    weight[(a, b)] = -m * g * (yg - point_a[1]);
                }
            }
        }
        let hydro = DMatrix::from_fn(n, n, |a, b| {
            hydrostatics.stiffness_per_rho_g[(rigid[a], rigid[b])] * rho * g
        });
        let external = |matrix: &DMatrix<f64>| {
            if matrix.is_empty() {
                DMatrix::zeros(n, n)
            } else {
                matrix.clone()
            }
        };
        Ok(Floating {
            roll: kinds.iter().position(|(kind, _)| *kind == RigidKind::Roll),
            viscous_roll: None,
            dof_count: hull.dof_count(),
            mass: mass / rho,
            restoring: (hydro + weight + external(&p.stiffness)) / rho,
            damping: external(&p.damping) / rho,
            g,
            rigid,
        })
    }

    /// The motion per unit wave amplitude of every DOF (held DOFs zero) at `omega` (rad/s),
    /// from the complex added mass per rho (`A~ / rho`, all DOFs) and the exciting force per
    /// `rho g a` (all DOFs) of one heading.
    ///
    /// # Errors
    /// A singular equation of motion.
    pub fn rao(
        &self,
        omega: f64,
        g: f64,
        added_mass_per_rho: &DMatrix<Complex64>,
        excitation_per_rho_g: &[Complex64],
    ) -> Result<DVector<Complex64>, MotionError> {
        let n = self.rigid.len();
        let w = Complex64::new(omega, 0.0);
        let i = Complex64::new(0.0, 1.0);
        let mut damping = self.damping.clone();
        if let (Some(r), Some(b_eq)) = (self.roll, self.viscous_roll_damping(omega)?) {
            damping[(r, r)] += b_eq / self.viscous_roll.as_ref().map_or(1.0, |(p, _)| p.rho);
        }
        let system = DMatrix::from_fn(n, n, |a, b| {
            let added = added_mass_per_rho[(self.rigid[a], self.rigid[b])];
            -w * w * (self.mass[(a, b)] + added) + i * w * damping[(a, b)] + self.restoring[(a, b)]
        });
        let force = DVector::from_fn(n, |a, _| excitation_per_rho_g[self.rigid[a]] * g);
        let solved = system
            .lu()
            .solve(&force)
            .filter(|x| x.iter().all(|z| z.re.is_finite() && z.im.is_finite()))
            .ok_or(MotionError::Singular { omega })?;
        let mut out = DVector::zeros(self.dof_count);
        for (a, &dof) in self.rigid.iter().enumerate() {
            out[dof] = solved[a];
        }
        Ok(out)
    }
}

impl Floating {
    /// The motion per unit wave amplitude at every frequency of `sweep` (a sweep of this
    /// floating section's hull with its exciting forces; any scale R), in the gravity of
    /// [`Floating::new`]: one
    /// matrix per frequency, rows the hull's DOFs (held ones zero), columns the sweep's
    /// headings; `xi_j` in m per m of amplitude for a translation, rad per m for a rotation.
    ///
    /// # Errors
    /// A sweep of another DOF count or without exciting forces, a singular equation of motion.
    pub fn sweep_raos(&self, sweep: &SweepResult) -> Result<Vec<DMatrix<Complex64>>, MotionError> {
        let g = self.g;
        let n = sweep.dof_names.len();
        if n != self.dof_count || sweep.excitation.len() != sweep.kr.len() {
            return Err(MotionError::OtherSweep {
                dofs: n,
                expected: self.dof_count,
            });
        }
        let r = sweep.reference_half_beam;
        let length = |j: usize| r.powi(i32::from(sweep.length_exponents[j]));
        // The sweep's A~ / (rho pi R^2) keeps the DOFs' own units; its exciting force is per
        // rho g a R^(1 + e_j).
        let area = std::f64::consts::PI * r * r;
        sweep
            .kr
            .iter()
            .zip(&sweep.added_mass)
            .zip(&sweep.excitation)
            .map(|((kr, added), forces)| {
                let omega = (kr * g / r).sqrt();
                let added_per_rho = added * Complex64::new(area, 0.0);
                let columns = (0..forces.direct.ncols())
                    .map(|h| {
                        let excitation: Vec<Complex64> = (0..n)
                            .map(|j| forces.direct[(j, h)] * r * length(j))
                            .collect();
                        self.rao(omega, g, &added_per_rho, &excitation)
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(DMatrix::from_columns(&columns))
            })
            .collect()
    }

    /// The mean drift per `rho g a^2` of this floating section at every frequency of `sweep`
    /// (swept with its drift): one matrix per frequency, rows the hull's DOFs, columns the
    /// sweep's headings, in SI of the DOF (N/m per m^2 of amplitude for a translation, N per m^2
    /// for roll), as [`crate::bem::Drift::mean_drift`] gives the fixed section's.
    ///
    /// A rigid sway row is the far field (Maruo) with the waves the motion radiates
    /// ([`crate::bem::Drift::horizontal_far_field_moving`]); the other rows are the pressure
    /// integration over the moving section ([`crate::bem::Drift::near_field_moving`]: relative
    /// elevation, velocity squared, the pressure at the moved contour, the rotation of the
    /// first-order force, the rotation's second-order hydrostatics). Roll is the moment about
    /// the roll reference point's mean position; an elastic row is the generalized force in
    /// the body's axes, with the elastic DOFs held.
    ///
    /// # Errors
    /// As [`Floating::sweep_raos`]; a sweep without drift ([`MotionError::OtherSweep`]).
    pub fn sweep_drift(&self, sweep: &SweepResult) -> Result<Vec<DMatrix<f64>>, MotionError> {
        let raos = self.sweep_raos(sweep)?;
        sweep
            .excitation
            .iter()
            .zip(&raos)
            .map(|(forces, rao)| {
                let drift = forces.drift.as_ref().ok_or(MotionError::OtherSweep {
                    dofs: sweep.dof_names.len(),
                    expected: self.dof_count,
                })?;
                let headings = drift.cosines.len().min(rao.ncols());
                let columns: Vec<Vec<f64>> = (0..headings)
                    .map(|h| {
                        let motion: Vec<Complex64> = rao.column(h).iter().copied().collect();
                        drift.mean_drift_moving(h, &motion)
                    })
                    .collect();
                Ok(DMatrix::from_fn(self.dof_count, headings, |j, h| {
                    columns[h][j]
                }))
            })
            .collect()
    }

    /// This section with Ikeda's viscous roll damping of `params` (per unit length, in water of
    /// density `params.rho`) linearized at the roll amplitude `roll_amplitude` (rad, `>= 0`;
    /// 0 keeps the linear parts only) added to the roll's external damping at every frequency.
    ///
    /// # Errors
    /// A section without a rigid roll DOF, or an input Ikeda's formulas refuse (named).
    pub fn with_viscous_roll(
        mut self,
        params: RollDampingParams,
        roll_amplitude: f64,
    ) -> Result<Floating, MotionError> {
        if self.roll.is_none() {
            return Err(MotionError::Field {
                field: "viscous roll damping",
                reason: "needs a rigid roll DOF".into(),
            });
        }
        equivalent_roll_damping(&params, 1.0, roll_amplitude).map_err(|e| MotionError::Field {
            field: "viscous roll damping",
            reason: e.to_string(),
        })?;
        self.viscous_roll = Some((params, roll_amplitude));
        Ok(self)
    }

    /// The equivalent linear viscous roll damping `B_eq(omega)` (N m s per m per rad) that
    /// [`Floating::with_viscous_roll`] adds, or `None` without it.
    ///
    /// # Errors
    /// A frequency Ikeda's formulas refuse (not finite and positive).
    pub fn viscous_roll_damping(&self, omega: f64) -> Result<Option<f64>, MotionError> {
        let Some((params, amplitude)) = &self.viscous_roll else {
            return Ok(None);
        };
        equivalent_roll_damping(params, omega, *amplitude)
            .map(Some)
            .map_err(|e| MotionError::Field {
                field: "viscous roll damping",
                reason: e.to_string(),
            })
    }

    /// Whether DOF `j` of the hull moves (a rigid DOF) rather than being held.
    pub fn moves(&self, j: usize) -> bool {
        self.rigid.contains(&j)
    }
}

#[cfg(test)]
mod tests;
