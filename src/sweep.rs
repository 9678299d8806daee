//! Frequency sweeps: the complex added mass on a grid of nondimensional frequencies `kR`,
//! computed in parallel, plus the two limits, and the coefficient table of docs/DESIGN.md.
//!
//! Everything here is nondimensional: frequencies as `kR = omega^2 R / g`, added mass as
//! `A~_ij / (rho pi R^2)`. A frequency whose solve fails is reported in
//! [`SweepResult::failures`] and the rest of the sweep goes on; so is a frequency whose values
//! are not finite after the extrapolation to zero panel size or the normalization. Every number
//! of a [`SweepResult`] is finite, and a sweep in which every frequency failed is an error
//! ([`SweepError::NothingComputed`]).
//!
//! # Limits
//! The sizes the parameters decide are bounded, and checked before anything is allocated
//! ([`SweepParams::validate`]): [`MAX_FREQUENCIES`], [`MAX_EXTRAPOLATION_LEVELS`],
//! [`MAX_THREADS`], [`MAX_TABLE_ENTRIES`], and the panel counts of [`crate::panels`]
//! ([`crate::panels::MAX_BODY_PANELS`], [`crate::panels::MAX_LID_PANELS`]).
//!
//! `A_inf` comes from the `omega -> inf` problem (`phi = 0` on `y = 0`). `A(0)` comes from the
//! rigid-lid problem and is finite only for entries where at least one of the two DOFs has no
//! net flux through the contour (`integral n_j ds = 0`); entries between two DOFs with net flux
//! (heave, `cb2`, `cb5`) diverge like `-(flux_i flux_j / (pi^2 R^2)) ln kR` and are left out.
//!
//! Every wave frequency also gives the exciting force of regular waves from headings 0 and 180
//! ([`crate::bem`]), nondimensional as in docs/DESIGN.md: `X_j / (rho g a R^(1 + e_j))`, `e_j` the
//! DOF's length exponent ([`Hull::dof_unit`]). Its long-wave limit (`kR = 0` rows) is the
//! hydrostatic one, `X_j -> rho g a integral_C n_j ds`: the scattered wave vanishes with k.

mod error;
mod floating;
mod table;

pub use error::SweepError;
pub use floating::FloatingTableError;
pub use table::ExcitationPart;

use crate::bem::{
    BemError, IrregularFrequencies, Problem, RadiationSolution, WaveForces, HEADING_COSINES,
};
use crate::green::{finite_depth, FreeSurface};
use crate::hull::Hull;
use crate::panels::{self, Mesh, PanelError, PanelParams};
use crate::units::{self, WaterDepth};
use crate::xml::{format_number, Notation};
use nalgebra::DMatrix;
use num_complex::Complex64;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

/// Most frequencies in one sweep: 500 times the default grid. The sweep's time and its table
/// grow in proportion (at the default 128 panels about 0.05 s of solving per frequency, so
/// the limit is over an hour on two cores).
pub const MAX_FREQUENCIES: usize = 100_000;

/// Most discretization levels: each level halves the panel count and the coarsest needs at
/// least 4 panels, so [`crate::panels::MAX_BODY_PANELS`] (8192 = 4 * 2^11) allows 12.
pub const MAX_EXTRAPOLATION_LEVELS: usize = 12;

/// Most worker threads: each holds its own dense panel system while it solves, and beyond the
/// machine's cores more threads only add memory.
pub const MAX_THREADS: usize = 1024;

/// Most entries of the added-mass table, frequencies times DOFs squared: 16 bytes each in
/// memory (and as much again for the exciting force and the fit's copy) and about 60 bytes
/// each as CSV text, 1.2 GB at the limit. The default 9-DOF sweep has 16,281.
pub const MAX_TABLE_ENTRIES: usize = 20_000_000;

/// A size that the parameters of a sweep decide, and its limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SizeLimit {
    /// Frequencies of the grid ([`MAX_FREQUENCIES`]).
    Frequencies,
    /// Discretization levels ([`MAX_EXTRAPOLATION_LEVELS`]).
    ExtrapolationLevels,
    /// Worker threads ([`MAX_THREADS`]).
    Threads,
    /// Entries of the added-mass table, frequencies times DOFs squared ([`MAX_TABLE_ENTRIES`]).
    TableEntries,
}

impl SizeLimit {
    /// The largest value allowed.
    pub fn max(self) -> usize {
        match self {
            SizeLimit::Frequencies => MAX_FREQUENCIES,
            SizeLimit::ExtrapolationLevels => MAX_EXTRAPOLATION_LEVELS,
            SizeLimit::Threads => MAX_THREADS,
            SizeLimit::TableEntries => MAX_TABLE_ENTRIES,
        }
    }

