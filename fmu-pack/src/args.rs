//! The command line's arguments shared by the subcommands and by the sections, ships and
//! imported databases they dispatch to: the hull and its sweep settings, `sweep`, `pack` and
//! `inspect`.

use crate::hull_arg;
use crate::pipeline;
use clap::Args;
use hydrofmu::bem::IrregularFrequencies;
use hydrofmu::fmu;
use hydrofmu::hull::Hull;
use hydrofmu::panels::PanelParams;
use hydrofmu::sweep::{self, SweepParams};
use hydrofmu::units::WaterDepth;
use std::path::PathBuf;

/// The hull and the sweep settings, shared by `fmu-pack sweep` and `fmu-pack fit`.
#[derive(Args, Debug, Clone)]
pub struct HullSweepArgs {
    /// The input, chosen by the file: `semicircle` or `circle` (built-in sections), a hull
    /// file (section XML, docs/HULL_FORMAT.md), a ship file (XML with a `<ship>` root, strip
    /// theory, docs/SHIPS.md), WAMIT files `NAME.1` (with `NAME.3` and `NAME.hst` beside) or a
    /// Capytaine NetCDF-3 dataset `NAME.nc` (imported 3D databases, docs/DATABASES.md).
    pub hull: String,
    /// Centre depth over radius H/R of the built-in circle (> 1; 0 gives the semicircle).
    #[arg(long = "depth", value_name = "H_OVER_R")]
    pub depth: Option<f64>,
    /// The water depth in metres (`inf`: deep water, the default), flat bottom; overrides a
    /// hull or ship file's `depth` attribute; for WAMIT files the depth they were computed in
    /// (docs/FINITE_DEPTH.md). Not the circle's `--depth`.
    #[arg(
        long = "water-depth",
        value_name = "METRES",
        allow_hyphen_values = true
    )]
    pub water_depth: Option<f64>,
    /// Radius R of the built-in hulls, in metres.
    #[arg(long, default_value_t = 1.0)]
    pub radius: f64,
    /// Panels on the wetted contour (default: 128, more for a submerged hull close to the
    /// surface; see docs/DESIGN-NOTES.md).
    #[arg(long)]
    pub panels: Option<usize>,
    /// Log-spaced grid of kR.
    #[arg(
        long,
        value_name = "MIN:MAX:COUNT",
        default_value = "0.01:10:201",
        allow_hyphen_values = true
    )]
    pub kr: String,
    /// Comma-separated DOFs to keep (default: all of the hull's).
    #[arg(long, value_name = "a,b,..")]
    pub dofs: Option<String>,
    /// Schilder et al.'s plain source method: do not remove irregular frequencies.
    #[arg(long)]
    pub plain: bool,
    /// Discretization levels (N, N/2, N/4, ...) extrapolated to zero panel size; 1 gives the
    /// plain N-panel result. Default 3 (a ship's sections with corners: 2, docs/SHIPS.md).
    #[arg(long)]
    pub levels: Option<usize>,
    /// Worker threads (at most 1024).
    #[arg(long, default_value_t = default_threads())]
    pub threads: usize,
    /// Ship files only: log-spaced grid of wave frequencies omega in rad/s (default: 100
    /// points from kR = 0.01 to 5, R the largest section half-beam).
    #[arg(long, value_name = "MIN:MAX:COUNT", allow_hyphen_values = true)]
    pub omega: Option<String>,
    /// Ship files only: wave headings in degrees, comma-separated (0 following seas, 90 from
    /// starboard towards port, 180 head seas). Default 0,45,90,135,180.
    #[arg(long, value_name = "DEG,DEG,..", allow_hyphen_values = true)]
    pub headings: Option<String>,
    /// Imported WAMIT files only: the length scale ULEN of their nondimensional values, in
    /// metres (default 1, as Capytaine and BEMRosetta write them).
    #[arg(long, value_name = "METRES")]
    pub length_scale: Option<f64>,
    /// Imported WAMIT files only: what their first column holds: `period` (s, WAMIT's
    /// default), `omega` (rad/s) or `hz` (default: what `NAME.cfg` beside them declares with
    /// `IPEROUT`, else the period).
    #[arg(long, value_name = "period|omega|hz")]
    pub frequency_column: Option<String>,
    /// Imported files only: their exciting force is in exp(-i omega t) (older HAMS builds):
    /// conjugate it.
    #[arg(long)]
    pub conjugate: bool,
}

