//! The near-field mean drift of a section that moves: Hermitian forms over its rigid motion.
//!
//! A section whose rigid DOFs (sway `xi_x`, heave `xi_y`, roll `theta` about `P`) move by `xi`
//! per unit wave amplitude displaces its contour point `r` by `X = (xi_x - theta (y - y_P),
//! xi_y + theta (x - x_P))`. Its total first-order potential is `psi + nu sum_j xi_j phi_j`
//! (in elevation units: the dynamic pressure is `rho g a Psi`; `nu = omega^2 / g`, the
//! wavenumber `k` in deep water, `k tanh kh` in depth `h`), with the diffraction problem's
//! `psi = psi_0 + psi_D` and the radiation potentials `phi_j` per unit velocity. Pressure
//! integration to second order over the mean wetted contour `S_0` (Pinkster 1980; Ogilvie 1983),
//! per `rho g a^2` and with the mean of products `<Re(A e^{iwt}) Re(B e^{iwt})> = Re(A B*) / 2`:
//!
//! ```text
//! D_j = sum_waterlines |zeta_r|^2 n_j / (4 |n_x|)           zeta_r = Psi - X_y (relative elevation)
//!     + int_S0 [ -|d Psi/ds|^2 / (4nu) - nu |X_n|^2 / 4     (velocity squared; dPsi/dn = nu X_n)
//!              + Re(X_s conj(d Psi/ds)) / 2 + nu |X_n|^2 / 2 (X . grad p: the pressure at the moved point)
//!              + |theta|^2 (y - y_P) / 4 ] n_j ds            (second-order hydrostatics of the rotation)
//!     + rigid terms of the row
//! ```
//!
//! `n` is the panel normal (out of the fluid), `n_j` the DOF's generalized normal, `X_n`, `X_s`
//! the displacement's normal and tangential components. Rows in earth-fixed axes add what the
//! turning of the body does to them, with the first-order force on `S_0`,
//! `F1 = int (Psi - X_y) n ds`, and the buoyancy `F0 = -int y n ds`:
//!
//! - a force (sway, heave and the horizontal row): the rotation of the first-order force
//!   `Re(theta conj(J F1)) / 2` (`J` turns by +90 degrees) and the second-order rotation of the
//!   hydrostatic force `|theta|^2 / 4 int y n ds`;
//! - the roll moment, about the roll reference point's MEAN position: the lever's translation,
//!   `Re(xi_t x conj(F1 + theta J F0)) / 2`, `xi_t = (xi_x, xi_y)`;
//! - an elastic row is a generalized force in the body's axes: nothing more.
//!
//! The drift is a Hermitian form in `z = [1, xi_rigid]`: `D_j = z^H Q_j z`, so the sweep stores
//! `Q_j` and any motion (from any mass properties) gives its drift; `Q_j[(0, 0)]` is the fixed
//! section's drift. Elastic DOFs are held: their motion (which would also turn the contour's
//! normals locally) is not in the forms.

use crate::hull::RigidKind;
use crate::panels::Mesh;
use nalgebra::DMatrix;
use num_complex::Complex64;

/// What a drift row measures.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Row {
    /// The force along x (sway, or the horizontal row).
    ForceX,
    /// The force along y (heave).
    ForceY,
    /// The moment about the roll reference point's mean position.
    Moment,
    /// A generalized force of an elastic DOF, in the body's axes.
    Body,
}

/// The rigid DOFs that move: their columns in the forms (1-based: column 0 is the wave).
#[derive(Clone, Debug, Default)]
pub(super) struct Motion {
    /// DOF index of each moving column.
    pub dofs: Vec<usize>,
    sway: Option<usize>,
    heave: Option<usize>,
    /// Column and reference point of the roll DOF.
    roll: Option<(usize, [f64; 2])>,
}

impl Motion {
    pub fn of(mesh: &Mesh) -> Motion {
        let mut motion = Motion::default();
        for (j, rigid) in mesh.rigid.iter().enumerate() {
            let Some((kind, reference)) = *rigid else {
                continue;
            };
            let column = motion.dofs.len() + 1;
            let slot = match kind {
                RigidKind::Sway => &mut motion.sway,
                RigidKind::Heave => &mut motion.heave,
                RigidKind::Roll => {
                    if motion.roll.is_some() {
                        continue;
                    }
                    motion.roll = Some((column, reference));
                    motion.dofs.push(j);
                    continue;
                }
            };
            if slot.is_none() {
                *slot = Some(column);
                motion.dofs.push(j);
            }
        }
        motion
    }

    /// Size of the forms.
    fn size(&self) -> usize {
        self.dofs.len() + 1
    }

    /// Displacement of the point `p` per unit motion of each column (column 0: zero).
    fn displacement(&self, p: [f64; 2]) -> Vec<[f64; 2]> {
        let mut out = vec![[0.0; 2]; self.size()];
        if let Some(c) = self.sway {
            out[c] = [1.0, 0.0];
        }
        if let Some(c) = self.heave {
            out[c] = [0.0, 1.0];
        }
        if let Some((c, reference)) = self.roll {
            out[c] = [-(p[1] - reference[1]), p[0] - reference[0]];
        }
        out
    }

    /// Unit vector of a column, or zeros.
    fn unit(&self, column: Option<usize>) -> Vec<Complex64> {
        let mut out = vec![Complex64::default(); self.size()];
        if let Some(c) = column {
            out[c] = Complex64::new(1.0, 0.0);
        }
        out
    }
}