    /// What is counted, in words.
    pub fn quantity(self) -> &'static str {
        match self {
            SizeLimit::Frequencies => "frequencies",
            SizeLimit::ExtrapolationLevels => "discretization levels",
            SizeLimit::Threads => "worker threads",
            SizeLimit::TableEntries => "added-mass table entries (frequencies x DOFs^2)",
        }
    }

    /// Why the limit is there (see the constants).
    pub fn reason(self) -> &'static str {
        match self {
            SizeLimit::Frequencies => {
                "the sweep's time and its table grow with each frequency; 500 times the default grid"
            }
            SizeLimit::ExtrapolationLevels => {
                "each level halves the panels, and the coarsest of the largest mesh keeps 4"
            }
            SizeLimit::Threads => "each thread holds its own dense panel system",
            SizeLimit::TableEntries => "about 1.2 GB of CSV text at the limit",
        }
    }
}

/// Parameters of a sweep, with documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepParams {
    /// The `kR` values to solve at (each finite and > 0). Default: 201 log-spaced points over
    /// 0.01 ..= 10.
    pub kr: Vec<f64>,
    /// Discretization. Default: [`PanelParams::default`].
    pub panels: PanelParams,
    /// Irregular frequency treatment. Default: removed with an interior lid.
    pub irregular_frequencies: IrregularFrequencies,
    /// Discretization levels N, N/2, N/4, ... extrapolated to zero panel size (see
    /// [`Solver`]); 1 means the plain N-panel result. Default 3.
    pub extrapolation_levels: usize,
    /// Worker threads (explicit; no global pool is touched). Default 2.
    pub threads: usize,
    /// Also solve the diffraction problems for the exciting forces (two more right-hand sides
    /// per solve; their cost is within the run-to-run noise of the sweep time,
    /// docs/BENCHMARKS.md). Default true.
    pub excitation: bool,
    /// Water depth. Default: [`WaterDepth::Infinite`].
    pub depth: WaterDepth,
}

impl Default for SweepParams {
    fn default() -> Self {
        Self {
            kr: log_grid(0.01, 10.0, 201).expect("the default grid is valid"),
            panels: PanelParams::default(),
            irregular_frequencies: IrregularFrequencies::RemoveWithLid,
            extrapolation_levels: 3,
            threads: 2,
            excitation: true,
            depth: WaterDepth::Infinite,
        }
    }
}

impl SweepParams {
    /// Checks the parameters for a sweep of `hull`, before anything is allocated: at least
    /// one frequency, each finite and > 0; the thread count in 1 ..= [`MAX_THREADS`]; the
    /// sizes within [`MAX_FREQUENCIES`], [`MAX_EXTRAPOLATION_LEVELS`] and
    /// [`MAX_TABLE_ENTRIES`]; the body panels within 4 ..=
    /// [`crate::panels::MAX_BODY_PANELS`] at every level. [`run`] calls it first.
    ///
    /// # Errors
    /// The first parameter out of bounds.
    pub fn validate(&self, hull: &Hull) -> Result<(), SweepError> {
        let too_large = |limit: SizeLimit, requested: usize| {
            (requested > limit.max()).then_some(SweepError::TooLarge { limit, requested })
        };
        if self.threads == 0 {
            return Err(SweepError::Threads {
                threads: 0,
                message: String::new(),
            });
        }
        let dofs = hull.dof_count();
        let entries = self.kr.len().saturating_mul(dofs.saturating_mul(dofs));
        let oversized = too_large(SizeLimit::Threads, self.threads)
            .or_else(|| too_large(SizeLimit::Frequencies, self.kr.len()))
            .or_else(|| too_large(SizeLimit::ExtrapolationLevels, self.extrapolation_levels))
            .or_else(|| too_large(SizeLimit::TableEntries, entries));
        if let Some(error) = oversized {
            return Err(error);
        }
        if self.kr.is_empty() {
            return Err(SweepError::NoFrequencies);
        }
        if let WaterDepth::Finite(h) = self.depth {
            let refuse = |reason: String| {
                Err(SweepError::Depth {
                    depth: self.depth,
                    reason,
                })
            };
            if !(h.is_finite() && h > 0.0) {
                return refuse("must be finite and > 0 (`inf` for deep water)".to_string());
            }
            let keel = keel(hull);
            if keel <= -h {
                return refuse(format!(
                    "the hull reaches the bottom: its keel is at y = {} m, the bottom at y = -{} m",
                    readable(keel),
                    readable(h)
                ));
            }
        }
        if let Some(bad) = self.kr.iter().find(|k| !(k.is_finite() && **k > 0.0)) {
            return Err(SweepError::Frequency(*bad));
        }
        check_levels(&self.panels, self.extrapolation_levels)
    }
}

