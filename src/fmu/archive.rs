//! The `.fmu` archive: one body, one network, a Linux binary (and a Windows one when given), in
//! either FMI standard.
//!
//! Archive layout (zip, deflate, forward slashes, no links, no zip64), in this member order:
//!
//! ```text
//! modelDescription.xml
//! binaries/linux64/<modelIdentifier>.so       the hydrofmu cdylib (FMI 2.0)
//! binaries/x86_64-linux/<modelIdentifier>.so  the same library (FMI 3.0)
//! binaries/win64/<modelIdentifier>.dll        the Windows x86_64 build, when given (FMI 2.0)
//! binaries/x86_64-windows/<modelIdentifier>.dll  the same (FMI 3.0)
//! resources/network.xml                       the equivalent network
//! resources/options.xml                       flags (keep_inf_mass)
//! resources/hull.xml                          when the hull is known (a section)
//! resources/excitation.csv                    the exciting force, when swept or imported
//! resources/hydrostatics.csv                  the restoring of a whole body
//! resources/drift.csv                         the mean drift table, when packed with one
//! resources/viscous.csv                       the viscous damping, when packed with it
//! resources/crossflow.csv                     a ship's cross-flow strips, when packed with them
//! documentation/index.html                    summary, coefficients, variables, reports
//! documentation/plots/fit-<i>-<j>.svg         fit against data, when given
//! documentation/scene.txt                     the scene or fit report, when given
//! extra/com.open-simulation-platform/<modelName>_OspModelDescription.xml
//! ```
//!
//! The GUID is that of the packed resources ([`Resources::guid`]), so two hulls (or two
//! networks, or two flag sets) never share one, and the FMU checks it at instantiation. The
//! bytes depend only on the inputs: every member has the zip's default timestamp and mode 0644.
//!
//! ```
//! use hydrofmu::database::import::{self, ImportParams};
//! use hydrofmu::fmu::{Archive, Body, FmiVersion, PackedNetwork, SceneDocumentation};
//! use hydrofmu::scene::BodyScene;
//! use hydrofmu::{Hull, PanelParams, Scene, SweepParams};
//! use std::path::Path;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let dir = std::env::temp_dir().join(format!("hydrofmu-archive-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! // A stand-in for the hydrofmu shared library (`target/release/libhydrofmu.so`).
//! let binary = b"\x7fELF stand-in".to_vec();
//!
//! // A section: the built-in semicircle, swept coarsely (few panels and frequencies).
//! let hull = Hull::semicircle(1.0)?.select_dofs(&["sway", "heave"])?;
//! let scene = Scene {
//!     sweep: SweepParams {
//!         kr: (0..12).map(|k| 0.04 * 1.6f64.powi(k)).collect(),
//!         panels: PanelParams { body_panels: 24, ..PanelParams::default() },
//!         extrapolation_levels: 1,
//!         ..SweepParams::default()
//!     },
//!     ..Scene::new(hull.clone())
//! }
//! .build()?;
//! let sweep = scene.sweep(&|_done, _total| {})?;
//! let fit = scene.fit(&scene.response(&sweep)?)?;
//! let body = Body::section(&hull);
//! let network = PackedNetwork::from_network(fit.network);
//! Archive::new(body, network, "Semicircle", binary.clone())
//!     .build()?
//!     .write(&dir.join("Semicircle.fmu"))?;
//!
//! // A 3D database: WAMIT files, fitted over all their frequencies by the whole-body scene,
//! // whose report goes into documentation/scene.txt.
//! let database = import::import(Path::new("tests/data/wamit/sphere.1"), &ImportParams::new())?;
//! let fitted = BodyScene::new(database).fit()?;
//! let body = Body::whole(&fitted.database, None)?;
//! let network = PackedNetwork::from_network(fitted.fit.network.clone());
//! let mut archive = Archive::new(body, network, "Sphere", binary);
//! archive.scene = Some(SceneDocumentation { scene: fitted.scene_text(), ..Default::default() });
//! archive.fmi = FmiVersion::V3;
//! let packed = archive.build()?;
//! let osp = packed.write(&dir.join("Sphere.fmu"))?;
//! assert!(dir.join("Sphere.fmu").is_file());
//! assert_eq!(osp, Some(dir.join("hydrofmu Sphere_OspModelDescription.xml")));
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok(())
//! # }
//! ```

