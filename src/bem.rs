//! The source panel method (Schilder et al., eq. 10 and 13): radiation potentials and the complex added
//! mass matrix at one frequency.
//!
//! The potential of DOF `j` is a distribution of constant-strength sources on the panels,
//!
//! ```text
//! phi_j(x) = sum_p sigma_pj integral_{panel p} G(x, x0) ds0,
//! ```
//!
//! with the free-surface Green function `G` of [`crate::green`]. The panel integrals are exact
//! (analytic for the Rankine parts, adaptive for the wave part), never the midpoint rule next
//! to the singularity. Collocation at the body panel centres `x_l` enforces the body condition
//!
//! ```text
//! d(phi_j)/dn (x_l) = n_j(x_l)            (n out of the fluid, into the body)
//! ```
//!
//! and one LU factorization per frequency serves all DOFs as right-hand sides (on a mesh
//! symmetric about `x = 0`, two of half the size: its symmetric and antisymmetric halves). The
//! complex added mass follows from
//!
//! ```text
//! A~_ij = rho integral_C n_i phi_j ds  ~  rho sum_l n_i(x_l) phi_j(x_l) L_l  =  a_ij - i b_ij/omega.
//! ```
//!
//! # Exciting force of incident waves
//! At a wave frequency the same factorization also gives the exciting force of a regular wave
//! of amplitude `a` and heading 0 (towards +x) or 180 (towards -x), docs/DESIGN.md "Waves and
//! hydrostatics". With the incident potential `phi_0 = (i g a / omega) psi_0`,
//! `psi_0 = e^{k y -+ i k x}`, the force per `rho g a` is
//!
//! ```text
//! x_j = X_j / (rho g a) = integral_C (psi_0 + psi_D) n_j ds                  (direct)
//!                       = integral_C (psi_0 n_j - phi_j d(psi_0)/dn) ds      (Haskind)
//! ```
//!
//! with the diffraction potential `psi_D` solved for `d(psi_D)/dn = -d(psi_0)/dn` (two more
//! right-hand sides, the lid rows zero as for radiation), and the radiation potentials
//! `phi_j` the added mass already uses. The first term alone is the Froude-Krylov force.
//! `psi_0` and its normal derivative are exact panel means (`e^{alpha . x}` integrates in
//! closed form along a straight panel), so only `n_j` is sampled at the centres, as for
//! the added mass.
//!
//! # Irregular frequencies
//! A source distribution on an open contour fails where the interior problem (the potential
//! the same sources induce inside the body: zero on the contour, free-surface condition on
//! the interior waterplane) resonates: for the semicircle at kR = 1.8182, 3.2523, 4.7776, ...
//! With [`IrregularFrequencies::RemoveWithLid`] (default), sources are also placed on the
//! interior lid `y = 0` between the waterline points, and the extended condition
//!
//! ```text
//! d(phi)/dy = 0   at the lid panel centres, approached from inside the body,
//! ```
//!
//! is imposed. The interior problem then has a Dirichlet condition on the contour and a
//! Neumann condition on the lid, which has no eigenvalues, so the combined system is uniquely
//! solvable at every frequency. The exterior potential is unchanged (Green's identity in the
//! interior gives the lid strength `k phi_int`, a smooth density). Imposing `phi = 0` on the
//! lid instead also removes the resonances, but makes the interior potential jump at the
//! waterline corners and does not converge (measured: 0.465 against 0.497 for the sway added
//! mass at kR = 0.5, at every panel count). The two frequency limits have no irregular
//! frequencies and always use the plain method. [`IrregularFrequencies::Keep`] is Schilder et al.'s
//! plain method.

mod depth;
mod drift;
mod linear;

pub use drift::Drift;
use linear::{mirror_map, solve_dense, solve_mirrored};

use crate::green::finite_depth::DepthError;
use crate::green::{FreeSurface, GreenError, GreenFunction, PanelIntegral, PanelPairs};
use crate::panels::{Mesh, Panel};
use crate::units::WaterDepth;
use crate::xml::{format_number, Notation};
use faer::complex_native::c64;
use faer::Mat;
use nalgebra::DMatrix;
use num_complex::Complex64;
use std::fmt;
use std::time::{Duration, Instant};

/// How irregular frequencies are treated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum IrregularFrequencies {
    /// Schilder et al.'s plain source method: spikes near the interior eigenfrequencies.
    Keep,
    /// Sources on the interior free-surface lid with `d(phi)/dy = 0` there (extended boundary
    /// condition). No effect on closed (submerged) contours, which have no irregular
    /// frequencies. A [`crate::sweep::Solver`] leaves the lid out far below the first
    /// irregular frequency (`LID_FREE_FRACTION`).
    #[default]
    RemoveWithLid,
}