/// The lowest `y` of the hull's contour (m): its nodes and 4097 points along it.
fn keel(hull: &Hull) -> f64 {
    let samples = (0..=4096).map(|i| f64::from(i) / 4096.0);
    samples
        .chain(hull.breakpoints())
        .map(|s| hull.point(s)[1])
        .fold(0.0, f64::min)
}

/// The panel counts of every level: 1 ..= [`MAX_EXTRAPOLATION_LEVELS`] levels, the finest
/// within 4 ..= [`crate::panels::MAX_BODY_PANELS`], the coarsest with at least 4 panels.
fn check_levels(panels: &PanelParams, levels: usize) -> Result<(), SweepError> {
    if levels == 0 {
        return Err(SweepError::NoLevels);
    }
    if levels > MAX_EXTRAPOLATION_LEVELS {
        return Err(SweepError::TooLarge {
            limit: SizeLimit::ExtrapolationLevels,
            requested: levels,
        });
    }
    if panels.body_panels < 4 {
        return Err(SweepError::Mesh(PanelError::TooFewPanels {
            requested: panels.body_panels,
        }));
    }
    if panels.body_panels > panels::MAX_BODY_PANELS {
        return Err(SweepError::Mesh(PanelError::TooManyPanels {
            requested: panels.body_panels,
        }));
    }
    let coarsest = panels.body_panels >> (levels - 1);
    if levels > 1 && coarsest < 4 {
        return Err(SweepError::TooFewPanelsForLevels {
            panels: panels.body_panels,
            levels,
            coarsest,
        });
    }
    Ok(())
}

/// A log-spaced grid of `count` points from `min` to `max` inclusive.
///
/// # Errors
/// `min <= 0`, `max < min`, non-finite bounds, `count` of 0 (1 point requires
/// `min == max`), or more than [`MAX_FREQUENCIES`] points.
pub fn log_grid(min: f64, max: f64, count: usize) -> Result<Vec<f64>, SweepError> {
    if !(min.is_finite() && max.is_finite() && min > 0.0) {
        return Err(SweepError::Grid { min, max, count });
    }
    if count > MAX_FREQUENCIES {
        return Err(SweepError::TooLarge {
            limit: SizeLimit::Frequencies,
            requested: count,
        });
    }
    if max < min || count == 0 || (count == 1 && max != min) {
        return Err(SweepError::Grid { min, max, count });
    }
    if count == 1 {
        return Ok(vec![min]);
    }
    let (a, b) = (min.ln(), max.ln());
    Ok((0..count)
        .map(|i| {
            if i == 0 {
                min
            } else if i + 1 == count {
                max
            } else {
                (a + (b - a) * i as f64 / (count - 1) as f64).exp()
            }
        })
        .collect())
}

/// The radiation solver of a sweep: the panel method on the requested mesh, extrapolated to
/// zero panel size.
///
/// Constant-strength flat panels with midpoint collocation converge at first order in the
/// panel size h ~ 1/N: `A_N = A + c1/N + c2/N^2 + ...` (measured: the error halves with each
/// doubling, see docs/VALIDATION.md). The solver solves on meshes of `N`, `N/2`, `N/4`, ...
/// panels (`levels` of them, same clustering) and extrapolates the polynomial in `h = 1/N`
/// through them to `h = 0` (Richardson extrapolation, Neville's scheme). Two levels remove
/// the first-order term, three levels also the second-order one; the coarser meshes add 1/4
/// and 1/16 of the influence work of the fine one (measured wall time of the default sweep:
/// 1.5 times the plain one, docs/PERFORMANCE.md).
///
/// # Irregular frequencies below a proven bound
/// The interior lid ([`IrregularFrequencies::RemoveWithLid`]) costs unknowns at every
/// frequency, but the interior problem it suppresses (Dirichlet on the contour,
/// `d(phi)/dy = k phi` on the waterplane) has no eigenvalue below its first one, and that is at
/// least the first one of any larger domain with the same waterplane: for a section inside the
/// rectangle of its waterline beam `B` and draft `T`,
///
/// ```text
/// k_1 >= (pi / B) coth(pi T / B)        (the rectangle's; the semicircle: 1.713/R < 1.818/R)
/// ```
///
/// (extend an admissible interior potential by zero into the rectangle: the Rayleigh quotient
/// `int |grad phi|^2 / int_lid phi^2` is unchanged). Below `LID_FREE_FRACTION` of that bound
/// the wave solves of every level leave the lid out ([`Solver::lid_free_below`]).
pub struct Solver {
    problems: Vec<Problem>,
    lid_free_below: f64,
}