/// `q += weight (conj(w) v^T + conj(v) w^T) / 2`: then `z^H q z` gains
/// `weight Re((v . z) conj(w . z))`.
fn add_product(q: &mut DMatrix<Complex64>, weight: f64, v: &[Complex64], w: &[Complex64]) {
    if weight == 0.0 {
        return;
    }
    let half = 0.5 * weight;
    for a in 0..v.len() {
        for b in 0..v.len() {
            q[(a, b)] += (w[a].conj() * v[b] + v[a].conj() * w[b]) * half;
        }
    }
}

fn to_complex(v: &[f64]) -> Vec<Complex64> {
    v.iter().map(|&x| Complex64::new(x, 0.0)).collect()
}

/// A waterline point of one heading.
pub(super) struct Waterline {
    /// `Psi` (coefficients over `[1, xi]`).
    pub potential: Vec<Complex64>,
    /// The generalized normal `n_j` of each row.
    pub normals: Vec<f64>,
    /// `|n_x|`, bounded away from 0.
    pub n_x: f64,
    /// Position.
    pub point: [f64; 2],
}

/// One heading's panel and waterline data for the forms: coefficient vectors over `[1, xi]`.
pub(super) struct Heading {
    /// `Psi` at each panel.
    pub potential: Vec<Vec<Complex64>>,
    /// `d Psi / ds` at each panel.
    pub tangential: Vec<Vec<Complex64>>,
    /// The waterline points.
    pub waterlines: Vec<Waterline>,
}

/// The forms `Q_j` of one heading, rows the DOFs then the horizontal force; `nu = omega^2 / g`.
pub(super) fn forms(
    mesh: &Mesh,
    nu: f64,
    motion: &Motion,
    heading: &Heading,
    normal: &dyn Fn(usize, usize) -> f64,
) -> Vec<DMatrix<Complex64>> {
    let dofs = mesh.dof_names.len();
    let size = motion.size();
    let theta = motion.unit(motion.roll.map(|(c, _)| c));
    let y_reference = motion.roll.map_or(0.0, |(_, p)| p[1]);
    // Per panel: displacement components per column.
    let panels: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = mesh
        .body
        .iter()
        .map(|panel| {
            let u = motion.displacement(panel.centre);
            let t = [panel.normal[1], -panel.normal[0]];
            let normal = u
                .iter()
                .map(|d| d[0] * panel.normal[0] + d[1] * panel.normal[1]);
            let tangential = u.iter().map(|d| d[0] * t[0] + d[1] * t[1]);
            (
                normal.collect(),
                tangential.collect(),
                u.iter().map(|d| d[1]).collect(),
            )
        })
        .collect();
    // First-order force on S_0 and buoyancy.
    let mut first = [
        vec![Complex64::default(); size],
        vec![Complex64::default(); size],
    ];
    let mut buoyancy = [0.0; 2];
    for (l, panel) in mesh.body.iter().enumerate() {
        for (axis, force) in first.iter_mut().enumerate() {
            let weight = panel.normal[axis] * panel.length;
            for (c, f) in force.iter_mut().enumerate() {
                *f += (heading.potential[l][c] - panels[l].2[c]) * weight;
            }
            buoyancy[axis] -= panel.centre[1] * weight;
        }
    }
    let earth_first = [
        (0..size)
            .map(|c| first[0][c] - theta[c] * buoyancy[1])
            .collect::<Vec<_>>(),
        (0..size)
            .map(|c| first[1][c] + theta[c] * buoyancy[0])
            .collect::<Vec<_>>(),
    ];
    let turned_first = [
        first[1].iter().map(|f| -f).collect::<Vec<_>>(),
        first[0].clone(),
    ];
    (0..=dofs)
        .map(|j| {
            let row = if j == dofs {
                Row::ForceX
            } else {
                match mesh.rigid[j] {
                    Some((RigidKind::Sway, _)) => Row::ForceX,
                    Some((RigidKind::Heave, _)) => Row::ForceY,
                    Some((RigidKind::Roll, _)) => Row::Moment,
                    None => Row::Body,
                }
            };
            let mut q = DMatrix::zeros(size, size);
            for line in &heading.waterlines {
                let mut relative = line.potential.clone();
                for (r, u) in relative.iter_mut().zip(motion.displacement(line.point)) {
                    *r -= u[1];
                }
                add_product(
                    &mut q,
                    line.normals[j] / (4.0 * line.n_x),
                    &relative,
                    &relative,
                );
            }
            let mut hydrostatic = 0.0;
            let mut height = [0.0; 2];
            for (l, panel) in mesh.body.iter().enumerate() {
                let weight = normal(l, j) * panel.length;
                let (x_n, x_s, _) = &panels[l];
                let tangential = &heading.tangential[l];
                add_product(&mut q, -weight / (4.0 * nu), tangential, tangential);
                // -nu/4 (velocity squared) + nu/2 (X . grad p) of |X_n|^2.
                let x_n = to_complex(x_n);
                add_product(&mut q, 0.25 * nu * weight, &x_n, &x_n);
                add_product(&mut q, 0.5 * weight, &to_complex(x_s), tangential);
                hydrostatic += (panel.centre[1] - y_reference) * weight;
                for (axis, h) in height.iter_mut().enumerate() {
                    *h += panel.centre[1] * panel.normal[axis] * panel.length;
                }
            }
            add_product(&mut q, 0.25 * hydrostatic, &theta, &theta);
            match row {
                Row::ForceX | Row::ForceY => {
                    let axis = usize::from(row == Row::ForceY);
                    add_product(&mut q, 0.5, &theta, &turned_first[axis]);
                    add_product(&mut q, 0.25 * height[axis], &theta, &theta);
                }
                Row::Moment => {
                    add_product(&mut q, 0.5, &motion.unit(motion.sway), &earth_first[1]);
                    add_product(&mut q, -0.5, &motion.unit(motion.heave), &earth_first[0]);
                }
                Row::Body => {}
            }
            q
        })
        .collect()
}