/// The result of one radiation solve.
#[derive(Clone, Debug)]
pub struct RadiationSolution {
    /// Complex added mass `A~_ij / rho` (per unit density), symmetrized: `(A + A^T)/2`.
    pub added_mass: DMatrix<Complex64>,
    /// Reciprocity residual before symmetrization: `max |A_ij - A_ji| / max_k |A_kk|`.
    pub reciprocity_residual: f64,
    /// Time in the Green function and panel integrals.
    pub influence_time: Duration,
    /// Time assembling the system and the added mass from the source strengths.
    pub assembly_time: Duration,
    /// Time in the LU factorization and the solves.
    pub factorization_time: Duration,
    /// Exciting forces of the incident waves (wave frequencies only; `None` for the limits).
    pub wave_forces: Option<WaveForces>,
}

/// Wave headings of [`WaveForces`], degrees: 0 towards +x, 180 towards -x.
pub const HEADINGS: [f64; 2] = [0.0, 180.0];

/// The transverse direction cosines of [`HEADINGS`] (see [`Problem::solve_waves`]).
pub(crate) const HEADING_COSINES: [f64; 2] = [1.0, -1.0];

/// Exciting forces per unit wave amplitude and per `rho g`, `x_j = X_j / (rho g a)` (m for
/// a displacement DOF, m^2 for an angle or mode amplitude), one column per entry of
/// [`HEADINGS`], one row per DOF.
#[derive(Clone, Debug, PartialEq)]
pub struct WaveForces {
    /// By the Haskind relation from the radiation potentials: the check.
    pub haskind: DMatrix<Complex64>,
    /// By the direct diffraction solve (Froude-Krylov plus scattered wave): the product's
    /// value. Measured against 1024 panels it is about 30 times more accurate than the
    /// Haskind value at kR = 8..10 (docs/WAVES.md), where `d(psi_0)/dn ~ k` amplifies the
    /// radiation potentials' error near the waterline corners.
    pub direct: DMatrix<Complex64>,
    /// The Froude-Krylov part alone (the incident wave's pressure).
    pub froude_krylov: DMatrix<Complex64>,
    /// The far field and the fixed section's mean drift force (headings 0 and 180 only:
    /// `None` for oblique waves).
    pub drift: Option<Drift>,
}

impl WaveForces {
    /// `(a self + b other) / c`, entry-wise in all three parts (Richardson extrapolation).
    pub fn combine(&self, a: f64, other: &WaveForces, b: f64, c: f64) -> WaveForces {
        let mix = |x: &DMatrix<Complex64>, y: &DMatrix<Complex64>| {
            (x * Complex64::new(a, 0.0) + y * Complex64::new(b, 0.0)) / Complex64::new(c, 0.0)
        };
        WaveForces {
            haskind: mix(&self.haskind, &other.haskind),
            direct: mix(&self.direct, &other.direct),
            froude_krylov: mix(&self.froude_krylov, &other.froude_krylov),
            drift: match (&self.drift, &other.drift) {
                (Some(x), Some(y)) => Some(x.combine(a, y, b, c)),
                _ => None,
            },
        }
    }

    /// Largest `|haskind - direct|` over DOFs and headings.
    pub fn haskind_direct_difference(&self) -> f64 {
        (&self.haskind - &self.direct)
            .iter()
            .map(|z| z.norm())
            .fold(0.0, f64::max)
    }
}

/// A solve that failed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum BemError {
    /// The Green function refused the free-surface condition.
    Green(GreenError),
    /// The influence matrix could not be factorized.
    Singular {
        /// The free-surface condition of the solve.
        surface: FreeSurface,
        /// Body panels.
        body_panels: usize,
        /// Interior lid panels.
        lid_panels: usize,
    },
    /// The solve gave a NaN or infinite added mass or exciting force.
    NonFinite {
        /// The free-surface condition of the solve.
        surface: FreeSurface,
    },
    /// The finite-depth Green function refused the depth or the frequency (for example a
    /// frequency where the dispersion relation cannot be solved).
    Depth(DepthError),
    /// A mesh node lies on or below the bottom.
    BelowBottom {
        /// Water depth (m).
        depth: f64,
        /// The lowest node's `y` (m).
        keel: f64,
    },
    /// Every level was finite but their extrapolation to zero panel size is not (see
    /// [`crate::sweep::Solver`]).
    NonFiniteExtrapolation {
        /// The free-surface condition of the solve.
        surface: FreeSurface,
        /// The discretization levels extrapolated.
        levels: usize,
    },
}

/// The free-surface condition in words, for messages.
pub(crate) fn describe_surface(surface: FreeSurface) -> String {
    match surface {
        FreeSurface::RigidLid => "the zero-frequency limit (rigid lid)".to_string(),
        FreeSurface::Dirichlet => "the infinite-frequency limit".to_string(),
        FreeSurface::Wave { wavenumber } => format!(
            "the wavenumber {} 1/m",
            format_number(wavenumber, Notation::Plain)
        ),
    }
}

