//! Far-field wave amplitudes and the mean wave drift force of a fixed section, in deep water
//! or in water of depth `h`.
//!
//! # Far field
//! Far from the body the wave part of the Green function is `i e^{k(y + y0)} e^{-ik|x - x0|}`
//! in deep water and `i A0 Z0(y) Z0(y0) e^{-ik|x - x0|}` in depth `h`
//! ([`crate::green`], [`crate::green::finite_depth`]: `Z0(y) = cosh k(y + h)`,
//! `A0 = 2/(2kh + sinh 2kh)`, `k` the propagating wavenumber, `nu = omega^2/g = k tanh kh`).
//! So a source distribution `sigma` radiates, towards `s = +1` (+x) or `s = -1` (-x), the
//! potential `K(s) Z(y) e^{-i s k x}` with `Z(y) = e^{ky}` (deep) or `cosh k(y + h)/cosh kh`
//! (unit value at `y = 0`) and the Kochin amplitude
//!
//! ```text
//! deep:    K(s) = i sum_p sigma_p integral_{panel p} e^{k y0 + i s k x0} ds0
//! depth h: K(s) = i C sum_p sigma_p integral_{panel p} [e^{k y0} + q e^{-k y0}] e^{i s k x0} ds0
//!          q = e^{-2kh},  C = A0 cosh(kh) e^{kh} / 2 = (1 + q) / (1 - q^2 + 4 kh q)
//! ```
//!
//! over body and lid panels (exact panel integrals; `C -> 1`, `q -> 0` as `kh -> inf`). A
//! unit-amplitude incident wave `psi_0 = Z(y) e^{-i c k x}` has the elevation `e^{-i c k x}`,
//! so the scattered wave of heading `c` has the elevation amplitude `K_D(s)`; its reflection
//! coefficient is `R = K_D(-c)` and its transmission coefficient `T = 1 + K_D(c)`. The
//! radiation potential of DOF j per unit velocity raises the elevation `nu K_j(s)` per unit
//! displacement. Energy: the waves carry `rho g |a|^2 c_g / 2` each, `c_g = (omega / 2k)(1 + G)`,
//! `G = 2kh / sinh 2kh` (0 in deep water), so
//! `-Im A~_jj / rho = tanh(kh) (1 + G) (|K_j(+1)|^2 + |K_j(-1)|^2) / 2`, and a fixed, lossless
//! section has `|R|^2 + |T|^2 = 1`.
//!
//! # Mean drift, far field (Maruo)
//! The mean horizontal force per unit length in a regular wave of amplitude `a` is the momentum
//! the waves bring minus what they take away,
//!
//! ```text
//! F_x = c (rho g a^2 / 4) (1 + G) (1 + |R|^2 - |T|^2)     (= c (rho g a^2 / 2) (1 + G) |R|^2 without losses)
//! ```
//!
//! The mean momentum flux through a vertical plane, with the mean of the second-order pressure
//! `-rho |grad Phi|^2 / 2` (the second-order potential periodic: no Bernoulli constant) and the
//! linear theory's zero mean level on both sides, is
//! `int_{-h}^0 rho <u^2 - w^2> / 2 dy + rho g <eta^2> / 2`: `(rho g a^2 / 4)(1 + G)` for a
//! progressive wave; the cross terms of the incident and the reflected wave cancel, so the
//! flux is the same at every `x`, and it is what the pressure integration below sums on the
//! body. (Longuet-Higgins and Stewart's radiation stress `(rho g a^2 / 4)(1 + 2G)` takes the
//! mean pressure `-rho <w^2>` of a progressive wave, which a partly standing wave does not
//! have.) The set-down's hydrostatic force is left out (both sides at the still-water level).
//!
//! # Mean drift, near field (pressure integration on the fixed section)
//! The mean of the second-order pressure `-rho |grad Phi|^2 / 2` on the wetted contour and of the
//! first-order pressure over the strip between the mean and the instantaneous waterline give, per
//! `rho g a^2`, in the direction of DOF j,
//!
//! ```text
//! D_j = sum_waterlines |psi|^2 n_j / (4 |n_x|)  -  (1 / 4 nu) integral_C |d(psi)/ds|^2 n_j ds
//! ```
//!
//! with the total potential `psi = psi_0 + psi_D` in elevation units (`Phi = g a psi / (i omega)`,
//! so `|grad Phi|^2 = (g a^2 / nu) |grad psi|^2` in any depth; the normal velocity is zero on a
//! fixed body) and `n_j / |n_x|` the strip's length per unit height times `n_j`. The tangential
//! derivative is a three-point difference of the panel values along the contour, the waterline
//! values a quadratic extrapolation of the three panels nearest to each waterline point: both
//! second order in the panel length, and extrapolated to zero panel size with the rest of a
//! sweep.

