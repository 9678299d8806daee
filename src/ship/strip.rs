//! The ship's sweep: every distinct section solved at every frequency (in parallel), then the
//! strip integration of the module docs into whole-ship coefficients in SI.
//!
//! Each section is solved with the panel method of [`crate::bem`] for its rigid sway, heave
//! and roll about the origin and the elastic DOFs the ship's modes use
//! ([`Hull::ship_section`]), Richardson-extrapolated over the discretization levels as a
//! section sweep is ([`Solver`]), in the sweep's water depth ([`Solver::with_depth`]). The
//! incident wave of heading `beta` reaches the section at `x` as `e^{-i k x cos beta}` times a
//! 2D wave of transverse direction cosine `sin beta` ([`crate::bem::Problem::solve_waves`]),
//! `k` the root of `omega^2 = g k tanh(k h)`; the sectional force is the Haskind form, the
//! zero-speed Salvesen-Tuck-Faltinsen one. The sectional restoring is
//! [`crate::hydrostatics::stiffness`]; rigid pitch adds `rho g V z_B` (the buoyancy's own
//! moment arm, as roll's closed form has per section).

use super::{SectionMotion, Ship};
use crate::bem::{IrregularFrequencies, RadiationSolution};
use crate::database::Database;
use crate::green::FreeSurface;
use crate::hull::Hull;
use crate::hydrostatics::{self, HydrostaticsError};
use crate::panels::PanelParams;
use crate::sweep::{log_grid, Solver, SweepError, SweepParams};
use crate::units::WaterDepth;
use nalgebra::DMatrix;
use num_complex::Complex64;
use rayon::prelude::*;
use std::fmt;
use std::sync::atomic::{AtomicUsize, Ordering};

/// 8-point Gauss-Legendre nodes and weights on [-1, 1].
const GAUSS: [(f64, f64); 8] = crate::numerics::GAUSS_LEGENDRE_8;

/// Most section solves (distinct sections x frequencies) of one ship sweep: every solve is
/// kept until the strip integration (a few kB each at 9 section DOFs, so about 1 GB at the
/// limit) and costs a few ms (about 10 minutes on 2 cores at the limit).
pub const MAX_SECTION_SOLVES: usize = 250_000;

/// Most wave headings of one ship sweep.
pub const MAX_HEADINGS: usize = crate::waves::MAX_HEADINGS;

/// Parameters of a ship sweep, with documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct ShipSweepParams {
    /// Wave frequencies omega, rad/s (each finite and > 0). Default
    /// ([`ShipSweepParams::for_ship`]): 100 log-spaced points from `kR = 0.01` to `kR = 5`,
    /// R the largest section half-beam.
    pub omega: Vec<f64>,
    /// Wave headings, degrees (0: towards +x, following seas; 90: towards +y; 180: head
    /// seas). Default 0, 45, 90, 135, 180.
    pub headings: Vec<f64>,
    /// Discretization of the smooth sections (semicircles, Lewis forms, hull files and offsets
    /// without corners off the mirror axis). Default 64 body panels: a ship's sections are
    /// many, and smooth ones converge fast.
    pub panels: PanelParams,
    /// Discretization of sections with corners off the mirror axis (hull files, offsets; see
    /// [`ShipSweepParams::panels_for`]). Default 128 body panels.
    pub panels_with_corners: PanelParams,
    /// Discretization levels extrapolated for the smooth sections (see [`Solver`]). Default 3.
    pub extrapolation_levels: usize,
    /// Levels for the sections with corners. Default 2: the extrapolation assumes an error
    /// smooth in the panel size, which corners disturb, most on the coarsest level. Largest
    /// diagonal error at 128 panels with 1, 2, 3 levels (docs/SHIPS.md): the box barge's
    /// heave, pitch and bending 0.055 %, 0.091 %, 0.77 % (against 512 panels, 3 levels); the
    /// sections of `examples/hulls/barge.xml` 1.0 %, 0.32 %, 0.52 % and `midship.xml` 0.67 %,
    /// 0.49 %, 0.55 % (against 1024 panels, 3 levels).
    pub levels_with_corners: usize,
    /// Irregular frequencies. Default: removed with an interior lid.
    pub irregular_frequencies: IrregularFrequencies,
    /// Worker threads (explicit). Default 2.
    pub threads: usize,
    /// Water density, kg/m^3. Default 1025.
    pub rho: f64,
    /// Gravity, m/s^2. Default 9.81.
    pub g: f64,
    /// Also the fixed ship's mean wave drift ([`super::drift`], `Database::drift`). Default
    /// false: it costs a second diffraction solve of every section at every frequency.
    pub drift: bool,
    /// Water depth (the ship file's `depth`, `--water-depth`). Default deep water. Every
    /// wavenumber of the strip integration solves `omega^2 = g k tanh(k h)`
    /// ([`WaterDepth::wavenumber`]); each section is validated (one reaching the bottom is
    /// refused) and solved in it, `A_inf`, the long-wave force and the mean drift included.
    pub depth: WaterDepth,
}