impl fmt::Display for BemError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("panel method: ")?;
        match self {
            BemError::Green(e) => write!(f, "{e}"),
            BemError::Depth(e) => write!(f, "finite depth: {e}"),
            BemError::BelowBottom { depth, keel } => write!(
                f,
                "the hull reaches the bottom: keel at y = {} m, water depth {} m (the hull \
                 must lie above y = -depth)",
                format_number(*keel, Notation::Plain),
                format_number(*depth, Notation::Plain)
            ),
            BemError::Singular {
                surface,
                body_panels,
                lid_panels,
            } => write!(
                f,
                "singular influence matrix at {} ({body_panels} body and {lid_panels} lid panels)",
                describe_surface(*surface)
            ),
            BemError::NonFinite { surface } => write!(
                f,
                "non-finite added mass or exciting force at {}",
                describe_surface(*surface)
            ),
            BemError::NonFiniteExtrapolation { surface, levels } => write!(
                f,
                "non-finite added mass or exciting force at {} after the extrapolation of \
                 {levels} discretization levels to zero panel size",
                describe_surface(*surface)
            ),
        }
    }
}

impl std::error::Error for BemError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            BemError::Green(e) => Some(e),
            BemError::Depth(e) => Some(e),
            _ => None,
        }
    }
}

impl From<GreenError> for BemError {
    fn from(e: GreenError) -> Self {
        BemError::Green(e)
    }
}

fn to_faer(z: Complex64) -> c64 {
    c64 { re: z.re, im: z.im }
}

fn from_faer(z: c64) -> Complex64 {
    Complex64::new(z.re, z.im)
}

/// Solves the radiation problem of every DOF of `mesh` for the free-surface condition
/// `surface`. For many frequencies on one mesh, [`Problem`] reuses the
/// frequency-independent part.
///
/// # Errors
/// A singular or non-finite system (for example a degenerate mesh), reported with the
/// frequency, so that a sweep can carry on with its other frequencies.
pub fn solve(
    mesh: &Mesh,
    surface: FreeSurface,
    irregular: IrregularFrequencies,
) -> Result<RadiationSolution, BemError> {
    // One frequency: pair by pair, without preparing the pairs for many.
    Problem::with_pairs(mesh.clone(), false)?.solve(surface, irregular)
}

/// Influence of every panel (body, then lid) at every collocation point.
struct Influence {
    /// Rows: body collocation points (normal derivative), then lid centres (d/dy from below).
    system: Mat<c64>,
    /// Potential at the body panels (panel mean for pairs near a singularity of the kernel,
    /// centre value otherwise).
    potential: Mat<c64>,
}

/// The panel method on one mesh, with the frequency-independent Rankine part
/// `(1/2pi) ln(r0/r1)` (the omega -> inf Green function) computed once. A wave solve adds
/// only the frequency-dependent remainder.
pub struct Problem {
    mesh: Mesh,
    mirror: Option<Vec<usize>>,
    dirichlet: Influence,
    /// Prepared for many wave frequencies (`None`: pair by pair).
    wave_pairs: Option<WavePairs>,
    /// The finite-depth parts (`None`: deep water).
    depth: Option<depth::DepthParts>,
}

/// The (collocation point, panel) pairs a wave solve evaluates, with their
/// frequency-independent part: body on body first, then every pair that involves the lid.
/// A pair whose potential is a panel mean brings the Gauss points of the mean along.
struct WavePairs {
    body: PanelPairs,
    lid: PanelPairs,
    /// Body and lid panels.
    unknowns: usize,
    /// `slot[i * unknowns + p]`: the centre value's index in `body` then `lid` (`u32::MAX`: a
    /// row copied from its mirror image).
    slot: Vec<u32>,
    /// `mean_slot[i * unknowns + p]`: the index of the first Gauss point of the panel mean, where
    /// there is one.
    mean_slot: Vec<u32>,
}

impl WavePairs {
    fn new(mesh: &Mesh, mirror: Option<&[usize]>) -> Self {
        let body_count = mesh.body.len();
        let unknowns = body_count + mesh.lid.len();
        let is_copy = |i: usize| mirror.is_some_and(|m| m[i] < i);
        let mut slot = vec![u32::MAX; unknowns * unknowns];
        let mut mean_slot = vec![u32::MAX; unknowns * unknowns];
        let mut body = Vec::new();
        let mut lid = Vec::new();
        for p in 0..unknowns {
            let source = unknown_panel(mesh, p);
            for i in (0..unknowns).filter(|&i| !is_copy(i)) {
                let field = unknown_panel(mesh, i);
                let set = if i < body_count && p < body_count {
                    &mut body
                } else {
                    &mut lid
                };
                slot[i * unknowns + p] = set.len() as u32;
                set.push((field.centre, source.start, source.end));
                if i < body_count && needs_mean(field, source, Singular::Image) {
                    mean_slot[i * unknowns + p] = set.len() as u32;
                    set.extend(mean_points(field).map(|x| (x, source.start, source.end)));
                }
            }
        }
        // Lid pairs come after the body pairs.
        for i in 0..unknowns {
            for p in 0..unknowns {
                if i >= body_count || p >= body_count {
                    for s in [
                        &mut slot[i * unknowns + p],
                        &mut mean_slot[i * unknowns + p],
                    ] {
                        if *s != u32::MAX {
                            *s += body.len() as u32;
                        }
                    }
                }
            }
        }
        Self {
            body: PanelPairs::new(body),
            lid: PanelPairs::new(lid),
            unknowns,
            slot,
            mean_slot,
        }
    }
}