/// The fraction of the lower bound on the first irregular wavenumber below which a wave solve
/// leaves the interior lid out (see [`Solver`]). Measured at 0.5 (the plain and the lid
/// solutions, each extrapolated over 3 levels, against each other, as a fraction of the scale):
/// the semicircle at 128 panels 3.7e-5 in `A~` and 3.2e-5 in the exciting force, at 64 panels
/// 2.6e-4 and 3.6e-4; a hull-file Wigley section at 64 panels 2.4e-4 and 2.8e-4; a box at
/// 128 panels and 2 levels 6.1e-5 and 1.9e-4. Against 1024 panels the plain semicircle at
/// 128 panels is as accurate as the lid one there (3.5e-5 against 3.8e-5 at kR 0.5). Half the
/// bound keeps clear of the first resonance, where the plain method's error grows (1.2e-4 in
/// the force at 0.9 of the bound).
pub(crate) const LID_FREE_FRACTION: f64 = 0.5;

/// The wavenumber (1/m) below which `mesh`'s interior problem provably has no eigenvalue,
/// times `LID_FREE_FRACTION`: see [`Solver`]. Zero for a mesh without a lid, or one reaching
/// outside the vertical lines through its waterline points (no bound).
fn lid_free_wavenumber(mesh: &Mesh) -> f64 {
    let xs = mesh.lid.iter().flat_map(|p| [p.start[0], p.end[0]]);
    let (left, right) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let beam = right - left;
    if !(beam > 0.0 && beam.is_finite()) {
        return 0.0;
    }
    let tolerance = 1e-9 * beam;
    let nodes = || mesh.body.iter().flat_map(|p| [p.start, p.end]);
    if nodes().any(|q| q[0] < left - tolerance || q[0] > right + tolerance) {
        return 0.0;
    }
    let draft = nodes().map(|q| -q[1]).fold(0.0, f64::max);
    if !(draft > 0.0 && draft.is_finite()) {
        return 0.0;
    }
    let pi = std::f64::consts::PI;
    LID_FREE_FRACTION * (pi / beam) / (pi * draft / beam).tanh()
}

impl Solver {
    /// Discretizes `hull` for `panels`, and at `levels - 1` successively halved panel counts
    /// (`levels >= 1`; 1 means no extrapolation).
    ///
    /// # Errors
    /// The discretization errors of [`panels::discretize`]; `levels` of 0 or more than
    /// [`MAX_EXTRAPOLATION_LEVELS`]; a coarsest mesh below 4 panels (checked before any
    /// mesh is made).
    pub fn new(hull: &Hull, panels: &PanelParams, levels: usize) -> Result<Self, SweepError> {
        Self::with_depth(hull, panels, levels, WaterDepth::Infinite)
    }

    /// As [`Solver::new`] in water of depth `depth` ([`Problem::with_depth`]: a wave solve's
    /// wavenumber is then `nu = omega^2/g`).
    ///
    /// # Errors
    /// As [`Solver::new`]; a hull reaching the bottom ([`BemError::BelowBottom`]).
    pub fn with_depth(
        hull: &Hull,
        panels: &PanelParams,
        levels: usize,
        depth: WaterDepth,
    ) -> Result<Self, SweepError> {
        check_levels(panels, levels)?;
        // Every level keeps the vertices the coarsest one has room for.
        let coarsest = panels.body_panels >> (levels - 1);
        let problems = (0..levels)
            .map(|level| {
                let count = panels.body_panels >> level;
                let params = PanelParams {
                    body_panels: count,
                    vertex_budget: Some(panels.vertex_budget.unwrap_or(coarsest).min(coarsest)),
                    ..*panels
                };
                let mesh = panels::discretize(hull, &params).map_err(SweepError::Mesh)?;
                Problem::with_depth(mesh, depth).map_err(SweepError::Problem)
            })
            .collect::<Result<Vec<_>, _>>()?;
        // The finest mesh decides for every level, so that all levels solve one problem.
        let lid_free_below = lid_free_wavenumber(problems[0].mesh());
        Ok(Self {
            problems,
            lid_free_below,
        })
    }

    /// The wavenumber (1/m) below which the wave solves leave the interior lid out, as the
    /// first irregular frequency lies far above (`LID_FREE_FRACTION` of a proven lower bound,
    /// see [`Solver`]); 0 where there is no lid or no bound.
    pub fn lid_free_below(&self) -> f64 {
        self.lid_free_below
    }