use crate::panels::{Mesh, Panel};
use faer::Mat;
use nalgebra::DMatrix;
use num_complex::Complex64;

use super::{from_faer, unknown_panel};

mod moving;

/// The far-field and drift quantities of one frequency, for the headings 0 and 180 of a
/// section ([`super::HEADINGS`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Drift {
    /// Far-field elevation amplitudes. Row `j` below the DOF count: the wave DOF j radiates per
    /// unit displacement; row `dofs + h`: the wave heading `h` scatters per unit incident
    /// amplitude. Column 0: travelling towards -x, column 1: towards +x.
    pub far_field: DMatrix<Complex64>,
    /// Mean force of the fixed section per `rho g a^2` by pressure integration: rows the DOFs
    /// (m^e per m^2 of amplitude, `e` the DOF's length exponent), then the horizontal force;
    /// one column per heading.
    pub near_field: DMatrix<f64>,
    /// The headings' transverse direction cosines (1: towards +x, -1: towards -x).
    pub cosines: Vec<f64>,
    /// The DOFs whose normal velocity is the panel normal's x component (rigid sway): their
    /// drift is the horizontal force, which the far field gives more accurately.
    pub horizontal: Vec<bool>,
    /// The near-field drift of the section moving, per `rho g a^2`: for each heading, one
    /// Hermitian form per row (the DOFs, then the horizontal force) over `z = [1, xi]`, `xi`
    /// the motion of the rigid DOFs [`Drift::moving`] per unit wave amplitude, so that
    /// `D_j = z^H Q_j z` (the module `moving` gives the terms). `Q_j[(0, 0)]` is
    /// [`Drift::near_field`].
    pub motion_forms: Vec<Vec<DMatrix<Complex64>>>,
    /// The DOF index of each motion the forms take, after the wave's column: the rigid DOFs.
    pub moving: Vec<usize>,
    /// The mean momentum flux of a progressive wave per `rho g a^2 / 4`: `1 + 2kh / sinh 2kh`
    /// in depth `h`, 1 in deep water.
    pub momentum_factor: f64,
}

impl Drift {
    /// `(a self + b other) / c`, entry-wise (Richardson extrapolation).
    pub fn combine(&self, a: f64, other: &Drift, b: f64, c: f64) -> Drift {
        let far = (&self.far_field * Complex64::new(a, 0.0)
            + &other.far_field * Complex64::new(b, 0.0))
            / Complex64::new(c, 0.0);
        let forms = self
            .motion_forms
            .iter()
            .zip(&other.motion_forms)
            .map(|(mine, theirs)| {
                mine.iter()
                    .zip(theirs)
                    .map(|(p, q)| {
                        (p * Complex64::new(a, 0.0) + q * Complex64::new(b, 0.0))
                            / Complex64::new(c, 0.0)
                    })
                    .collect()
            })
            .collect();
        Drift {
            far_field: far,
            near_field: (&self.near_field * a + &other.near_field * b) / c,
            cosines: self.cosines.clone(),
            horizontal: self.horizontal.clone(),
            motion_forms: forms,
            moving: self.moving.clone(),
            momentum_factor: self.momentum_factor,
        }
    }

    /// Number of DOFs.
    fn dof_count(&self) -> usize {
        self.far_field.nrows() - self.cosines.len()
    }

    /// The reflection coefficient `R` of heading `h` (complex elevation of the reflected wave
    /// per unit incident amplitude, at x = 0).
    pub fn reflection(&self, h: usize) -> Complex64 {
        let towards = if self.cosines[h] > 0.0 { 0 } else { 1 };
        self.far_field[(self.dof_count() + h, towards)]
    }

    /// The transmission coefficient `T` of heading `h`.
    pub fn transmission(&self, h: usize) -> Complex64 {
        let towards = if self.cosines[h] > 0.0 { 1 } else { 0 };
        Complex64::new(1.0, 0.0) + self.far_field[(self.dof_count() + h, towards)]
    }