/// The incident wave's phase at station `x` (m) for wavenumber `k` (1/m, the depth's) and
/// heading `heading` (deg): `e^{-i k x cos(heading)}`.
pub(crate) fn wave_phase(k: f64, heading: f64, x: f64) -> Complex64 {
    let along = k * heading.to_radians().cos();
    Complex64::new(0.0, -along * x).exp()
}

impl ShipSweepParams {
    /// The discretization of `section`: [`ShipSweepParams::panels_with_corners`] for a contour
    /// with corners off its mirror axis (a hull file or offsets turning more than
    /// `CORNER_ANGLE` at a point, `off_axis_corner_count`),
    /// [`ShipSweepParams::panels`] for a smooth one (a built-in form, or points along a smooth
    /// curve, a keel on the axis allowed).
    pub fn panels_for(&self, section: &Hull) -> &PanelParams {
        if crate::panels::off_axis_corner_count(section) > 0 {
            &self.panels_with_corners
        } else {
            &self.panels
        }
    }

    /// The extrapolation levels of `section` (see [`ShipSweepParams::panels_for`]).
    pub fn levels_for(&self, section: &Hull) -> usize {
        if crate::panels::off_axis_corner_count(section) > 0 {
            self.levels_with_corners
        } else {
            self.extrapolation_levels
        }
    }

    /// The defaults for `ship` (see the fields).
    pub fn for_ship(ship: &Ship) -> Self {
        let g = 9.81;
        let radius = ship
            .sections()
            .iter()
            .map(Hull::reference_half_beam)
            .fold(0.0, f64::max);
        let omega = log_grid(0.01, 5.0, 100)
            .expect("a valid grid")
            .iter()
            .map(|kr| crate::units::omega_from_kr(*kr, radius, g))
            .collect();
        Self {
            omega,
            headings: vec![0.0, 45.0, 90.0, 135.0, 180.0],
            panels: PanelParams {
                body_panels: 64,
                ..PanelParams::default()
            },
            panels_with_corners: PanelParams::default(),
            extrapolation_levels: 3,
            levels_with_corners: 2,
            irregular_frequencies: IrregularFrequencies::RemoveWithLid,
            threads: 2,
            rho: 1025.0,
            g,
            drift: false,
            depth: ship.depth(),
        }
    }
}

/// Why a ship sweep could not run or gave nothing.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ShipSweepError {
    /// A parameter out of range.
    Parameters(String),
    /// A section could not be prepared or its limits failed.
    Section {
        /// The first station with this section, m.
        station_x: f64,
        /// The cause.
        cause: SweepError,
    },
    /// A section's restoring is not finite.
    Hydrostatics(HydrostaticsError),
    /// Every frequency failed.
    NothingComputed {
        /// Each frequency (rad/s) with the reason.
        failures: Vec<(f64, String)>,
    },
}