impl HullSweepArgs {
    /// Refuses the options of imported databases for a section or a ship.
    pub fn refuse_import_options(&self) -> Result<(), String> {
        let given = [
            ("--length-scale", self.length_scale.is_some()),
            ("--frequency-column", self.frequency_column.is_some()),
            ("--conjugate", self.conjugate),
        ];
        match given.iter().find(|(_, g)| *g) {
            Some((flag, _)) => Err(format!(
                "{flag} applies to an imported database (NAME.1), not to '{}'",
                self.hull
            )),
            None => Ok(()),
        }
    }
}

/// One worker thread per core, within [`sweep::MAX_THREADS`].
fn default_threads() -> usize {
    std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(sweep::MAX_THREADS)
}

impl HullSweepArgs {
    /// The hull and the sweep parameters.
    pub fn resolve(&self) -> Result<(Hull, SweepParams), String> {
        self.refuse_import_options()?;
        if self.omega.is_some() || self.headings.is_some() {
            return Err(
                "--omega and --headings apply to ship files (docs/SHIPS.md); a \
                        section's grid is --kr"
                    .to_string(),
            );
        }
        let hull = hull_arg::resolve(&self.hull, self.radius, self.depth, self.dofs.as_deref())?;
        let params = SweepParams {
            kr: parse_grid(&self.kr)?,
            panels: panel_params(&hull, self.panels),
            irregular_frequencies: if self.plain {
                IrregularFrequencies::Keep
            } else {
                IrregularFrequencies::RemoveWithLid
            },
            extrapolation_levels: self
                .levels
                .unwrap_or(SweepParams::default().extrapolation_levels),
            threads: self.threads,
            excitation: true,
            depth: match self.water_depth {
                Some(metres) => WaterDepth::new(metres)
                    .map_err(|e| format!("--water-depth {metres}: {e} (`inf` for deep water)"))?,
                None => hull.water_depth(),
            },
        };
        Ok((hull, params))
    }
}

/// Arguments of `fmu-pack sweep`.
#[derive(Args, Debug, Clone)]
pub struct SweepArgs {
    /// The hull and the sweep settings.
    #[command(flatten)]
    pub sweep: HullSweepArgs,
    /// Output CSV file (`-` for standard output).
    #[arg(short = 'o', long = "output", value_name = "FILE.csv")]
    pub output: PathBuf,
    /// Also write the exciting force of regular waves from headings 0 and 180 (direct
    /// diffraction solve, checked by the Haskind relation), `kR,j,heading,re,im` with
    /// `X_j / (rho g a R^(1 + e_j))` (docs/WAVES.md).
    #[arg(long, value_name = "FILE.csv")]
    pub excitation: Option<PathBuf>,
    /// Also write the Froude-Krylov part of the exciting force alone, in the same format.
    #[arg(long = "froude-krylov", value_name = "FILE.csv")]
    pub froude_krylov: Option<PathBuf>,
    /// Also write the mean wave drift of the fixed section (docs/DRIFT.md), `kR,j,heading,value`
    /// with `D_j / (rho g R^e_j)`, `a^2 D_j` the mean force in DOF j of a regular wave of
    /// amplitude a (sections only).
    #[arg(long, value_name = "FILE.csv")]
    pub drift: Option<PathBuf>,
    /// Also write the floating section's motion per unit wave amplitude (docs/DRIFT.md),
    /// `kR,j,heading,re,im` with `xi_j R^e_j / a`, rigid DOFs (elastic DOFs held); needs the
    /// mass properties (the hull file's <mass>, or --mass, --cog and --gyradius), with which
    /// --drift gives the floating section's drift.
    #[arg(long, value_name = "FILE.csv")]
    pub rao: Option<PathBuf>,
    /// With --rao: add to the roll's damping Ikeda's viscous roll damping estimated from the
    /// section (docs/VISCOUS.md), linearized at this roll amplitude in degrees frequency by
    /// frequency, B_eq = B_l(omega) + 8/(3 pi) omega phi_a B_q; 0 keeps the linear parts
    /// (friction, bilge keels).
    #[arg(long, value_name = "DEG", requires = "rao")]
    pub viscous_amplitude: Option<f64>,
    /// The floating section's mass properties and moorings.
    #[command(flatten)]
    pub floating: FloatingArgs,
    /// Also write the hydrostatic restoring `C / (rho g)` of the DOFs (docs/HYDROSTATICS.md),
    /// `i,j,value` in SI per unit length (a ship: `C` itself, whole-ship SI, `i,j,c`).
    #[arg(long, value_name = "FILE.csv")]
    pub hydrostatics: Option<PathBuf>,
    /// Also write the tables as WAMIT files PREFIX.1, PREFIX.3 (with an exciting force) and
    /// PREFIX.hst, ULEN = 1 m; a section's per unit length, as a 1 m slice in beam seas
    /// (docs/DATABASES.md, "Export").
    #[arg(long, value_name = "PREFIX")]
    pub wamit: Option<PathBuf>,
    /// Also write the tables as a Capytaine dataset in NetCDF-3; a section's per unit length
    /// (docs/DATABASES.md, "Export").
    #[arg(long, value_name = "FILE.nc")]
    pub netcdf: Option<PathBuf>,
}