    /// The fixed section's mean horizontal force per `rho g a^2` by the momentum of the far
    /// field (Maruo): `c (1 + G) (1 + |R|^2 - |T|^2) / 4` ([`Drift::momentum_factor`]).
    pub fn horizontal_far_field(&self, h: usize) -> f64 {
        let (r, t) = (self.reflection(h), self.transmission(h));
        self.momentum(h, r, t)
    }

    /// `c (1 + G) (1 + |R|^2 - |T|^2) / 4` of heading `h`.
    fn momentum(&self, h: usize, r: Complex64, t: Complex64) -> f64 {
        self.cosines[h].signum() * (1.0 + r.norm_sqr() - t.norm_sqr()) / 4.0 * self.momentum_factor
    }

    /// The reflection and transmission coefficients of heading `h` for a section that moves
    /// by `motion` per unit wave amplitude (every DOF, e.g. [`crate::motion::Floating::rao`]):
    /// the scattered wave plus the waves the motion radiates.
    pub fn coefficients_moving(&self, h: usize, motion: &[Complex64]) -> (Complex64, Complex64) {
        let (reflected, transmitted) = if self.cosines[h] > 0.0 {
            (0, 1)
        } else {
            (1, 0)
        };
        let radiated = |column: usize| -> Complex64 {
            (0..self.dof_count())
                .map(|j| motion[j] * self.far_field[(j, column)])
                .sum()
        };
        (
            self.reflection(h) + radiated(reflected),
            self.transmission(h) + radiated(transmitted),
        )
    }

    /// The mean horizontal force per `rho g a^2` on a section that moves by `motion`, by the
    /// momentum of the far field: `c (1 + G) (1 + |R|^2 - |T|^2) / 4`.
    pub fn horizontal_far_field_moving(&self, h: usize, motion: &[Complex64]) -> f64 {
        let (r, t) = self.coefficients_moving(h, motion);
        self.momentum(h, r, t)
    }

    /// The fixed section's mean horizontal force per `rho g a^2` by pressure integration.
    pub fn horizontal_near_field(&self, h: usize) -> f64 {
        self.near_field[(self.dof_count(), h)]
    }

    /// The fixed section's mean drift per `rho g a^2`, one row per DOF, one column per heading:
    /// the far field for a rigid sway DOF, pressure integration for the others.
    pub fn mean_drift(&self) -> DMatrix<f64> {
        let dofs = self.dof_count();
        DMatrix::from_fn(dofs, self.cosines.len(), |j, h| {
            if self.horizontal[j] {
                self.horizontal_far_field(h)
            } else {
                self.near_field[(j, h)]
            }
        })
    }

    /// The near-field mean drift per `rho g a^2` of heading `h` on the section moving by
    /// `motion` per unit wave amplitude (every DOF; only the rigid ones, [`Drift::moving`],
    /// enter): one value per DOF, then the horizontal force.
    pub fn near_field_moving(&self, h: usize, motion: &[Complex64]) -> Vec<f64> {
        let z: Vec<Complex64> = std::iter::once(Complex64::new(1.0, 0.0))
            .chain(self.moving.iter().map(|&j| motion[j]))
            .collect();
        self.motion_forms[h]
            .iter()
            .map(|q| {
                let mut value = Complex64::default();
                for (a, za) in z.iter().enumerate() {
                    for (b, zb) in z.iter().enumerate() {
                        value += za.conj() * q[(a, b)] * zb;
                    }
                }
                value.re
            })
            .collect()
    }

    /// The mean drift per `rho g a^2` of heading `h` on the section moving by `motion`: the
    /// far field with the radiated waves for a rigid sway DOF, pressure integration for the
    /// others (as [`Drift::mean_drift`] for the fixed section).
    pub fn mean_drift_moving(&self, h: usize, motion: &[Complex64]) -> Vec<f64> {
        let near = self.near_field_moving(h, motion);
        (0..self.dof_count())
            .map(|j| {
                if self.horizontal[j] {
                    self.horizontal_far_field_moving(h, motion)
                } else {
                    near[j]
                }
            })
            .collect()
    }