impl fmt::Display for ShipSweepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShipSweepError::Parameters(m) => write!(f, "{m}"),
            ShipSweepError::Section { station_x, cause } => {
                write!(f, "the section at x = {station_x} m: {cause}")
            }
            ShipSweepError::Hydrostatics(e) => write!(f, "{e}"),
            ShipSweepError::NothingComputed { failures } => {
                write!(f, "every frequency failed")?;
                if let Some((omega, why)) = failures.first() {
                    write!(f, "; the first, omega = {omega} rad/s: {why}")?;
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for ShipSweepError {}

/// One Gauss point's share of one station's section: `weight * T^T Q T` with `T` the
/// section coordinates of every ship DOF.
pub(super) struct Share {
    section: usize,
    x: f64,
    weight: f64,
    /// Section DOFs x ship DOFs.
    coordinates: DMatrix<f64>,
}

/// Elastic section DOFs used by the ship's modes, per section, in first-use order.
fn elastic_names(ship: &Ship) -> Vec<Vec<String>> {
    let mut names = vec![Vec::<String>::new(); ship.sections().len()];
    for dof in ship.dofs() {
        let Some(motions) = &dof.motions else {
            continue;
        };
        for (motion, station) in motions.iter().zip(ship.stations()) {
            if let Some(k) = station.section {
                for (name, _) in &motion.amplitudes {
                    if !names[k].contains(name) {
                        names[k].push(name.clone());
                    }
                }
            }
        }
    }
    names
}

/// The section coordinates (sway, heave, roll, elastic amplitudes in `elastic` order) of
/// `motion`.
fn coordinates(motion: &SectionMotion, elastic: &[String]) -> Vec<f64> {
    let mut c = vec![motion.sway, motion.heave, motion.roll];
    c.extend(elastic.iter().map(|name| {
        motion
            .amplitudes
            .iter()
            .find(|(n, _)| n == name)
            .map_or(0.0, |(_, a)| *a)
    }));
    c
}

/// The Gauss shares of every interval between consecutive stations of `chosen` (indices into
/// the ship's stations, ascending: all of them, or every second one for the spacing's error
/// estimate).
fn shares(ship: &Ship, elastic: &[Vec<String>], chosen: &[usize]) -> Vec<Share> {
    let stations = ship.stations();
    let n = ship.dofs().len();
    let mut out = Vec::new();
    for pair in chosen.windows(2) {
        let (i, next) = (pair[0], pair[1]);
        let (a, b) = (stations[i].x, stations[next].x);
        let half = (b - a) / 2.0;
        let motions: Vec<[SectionMotion; 2]> = (0..n)
            .map(|r| [ship.motion(r, i), ship.motion(r, next)])
            .collect();
        for &(node, gauss_weight) in &GAUSS {
            let t = (node + 1.0) / 2.0;
            let x = a + half * (node + 1.0);
            for (end, end_weight) in [(i, 1.0 - t), (next, t)] {
                let Some(section) = stations[end].section else {
                    continue;
                };
                let names = &elastic[section];
                let mut coordinates_at = DMatrix::zeros(3 + names.len(), n);
                for (r, pair) in motions.iter().enumerate() {
                    let (c0, c1) = (coordinates(&pair[0], names), coordinates(&pair[1], names));
                    for (k, (u, v)) in c0.iter().zip(&c1).enumerate() {
                        coordinates_at[(k, r)] = (1.0 - t) * u + t * v;
                    }
                }
                out.push(Share {
                    section,
                    x,
                    weight: end_weight * gauss_weight * half,
                    coordinates: coordinates_at,
                });
            }
        }
    }
    out
}

/// `sum weight T^T Q_section T` over the shares.
fn integrate_real(shares: &[Share], n: usize, of: impl Fn(usize) -> DMatrix<f64>) -> DMatrix<f64> {
    let mut total = DMatrix::zeros(n, n);
    for share in shares {
        let q = of(share.section);
        total += share.coordinates.transpose() * q * &share.coordinates * share.weight;
    }
    total
}

/// `sum weight T^T q_section` over the shares.
pub(super) fn integrate_vector(
    shares: &[Share],
    n: usize,
    of: impl Fn(usize) -> Vec<f64>,
) -> Vec<f64> {
    let mut total = vec![0.0; n];
    for share in shares {
        let q = of(share.section);
        for (r, value) in total.iter_mut().enumerate() {
            *value += share.weight
                * q.iter()
                    .enumerate()
                    .map(|(j, v)| v * share.coordinates[(j, r)])
                    .sum::<f64>();
        }
    }
    total
}

fn integrate_complex(
    shares: &[Share],
    n: usize,
    of: &dyn Fn(usize) -> DMatrix<Complex64>,
) -> DMatrix<Complex64> {
    let mut total = DMatrix::<Complex64>::zeros(n, n);
    for share in shares {
        let t = share.coordinates.map(|v| Complex64::new(v, 0.0));
        total += t.transpose() * of(share.section) * &t * Complex64::new(share.weight, 0.0);
    }
    total
}

/// The strip integrals of one frequency: added mass, exciting and Froude-Krylov forces (DOFs x
/// headings), and with every second station alone the added mass and exciting force.
struct StripIntegrals {
    added: DMatrix<Complex64>,
    excitation: DMatrix<Complex64>,
    froude_krylov: DMatrix<Complex64>,
    coarse: Option<(DMatrix<Complex64>, DMatrix<Complex64>)>,
    drift: Option<DMatrix<f64>>,
}

/// Runs the ship's sweep. `progress(done, total)` after each section solve.
///
/// # Errors
/// Parameters out of range (checked before any allocation, with the section sweep's bounds
/// for every section, [`MAX_SECTION_SOLVES`] and the section sweep's table limit), a section
/// whose meshes or frequency limits fail, a non-finite restoring, or a sweep in which every
/// frequency failed. Failures at single frequencies are not errors.
pub fn run(
    ship: &Ship,
    params: &ShipSweepParams,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Database, ShipSweepError> {
    let bad = |m: String| ShipSweepError::Parameters(m);
    for (what, value) in [("rho", params.rho), ("g", params.g)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(bad(format!(
                "{what} must be positive and finite, got {value}"
            )));
        }
    }
    if params.headings.is_empty() || params.headings.len() > MAX_HEADINGS {
        return Err(bad(format!(
            "{} headings; give 1 to {MAX_HEADINGS}",
            params.headings.len()
        )));
    }
    if let Some(h) = params.headings.iter().find(|h| !h.is_finite()) {
        return Err(bad(format!("heading {h} is not finite")));
    }
    // Headings are directions: two equal modulo 360 would be one table column twice.
    for (k, &a) in params.headings.iter().enumerate() {
        let same = |&&b: &&f64| crate::waves::same_direction(a, b);
        if let Some(&b) = params.headings[..k].iter().find(same) {
            return Err(bad(format!(
                "headings {b} and {a} are the same direction (equal modulo 360 degrees): give \
                 each once"
            )));
        }
    }
    if let Some(w) = params.omega.iter().find(|w| !(w.is_finite() && **w > 0.0)) {
        return Err(bad(format!(
            "frequency {w} rad/s must be positive and finite"
        )));
    }
    if let Some(w) = params
        .omega
        .iter()
        .find(|w| params.depth.wavenumber(**w, params.g).is_err())
    {
        let e = params.depth.wavenumber(*w, params.g).unwrap_err();
        return Err(bad(format!(
            "frequency {w} rad/s in water depth {}: {e}",
            params.depth
        )));
    }
    let solves = ship.sections().len().saturating_mul(params.omega.len());
    if solves > MAX_SECTION_SOLVES {
        return Err(bad(format!(
            "{} distinct sections x {} frequencies = {solves} section solves; at most \
             {MAX_SECTION_SOLVES} (each is kept until the strip integration)",
            ship.sections().len(),
            params.omega.len()
        )));
    }
    let n = ship.dofs().len();
    let entries = params.omega.len().saturating_mul(n * n);
    if entries > crate::sweep::MAX_TABLE_ENTRIES {
        return Err(bad(format!(
            "{} frequencies x {n}^2 DOF pairs = {entries} table entries; at most {}",
            params.omega.len(),
            crate::sweep::MAX_TABLE_ENTRIES
        )));
    }
    let elastic = elastic_names(ship);
    let sections: Vec<Hull> = ship
        .sections()
        .iter()
        .zip(&elastic)
        .map(|(hull, names)| {
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            hull.ship_section(&names)
        })
        .collect::<Result<_, _>>()
        .map_err(|e| bad(e.to_string()))?;
    let first_x = |k: usize| {
        ship.stations()
            .iter()
            .find(|s| s.section == Some(k))
            .map_or(f64::NAN, |s| s.x)
    };
    let section_error = |k: usize| {
        move |cause| ShipSweepError::Section {
            station_x: first_x(k),
            cause,
        }
    };
    for (k, hull) in sections.iter().enumerate() {
        let as_section = SweepParams {
            kr: params
                .omega
                .iter()
                .map(|w| crate::units::kr_from_omega(*w, hull.reference_half_beam(), params.g))
                .collect(),
            panels: *params.panels_for(hull),
            irregular_frequencies: params.irregular_frequencies,
            extrapolation_levels: params.levels_for(hull),
            threads: params.threads,
            excitation: true,
            depth: params.depth,
        };
        as_section.validate(hull).map_err(section_error(k))?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(params.threads)
        .build()
        .map_err(|e| bad(format!("cannot start {} threads: {e}", params.threads)))?;

    let solvers: Vec<Solver> = pool.install(|| {
        sections
            .par_iter()
            .enumerate()
            .map(|(k, hull)| {
                let (panels, levels) = (params.panels_for(hull), params.levels_for(hull));
                Solver::with_depth(hull, panels, levels, params.depth).map_err(section_error(k))
            })
            .collect::<Result<_, _>>()
    })?;
    let limits: Vec<RadiationSolution> = pool.install(|| {
        solvers
            .par_iter()
            .enumerate()
            .map(|(k, solver)| {
                solver
                    .solve(FreeSurface::Dirichlet, IrregularFrequencies::Keep)
                    .map_err(|cause| SweepError::Limit {
                        surface: FreeSurface::Dirichlet,
                        cause,
                    })
                    .map_err(section_error(k))
            })
            .collect::<Result<_, _>>()
    })?;
    let restoring: Vec<hydrostatics::Hydrostatics> = sections
        .iter()
        .map(hydrostatics::stiffness)
        .collect::<Result<_, _>>()
        .map_err(ShipSweepError::Hydrostatics)?;

    // Distinct transverse direction cosines of the headings.
    let mut cosines: Vec<f64> = Vec::new();
    let column: Vec<usize> = params
        .headings
        .iter()
        .map(|h| {
            let c = h.to_radians().sin();
            match cosines.iter().position(|d| (d - c).abs() < 1e-12) {
                Some(k) => k,
                None => {
                    cosines.push(c);
                    cosines.len() - 1
                }
            }
        })
        .collect();

    let tasks: Vec<(usize, usize)> = (0..sections.len())
        .flat_map(|k| (0..params.omega.len()).map(move |w| (k, w)))
        .collect();
    let done = AtomicUsize::new(0);
    type Solved = (
        Result<RadiationSolution, String>,
        Option<Result<DMatrix<f64>, String>>,
    );
    let (solutions, section_drifts): (Vec<_>, Vec<_>) = pool.install(|| {
        tasks
            .par_iter()
            .map(|&(k, w)| -> Solved {
                let omega = params.omega[w];
                // nu = omega^2/g: the section's problem finds the depth's propagating k.
                let wavenumber = crate::units::wavenumber(omega, params.g);
                let at = |e| format!("the section at x = {} m: {e}", first_x(k));
                let solution = solvers[k]
                    .solve_waves(
                        FreeSurface::Wave { wavenumber },
                        params.irregular_frequencies,
                        &cosines,
                    )
                    .map_err(|e| at(e.to_string()));
                let drift = params.drift.then(|| {
                    super::drift::section_drift(
                        &solvers[k],
                        wavenumber,
                        params.irregular_frequencies,
                    )
                    .map_err(at)
                });
                progress(done.fetch_add(1, Ordering::Relaxed) + 1, tasks.len());
                (solution, drift)
            })
            .unzip()
    });

    let all: Vec<usize> = (0..ship.stations().len()).collect();
    let coarse_shares =
        (all.len() >= 3).then(|| shares(ship, &elastic, &every_second_station(all.len())));
    let shares = shares(ship, &elastic, &all);
    let mut spacing = SpacingEstimate::new(n);
    let (rho, g) = (params.rho, params.g);
    let added_mass_inf = integrate_real(&shares, n, |k| limits[k].added_mass.map(|z| z.re)) * rho;
    let mut stiffness = integrate_real(&shares, n, |k| restoring[k].stiffness_per_rho_g.clone());
    if let Some(pitch) = ship
        .dofs()
        .iter()
        .position(|d| d.name == "pitch" && d.motions.is_none())
    {
        // rho g V z_B: the integral of the sectional A z_B.
        stiffness[(pitch, pitch)] += buoyancy_moment(&shares, &restoring);
    }
    let stiffness_hydrostatic = stiffness * (rho * g);
    let flux: Vec<Vec<f64>> = solvers.iter().map(Solver::long_wave_excitation).collect();
    let excitation_long_wave = Some(
        integrate_vector(&shares, n, |k| flux[k].clone())
            .iter()
            .map(|x| x * rho * g)
            .collect(),
    );

    let mut result = Database {
        name: ship.name().to_string(),
        source: "strip theory (zero-speed Salvesen-Tuck-Faltinsen)".to_string(),
        dof_names: ship.dof_names().iter().map(|s| s.to_string()).collect(),
        rho,
        g,
        omega: Vec::new(),
        added_mass: Vec::new(),
        added_mass_inf,
        headings: params.headings.clone(),
        excitation: Vec::new(),
        froude_krylov: Vec::new(),
        excitation_long_wave,
        stiffness_hydrostatic,
        dof_units: ship.dof_units(),
        reference_length: sections
            .iter()
            .map(Hull::reference_half_beam)
            .fold(0.0, f64::max),
        failures: Vec::new(),
        warnings: Vec::new(),
        notes: Vec::new(),
        noise: DMatrix::zeros(n, n),
        body_panels: solvers.iter().map(|s| s.mesh().body.len()).collect(),
        drift: Vec::new(),
        drift_headings: Vec::new(),
        depth: params.depth,
    };
    let count = params.omega.len();
    // The strip integrals of one frequency (`Err`: why there are none).
    let integrate_at = |w: usize| -> Result<StripIntegrals, String> {
        let omega = params.omega[w];
        let solved = (0..sections.len())
            .map(|k| solutions[k * count + w].as_ref().map_err(Clone::clone))
            .collect::<Result<Vec<&RadiationSolution>, String>>()?;
        let waves = solved
            .iter()
            .map(|s| s.wave_forces.as_ref())
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| "a section's solve gave no exciting force".to_string())?;
        let drift = if params.drift {
            let sections_drift = (0..sections.len())
                .map(|k| match &section_drifts[k * count + w] {
                    Some(Ok(d)) => Ok(d.clone()),
                    Some(Err(e)) => Err(e.clone()),
                    None => Err("no drift solve".to_string()),
                })
                .collect::<Result<Vec<_>, String>>()?;
            Some(super::drift::integrate(
                &shares,
                n,
                &params.headings,
                &sections_drift,
                rho * g,
            ))
        } else {
            None
        };
        let added = integrate_complex(&shares, n, &|k| solved[k].added_mass.clone())
            * Complex64::new(rho, 0.0);
        let k = params
            .depth
            .wavenumber(omega, g)
            .map_err(|e| e.to_string())?;
        // Wave phase at each station for each heading: e^{-i k x cos(beta)}.
        let phases = |shares: &[Share]| -> Vec<Vec<Complex64>> {
            params
                .headings
                .iter()
                .map(|heading| {
                    shares
                        .iter()
                        .map(|s| wave_phase(k, *heading, s.x))
                        .collect()
                })
                .collect()
        };
        let force = |shares: &[Share], phases: &[Vec<Complex64>], froude_krylov_only: bool| {
            DMatrix::from_fn(n, params.headings.len(), |r, h| {
                shares
                    .iter()
                    .zip(&phases[h])
                    .map(|(s, &phase)| {
                        let x = if froude_krylov_only {
                            &waves[s.section].froude_krylov
                        } else {
                            &waves[s.section].haskind
                        };
                        (0..s.coordinates.nrows())
                            .map(|j| x[(j, column[h])] * s.coordinates[(j, r)])
                            .sum::<Complex64>()
                            * phase
                            * s.weight
                    })
                    .sum::<Complex64>()
                    * (rho * g)
            })
        };
        let all_phases = phases(&shares);
        let coarse = coarse_shares.as_deref().map(|coarse_shares| {
            let added = integrate_complex(coarse_shares, n, &|k| solved[k].added_mass.clone())
                * Complex64::new(rho, 0.0);
            (added, force(coarse_shares, &phases(coarse_shares), false))
        });
        Ok(StripIntegrals {
            excitation: force(&shares, &all_phases, false),
            froude_krylov: force(&shares, &all_phases, true),
            added,
            coarse,
            drift,
        })
    };
    let integrals: Vec<Result<StripIntegrals, String>> =
        pool.install(|| (0..count).into_par_iter().map(integrate_at).collect());
    let mut coarse: Option<String> = None;
    for (integrals, &omega) in integrals.into_iter().zip(&params.omega) {
        let integrals = match integrals {
            Ok(integrals) => integrals,
            Err(why) => {
                result.failures.push((omega, why));
                continue;
            }
        };
        let StripIntegrals {
            added,
            excitation,
            froude_krylov,
            coarse: coarse_integrals,
            drift,
        } = integrals;
        if let Some((coarse_added, coarse_excitation)) = &coarse_integrals {
            spacing.add(omega, &added, coarse_added, &excitation, coarse_excitation);
        }
        let finite = |z: &Complex64| z.re.is_finite() && z.im.is_finite();
        let drift_finite = drift.iter().flatten().all(|x| x.is_finite());
        if !(added.iter().all(finite) && excitation.iter().all(finite) && drift_finite) {
            result
                .failures
                .push((omega, "non-finite strip integral".to_string()));
            continue;
        }
        if coarse.is_none() {
            let k = params
                .depth
                .wavenumber(omega, g)
                .map_err(|e| ShipSweepError::Parameters(e.to_string()))?;
            coarse = solvers.iter().find_map(|s| s.mesh().wavelength_warning(k));
        }
        result.omega.push(omega);
        result.added_mass.push(added);
        result.excitation.push(excitation);
        result.froude_krylov.push(froude_krylov);
        result.drift.extend(drift);
    }
    if result.omega.is_empty() {
        return Err(ShipSweepError::NothingComputed {
            failures: result.failures,
        });
    }
    if params.drift {
        result.drift_headings = params.headings.clone();
    }
    if let Some(w) = coarse {
        result.warnings.push(w);
    }
    if coarse_shares.is_some() {
        result
            .notes
            .push(spacing.note(&result.dof_names, &params.headings));
        result
            .warnings
            .extend(spacing.warning(&ship.dof_units(), ship.length()));
    }
    for (k, solver) in solvers.iter().enumerate() {
        if let Some(w) = solver.dropped_vertices_warning() {
            result
                .warnings
                .push(format!("the section first at x = {} m: {w}", first_x(k)));
        }
    }
    let smooth: Vec<usize> = solvers
        .iter()
        .map(|s| s.mesh().smooth_vertices_between_nodes)
        .filter(|&n| n > 0)
        .collect();
    if !smooth.is_empty() {
        result.notes.push(format!(
            "{} of {} distinct sections are meshed as smooth curves through their points (more \
             points than the coarsest level's nodes; {} points in all lie between panel nodes, \
             the same at every level; corners stay nodes)",
            smooth.len(),
            solvers.len(),
            smooth.iter().sum::<usize>()
        ));
    }
    Ok(result)
}

/// Every second of `count` stations, and the last: the same sections, twice the spacing.
fn every_second_station(count: usize) -> Vec<usize> {
    (0..count)
        .filter(|&i| i % 2 == 0 || i + 1 == count)
        .collect()
}

/// The station spacing's error estimate: the largest change of each DOF's diagonal `A~` and
/// exciting force when every second station alone is integrated (the same sections, twice
/// the spacing), as a fraction of the DOF's largest value over the sweep. The trapezoid-like
/// rule between stations converges as `h^2` where the sections vary smoothly (the full
/// spacing's error is then about a third of this change) and only as `h` where they end
/// abruptly (a pointed end: about as large as the change).
/// Change with every second station (a fraction of the DOF's largest value) above which the
/// ship report warns: at 2 % the full spacing's own error is 0.7 % to 2 % (a third of the
/// change where the sections vary smoothly, as large next to an abrupt end).
const SPACING_WARNING: f64 = 0.02;

struct SpacingEstimate {
    added_change: Vec<(f64, f64)>,
    added_scale: Vec<f64>,
    force_change: Vec<(f64, f64, usize)>,
    force_scale: Vec<f64>,
}

impl SpacingEstimate {
    fn new(n: usize) -> Self {
        SpacingEstimate {
            added_change: vec![(0.0, 0.0); n],
            added_scale: vec![0.0; n],
            force_change: vec![(0.0, 0.0, 0); n],
            force_scale: vec![0.0; n],
        }
    }

    fn add(
        &mut self,
        omega: f64,
        added: &DMatrix<Complex64>,
        coarse_added: &DMatrix<Complex64>,
        force: &DMatrix<Complex64>,
        coarse_force: &DMatrix<Complex64>,
    ) {
        for r in 0..self.added_scale.len() {
            self.added_scale[r] = self.added_scale[r].max(added[(r, r)].norm());
            let d = (added[(r, r)] - coarse_added[(r, r)]).norm();
            if d > self.added_change[r].0 {
                self.added_change[r] = (d, omega);
            }
            for h in 0..force.ncols() {
                self.force_scale[r] = self.force_scale[r].max(force[(r, h)].norm());
                let d = (force[(r, h)] - coarse_force[(r, h)]).norm();
                if d > self.force_change[r].0 {
                    self.force_change[r] = (d, omega, h);
                }
            }
        }
    }

    /// A warning naming the DOFs whose `A~` or exciting force changes by more than
    /// [`SPACING_WARNING`] of its largest value with every second station, else `None`. A
    /// value that is zero but for rounding (the pitch force of beam seas on a fore-and-aft
    /// symmetric ship) is left out: below 1e-9 of the largest over the DOFs, a DOF of length
    /// exponent 1 (angles, modes) taken over the ship's `length`.
    fn warning(&self, units: &[crate::fmu::DofUnit], length: f64) -> Option<String> {
        let arm = |u: &crate::fmu::DofUnit| {
            length
                .max(f64::MIN_POSITIVE)
                .powi(i32::from(u.length_exponent))
        };
        // Diagonal A~ carries the arm squared, a force the arm.
        let floor = |scales: &[f64], power: i32| {
            1e-9 * units
                .iter()
                .zip(scales)
                .map(|(u, s)| s / arm(u).powi(power))
                .fold(0.0, f64::max)
        };
        let (added_floor, force_floor) = (floor(&self.added_scale, 2), floor(&self.force_scale, 1));
        let fraction = |change: f64, scale: f64, comparable: f64, floor: f64| {
            if comparable > floor && scale > 0.0 {
                change / scale
            } else {
                0.0
            }
        };
        let large: Vec<String> = units
            .iter()
            .enumerate()
            .filter_map(|(r, unit)| {
                let a = arm(unit);
                let (added, force) = (self.added_scale[r], self.force_scale[r]);
                let change =
                    fraction(self.added_change[r].0, added, added / (a * a), added_floor).max(
                        fraction(self.force_change[r].0, force, force / a, force_floor),
                    );
                (change > SPACING_WARNING).then(|| format!("{} {:.1} %", unit.name, 100.0 * change))
            })
            .collect();
        (!large.is_empty()).then(|| {
            format!(
                "station spacing: every second station alone changes {} (A~ or exciting force, \
                 of the largest value): the stations may be too far apart where the sections \
                 change fast; next to an abrupt end (an empty end station) the error is about as \
                 large; give more stations there (see the note)",
                large.join(", ")
            )
        })
    }

    fn note(&self, names: &[String], headings: &[f64]) -> String {
        let fraction = |d: f64, scale: f64| if scale > 0.0 { d / scale } else { 0.0 };
        let entries: Vec<String> = names
            .iter()
            .enumerate()
            .map(|(r, name)| {
                let (da, wa) = self.added_change[r];
                let (df, wf, h) = self.force_change[r];
                format!(
                    "{name} A~ {:.2} % (omega {wa:.3}), force {:.2} % (omega {wf:.3}, heading {})",
                    100.0 * fraction(da, self.added_scale[r]),
                    100.0 * fraction(df, self.force_scale[r]),
                    headings.get(h).copied().unwrap_or(f64::NAN)
                )
            })
            .collect();
        format!(
            "station spacing: every second station alone changes, as a fraction of each DOF's \
             largest value: {}; the spacing's own error is about a third of that where the \
             sections vary smoothly and as large near an abrupt end (refine the stations there)",
            entries.join("; ")
        )
    }
}

/// `integral A(x) z_B(x) dx` over the stations (the rigid pitch's buoyancy moment arm, per
/// `rho g`), with the same linear interpolation between stations.
fn buoyancy_moment(shares: &[Share], restoring: &[hydrostatics::Hydrostatics]) -> f64 {
    shares
        .iter()
        .map(|s| {
            let h = &restoring[s.section];
            s.weight * h.submerged_area * h.centre_of_buoyancy[1]
        })
        .sum()
}