/// Whether the potential of `source` at `field` is the panel mean rather than the centre
/// value: phi of a constant-strength panel is log-singular in slope at and next to the kernel's
/// singularity, so the centre value misrepresents the mean by O(L) there (by
/// (L/2pi)(ln 2 - 1/2) on the panel itself).
fn needs_mean(field: &Panel, source: &Panel, singular: Singular) -> bool {
    let singular_at = match singular {
        Singular::Source => *source,
        Singular::Image => image(source),
    };
    let reach = NEAR_FIELD_RATIO * field.length.max(source.length);
    squared_distance_to_panel(field.centre, &singular_at) <= reach * reach
}

/// The points of [`panel_mean`] on `panel`.
fn mean_points(panel: &Panel) -> impl Iterator<Item = [f64; 2]> + '_ {
    GAUSS_NODES.iter().map(|&t| {
        let u = 0.5 * (1.0 + t);
        [
            panel.start[0] + u * (panel.end[0] - panel.start[0]),
            panel.start[1] + u * (panel.end[1] - panel.start[1]),
        ]
    })
}

/// Panel `p` of the unknowns (body, then lid).
fn unknown_panel(mesh: &Mesh, p: usize) -> &Panel {
    if p < mesh.body.len() {
        &mesh.body[p]
    } else {
        &mesh.lid[p - mesh.body.len()]
    }
}

impl Problem {
    /// Prepares `mesh` for many frequencies: computes the Rankine influence of all panels and
    /// prepares the wave part's panel pairs ([`crate::green::PanelPairs`], about five
    /// frequencies' worth of work).
    ///
    /// # Errors
    /// Never for a valid mesh; kept fallible for the Green function's checks.
    pub fn new(mesh: Mesh) -> Result<Self, BemError> {
        Self::with_pairs(mesh, true)
    }

    /// As [`Problem::new`]; `prepare = false` leaves the wave part's pairs unprepared (for a
    /// single frequency, where preparing costs more than it saves), as does a mesh of more
    /// than [`MAX_PREPARED_PAIRS`] pairs.
    fn with_pairs(mesh: Mesh, prepare: bool) -> Result<Self, BemError> {
        let green = GreenFunction::new(FreeSurface::Dirichlet)?;
        let unknowns = mesh.body.len() + mesh.lid.len();
        let mirror = mirror_map(&mesh);
        let dirichlet = influence(
            &mesh,
            mirror.as_deref(),
            unknowns,
            Singular::Source,
            &Computed {
                mesh: &mesh,
                kernel: |x, a, b| green.panel_integral(x, a, b),
            },
        );
        // Prepared pairs take about 0.3 kB each, some 20 times the dense system's entries:
        // above the bound a fine mesh evaluates pair by pair (its factorization dominates).
        let rows = match &mirror {
            Some(m) => (0..unknowns).filter(|&i| m[i] >= i).count(),
            None => unknowns,
        };
        let prepare = prepare && rows * unknowns <= MAX_PREPARED_PAIRS;
        let wave_pairs = prepare.then(|| WavePairs::new(&mesh, mirror.as_deref()));
        Ok(Self {
            mesh,
            mirror,
            dirichlet,
            wave_pairs,
            depth: None,
        })
    }

    /// As [`Problem::new`] in water of depth `depth`. In finite depth a wave solve's
    /// [`FreeSurface::Wave`] wavenumber is `nu = omega^2/g` (the deep-water wavenumber of the
    /// frequency): the propagating wavenumber solves `nu = k tanh kh`. The limits are those
    /// of the strip (see [`crate::green::finite_depth`]).
    ///
    /// # Errors
    /// [`BemError::BelowBottom`] when a node of the mesh lies at or below `y = -depth`.
    pub fn with_depth(mesh: Mesh, depth: WaterDepth) -> Result<Self, BemError> {
        let WaterDepth::Finite(h) = depth else {
            return Self::new(mesh);
        };
        if !(h.is_finite() && h > 0.0) {
            return Err(BemError::Depth(DepthError::InvalidDepth(h)));
        }
        let keel = mesh
            .body
            .iter()
            .flat_map(|p| [p.start[1], p.end[1]])
            .fold(0.0, f64::min);
        if keel <= -h {
            return Err(BemError::BelowBottom { depth: h, keel });
        }
        let mut problem = Self::new(mesh)?;
        problem.depth = Some(depth::DepthParts::new(&problem.mesh, h));
        Ok(problem)
    }