    /// The mesh of the requested panel count.
    pub fn mesh(&self) -> &Mesh {
        self.problems[0].mesh()
    }

    /// A warning when a level's mesh leaves contour vertices out (more vertices than its
    /// panels hold, [`Mesh::dropped_vertices`]): the counts per level, else `None`.
    pub fn dropped_vertices_warning(&self) -> Option<String> {
        let levels: Vec<String> = self
            .problems
            .iter()
            .map(|p| p.mesh())
            .filter(|m| m.dropped_vertices > 0)
            .map(|m| format!("{} at {} panels", m.dropped_vertices, m.body.len()))
            .collect();
        (!levels.is_empty()).then(|| {
            format!(
                "contour vertices left out of the mesh (more vertices than panels; those where \
                 the contour turns least are cut along chords): {}; raise the panel count to keep \
                 them all",
                levels.join(", ")
            )
        })
    }

    /// A note when the contour's smooth vertices lie between panel nodes (more vertices than
    /// the coarsest level holds, [`Mesh::smooth_vertices_between_nodes`]), else `None`.
    pub fn smooth_vertices_note(&self) -> Option<String> {
        let count = self.mesh().smooth_vertices_between_nodes;
        (count > 0).then(|| {
            format!(
                "{count} smooth contour vertices (turning less than {} degrees) lie between panel \
                 nodes at every level: more vertices than the coarsest level's {} panels hold, so \
                 the contour is meshed as a smooth curve through them and every level sees the \
                 same geometry; its corners stay nodes",
                panels::CORNER_ANGLE.to_degrees().round(),
                self.problems.last().map_or(0, |p| p.mesh().body.len())
            )
        })
    }

    /// The long-wave limit of the exciting force per `rho g a`, `integral_C n_j ds` for every
    /// DOF (the net flux), extrapolated over the levels like the solves.
    pub fn long_wave_excitation(&self) -> Vec<f64> {
        let h: Vec<f64> = self
            .problems
            .iter()
            .map(|p| 1.0 / p.mesh().body.len() as f64)
            .collect();
        let mut table: Vec<Vec<f64>> = self.problems.iter().map(|p| p.mesh().net_flux()).collect();
        for m in 1..table.len() {
            for i in 0..table.len() - m {
                let (hi, hj) = (h[i], h[i + m]);
                table[i] = table[i]
                    .iter()
                    .zip(&table[i + 1])
                    .map(|(a, b)| (a * -hj + b * hi) / (hi - hj))
                    .collect();
            }
        }
        table.swap_remove(0)
    }

    /// `A~ / rho` (and at a wave frequency the exciting forces) for `surface`, extrapolated,
    /// with the reciprocity residual of the finest solve and the stage times summed over the
    /// levels.
    ///
    /// # Errors
    /// A failure at any level.
    pub fn solve(
        &self,
        surface: FreeSurface,
        irregular: IrregularFrequencies,
    ) -> Result<RadiationSolution, BemError> {
        self.solve_with(surface, irregular, true)
    }

    /// As [`Solver::solve`]; `excitation = false` leaves the exciting forces out.
    ///
    /// # Errors
    /// A failure at any level.
    pub fn solve_with(
        &self,
        surface: FreeSurface,
        irregular: IrregularFrequencies,
        excitation: bool,
    ) -> Result<RadiationSolution, BemError> {
        let cosines: &[f64] = if excitation { &HEADING_COSINES } else { &[] };
        self.solve_waves(surface, irregular, cosines)
    }