use super::description::FIXED_XML;
use super::{osp, DescriptionInfo, DofUnit, Extent, Layout, Resources};
use crate::database::Database;
use crate::hull::Hull;
use crate::model::viscous::{parse_csv, write_csv, Frame, Viscous};
use crate::model::{Model, ModelOptions};
use crate::network::Network;
use crate::sweep::{ExcitationPart, SweepResult};
use crate::xml::escape;
use nalgebra::{DMatrix, DVector};
use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The scene report inside the archive (plain text).
pub const SCENE_FILE: &str = "documentation/scene.txt";
/// Largest FMU library accepted (256 MiB; the release build is under 1 MB, a debug build 17 MB).
pub const MAX_BINARY_BYTES: u64 = 256 << 20;
/// The first bytes of a Windows DLL (a PE file's DOS header).
const WINDOWS_BINARY_MAGIC: &[u8] = b"MZ";

/// Why an archive cannot be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArchiveError(pub String);

impl fmt::Display for ArchiveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ArchiveError {}

impl From<String> for ArchiveError {
    fn from(s: String) -> Self {
        ArchiveError(s)
    }
}

impl From<&str> for ArchiveError {
    fn from(s: &str) -> Self {
        ArchiveError(s.to_string())
    }
}

/// The FMI standard of an archive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FmiVersion {
    /// FMI 2.0: `binaries/linux64/`, fmi2 functions.
    #[default]
    V2,
    /// FMI 3.0: `binaries/x86_64-linux/`, fmi3 functions, matrices as array variables.
    V3,
}

impl FmiVersion {
    /// The folder of the Linux binary under `binaries/`.
    pub fn platform(self) -> &'static str {
        match self {
            FmiVersion::V2 => "linux64",
            FmiVersion::V3 => "x86_64-linux",
        }
    }

    /// The folder of the Windows x86_64 binary under `binaries/`.
    pub fn windows_platform(self) -> &'static str {
        match self {
            FmiVersion::V2 => "win64",
            FmiVersion::V3 => "x86_64-windows",
        }
    }
}

/// What the archive needs to know about the body: a hull section or a whole body.
#[derive(Clone, Debug)]
pub struct Body {
    /// Name (shown in the model description and the documentation).
    pub name: String,
    /// DOFs with their units, in the body's order.
    pub dofs: Vec<DofUnit>,
    /// Canonical hull file text, packed as `resources/hull.xml`.
    pub xml: Option<String>,
    /// Forces per unit length (a section) or of the whole body (a ship, a database).
    pub extent: Extent,
    /// The restoring table, packed as `resources/hydrostatics.csv` (a whole body).
    pub hydrostatics_csv: Option<String>,
    /// The exciting force table, packed as `resources/excitation.csv`.
    pub excitation_csv: Option<String>,
    /// The mean drift table, packed as `resources/drift.csv` ([`Body::with_sweep_drift`]).
    pub drift_csv: Option<String>,
    /// Viscous damping `(B_l, B_q)` in the body's DOF order ([`Body::with_viscous`]).
    pub viscous: Option<(DMatrix<f64>, DVector<f64>)>,
    /// A ship's cross-flow strips, packed as `resources/crossflow.csv` ([`Body::with_crossflow`]).
    pub crossflow_csv: Option<String>,
    /// A fit report for the documentation and `documentation/scene.txt` (a whole body).
    pub report: Option<String>,
}

/// `name` with its first letter capitalized.
fn capitalized(name: &str) -> String {
    let mut name = name.to_string();
    if let Some(first) = name.get_mut(0..1) {
        first.make_ascii_uppercase();
    }
    name
}

impl Body {
    /// A hull section (no exciting force: see [`Body::with_sweep_excitation`]).
    pub fn section(hull: &Hull) -> Body {
        Body {
            name: capitalized(hull.name()),
            dofs: hull.dof_units(),
            xml: Some(hull.to_xml_string()),
            extent: Extent::PerUnitLength,
            hydrostatics_csv: None,
            excitation_csv: None,
            drift_csv: None,
            viscous: None,
            crossflow_csv: None,
            report: None,
        }
    }