/// The mass properties and moorings of a floating section: each option replaces the field of
/// the hull file's `<mass>` element (docs/HULL_FORMAT.md); `--fixed` holds a section whose
/// file gives one.
#[derive(Args, Debug, Clone, Default)]
pub struct FloatingArgs {
    /// The floating section's mass per unit length (kg/m), or `displaced`: the displaced
    /// mass at rho = 1025 kg/m^3 (free floating). Replaces the hull file's <mass value>.
    #[arg(long, value_name = "KG_PER_M|displaced", allow_hyphen_values = true)]
    pub mass: Option<String>,
    /// Its centre of gravity `X,Y` (m; the hull's frame: y up, free surface at y = 0).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub cog: Option<String>,
    /// Its radius of gyration about the centre of gravity (m).
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub gyradius: Option<f64>,
    /// External (mooring) stiffness on rigid DOFs, per unit length: `DOF=VALUE,...` (N/m per m
    /// for sway and heave, N.m/rad per m for roll).
    #[arg(long, value_name = "DOF=K,..", allow_hyphen_values = true)]
    pub mooring: Option<String>,
    /// External (mooring) damping on rigid DOFs, per unit length: `DOF=VALUE,...` (N.s/m per
    /// m, N.m.s/rad per m).
    #[arg(
        long = "mooring-damping",
        value_name = "DOF=B,..",
        allow_hyphen_values = true
    )]
    pub mooring_damping: Option<String>,
    /// Hold the section fixed although its hull file gives <mass>.
    #[arg(long)]
    pub fixed: bool,
}

impl FloatingArgs {
    /// Whether any mass property or mooring is given (not `--fixed`).
    pub fn given(&self) -> bool {
        self.mass.is_some()
            || self.cog.is_some()
            || self.gyradius.is_some()
            || self.mooring.is_some()
            || self.mooring_damping.is_some()
    }
}

/// Parses `MIN:MAX:COUNT`.
pub fn parse_grid(text: &str) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let [min, max, count] = parts.as_slice() else {
        return Err(format!("--kr '{text}': expected MIN:MAX:COUNT"));
    };
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .map_err(|_| format!("--kr '{text}': '{s}' is not a number"))
    };
    let count = count
        .trim()
        .parse::<usize>()
        .map_err(|_| format!("--kr '{text}': COUNT '{count}' is not a positive integer"))?;
    sweep::log_grid(number(min)?, number(max)?, count).map_err(|e| pipeline::sweep_message(&e))
}

/// The panel parameters for `hull`: the automatic default, or the count given.
pub fn panel_params(hull: &Hull, panels: Option<usize>) -> PanelParams {
    let automatic = PanelParams::for_hull(hull);
    PanelParams {
        body_panels: panels.unwrap_or(automatic.body_panels),
        ..automatic
    }
}