    /// The water depth.
    pub fn water_depth(&self) -> WaterDepth {
        self.depth
            .as_ref()
            .map_or(WaterDepth::Infinite, |d| WaterDepth::Finite(d.depth()))
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Solves the radiation problem of every DOF for `surface`, and at a wave frequency the
    /// two diffraction problems ([`WaveForces`]).
    ///
    /// # Errors
    /// As [`solve`].
    pub fn solve(
        &self,
        surface: FreeSurface,
        irregular: IrregularFrequencies,
    ) -> Result<RadiationSolution, BemError> {
        self.solve_with(surface, irregular, true)
    }

    /// As [`Problem::solve`]; `excitation = false` leaves the diffraction problems out
    /// (`wave_forces` is then `None`), for a caller that needs the added mass only.
    ///
    /// # Errors
    /// As [`solve`].
    pub fn solve_with(
        &self,
        surface: FreeSurface,
        irregular: IrregularFrequencies,
        excitation: bool,
    ) -> Result<RadiationSolution, BemError> {
        let cosines: &[f64] = if excitation { &HEADING_COSINES } else { &[] };
        self.solve_waves(surface, irregular, cosines)
    }

    /// As [`Problem::solve`], with one incident wave per entry of `transverse`: the wave
    /// `psi_0 = e^{k y - i k c x}` of transverse direction cosine `c` (1: heading 0, towards
    /// +x; -1: heading 180; 0: crests across the section, as a ship's section sees head or
    /// following seas). For `|c| < 1` `psi_0` is the cross-section trace of an oblique 3D wave
    /// (strip theory); the Haskind value is then the zero-speed Salvesen-Tuck-Faltinsen
    /// sectional force and the direct value that of a 2D diffraction problem driven by the
    /// same normal velocity. The columns of [`WaveForces`] follow `transverse`; an empty
    /// list leaves the exciting forces out.
    ///
    /// # Errors
    /// As [`solve`].
    pub fn solve_waves(
        &self,
        surface: FreeSurface,
        irregular: IrregularFrequencies,
        transverse: &[f64],
    ) -> Result<RadiationSolution, BemError> {
        let mesh = &self.mesh;
        let use_lid = matches!(surface, FreeSurface::Wave { .. })
            && irregular == IrregularFrequencies::RemoveWithLid
            && !mesh.lid.is_empty();
        let body_count = mesh.body.len();
        let lid_count = if use_lid { mesh.lid.len() } else { 0 };
        let unknowns = body_count + lid_count;
        let start = Instant::now();
        let (influence, propagating) = self.influence_for(surface, use_lid)?;
        let Influence { system, potential } = influence;
        let influence_time = start.elapsed();
        let waves = match surface {
            FreeSurface::Wave { wavenumber } if !transverse.is_empty() => Some((
                propagating.unwrap_or(wavenumber),
                transverse,
                self.depth.as_ref().map(|d| d.depth()),
            )),
            _ => None,
        };
        // The mirror map serves the solve when it maps the unknowns in use onto themselves.
        let mirror = self
            .mirror
            .as_deref()
            .filter(|m| m[..unknowns].iter().all(|&q| q < unknowns));
        solve_system(
            mesh,
            surface,
            (system, mirror),
            potential,
            influence_time,
            lid_count,
            waves,
        )
    }
}

impl Problem {
    /// The influence of the unknowns in use (the lid's with `use_lid`) for `surface`, and in
    /// finite depth at a wave frequency the propagating wavenumber.
    fn influence_for(
        &self,
        surface: FreeSurface,
        use_lid: bool,
    ) -> Result<(Influence, Option<f64>), BemError> {
        let mesh = &self.mesh;
        let green = GreenFunction::new(surface)?;
        let body_count = mesh.body.len();
        let unknowns = body_count + if use_lid { mesh.lid.len() } else { 0 };
        let cached = &self.dirichlet;
        let mirror = self.mirror.as_deref();
        let mut influence = match surface {
            FreeSurface::Dirichlet => Influence {
                system: cached.system.submatrix(0, 0, unknowns, unknowns).to_owned(),
                potential: cached
                    .potential
                    .submatrix(0, 0, body_count, unknowns)
                    .to_owned(),
            },
            FreeSurface::Wave { .. } => {
                let mut wave = match &self.wave_pairs {
                    Some(pairs) => {
                        let mut values = Vec::new();
                        green.panel_integrals_beyond_dirichlet(&pairs.body, &mut values);
                        if use_lid {
                            let mut lid = Vec::new();
                            green.panel_integrals_beyond_dirichlet(&pairs.lid, &mut lid);
                            values.append(&mut lid);
                        }
                        let looked_up = LookedUp {
                            pairs,
                            values: &values,
                        };
                        influence(mesh, mirror, unknowns, Singular::Image, &looked_up)
                    }
                    None => {
                        let computed = Computed {
                            mesh,
                            kernel: |x, a, b| green.panel_integral_beyond_dirichlet(x, a, b),
                        };
                        influence(mesh, mirror, unknowns, Singular::Image, &computed)
                    }
                };
                depth::add(&mut wave, cached);
                wave
            }
            FreeSurface::RigidLid => influence(
                mesh,
                mirror,
                unknowns,
                Singular::Source,
                &Computed {
                    mesh,
                    kernel: |x, a, b| green.panel_integral(x, a, b),
                },
            ),
        };
        let propagating = match &self.depth {
            Some(parts) => parts
                .add_to(mesh, surface, &mut influence)
                .map_err(BemError::Depth)?,
            None => None,
        };
        Ok((influence, propagating))
    }
}

/// Where a kernel's potential is singular, which decides the pairs whose potential is the
/// panel mean rather than the centre value: at the source (`ln r0`: the full Green function
/// and its Dirichlet limit), or only at the source's image above the free surface (the wave
/// part beyond the Dirichlet limit, `ln p` at `p = 0`: smooth everywhere in the fluid but near
/// the surface, so only pairs near the waterline need the mean).
#[derive(Clone, Copy, PartialEq)]
enum Singular {
    Source,
    Image,
}

/// The panel integrals of a kernel (some Green function) over panel `p` at collocation panel
/// `i` (unknown indices), computed or looked up: at the panel's centre, and the potential's mean
/// over the collocation panel ([`panel_mean`]).
trait PairValues {
    fn centre(&self, i: usize, p: usize) -> PanelIntegral;
    fn mean(&self, i: usize, p: usize) -> Complex64;
}

/// [`PairValues`] computed by a kernel.
struct Computed<'a, K> {
    mesh: &'a Mesh,
    kernel: K,
}