    /// Keeps the DOF rows `index` (in that order) and the rest.
    pub(crate) fn select(&self, index: &[usize]) -> Drift {
        let dofs = self.dof_count();
        let rows: Vec<usize> = index
            .iter()
            .copied()
            .chain(dofs..self.far_field.nrows())
            .collect();
        let near_rows: Vec<usize> = index.iter().copied().chain([dofs]).collect();
        // The forms keep the motions of the rigid DOFs kept, renumbered.
        let kept: Vec<(usize, usize)> = self
            .moving
            .iter()
            .enumerate()
            .filter_map(|(c, j)| index.iter().position(|i| i == j).map(|new| (c + 1, new)))
            .collect();
        let columns: Vec<usize> = std::iter::once(0).chain(kept.iter().map(|k| k.0)).collect();
        let forms = self
            .motion_forms
            .iter()
            .map(|heading| {
                near_rows
                    .iter()
                    .map(|&j| heading[j].select_rows(&columns).select_columns(&columns))
                    .collect()
            })
            .collect();
        Drift {
            far_field: self.far_field.select_rows(&rows),
            near_field: self.near_field.select_rows(&near_rows),
            cosines: self.cosines.clone(),
            horizontal: index.iter().map(|&j| self.horizontal[j]).collect(),
            motion_forms: forms,
            moving: kept.iter().map(|k| k.1).collect(),
            momentum_factor: self.momentum_factor,
        }
    }
}

/// The mean of `e^{alpha . x}` over a straight panel: `e^{alpha . c} sinh(w) / w`,
/// `w = alpha . (b - a) / 2`.
pub(super) fn exponential_mean(panel: &Panel, alpha: [Complex64; 2]) -> Complex64 {
    let centre = alpha[0] * panel.centre[0] + alpha[1] * panel.centre[1];
    let half = (alpha[0] * (panel.end[0] - panel.start[0])
        + alpha[1] * (panel.end[1] - panel.start[1]))
        * 0.5;
    let shape = if half.norm() < 1e-4 {
        Complex64::new(1.0, 0.0) + half * half / 6.0
    } else {
        half.sinh() / half
    };
    centre.exp() * shape
}

/// The propagating wave of a drift solve: its wavenumber `k`, `nu = omega^2 / g` and the depth.
#[derive(Clone, Copy, Debug)]
pub(super) struct Wave {
    /// The propagating wavenumber `k` (1/m).
    pub wavenumber: f64,
    /// The water depth `h` (m); `None`: deep water.
    pub depth: Option<f64>,
}

impl Wave {
    /// `nu = omega^2 / g`: `k tanh kh`, `k` in deep water.
    fn nu(&self) -> f64 {
        let k = self.wavenumber;
        self.depth.map_or(k, |h| k * (k * h).tanh())
    }

    /// `q = e^{-2kh}` (0 in deep water).
    fn bottom_ratio(&self) -> f64 {
        self.depth
            .map_or(0.0, |h| (-2.0 * self.wavenumber * h).exp())
    }

    /// `1 + G`, `G = 2kh / sinh 2kh = 4 kh q / (1 - q^2)` (1 in deep water).
    fn momentum_factor(&self) -> f64 {
        match self.depth {
            None => 1.0,
            Some(h) => {
                let (kh, q) = (self.wavenumber * h, self.bottom_ratio());
                1.0 + 4.0 * kh * q / (1.0 - q * q)
            }
        }
    }
}

/// Kochin amplitudes `K(s)` of every column of `strengths` (unknowns: body, then lid panels),
/// columns `s = -1, +1`.
fn kochin(
    mesh: &Mesh,
    wave: Wave,
    strengths: &Mat<faer::complex_native::c64>,
) -> DMatrix<Complex64> {
    let k = wave.wavenumber;
    let unknowns = strengths.nrows();
    let mut out = DMatrix::zeros(strengths.ncols(), 2);
    for (column, s) in [-1.0, 1.0].into_iter().enumerate() {
        let alpha = [Complex64::new(0.0, s * k), Complex64::new(k, 0.0)];
        let weights: Vec<Complex64> = match wave.depth {
            None => (0..unknowns)
                .map(|p| {
                    let panel = unknown_panel(mesh, p);
                    Complex64::new(0.0, panel.length) * exponential_mean(panel, alpha)
                })
                .collect(),
            Some(h) => {
                let q = wave.bottom_ratio();
                let scale = (1.0 + q) / (1.0 - q * q + 4.0 * k * h * q);
                let down = [alpha[0], Complex64::new(-k, 0.0)];
                (0..unknowns)
                    .map(|p| {
                        let panel = unknown_panel(mesh, p);
                        let mean =
                            exponential_mean(panel, alpha) + exponential_mean(panel, down) * q;
                        Complex64::new(0.0, panel.length * scale) * mean
                    })
                    .collect()
            }
        };
        for q in 0..strengths.ncols() {
            out[(q, column)] = (0..unknowns)
                .map(|p| from_faer(strengths.read(p, q)) * weights[p])
                .sum();
        }
    }
    out
}

