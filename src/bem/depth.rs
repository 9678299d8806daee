//! Finite water depth in the panel method: the one place that decides deep or finite.
//!
//! In water of depth `h` the Green function is the deep-water one of the same
//! `nu = omega^2/g` plus the bottom image `(1/2pi) ln r2` and a remainder smooth in the
//! strip ([`crate::green::finite_depth`]); so are its two limits. A [`super::Problem`] in
//! finite depth keeps its deep-water parts (the `omega -> inf` influence computed once, the
//! wave part per frequency) and adds:
//! * the bottom image, computed once (the potential as the collocation panel's mean where the
//!   field point lies within a few panel lengths of the source panel's image in the bottom);
//! * at a wave frequency, the remainder of every pair from one matrix product
//!   ([`FiniteDepthGreen::remainder_integrals`]);
//! * for the limits, the strips' closed-form remainders ([`limit_remainder_integral`]): the
//!   `omega -> inf` one computed once, the rigid-lid one when it is solved.
//!
//! The incident wave is `psi_0 = cosh k(y + h)/cosh(kh) e^{-i k c x}`, `k` the root of
//! `nu = k tanh kh`, its panel means exact (two exponentials).

use super::{drift, unknown_panel, Influence, NEAR_FIELD_RATIO};
use crate::green::finite_depth::{
    bottom_image_integral, limit_remainder_integral, DepthError, FiniteDepthGreen,
};
use crate::green::{FreeSurface, Point};
use crate::panels::{Mesh, Panel};
use faer::complex_native::c64;
use faer::Mat;
use num_complex::Complex64;

/// The frequency-independent finite-depth parts of a mesh's influence.
pub(super) struct DepthParts {
    depth: f64,
    /// The bottom image `(1/2pi) ln r2`, every unknown.
    bottom: Influence,
    /// The `omega -> inf` strip's remainder, every unknown.
    dirichlet: Influence,
}

/// `f(i, p) -> (value, gradient)` of the unknowns into an [`Influence`]: body rows the normal
/// derivative and the potential, lid rows `d/dy`.
fn fill(mesh: &Mesh, mut f: impl FnMut(usize, usize) -> (Complex64, [Complex64; 2])) -> Influence {
    let body_count = mesh.body.len();
    let unknowns = body_count + mesh.lid.len();
    let mut system = Mat::<c64>::zeros(unknowns, unknowns);
    let mut potential = Mat::<c64>::zeros(body_count, unknowns);
    let c = |z: Complex64| c64 { re: z.re, im: z.im };
    for i in 0..unknowns {
        let field = unknown_panel(mesh, i);
        for p in 0..unknowns {
            let (value, gradient) = f(i, p);
            if i < body_count {
                let normal = gradient[0] * field.normal[0] + gradient[1] * field.normal[1];
                system.write(i, p, c(normal));
                potential.write(i, p, c(value));
            } else {
                system.write(i, p, c(gradient[1]));
            }
        }
    }
    Influence { system, potential }
}

/// Adds the first `unknowns` unknowns of `part` to `target`.
pub(super) fn add(target: &mut Influence, part: &Influence) {
    let (unknowns, body) = (target.system.ncols(), target.potential.nrows());
    target.system += part.system.submatrix(0, 0, unknowns, unknowns);
    target.potential += part.potential.submatrix(0, 0, body, unknowns);
}

/// The panel reflected in the bottom `y = -h`.
fn bottom_image(panel: &Panel, h: f64) -> Panel {
    let reflect = |p: Point| [p[0], -2.0 * h - p[1]];
    Panel {
        start: reflect(panel.start),
        end: reflect(panel.end),
        centre: reflect(panel.centre),
        length: panel.length,
        normal: [panel.normal[0], -panel.normal[1]],
    }
}

impl DepthParts {
    /// The parts for `mesh` in depth `h` (m; every node above the bottom).
    pub(super) fn new(mesh: &Mesh, h: f64) -> Self {
        let bottom = fill(mesh, |i, p| {
            let (field, source) = (unknown_panel(mesh, i), unknown_panel(mesh, p));
            let integral = bottom_image_integral(h, field.centre, source.start, source.end);
            let reach = NEAR_FIELD_RATIO * field.length.max(source.length);
            let near = super::squared_distance_to_panel(field.centre, &bottom_image(source, h))
                <= reach * reach;
            let value = if near && i < mesh.body.len() {
                super::panel_mean(field, |x| {
                    bottom_image_integral(h, x, source.start, source.end).potential
                })
            } else {
                integral.potential
            };
            (value, integral.gradient)
        });
        Self {
            depth: h,
            bottom,
            dirichlet: limit(mesh, FreeSurface::Dirichlet, h),
        }
    }