impl<K: Fn([f64; 2], [f64; 2], [f64; 2]) -> PanelIntegral> PairValues for Computed<'_, K> {
    fn centre(&self, i: usize, p: usize) -> PanelIntegral {
        let source = unknown_panel(self.mesh, p);
        (self.kernel)(unknown_panel(self.mesh, i).centre, source.start, source.end)
    }

    fn mean(&self, i: usize, p: usize) -> Complex64 {
        let source = unknown_panel(self.mesh, p);
        panel_mean(unknown_panel(self.mesh, i), |x| {
            (self.kernel)(x, source.start, source.end).potential
        })
    }
}

/// [`PairValues`] of the wave part looked up from one frequency's values of [`WavePairs`].
struct LookedUp<'a> {
    pairs: &'a WavePairs,
    values: &'a [PanelIntegral],
}

impl PairValues for LookedUp<'_> {
    fn centre(&self, i: usize, p: usize) -> PanelIntegral {
        self.values[self.pairs.slot[i * self.pairs.unknowns + p] as usize]
    }

    fn mean(&self, i: usize, p: usize) -> Complex64 {
        let first = self.pairs.mean_slot[i * self.pairs.unknowns + p] as usize;
        weighted_mean(
            self.values[first..first + GAUSS_NODES.len()]
                .iter()
                .map(|v| v.potential),
        )
    }
}