/// Arc length of each body panel's centre along the contour.
fn centre_arc_lengths(mesh: &Mesh) -> Vec<f64> {
    let mut s = 0.0;
    mesh.body
        .iter()
        .map(|p| {
            let centre = s + 0.5 * p.length;
            s += p.length;
            centre
        })
        .collect()
}

/// Weights of the quadratic through `s[0..3]` at `t` (Lagrange).
fn quadratic_weights(s: [f64; 3], t: f64) -> [f64; 3] {
    [
        (t - s[1]) * (t - s[2]) / ((s[0] - s[1]) * (s[0] - s[2])),
        (t - s[0]) * (t - s[2]) / ((s[1] - s[0]) * (s[1] - s[2])),
        (t - s[0]) * (t - s[1]) / ((s[2] - s[0]) * (s[2] - s[1])),
    ]
}

/// The three body panels nearest each waterline point of an open contour and the point's arc
/// length: the contour's first and last node when they lie on `y = 0`.
fn waterlines(mesh: &Mesh, arc: &[f64], closed: bool) -> Vec<([usize; 3], f64)> {
    let n = mesh.body.len();
    if n < 3 {
        return Vec::new();
    }
    let on_surface = |y: f64| y.abs() <= 1e-9 * mesh.reference_half_beam.max(1e-300);
    let mut out = Vec::new();
    if !closed && on_surface(mesh.body[0].start[1]) {
        out.push(([0, 1, 2], 0.0));
    }
    if !closed && on_surface(mesh.body[n - 1].end[1]) {
        out.push((
            [n - 1, n - 2, n - 3],
            arc[n - 1] + 0.5 * mesh.body[n - 1].length,
        ));
    }
    out
}

/// Tangential derivative along the contour of panel values `f` (three-point differences on
/// the centres' arc lengths; one-sided at the ends of an open contour, wrapped on a closed one).
fn tangential_derivative(
    f: &[Complex64],
    arc: &[f64],
    closed: bool,
    perimeter: f64,
) -> Vec<Complex64> {
    let n = f.len();
    (0..n)
        .map(|l| {
            let (i0, i1, i2, offset) = if closed {
                ((l + n - 1) % n, l, (l + 1) % n, true)
            } else if l == 0 {
                (0, 1, 2, false)
            } else if l == n - 1 {
                (n - 3, n - 2, n - 1, false)
            } else {
                (l - 1, l, l + 1, false)
            };
            let mut s = [arc[i0], arc[i1], arc[i2]];
            if offset {
                if l == 0 {
                    s[0] -= perimeter;
                }
                if l == n - 1 {
                    s[2] += perimeter;
                }
            }
            // Derivative of the quadratic through the three points, at arc[l].
            let t = arc[l];
            let d = [
                ((t - s[1]) + (t - s[2])) / ((s[0] - s[1]) * (s[0] - s[2])),
                ((t - s[0]) + (t - s[2])) / ((s[1] - s[0]) * (s[1] - s[2])),
                ((t - s[0]) + (t - s[1])) / ((s[2] - s[0]) * (s[2] - s[1])),
            ];
            f[i0] * d[0] + f[i1] * d[1] + f[i2] * d[2]
        })
        .collect()
}