    /// As [`Solver::solve`], with the incident waves of [`Problem::solve_waves`].
    ///
    /// # Errors
    /// A failure at any level.
    pub fn solve_waves(
        &self,
        surface: FreeSurface,
        irregular: IrregularFrequencies,
        transverse: &[f64],
    ) -> Result<RadiationSolution, BemError> {
        let irregular = match surface {
            FreeSurface::Wave { wavenumber } if wavenumber < self.lid_free_below => {
                IrregularFrequencies::Keep
            }
            _ => irregular,
        };
        let mut solutions = Vec::with_capacity(self.problems.len());
        for problem in &self.problems {
            solutions.push(problem.solve_waves(surface, irregular, transverse)?);
        }
        let h: Vec<f64> = self
            .problems
            .iter()
            .map(|p| 1.0 / p.mesh().body.len() as f64)
            .collect();
        let mut table: Vec<DMatrix<Complex64>> =
            solutions.iter().map(|s| s.added_mass.clone()).collect();
        let mut waves: Vec<Option<WaveForces>> =
            solutions.iter().map(|s| s.wave_forces.clone()).collect();
        // Neville: table[i] <- value at h = 0 of the polynomial through points i ..= i + m.
        for m in 1..table.len() {
            for i in 0..table.len() - m {
                let (hi, hj) = (h[i], h[i + m]);
                let next = (&table[i] * Complex64::new(-hj, 0.0)
                    + &table[i + 1] * Complex64::new(hi, 0.0))
                    / Complex64::new(hi - hj, 0.0);
                table[i] = next;
                if let (Some(a), Some(b)) = (&waves[i], &waves[i + 1]) {
                    waves[i] = Some(a.combine(-hj, b, hi, hi - hj));
                }
            }
        }
        let mut finest = solutions.swap_remove(0);
        for other in &solutions {
            finest.influence_time += other.influence_time;
            finest.assembly_time += other.assembly_time;
            finest.factorization_time += other.factorization_time;
        }
        finest.added_mass = table.swap_remove(0);
        finest.wave_forces = waves.swap_remove(0);
        let finite = |z: &Complex64| z.re.is_finite() && z.im.is_finite();
        let forces_finite = finest.wave_forces.as_ref().is_none_or(|w| {
            w.haskind
                .iter()
                .chain(w.direct.iter())
                .chain(w.froude_krylov.iter())
                .all(finite)
        });
        if !(finest.added_mass.iter().all(finite) && forces_finite) {
            return Err(BemError::NonFiniteExtrapolation {
                surface,
                levels: self.problems.len(),
            });
        }
        Ok(finest)
    }
}

/// A number as messages print it: plain digits for magnitudes in [1e-4, 1e9), an exponent
/// otherwise (`1e300`, not 301 digits).
fn readable(x: f64) -> String {
    format_number(x, Notation::Plain)
}

/// Wall time spent in each stage, summed over all frequencies (and threads).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Green function evaluation and panel integrals.
    pub influence: Duration,
    /// System assembly and added mass integration.
    pub assembly: Duration,
    /// LU factorization and solves.
    pub factorization: Duration,
}

/// The result of a sweep, nondimensional.
#[derive(Clone, Debug)]
pub struct SweepResult {
    /// Hull name.
    pub hull_name: String,
    /// Centre depth over radius for the built-in circles (0 for the semicircle), else `None`.
    pub depth_over_radius: Option<f64>,
    /// DOF names.
    pub dof_names: Vec<String>,
    /// Reference half-beam R (m).
    pub reference_half_beam: f64,
    /// The water depth (tables: `# depth: h/R`, `inf` for deep water).
    pub depth: WaterDepth,
    /// The frequencies solved successfully, ascending.
    pub kr: Vec<f64>,
    /// `A~(kR) / (rho pi R^2)` at each entry of `kr`.
    pub added_mass: Vec<DMatrix<Complex64>>,
    /// Reciprocity residual of each solve.
    pub reciprocity_residual: Vec<f64>,
    /// `A_inf / (rho pi R^2)`.
    pub added_mass_inf: DMatrix<f64>,
    /// `A(0) / (rho pi R^2)`; entries that diverge are `None`.
    pub added_mass_zero: DMatrix<Option<f64>>,
    /// Each DOF's length exponent `e_j` (0: a length; 1: an angle or mode amplitude).
    pub length_exponents: Vec<u8>,
    /// Exciting forces `X_j / (rho g a R^(1 + e_j))` at each entry of `kr`, one column per
    /// heading of [`crate::bem::HEADINGS`].
    pub excitation: Vec<WaveForces>,
    /// The long-wave limit of the same (`kR -> 0`, every heading): `integral_C n_j ds / R^(1 + e_j)`.
    pub excitation_long_wave: Vec<f64>,
    /// Frequencies that failed, with the reason.
    pub failures: Vec<(f64, String)>,
    /// Physics sanity warnings (for example panels too coarse for the wavelength).
    pub warnings: Vec<String>,
    /// Notes on choices made for this hull (for example smooth contour vertices meshed
    /// between nodes).
    pub notes: Vec<String>,
    /// Time per stage.
    pub times: StageTimes,
    /// Panel counts used: body, lid.
    pub panel_counts: (usize, usize),
}