    /// A whole body from its database (a ship's strip theory, an import), with its restoring
    /// and exciting force tables; `report` is its fit report.
    pub fn whole(database: &Database, report: Option<String>) -> Result<Body, ArchiveError> {
        let excitation_csv = if database.excitation.is_empty() {
            None
        } else {
            let mut excitation = Vec::new();
            database
                .write_excitation_table(&mut excitation)
                .map_err(|e| format!("cannot format the excitation table: {e}"))?;
            Some(String::from_utf8_lossy(&excitation).into_owned())
        };
        Ok(Body {
            name: capitalized(&database.name),
            dofs: database.dof_units.clone(),
            xml: None,
            extent: Extent::WholeBody,
            hydrostatics_csv: Some(
                database
                    .hydrostatics_table()
                    .to_csv(&database.name, "whole body"),
            ),
            excitation_csv,
            drift_csv: None,
            viscous: None,
            crossflow_csv: None,
            report,
        })
    }

    /// The section's exciting force from its sweep, for the DOFs `names` (those of the
    /// network).
    pub fn with_sweep_excitation(
        mut self,
        sweep: &SweepResult,
        names: &[String],
    ) -> Result<Body, ArchiveError> {
        let sweep = sweep_of(sweep, names)?;
        let mut text = Vec::new();
        sweep
            .write_excitation_csv(&mut text, ExcitationPart::Total)
            .map_err(|e| format!("cannot format the excitation table: {e}"))?;
        self.excitation_csv = Some(String::from_utf8_lossy(&text).into_owned());
        Ok(self)
    }

    /// The section's mean drift table from its sweep ([`SweepResult::write_drift_csv`]), for
    /// the DOFs `names` (those of the network): the FMU gets `wave.drift` and `force_drift`.
    pub fn with_sweep_drift(
        mut self,
        sweep: &SweepResult,
        names: &[String],
    ) -> Result<Body, ArchiveError> {
        let sweep = sweep_of(sweep, names)?;
        if sweep.excitation.iter().all(|forces| forces.drift.is_none()) {
            return Err("the sweep has no drift force (no frequency solved with it)"
                .to_string()
                .into());
        }
        let mut text = Vec::new();
        sweep
            .write_drift_csv(&mut text)
            .map_err(|e| format!("cannot format the drift table: {e}"))?;
        self.drift_csv = Some(String::from_utf8_lossy(&text).into_owned());
        Ok(self)
    }
}

impl Body {
    /// As [`Body::with_sweep_drift`], for the section floating as `floating` (described by
    /// `description`, e.g. [`crate::motion::MassProperties`]'s line): its motion is of the whole
    /// swept hull, its drift table holds the DOFs `names` (the network's).
    ///
    /// # Errors
    /// As [`Body::with_sweep_drift`], and a motion that cannot be computed.
    pub fn with_floating_drift(
        mut self,
        sweep: &SweepResult,
        names: &[String],
        floating: &crate::motion::Floating,
        description: &str,
    ) -> Result<Body, ArchiveError> {
        let selected = sweep_of(sweep, names)?;
        let rows: Vec<usize> = names
            .iter()
            .filter_map(|n| sweep.dof_names.iter().position(|d| d == n))
            .collect();
        let drift = floating
            .sweep_drift(sweep)
            .map_err(|e| format!("the floating drift: {e}"))?;
        // Every frequency has its drift: `sweep_drift` refuses a sweep without.
        let values: Vec<(f64, nalgebra::DMatrix<f64>)> = sweep
            .kr
            .iter()
            .zip(drift)
            .map(|(kr, d)| (*kr, d.select_rows(&rows)))
            .collect();
        if values.is_empty() {
            return Err("the sweep has no drift force (no frequency solved with it)"
                .to_string()
                .into());
        }
        let mut text = Vec::new();
        selected
            .write_drift_values(&mut text, &format!("floating; {description}"), &values)
            .map_err(|e| format!("cannot format the drift table: {e}"))?;
        self.drift_csv = Some(String::from_utf8_lossy(&text).into_owned());
        Ok(self)
    }

