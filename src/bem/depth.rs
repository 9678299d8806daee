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
//!   ([`FiniteDepthGreen::remainder_rows`]): for a body panel its potential and normal
//!   derivative, for a lid panel `d/dy`; on a symmetric mesh only for one collocation point
//!   of each mirror pair (the other's row is `I(i, p) = I(m(i), m(p))`);
//! * for the limits, the strips' closed-form remainders ([`limit_remainder_integral`]): the
//!   `omega -> inf` one computed once, the rigid-lid one when it is solved.
//!
//! The incident wave is `psi_0 = cosh k(y + h)/cosh(kh) e^{-i k c x}`, `k` the root of
//! `nu = k tanh kh`, its panel means exact (two exponentials).

use super::{drift, unknown_panel, Influence, NEAR_FIELD_RATIO};
use crate::green::finite_depth::{
    bottom_image_integral, limit_remainder_integral, DepthError, FiniteDepthGreen, RemainderRow,
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
    /// The unknowns' mirror map on a symmetric mesh.
    mirror: Option<Vec<usize>>,
}

/// `f(i, p) -> (value, gradient)` of the unknowns into an [`Influence`]: body rows the normal
/// derivative and the potential, lid rows `d/dy`. With a `mirror` map the rows of mirrored
/// collocation points are copies, `I(i, p) = I(m(i), m(p))`.
fn fill(
    mesh: &Mesh,
    mirror: Option<&[usize]>,
    mut f: impl FnMut(usize, usize) -> (Complex64, [Complex64; 2]),
) -> Influence {
    let body_count = mesh.body.len();
    let unknowns = body_count + mesh.lid.len();
    let mut system = Mat::<c64>::zeros(unknowns, unknowns);
    let mut potential = Mat::<c64>::zeros(body_count, unknowns);
    let c = |z: Complex64| c64 { re: z.re, im: z.im };
    for i in (0..unknowns).filter(|&i| !is_copy(mirror, i)) {
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
    if let Some(m) = mirror {
        for i in (0..unknowns).filter(|&i| is_copy(mirror, i)) {
            for p in 0..unknowns {
                system.write(i, p, system.read(m[i], m[p]));
                if i < body_count {
                    potential.write(i, p, potential.read(m[i], m[p]));
                }
            }
        }
    }
    Influence { system, potential }
}

/// Whether row `i` is a copy of its mirror image's.
fn is_copy(mirror: Option<&[usize]>, i: usize) -> bool {
    mirror.is_some_and(|m| m[i] < i)
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
        let mirror = super::mirror_map(mesh);
        let bottom = fill(mesh, mirror.as_deref(), |i, p| {
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
        let dirichlet = limit(mesh, mirror.as_deref(), FreeSurface::Dirichlet, h);
        Self {
            depth: h,
            bottom,
            dirichlet,
            mirror,
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
                add(
                    target,
                    &limit(mesh, self.mirror.as_deref(), surface, self.depth),
                );
                Ok(None)
            }
            FreeSurface::Wave { wavenumber } => {
                let green = FiniteDepthGreen::new(wavenumber, self.depth)?;
                self.add_wave_remainder(mesh, &green, target);
                Ok(Some(green.wavenumber()))
            }
        }
    }

    /// Adds the remainder of `green` to the influence of the first `target.system.ncols()`
    /// unknowns: one [`FiniteDepthGreen::remainder_rows`] product for the rows that are not
    /// mirror copies.
    fn add_wave_remainder(&self, mesh: &Mesh, green: &FiniteDepthGreen, target: &mut Influence) {
        let unknowns = target.system.ncols();
        let body_count = mesh.body.len();
        let mirror = self
            .mirror
            .as_deref()
            .filter(|m| m[..unknowns].iter().all(|&q| q < unknowns));
        // first_row[i]: the value row (body) or d/dy row (lid) of unknown i.
        let mut first_row = vec![usize::MAX; unknowns];
        let mut rows = Vec::new();
        for i in (0..unknowns).filter(|&i| !is_copy(mirror, i)) {
            let field = unknown_panel(mesh, i);
            first_row[i] = rows.len();
            if i < body_count {
                rows.push(RemainderRow {
                    point: field.centre,
                    direction: None,
                });
            }
            let direction = if i < body_count {
                field.normal
            } else {
                [0.0, 1.0]
            };
            rows.push(RemainderRow {
                point: field.centre,
                direction: Some(direction),
            });
        }
        let panels: Vec<[Point; 2]> = (0..unknowns)
            .map(|p| {
                let panel = unknown_panel(mesh, p);
                [panel.start, panel.end]
            })
            .collect();
        let remainder = green.remainder_rows(&rows, &panels);
        for i in 0..unknowns {
            // A copied row reads its mirror image's row at the mirrored panel.
            let copy_of = mirror.filter(|_| is_copy(mirror, i));
            let row = first_row[copy_of.map_or(i, |m| m[i])];
            for p in 0..unknowns {
                let source = copy_of.map_or(p, |m| m[p]);
                if i < body_count {
                    let value = remainder.get(row, source) + from(target.potential.read(i, p));
                    target.potential.write(i, p, to(value));
                    let normal = remainder.get(row + 1, source) + from(target.system.read(i, p));
                    target.system.write(i, p, to(normal));
                } else {
                    let d_y = remainder.get(row, source) + from(target.system.read(i, p));
                    target.system.write(i, p, to(d_y));
                }
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
fn limit(mesh: &Mesh, mirror: Option<&[usize]>, surface: FreeSurface, h: f64) -> Influence {
    fill(mesh, mirror, |i, p| {
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