/// The drift quantities of one wave frequency: the far field of every solved column, and for
/// each heading of `cosines` (all +-1) the near-field mean force of the section fixed and the
/// forms that give it moving ([`moving`]).
///
/// `strengths`: source strengths (unknowns x (DOFs + headings)); `radiation`: each DOF's
/// potential per unit velocity at the body panels; `body_potential`: the diffraction potential
/// at the body panels, one column per heading; `incident`: the incident wave's panel means per
/// heading.
pub(super) fn drift(
    mesh: &Mesh,
    wave: Wave,
    cosines: &[f64],
    strengths: &Mat<faer::complex_native::c64>,
    radiation: &[Vec<Complex64>],
    body_potential: &[Vec<Complex64>],
    incident: &[Vec<(Complex64, Complex64)>],
) -> Drift {
    // Radiated elevation per unit displacement and near-field velocities scale with nu.
    let nu = wave.nu();
    let dofs = mesh.dof_names.len();
    let n = mesh.body.len();
    let mut far_field = kochin(mesh, wave, strengths);
    for j in 0..dofs {
        for s in 0..2 {
            far_field[(j, s)] *= nu;
        }
    }
    let arc = centre_arc_lengths(mesh);
    let perimeter: f64 = mesh.body.iter().map(|p| p.length).sum();
    let closed = {
        let (a, b) = (mesh.body[0].start, mesh.body[n - 1].end);
        (a[0] - b[0]).hypot(a[1] - b[1]) <= 1e-9 * mesh.reference_half_beam
    };
    let lines = waterlines(mesh, &arc, closed);
    // Generalized normals of the DOFs, then the horizontal force (n_x).
    let normal = |l: usize, j: usize| {
        if j < dofs {
            mesh.normal_velocity[(l, j)]
        } else {
            mesh.body[l].normal[0]
        }
    };
    let motion = moving::Motion::of(mesh);
    // The moving columns' potentials in elevation units (nu phi_j) and their derivatives.
    let radiated: Vec<Vec<Complex64>> = motion
        .dofs
        .iter()
        .map(|&j| radiation[j].iter().map(|phi| phi * nu).collect())
        .collect();
    let radiated_tangential: Vec<Vec<Complex64>> = radiated
        .iter()
        .map(|f| tangential_derivative(f, &arc, closed, perimeter))
        .collect();
    let columns = |first: &[Complex64], rest: &[Vec<Complex64>], l: usize| -> Vec<Complex64> {
        std::iter::once(first[l])
            .chain(rest.iter().map(|f| f[l]))
            .collect()
    };
    let mut near_field = DMatrix::zeros(dofs + 1, cosines.len());
    let mut motion_forms = Vec::with_capacity(cosines.len());
    for (h, wave) in incident.iter().enumerate() {
        let psi: Vec<Complex64> = (0..n).map(|l| wave[l].0 + body_potential[h][l]).collect();
        let tangential = tangential_derivative(&psi, &arc, closed, perimeter);
        let waterline_data = lines
            .iter()
            .map(|&(panels, s)| {
                let w = quadratic_weights(panels.map(|l| arc[l]), s);
                let at =
                    |f: &dyn Fn(usize) -> f64| -> f64 { (0..3).map(|m| w[m] * f(panels[m])).sum() };
                let values: Vec<Complex64> = (0..=motion.dofs.len())
                    .map(|c| {
                        (0..3)
                            .map(|m| {
                                let l = panels[m];
                                let value = if c == 0 { psi[l] } else { radiated[c - 1][l] };
                                value * w[m]
                            })
                            .sum()
                    })
                    .collect();
                let normals = (0..=dofs).map(|j| at(&|l| normal(l, j))).collect();
                let n_x = at(&|l| mesh.body[l].normal[0]).abs().max(1e-3);
                let point = if panels[0] == 0 {
                    mesh.body[0].start
                } else {
                    mesh.body[n - 1].end
                };
                moving::Waterline {
                    potential: values,
                    normals,
                    n_x,
                    point,
                }
            })
            .collect();
        let heading = moving::Heading {
            potential: (0..n).map(|l| columns(&psi, &radiated, l)).collect(),
            tangential: (0..n)
                .map(|l| columns(&tangential, &radiated_tangential, l))
                .collect(),
            waterlines: waterline_data,
        };
        let forms = moving::forms(mesh, nu, &motion, &heading, &normal);
        for (j, q) in forms.iter().enumerate() {
            near_field[(j, h)] = q[(0, 0)].re;
        }
        motion_forms.push(forms);
    }
    let horizontal = (0..dofs)
        .map(|j| {
            (0..n).all(|l| (mesh.normal_velocity[(l, j)] - mesh.body[l].normal[0]).abs() <= 1e-12)
        })
        .collect();
    Drift {
        far_field,
        near_field,
        cosines: cosines.to_vec(),
        horizontal,
        motion_forms,
        moving: motion.dofs,
        momentum_factor: wave.momentum_factor(),
    }
}

#[cfg(test)]
mod depth_tests;
#[cfg(test)]
mod tests;