    /// The body with viscous damping `-B_l v_r - B_q |v_r| v_r` (`linear` n x n, `quadratic`
    /// n, in the body's DOF order; docs/CURRENT.md): the FMU gets `damping_linear`,
    /// `damping_quadratic` (start values these), `current.speed`, `current.heading` and
    /// `force_viscous`. Coefficients that are not finite, negative or not positive
    /// semidefinite are refused, naming the parameter.
    pub fn with_viscous(
        mut self,
        linear: DMatrix<f64>,
        quadratic: DVector<f64>,
    ) -> Result<Body, ArchiveError> {
        let names: Vec<String> = self.dofs.iter().map(|d| d.name.clone()).collect();
        Viscous::new(&names, self.frame(), linear.clone(), quadratic.clone())?;
        self.viscous = Some((linear, quadratic));
        Ok(self)
    }

    /// The whole body (with viscous damping, [`Body::with_viscous`] first) with a ship's
    /// cross-flow strips (docs/CURRENT.md): the FMU adds their drag to `force_viscous` and
    /// gets `crossflow.drag_scale`.
    pub fn with_crossflow(
        mut self,
        strips: &[crate::model::crossflow::Strip],
    ) -> Result<Body, ArchiveError> {
        if self.viscous.is_none() || self.frame() != Frame::Body {
            return Err("cross-flow strips need a whole body with viscous damping".into());
        }
        let text = crate::model::crossflow::write_csv(strips);
        crate::model::crossflow::parse_csv(&text)?;
        self.crossflow_csv = Some(text);
        Ok(self)
    }

    /// Where the body's translations point for the current: a section's sway along x, a
    /// whole body's surge along x and sway along y.
    fn frame(&self) -> Frame {
        match self.extent {
            Extent::PerUnitLength => Frame::Section,
            Extent::WholeBody => Frame::Body,
        }
    }