/// Arguments of `fmu-pack pack`.
#[derive(Args, Debug, Clone)]
pub struct PackArgs {
    /// The hull and the sweep settings (as for `fmu-pack sweep`).
    #[command(flatten)]
    pub sweep: HullSweepArgs,
    /// Frequency band of the fit: `MIN:MAX` in kR, or `MIN:MAXrad/s` (default 0.05:5).
    #[arg(long, allow_hyphen_values = true)]
    pub band: Option<String>,
    /// Tolerance: largest error as a fraction of sqrt(|A_ii A_jj|) (default 0.01). A fit
    /// that misses it is an error and no archive is written, unless
    /// --allow-tolerance-miss.
    #[arg(long)]
    pub tol: Option<f64>,
    /// Write the archive even when the fit misses the tolerance (the summary and the
    /// archive's scene report say 'NOT met').
    #[arg(long)]
    pub allow_tolerance_miss: bool,
    /// Network order, fixed instead of the lowest that meets --tol: for one DOF's series
    /// chain its auxiliary DOFs; for the coupled network the poles per invariant block (a
    /// complex pair counted twice).
    #[arg(long)]
    pub order: Option<usize>,
    /// Largest communication step the master will use, in s: the band is cut at its
    /// Nyquist frequency pi / max-step.
    #[arg(long, value_name = "SECONDS")]
    pub max_step: Option<f64>,
    /// Use this network file instead of computing one.
    #[arg(long)]
    pub network: Option<PathBuf>,
    /// Keep A_inf inside the FMU: acceleration inputs, force includes -A_inf a.
    #[arg(long)]
    pub keep_inf_mass: bool,
    /// Give the FMU the mean wave drift (docs/DRIFT.md): parameter `wave.drift` (0 none, 1
    /// mean, 2 slow drift by Newman's approximation) and outputs `force_drift.<dof>`. A
    /// section's drift from its sweep (floating with the hull file's <mass> or the options
    /// below, else fixed); an imported database's from NAME.8 or NAME.9.
    #[arg(long)]
    pub drift: bool,
    /// The floating section whose drift --drift packs.
    #[command(flatten)]
    pub floating: FloatingArgs,
    /// Viscous damping and current (`--viscous`, `--damping-linear`, `--damping-quadratic`).
    #[command(flatten)]
    pub viscous: crate::viscous_args::ViscousArgs,
    /// Output archive (.fmu).
    #[arg(short = 'o', long)]
    pub output: PathBuf,
    /// The hydrofmu shared library to pack (default: HYDROFMU_BINARY, then next to
    /// fmu-pack, building it if fmu-pack runs from this workspace).
    #[arg(long)]
    pub binary: Option<PathBuf>,
    /// The Windows x86_64 DLL to pack too, as binaries/win64 (FMI 2.0) or
    /// binaries/x86_64-windows (FMI 3.0) (default: hydrofmu.dll next to the Linux library).
    #[arg(long)]
    pub binary_windows: Option<PathBuf>,
    /// Pack no Windows DLL, even when one is next to the Linux library.
    #[arg(long, conflicts_with = "binary_windows")]
    pub no_windows: bool,
    /// modelIdentifier (default: from the output file name).
    #[arg(long)]
    pub model_identifier: Option<String>,
    /// FMI version of the archive: 2 (default; OSP's libcosim reads 2.0 only) or 3 (the same
    /// FMU through the fmi3 functions, matrices as array variables).
    #[arg(long = "fmi", value_enum, default_value_t = FmiVersion::V2)]
    pub fmi: FmiVersion,
}

/// The FMI version of an archive.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FmiVersion {
    /// FMI 2.0: `binaries/linux64/`, fmi2 functions.
    #[default]
    #[value(name = "2")]
    V2,
    /// FMI 3.0: `binaries/x86_64-linux/`, fmi3 functions.
    #[value(name = "3")]
    V3,
}

impl From<FmiVersion> for fmu::FmiVersion {
    fn from(version: FmiVersion) -> Self {
        match version {
            FmiVersion::V2 => fmu::FmiVersion::V2,
            FmiVersion::V3 => fmu::FmiVersion::V3,
        }
    }
}

/// Arguments of `fmu-pack inspect`.
#[derive(Args, Debug, Clone)]
pub struct InspectArgs {
    /// The archive to inspect.
    pub fmu: PathBuf,
}

impl SweepArgs {
    /// Whether any option of a floating section is given.
    pub fn floats(&self) -> bool {
        self.rao.is_some() || self.floating.given()
    }
}