/// Runs a sweep of `hull`. `progress(done, total)` is called after each frequency. The
/// table's `H/R` is the hull's own ([`Hull::circle_depth_ratio`]).
///
/// # Errors
/// Invalid parameters ([`SweepParams::validate`]), a failure of either frequency limit
/// (without `A_inf` there is nothing to fit) or a non-finite limit, or a sweep in which every
/// frequency failed. Failures at single frequencies are not errors: see
/// [`SweepResult::failures`].
pub fn run(
    hull: &Hull,
    params: &SweepParams,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<SweepResult, SweepError> {
    params.validate(hull)?;
    let solver = Solver::with_depth(
        hull,
        &params.panels,
        params.extrapolation_levels,
        params.depth,
    )?;
    let mesh = solver.mesh();
    let radius = hull.reference_half_beam();
    let scale = units::added_mass_scale(1.0, radius);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(params.threads)
        .build()
        .map_err(|e| SweepError::Threads {
            threads: params.threads,
            message: e.to_string(),
        })?;

    let limit = |surface| {
        solver
            .solve(surface, IrregularFrequencies::Keep)
            .map_err(|cause| SweepError::Limit { surface, cause })
    };
    let infinite = limit(FreeSurface::Dirichlet)?;
    let zero = limit(FreeSurface::RigidLid)?;
    let added_mass_inf = infinite.added_mass.map(|z| z.re / scale);
    let flux = mesh.net_flux();
    let flux_tolerance = 1e-9 * mesh.body.iter().map(|p| p.length).sum::<f64>();
    let added_mass_zero = DMatrix::from_fn(flux.len(), flux.len(), |i, j| {
        let diverges = flux[i].abs() > flux_tolerance && flux[j].abs() > flux_tolerance;
        (!diverges).then(|| zero.added_mass[(i, j)].re / scale)
    });
    let non_finite = |quantity| SweepError::NonFinite {
        quantity,
        half_beam: radius,
    };
    if !added_mass_inf.iter().all(|a| a.is_finite()) {
        return Err(non_finite("A_inf"));
    }
    if !added_mass_zero.iter().flatten().all(|a| a.is_finite()) {
        return Err(non_finite("A(0)"));
    }

    let solve_at = |kr: f64| {
        let surface = FreeSurface::Wave {
            wavenumber: units::wavenumber_from_kr(kr, radius),
        };
        solver.solve_with(surface, params.irregular_frequencies, params.excitation)
    };
    let solutions = solve_all(&pool, &params.kr, &solve_at, progress);
    let total = params.kr.len();
    let length_exponents: Vec<u8> = hull.dof_units().iter().map(|u| u.length_exponent).collect();
    let force_scale: Vec<f64> = length_exponents
        .iter()
        .map(|&e| radius.powi(1 + i32::from(e)))
        .collect();
    let excitation_long_wave: Vec<f64> = solver
        .long_wave_excitation()
        .iter()
        .zip(&force_scale)
        .map(|(flux, scale)| flux / scale)
        .collect();
    if !excitation_long_wave.iter().all(|x| x.is_finite()) {
        return Err(non_finite("the long-wave exciting force"));
    }

    let mut result = SweepResult {
        hull_name: hull.name().to_string(),
        depth_over_radius: hull.circle_depth_ratio(),
        dof_names: mesh.dof_names.clone(),
        reference_half_beam: radius,
        depth: params.depth,
        kr: Vec::with_capacity(total),
        added_mass: Vec::with_capacity(total),
        reciprocity_residual: Vec::with_capacity(total),
        added_mass_inf,
        added_mass_zero,
        length_exponents,
        excitation: Vec::with_capacity(total),
        excitation_long_wave,
        failures: Vec::new(),
        warnings: Vec::new(),
        notes: Vec::new(),
        times: StageTimes::default(),
        panel_counts: (mesh.body.len(), mesh.lid.len()),
    };
    let mut coarse: Option<(f64, String)> = None;
    for (kr, solution) in solutions {
        match solution {
            Ok(RadiationSolution {
                wave_forces: None, ..
            }) if params.excitation => result
                .failures
                .push((kr, "the solve gave no exciting force".to_string())),
            Ok(solution) => {
                result.times.influence += solution.influence_time;
                result.times.assembly += solution.assembly_time;
                result.times.factorization += solution.factorization_time;
                let added_mass = solution.added_mass / Complex64::new(scale, 0.0);
                let mut forces = solution.wave_forces;
                for part in forces
                    .iter_mut()
                    .flat_map(|f| [&mut f.haskind, &mut f.direct, &mut f.froude_krylov])
                {
                    for (j, mut row) in part.row_iter_mut().enumerate() {
                        row /= Complex64::new(force_scale[j], 0.0);
                    }
                }
                let finite = |z: &Complex64| z.re.is_finite() && z.im.is_finite();
                let all_finite = added_mass.iter().all(finite)
                    && solution.reciprocity_residual.is_finite()
                    && forces.as_ref().is_none_or(|w| {
                        w.haskind
                            .iter()
                            .chain(w.direct.iter())
                            .chain(w.froude_krylov.iter())
                            .all(finite)
                    });
                if !all_finite {
                    result.failures.push((
                        kr,
                        format!(
                            "non-finite added mass or exciting force after the normalization \
                             by the reference half-beam R = {} m",
                            readable(radius)
                        ),
                    ));
                    continue;
                }
                result.kr.push(kr);
                result.added_mass.push(added_mass);
                result
                    .reciprocity_residual
                    .push(solution.reciprocity_residual);
                if let Some(forces) = forces {
                    result.excitation.push(forces);
                }
                if coarse.is_none() {
                    let nu = units::wavenumber_from_kr(kr, radius);
                    let k = match params.depth {
                        WaterDepth::Finite(h) => finite_depth::wavenumber(nu, h).unwrap_or(nu),
                        WaterDepth::Infinite => nu,
                    };
                    coarse = mesh.wavelength_warning(k).map(|w| (kr, w));
                }
            }
            Err(err) => result.failures.push((kr, err.to_string())),
        }
    }
    if result.kr.is_empty() {
        return Err(SweepError::NothingComputed {
            failures: result.failures,
        });
    }
    if let Some((_, warning)) = coarse {
        result.warnings.push(warning);
    }
    result.warnings.extend(solver.dropped_vertices_warning());
    result.notes.extend(solver.smooth_vertices_note());
    Ok(result)
}

/// The accuracy measure of the product: the largest `|A_ij - R_ij| / sqrt(|R_ii R_jj|)` over
/// matching frequencies and all entries, against `reference`. Entries of DOFs with no added
/// mass (`|R_ii| < 1e-8`, such as roll of a circle about its centre) are skipped. Returns the
/// error, the frequency index and the (0-based) entry where it occurs.
pub fn max_normalized_difference(
    added_mass: &[DMatrix<Complex64>],
    reference: &[DMatrix<Complex64>],
) -> (f64, usize, (usize, usize)) {
    let mut worst = (0.0, 0, (0, 0));
    for (k, (m, r)) in added_mass.iter().zip(reference).enumerate() {
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                let scale = (r[(i, i)].norm() * r[(j, j)].norm()).sqrt();
                if scale < 1e-8 {
                    continue;
                }
                let e = (m[(i, j)] - r[(i, j)]).norm() / scale;
                if e > worst.0 {
                    worst = (e, k, (i, j));
                }
            }
        }
    }
    worst
}