    /// `resources/viscous.csv` for the network's DOFs `names` (a subset of the body's).
    fn viscous_csv(&self, names: &[String]) -> Result<Option<String>, ArchiveError> {
        let Some((linear, quadratic)) = &self.viscous else {
            return Ok(None);
        };
        let index = names
            .iter()
            .map(|n| {
                self.dofs.iter().position(|d| &d.name == n).ok_or_else(|| {
                    format!("viscous damping: the network's DOF '{n}' is not the body's")
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let k = index.len();
        let linear = DMatrix::from_fn(k, k, |i, j| linear[(index[i], index[j])]);
        let quadratic = DVector::from_fn(k, |i, _| quadratic[index[i]]);
        Ok(Some(write_csv(names, self.frame(), &linear, &quadratic)))
    }
}

/// `sweep` restricted to the DOFs `names` (those of the network).
fn sweep_of(sweep: &SweepResult, names: &[String]) -> Result<SweepResult, ArchiveError> {
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    sweep.select_dofs(&names).ok_or_else(|| {
        format!(
            "the sweep has no exciting force for the DOFs {}",
            names.join(" ")
        )
        .into()
    })
}

/// The network to pack and the text of its `resources/network.xml`.
#[derive(Clone, Debug)]
pub struct PackedNetwork {
    network: Network,
    xml: String,
}

impl PackedNetwork {
    /// A network file's text, parsed once and packed verbatim (`source` names it in errors).
    pub fn from_text(xml: String, source: &str) -> Result<PackedNetwork, ArchiveError> {
        let network = Network::from_xml_str(&xml, source).map_err(|e| e.to_string())?;
        Ok(PackedNetwork { network, xml })
    }

    /// A computed network, packed in its canonical text.
    pub fn from_network(network: Network) -> PackedNetwork {
        let xml = network.to_xml_string();
        PackedNetwork { network, xml }
    }

    /// The network.
    pub fn network(&self) -> &Network {
        &self.network
    }
}

/// The documentation of a scene: its report, the fit report and the fit's figures.
#[derive(Clone, Debug, Default)]
pub struct SceneDocumentation {
    /// The scene report (packed as [`SCENE_FILE`]).
    pub scene: String,
    /// The fit report (its section of the index left out when empty: a whole body's scene
    /// report holds its fit).
    pub fit: String,
    /// `(file name, SVG)` figures, packed under `documentation/plots/`.
    pub plots: Vec<(String, String)>,
}

/// Everything an archive holds; [`Archive::build`] makes its bytes.
#[derive(Clone, Debug)]
pub struct Archive {
    /// The body.
    pub body: Body,
    /// Its network.
    pub network: PackedNetwork,
    /// Keep A_inf inside the FMU: acceleration inputs, the force includes `-A_inf a`.
    pub keep_inf_mass: bool,
    /// modelIdentifier (the binary's name in the archive).
    pub model_identifier: String,
    /// The FMI standard.
    pub fmi: FmiVersion,
    /// The hydrofmu shared library's bytes ([`read_binary`]).
    pub binary: Vec<u8>,
    /// The Windows x86_64 DLL's bytes, built from the same sources (`tools/build-windows.sh`).
    pub binary_windows: Option<Vec<u8>>,
    /// The scene's documentation, when a scene computed the network.
    pub scene: Option<SceneDocumentation>,
}

/// A built archive: its bytes and what it declares.
#[derive(Clone, Debug)]
pub struct Packed {
    /// The zip archive.
    pub bytes: Vec<u8>,
    /// GUID (FMI 3.0: instantiation token).
    pub guid: String,
    /// modelName.
    pub model_name: String,
    /// DOF names, in the network's order.
    pub dofs: Vec<String>,
    /// Length of the network's state vector.
    pub states: usize,
    /// The OSP model description (also inside the archive).
    pub osp_description: String,
    /// The text of [`SCENE_FILE`], when there is one.
    pub scene: Option<String>,
    /// The platforms the archive carries a binary for (folders under `binaries/`).
    pub platforms: Vec<String>,
}

impl Packed {
    /// Writes the archive to `path` and the OSP model description beside it
    /// ([`osp::path_beside`]); returns the description's path. Each file goes to a temporary
    /// file first and is renamed into place.
    pub fn write(&self, path: &Path) -> Result<Option<PathBuf>, ArchiveError> {
        write_renamed(path, &self.bytes)?;
        let beside = osp::path_beside(path, &self.model_name);
        if let Some(beside) = &beside {
            write_renamed(beside, self.osp_description.as_bytes())?;
        }
        Ok(beside)
    }
}

fn write_renamed(path: &Path, bytes: &[u8]) -> Result<(), ArchiveError> {
    let mut temporary = path.as_os_str().to_owned();
    temporary.push(format!(".{}.part", std::process::id()));
    let temporary = PathBuf::from(temporary);
    let err = |e: std::io::Error| ArchiveError(format!("cannot write {}: {e}", path.display()));
    std::fs::write(&temporary, bytes).map_err(err)?;
    std::fs::rename(&temporary, path).map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        err(e)
    })
}

/// Reads the hydrofmu shared library to pack, up to [`MAX_BINARY_BYTES`].
pub fn read_binary(path: &Path) -> Result<Vec<u8>, ArchiveError> {
    crate::input::read_bounded(path, MAX_BINARY_BYTES, "MAX_BINARY_BYTES")
        .map_err(|e| ArchiveError(format!("cannot read the binary {}: {e}", path.display())))
}

/// A modelIdentifier from a file name: letters, digits and `_`, starting with a letter.
pub fn identifier_from_path(path: &Path) -> String {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut id: String = stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if !id.starts_with(|c: char| c.is_ascii_alphabetic()) {
        id.insert_str(0, "hydrofmu_");
    }
    id
}

impl Archive {
    /// An FMI 2.0 archive of `network` for `body`, A_inf outside, without a scene.
    pub fn new(
        body: Body,
        network: PackedNetwork,
        model_identifier: &str,
        binary: Vec<u8>,
    ) -> Archive {
        Archive {
            body,
            network,
            keep_inf_mass: false,
            model_identifier: model_identifier.to_string(),
            fmi: FmiVersion::V2,
            binary,
            binary_windows: None,
            scene: None,
        }
    }

    /// The water depth of the packed tables: the excitation and drift tables must agree.
    pub fn depth(&self) -> Result<crate::units::WaterDepth, ArchiveError> {
        let resources = Resources::with_options(String::new(), None, false)
            .with_excitation(self.body.excitation_csv.clone())
            .with_drift(self.body.drift_csv.clone());
        resources_depth(&resources)
    }

    /// The archive's bytes, after checking that its resources instantiate.
    pub fn build(&self) -> Result<Packed, ArchiveError> {
        let body = &self.body;
        let keep_inf_mass = self.keep_inf_mass;
        let resources =
            Resources::with_options(self.network.xml.clone(), body.xml.clone(), keep_inf_mass)
                .with_excitation(body.excitation_csv.clone())
                .with_hydrostatics(body.hydrostatics_csv.clone())
                .with_drift(body.drift_csv.clone())
                .with_viscous(body.viscous_csv(&self.network.network.dof_names)?)
                .with_crossflow(body.crossflow_csv.clone());
        // The GUID is that of the packed texts.
        let guid = resources.guid();
        let options = ModelOptions {
            keep_inf_mass,
            guid: Some(guid.clone()),
        };
        let model = Model::new(&self.network.network, options).map_err(|e| e.to_string())?;
        let mut units = Vec::new();
        for name in model.dof_names() {
            let unit = body.dofs.iter().find(|d| &d.name == name).ok_or_else(|| {
                format!(
                    "the network's DOF '{name}' is not a DOF of hull '{}' ({})",
                    body.name,
                    body.dofs
                        .iter()
                        .map(|d| d.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })?;
            units.push(unit.clone());
        }
        let mut layout =
            Layout::with_extent(units, keep_inf_mass, body.extent).map_err(|e| e.to_string())?;
        if let Some(text) = &resources.drift_csv {
            crate::model::drift_table(text, model.dof_names()).map_err(|e| e.to_string())?;
            layout = layout.with_drift().map_err(|e| e.to_string())?;
        }
        if let Some(text) = &resources.viscous_csv {
            let (_, linear, quadratic) = parse_csv(text, model.dof_names())?;
            layout = layout
                .with_viscous(&linear, &quadratic)
                .map_err(|e| e.to_string())?;
            if resources.crossflow_csv.is_some() {
                layout = layout.with_crossflow().map_err(|e| e.to_string())?;
            }
        }
        if let crate::units::WaterDepth::Finite(depth) = resources_depth(&resources)? {
            layout = layout.with_depth(depth).map_err(|e| e.to_string())?;
        }
        let system = model.system();
        let model_name = format!("hydrofmu {}", body.name);
        let osp_description = osp::model_description(&layout);
        let info = DescriptionInfo {
            model_identifier: self.model_identifier.clone(),
            guid: guid.clone(),
            model_name: Some(model_name.clone()),
            description: Some(format!(
                "Hydrodynamic radiation forces on hull '{}' (DOFs {}), equivalent \
                 mass-spring-damper network with {} states",
                body.name,
                model.dof_names().join(", "),
                model.network_states()
            )),
            damping_direct: Some(system.damping_direct().clone()),
            added_mass_inf: Some(system.added_mass_inf().clone()),
        };
        let description = match self.fmi {
            FmiVersion::V2 => layout.model_description(FIXED_XML, &info),
            FmiVersion::V3 => layout.model_description_fmi3(FIXED_XML, &info),
        }
        .map_err(|e| e.to_string())?;
        let mut html = documentation(body, &layout, &model, &guid, keep_inf_mass);
        if let Some(report) = &body.report {
            let section = format!("<h2>Fit report</h2>\n<pre>{}</pre>\n", escape(report));
            html = before_body_end(html, &section);
        }
        let mut plot_entries = Vec::new();
        let mut scene_entry = body.report.clone();
        if let Some(scene) = &self.scene {
            let mut section = format!(
                "<h2>Scene: what this FMU models and leaves out</h2>\n<pre>{}</pre>\n",
                escape(&scene.scene)
            );
            if !scene.fit.is_empty() {
                section += &format!("<h2>Fit report</h2>\n<pre>{}</pre>\n", escape(&scene.fit));
            }
            scene_entry = Some(scene.scene.clone());
            for (name, svg) in &scene.plots {
                section += &format!("<p><img src=\"plots/{name}\" alt=\"{name}\"></p>\n");
                plot_entries.push((
                    format!("documentation/plots/{name}"),
                    svg.clone().into_bytes(),
                ));
            }
            html = before_body_end(html, &section);
        }

        let id = &self.model_identifier;
        let mut binaries = vec![(self.fmi.platform(), format!("{id}.so"), &self.binary)];
        if let Some(dll) = &self.binary_windows {
            if !dll.starts_with(WINDOWS_BINARY_MAGIC) {
                return Err("the Windows binary is not a DLL (no MZ header)".into());
            }
            binaries.push((self.fmi.windows_platform(), format!("{id}.dll"), dll));
        }
        let platforms = binaries.iter().map(|(p, ..)| p.to_string()).collect();
        let mut entries: Vec<(String, Vec<u8>)> =
            vec![("modelDescription.xml".into(), description.into_bytes())];
        for (platform, file, bytes) in binaries {
            entries.push((format!("binaries/{platform}/{file}"), bytes.clone()));
        }
        entries.extend([
            (
                format!("resources/{}", Resources::NETWORK_FILE),
                resources.network_xml.clone().into_bytes(),
            ),
            (
                format!("resources/{}", Resources::OPTIONS_FILE),
                resources.options_xml.clone().into_bytes(),
            ),
        ]);
        let optional = [
            (Resources::HULL_FILE, &resources.hull_xml),
            (Resources::EXCITATION_FILE, &resources.excitation_csv),
            (Resources::HYDROSTATICS_FILE, &resources.hydrostatics_csv),
            (Resources::DRIFT_FILE, &resources.drift_csv),
            (Resources::VISCOUS_FILE, &resources.viscous_csv),
            (Resources::CROSSFLOW_FILE, &resources.crossflow_csv),
        ];
        for (file, text) in optional {
            if let Some(text) = text {
                entries.push((format!("resources/{file}"), text.clone().into_bytes()));
            }
        }
        entries.push(("documentation/index.html".into(), html.into_bytes()));
        entries.extend(plot_entries);
        if let Some(text) = &scene_entry {
            entries.push((SCENE_FILE.into(), format!("{text}\n").into_bytes()));
        }
        if let Some(name) = osp::file_name(&model_name) {
            let path = format!("{}/{name}", osp::ARCHIVE_DIR);
            entries.push((path, osp_description.clone().into_bytes()));
        }
        // What the archive holds must instantiate: load its resources as an instance does.
        Model::from_resources(&resources)
            .map_err(|e| format!("the archive would not instantiate: {e}"))?;
        Ok(Packed {
            bytes: zip_archive(&entries)?,
            guid,
            model_name,
            dofs: model.dof_names().to_vec(),
            states: model.network_states(),
            osp_description,
            scene: scene_entry,
            platforms,
        })
    }
}

/// `html` with `section` inserted before `</body>` (appended without one).
fn before_body_end(html: String, section: &str) -> String {
    match html.rfind("</body>") {
        Some(at) => format!("{}{section}{}", &html[..at], &html[at..]),
        None => html + section,
    }
}

/// The zip's bytes: deflate, mode 0644, no zip64, the members in the given order.
fn zip_archive(entries: &[(String, Vec<u8>)]) -> Result<Vec<u8>, ArchiveError> {
    use zip::write::SimpleFileOptions;
    let err = |e: &dyn fmt::Display| ArchiveError(format!("cannot zip the archive: {e}"));
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644)
        .large_file(false);
    for (path, bytes) in entries {
        if path.contains('\\') || path.starts_with('/') || path.contains("..") {
            return Err(ArchiveError(format!("bad archive path {path}")));
        }
        zip.start_file(path.as_str(), options)
            .map_err(|e| err(&e))?;
        zip.write_all(bytes).map_err(|e| err(&e))?;
    }
    Ok(zip.finish().map_err(|e| err(&e))?.into_inner())
}

fn matrix_table(title: &str, names: &[String], m: &nalgebra::DMatrix<f64>) -> String {
    let mut t = format!("<h3>{}</h3>\n<table>\n<tr><th></th>", escape(title));
    for n in names {
        t += &format!("<th>{}</th>", escape(n));
    }
    t += "</tr>\n";
    for (i, n) in names.iter().enumerate() {
        t += &format!("<tr><th>{}</th>", escape(n));
        for j in 0..names.len() {
            t += &format!("<td>{:.6e}</td>", m[(i, j)]);
        }
        t += "</tr>\n";
    }
    t + "</table>\n"
}

fn documentation(
    body: &Body,
    layout: &Layout,
    model: &Model,
    guid: &str,
    keep_inf_mass: bool,
) -> String {
    let system = model.system();
    let mut rows = String::new();
    for v in layout.variables() {
        rows += &format!(
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape(&v.name),
            v.value_reference,
            v.causality.as_str(),
            escape(v.unit),
            escape(&v.description)
        );
    }
    let usage = if keep_inf_mass {
        "The force includes -A_inf a: connect the hull accelerations to <code>acceleration.&lt;dof&gt;</code>."
    } else {
        "Add <code>added_mass_inf</code> to the hull's mass matrix; the force excludes -A_inf q''."
    };
    format!(
        r#"<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>hydrofmu {name}</title>
<style>body{{font-family:sans-serif;max-width:60em;margin:2em auto}}table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}}td:first-child{{text-align:left}}</style>
</head><body>
<h1>hydrofmu: hull {name}</h1>
<p>FMI 2.0 co-simulation unit giving the hydrodynamic radiation force on the {body} ({extent}),
from an equivalent mass-spring-damper network stepped exactly over each communication step.
Conventions: {axes}; force = force on the hull by the water.</p>
<ul>
<li>GUID: <code>{guid}</code></li>
<li>DOFs: {dofs}</li>
<li>Network states: {states}</li>
<li>{usage}</li>
<li>Power = -force_radiation . velocity (delivered to the water through the radiated waves; the exciting force's work is not in it); energy = energy stored in the network.</li>
<li>rho and g (fixed parameters) rescale the network exactly.</li>
</ul>
<h2>Coefficients at rho = {rho}, g = {g}</h2>
{a_inf}{damping}
<h2>Variables</h2>
<table><tr><th>name</th><th>value reference</th><th>causality</th><th>unit</th><th>description</th></tr>
{rows}</table>
</body></html>
"#,
        name = escape(&body.name),
        body = match body.extent {
            Extent::PerUnitLength => "hull section",
            Extent::WholeBody => "whole ship (strip theory, docs/SHIPS.md)",
        },
        extent = body.extent.words(),
        axes = match body.extent {
            Extent::PerUnitLength => "x right, y up, free surface y = 0",
            Extent::WholeBody => "x forward, y to port, z up, origin on the free surface",
        },
        guid = escape(guid),
        dofs = escape(&model.dof_names().join(", ")),
        states = model.network_states(),
        usage = usage,
        rho = system.rho(),
        g = system.g(),
        a_inf = matrix_table("added_mass_inf", model.dof_names(), system.added_mass_inf()),
        damping = matrix_table("damping_direct", model.dof_names(), system.damping_direct()),
        rows = rows,
    )
}

#[cfg(test)]
mod drift_tests;
#[cfg(test)]
mod tests;

/// The water depth of the resources' excitation and drift tables: one depth for both, else an
/// error naming both files.
fn resources_depth(resources: &Resources) -> Result<crate::units::WaterDepth, ArchiveError> {
    let excitation_name = format!("resources/{}", Resources::EXCITATION_FILE);
    let drift_name = format!("resources/{}", Resources::DRIFT_FILE);
    let excitation = match &resources.excitation_csv {
        Some(text) => Some(
            crate::waves::ExcitationTable::from_csv_str(text, &excitation_name)
                .map_err(|e| e.to_string())?,
        ),
        None => None,
    };
    let drift = match &resources.drift_csv {
        Some(text) => Some(
            crate::waves::DriftTable::from_csv_str(text, &drift_name).map_err(|e| e.to_string())?,
        ),
        None => None,
    };
    Ok(crate::model::tables_depth(
        excitation.as_ref().map(|t| (t, excitation_name.as_str())),
        drift.as_ref().map(|t| (t, drift_name.as_str())),
    )?)
}