/// The influence of the first `unknowns` panels (body, then lid) from the panel integrals of
/// some Green function. With a `mirror` map, rows of mirrored collocation points are copied,
/// `I(i, p) = I(m(i), m(p))`, which halves the work on symmetric hulls.
fn influence(
    mesh: &Mesh,
    mirror: Option<&[usize]>,
    unknowns: usize,
    singular: Singular,
    values: &impl PairValues,
) -> Influence {
    let body_count = mesh.body.len();
    let panel = |p: usize| unknown_panel(mesh, p);
    let mut system = Mat::<c64>::zeros(unknowns, unknowns);
    let mut potential = Mat::<c64>::zeros(body_count, unknowns);
    // A mirror map is usable when it maps the unknowns in use onto themselves.
    let mirror = mirror.filter(|m| m[..unknowns].iter().all(|&q| q < unknowns));
    let is_copy = |i: usize| mirror.is_some_and(|m| m[i] < i);
    for p in 0..unknowns {
        let source = panel(p);
        for i in 0..unknowns {
            if is_copy(i) {
                continue;
            }
            let field = panel(i);
            let integral = values.centre(i, p);
            if i < body_count {
                let normal_derivative =
                    integral.gradient[0] * field.normal[0] + integral.gradient[1] * field.normal[1];
                system.write(i, p, to_faer(normal_derivative));
                let value = if needs_mean(field, source, singular) {
                    values.mean(i, p)
                } else {
                    integral.potential
                };
                potential.write(i, p, to_faer(value));
            } else {
                system.write(i, p, to_faer(integral.gradient[1]));
            }
        }
    }
    if let Some(m) = mirror {
        for i in (0..unknowns).filter(|&i| is_copy(i)) {
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

/// The incident wave of transverse direction cosine `cosine` on each body panel: the panel
/// means of `psi_0 = e^{k y - i k c x}` and of `d(psi_0)/dn`.
fn incident_wave(mesh: &Mesh, wavenumber: f64, cosine: f64) -> Vec<(Complex64, Complex64)> {
    let k = wavenumber;
    // grad psi_0 = alpha psi_0, alpha = (-i k c, k): c = 1 travels towards +x.
    let alpha = [Complex64::new(0.0, -k * cosine), Complex64::new(k, 0.0)];
    mesh.body
        .iter()
        .map(|panel| {
            let psi = drift::exponential_mean(panel, alpha);
            let normal_derivative = psi * (alpha[0] * panel.normal[0] + alpha[1] * panel.normal[1]);
            (psi, normal_derivative)
        })
        .collect()
}

/// Solves for the source strengths of every DOF (and, at a wave frequency, of the two
/// diffraction problems) and integrates the added mass and the exciting forces.
fn solve_system(
    mesh: &Mesh,
    surface: FreeSurface,
    (system, mirror): (Mat<c64>, Option<&[usize]>),
    potential: Mat<c64>,
    influence_time: Duration,
    lid_count: usize,
    waves: Option<(f64, &[f64], Option<f64>)>,
) -> Result<RadiationSolution, BemError> {
    let body_count = mesh.body.len();
    let unknowns = system.nrows();
    let dof_count = mesh.dof_names.len();
    let start = Instant::now();
    let incident: Vec<Vec<(Complex64, Complex64)>> = match waves {
        Some((k, cosines, None)) => cosines.iter().map(|&c| incident_wave(mesh, k, c)).collect(),
        Some((k, cosines, Some(h))) => cosines
            .iter()
            .map(|&c| depth::incident_wave(mesh, k, h, c))
            .collect(),
        None => Vec::new(),
    };
    let mut rhs = Mat::<c64>::zeros(unknowns, dof_count + incident.len());
    for (h, wave) in incident.iter().enumerate() {
        for (l, (_, normal_derivative)) in wave.iter().enumerate() {
            rhs.write(l, dof_count + h, to_faer(-normal_derivative));
        }
    }
    for l in 0..body_count {
        for j in 0..dof_count {
            rhs.write(
                l,
                j,
                c64 {
                    re: mesh.normal_velocity[(l, j)],
                    im: 0.0,
                },
            );
        }
    }
    let mut assembly_time = start.elapsed();

    let start = Instant::now();
    let strengths = match mirror {
        Some(m) => solve_mirrored(&system, rhs, m),
        None => solve_dense(system, rhs),
    }
    .ok_or(BemError::Singular {
        surface,
        body_panels: body_count,
        lid_panels: lid_count,
    })?;
    let factorization_time = start.elapsed();

    let start = Instant::now();
    let phi = &potential * &strengths;
    let mut added_mass = DMatrix::<Complex64>::zeros(dof_count, dof_count);
    for i in 0..dof_count {
        for j in 0..dof_count {
            added_mass[(i, j)] = (0..body_count)
                .map(|l| {
                    from_faer(phi.read(l, j)) * (mesh.normal_velocity[(l, i)] * mesh.body[l].length)
                })
                .sum();
        }
    }
    let wave_forces = (!incident.is_empty()).then(|| {
        let headings = incident.len();
        let mut forces = WaveForces {
            haskind: DMatrix::zeros(dof_count, headings),
            direct: DMatrix::zeros(dof_count, headings),
            froude_krylov: DMatrix::zeros(dof_count, headings),
            drift: None,
        };
        for (h, wave) in incident.iter().enumerate() {
            for j in 0..dof_count {
                let (mut fk, mut scattered, mut haskind_term) = (
                    Complex64::default(),
                    Complex64::default(),
                    Complex64::default(),
                );
                for (l, &(psi, normal_derivative)) in wave.iter().enumerate() {
                    let weight = mesh.normal_velocity[(l, j)] * mesh.body[l].length;
                    fk += psi * weight;
                    scattered += from_faer(phi.read(l, dof_count + h)) * weight;
                    haskind_term +=
                        from_faer(phi.read(l, j)) * normal_derivative * mesh.body[l].length;
                }
                forces.froude_krylov[(j, h)] = fk;
                forces.direct[(j, h)] = fk + scattered;
                forces.haskind[(j, h)] = fk - haskind_term;
            }
        }
        // The mean drift force, in deep water or the problem's depth.
        if let Some((k, cosines, depth)) = waves {
            if cosines.iter().all(|c| c.abs() == 1.0) && body_count >= 3 {
                let body_potential: Vec<Vec<Complex64>> = (0..headings)
                    .map(|h| {
                        (0..body_count)
                            .map(|l| from_faer(phi.read(l, dof_count + h)))
                            .collect()
                    })
                    .collect();
                let radiation: Vec<Vec<Complex64>> = (0..dof_count)
                    .map(|j| (0..body_count).map(|l| from_faer(phi.read(l, j))).collect())
                    .collect();
                forces.drift = Some(drift::drift(
                    mesh,
                    drift::Wave {
                        wavenumber: k,
                        depth,
                    },
                    cosines,
                    &strengths,
                    &radiation,
                    &body_potential,
                    &incident,
                ));
            }
        }
        forces
    });
    let finite = |z: &Complex64| z.re.is_finite() && z.im.is_finite();
    if !added_mass.iter().all(finite)
        || wave_forces
            .as_ref()
            .is_some_and(|w| !w.haskind.iter().chain(w.direct.iter()).all(finite))
    {
        return Err(BemError::NonFinite { surface });
    }
    let diagonal_scale = (0..dof_count)
        .map(|k| added_mass[(k, k)].norm())
        .fold(0.0, f64::max);
    let mut asymmetry: f64 = 0.0;
    for i in 0..dof_count {
        for j in 0..i {
            asymmetry = asymmetry.max((added_mass[(i, j)] - added_mass[(j, i)]).norm());
        }
    }
    let reciprocity_residual = if diagonal_scale > 0.0 {
        asymmetry / diagonal_scale
    } else {
        0.0
    };
    let symmetric = (&added_mass + added_mass.transpose()) * Complex64::new(0.5, 0.0);
    assembly_time += start.elapsed();
    Ok(RadiationSolution {
        added_mass: symmetric,
        reciprocity_residual,
        influence_time,
        assembly_time,
        factorization_time,
        wave_forces,
    })
}

/// Most (collocation point, panel) pairs a [`Problem`] prepares for many frequencies (about
/// 0.3 kB each, 0.3 GB in all, panel means aside): up to about 1450 body and lid panels on a
/// symmetric hull, 1024 on another. A finer mesh evaluates pair by pair.
pub(crate) const MAX_PREPARED_PAIRS: usize = 1 << 20;

/// Pairs of panels closer than this many panel lengths get the panel-averaged potential.
const NEAR_FIELD_RATIO: f64 = 3.0;
// (Measured, 2026-11-27: the wave part's means limited to pairs near the image, the Wigley
// sweep 25 % less CPU; tables moved by at most 2e-4 of the scale (the semicircle), within
// the discretization error.)

/// 8-point Gauss-Legendre nodes and weights on [-1, 1].
const GAUSS_NODES: [f64; 8] = [
    -0.960_289_856_497_536_3,
    -0.796_666_477_413_626_7,
    -0.525_532_409_916_329,
    -0.183_434_642_495_649_8,
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GAUSS_WEIGHTS: [f64; 8] = [
    0.101_228_536_290_376_3,
    0.222_381_034_453_374_5,
    0.313_706_645_877_887_3,
    0.362_683_783_378_362,
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// Mean of `f` over the panel, by Gauss-Legendre quadrature.
fn panel_mean(panel: &Panel, f: impl Fn([f64; 2]) -> Complex64) -> Complex64 {
    weighted_mean(mean_points(panel).map(f))
}

/// `sum_j f(x_j) w_j / 2` over the Gauss points, given the values `f(x_j)` in order.
fn weighted_mean(values: impl Iterator<Item = Complex64>) -> Complex64 {
    values.zip(GAUSS_WEIGHTS).map(|(f, w)| f * (0.5 * w)).sum()
}

/// The mirror image of a panel in the free surface `y = 0`.
fn image(panel: &Panel) -> Panel {
    Panel {
        start: [panel.start[0], -panel.start[1]],
        end: [panel.end[0], -panel.end[1]],
        centre: [panel.centre[0], -panel.centre[1]],
        length: panel.length,
        normal: [panel.normal[0], -panel.normal[1]],
    }
}

/// Squared distance from `point` to the nearest point of the panel.
fn squared_distance_to_panel(point: [f64; 2], panel: &Panel) -> f64 {
    let d = [panel.end[0] - panel.start[0], panel.end[1] - panel.start[1]];
    let r = [point[0] - panel.start[0], point[1] - panel.start[1]];
    let t = ((r[0] * d[0] + r[1] * d[1]) / (d[0] * d[0] + d[1] * d[1])).clamp(0.0, 1.0);
    let (x, y) = (r[0] - t * d[0], r[1] - t * d[1]);
    x * x + y * y
}

#[cfg(test)]
mod tests;