/// The accuracy measure of the exciting force: the largest `|x_j - r_j|` over matching
/// frequencies and both headings, relative to the largest `|r_j|` of the DOF over all of them
/// (direct values). DOFs that waves do not excite (largest `|r_j|` below 1e-8 of the largest
/// of all DOFs) are skipped. Returns the error, the frequency index and the (0-based) DOF.
pub fn max_excitation_difference(
    forces: &[WaveForces],
    reference: &[WaveForces],
) -> (f64, usize, usize) {
    let Some(first) = reference.first() else {
        return (0.0, 0, 0);
    };
    let largest: Vec<f64> = (0..first.direct.nrows())
        .map(|j| {
            reference
                .iter()
                .flat_map(|r| r.direct.row(j).iter().map(|z| z.norm()).collect::<Vec<_>>())
                .fold(0.0, f64::max)
        })
        .collect();
    let overall = largest.iter().copied().fold(0.0, f64::max);
    let mut worst = (0.0, 0, 0);
    for (k, (x, r)) in forces.iter().zip(reference).enumerate() {
        for (j, &scale) in largest.iter().enumerate() {
            if scale <= 1e-8 * overall {
                continue;
            }
            for h in 0..r.direct.ncols() {
                let e = (x.direct[(j, h)] - r.direct[(j, h)]).norm() / scale;
                if e > worst.0 {
                    worst = (e, k, j);
                }
            }
        }
    }
    worst
}

/// Solves every frequency on `pool`, in grid order; a failure stays with its frequency.
fn solve_all(
    pool: &rayon::ThreadPool,
    kr: &[f64],
    solve_at: &(dyn Fn(f64) -> Result<RadiationSolution, BemError> + Sync),
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Vec<(f64, Result<RadiationSolution, BemError>)> {
    let done = AtomicUsize::new(0);
    pool.install(|| {
        kr.par_iter()
            .map(|&k| {
                let solution = solve_at(k);
                progress(done.fetch_add(1, Ordering::Relaxed) + 1, kr.len());
                (k, solution)
            })
            .collect()
    })
}

#[cfg(test)]
mod tests;