    /// Adds the finite-depth parts of `surface` to the deep-water influence `target`; returns
    /// the propagating wavenumber at a wave frequency (`surface`'s wavenumber is `nu`).
    pub(super) fn add_to(
        &self,
        mesh: &Mesh,
        surface: FreeSurface,
        target: &mut Influence,
    ) -> Result<Option<f64>, DepthError> {
        add(target, &self.bottom);
        match surface {
            FreeSurface::Dirichlet => {
                add(target, &self.dirichlet);
                Ok(None)
            }
            FreeSurface::RigidLid => {
                add(target, &limit(mesh, surface, self.depth));
                Ok(None)
            }
            FreeSurface::Wave { wavenumber } => {
                let green = FiniteDepthGreen::new(wavenumber, self.depth)?;
                let unknowns = target.system.ncols();
                let fields: Vec<Point> = (0..unknowns)
                    .map(|i| unknown_panel(mesh, i).centre)
                    .collect();
                let panels: Vec<[Point; 2]> = (0..unknowns)
                    .map(|p| {
                        let panel = unknown_panel(mesh, p);
                        [panel.start, panel.end]
                    })
                    .collect();
                let integrals = green.remainder_integrals(&fields, &panels);
                let body_count = mesh.body.len();
                for i in 0..unknowns {
                    let field = unknown_panel(mesh, i);
                    for p in 0..unknowns {
                        let gradient = integrals.gradient(i, p);
                        let row = if i < body_count {
                            let value = integrals.value(i, p) + from(target.potential.read(i, p));
                            target.potential.write(i, p, to(value));
                            gradient[0] * field.normal[0] + gradient[1] * field.normal[1]
                        } else {
                            gradient[1]
                        };
                        target
                            .system
                            .write(i, p, to(row + from(target.system.read(i, p))));
                    }
                }
                Ok(Some(green.wavenumber()))
            }
        }
    }

    /// The depth (m).
    pub(super) fn depth(&self) -> f64 {
        self.depth
    }
}

fn to(z: Complex64) -> c64 {
    c64 { re: z.re, im: z.im }
}

fn from(z: c64) -> Complex64 {
    Complex64::new(z.re, z.im)
}

/// The remainder of a limit's strip Green function, every unknown.
fn limit(mesh: &Mesh, surface: FreeSurface, h: f64) -> Influence {
    fill(mesh, |i, p| {
        let (field, source) = (unknown_panel(mesh, i), unknown_panel(mesh, p));
        let (value, gradient) =
            limit_remainder_integral(surface, h, field.centre, source.start, source.end);
        let c = |x: f64| Complex64::new(x, 0.0);
        (c(value), [c(gradient[0]), c(gradient[1])])
    })
}

/// The incident wave of transverse direction cosine `cosine` in depth `h` on each body panel:
/// the panel means of `psi_0 = cosh k(y+h)/cosh(kh) e^{-ikcx}` and of `d(psi_0)/dn`.
pub(super) fn incident_wave(
    mesh: &Mesh,
    k: f64,
    h: f64,
    cosine: f64,
) -> Vec<(Complex64, Complex64)> {
    // psi_0 = [e^{ky - ikcx} + e^{-2kh} e^{-ky - ikcx}] / (1 + e^{-2kh}).
    let q = (-2.0 * k * h).exp();
    let up = [Complex64::new(0.0, -k * cosine), Complex64::new(k, 0.0)];
    let down = [Complex64::new(0.0, -k * cosine), Complex64::new(-k, 0.0)];
    mesh.body
        .iter()
        .map(|panel| {
            let dot = |a: [Complex64; 2]| a[0] * panel.normal[0] + a[1] * panel.normal[1];
            let (u, d) = (
                drift::exponential_mean(panel, up),
                drift::exponential_mean(panel, down) * q,
            );
            (
                (u + d) / (1.0 + q),
                (u * dot(up) + d * dot(down)) / (1.0 + q),
            )
        })
        .collect()
}
