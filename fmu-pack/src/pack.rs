//! `fmu-pack pack` and `fmu-pack inspect`: one `.fmu` archive per hull.
//!
//! Archive layout (zip, deflate, forward slashes, no links, no zip64):
//!
//! ```text
//! modelDescription.xml
//! binaries/linux64/<modelIdentifier>.so    copy of the hydrofmu cdylib (FMI 2.0)
//! binaries/x86_64-linux/<modelIdentifier>.so  the same library (FMI 3.0, `--fmi 3`)
//! resources/network.xml                    the equivalent network
//! resources/options.xml                    flags (keep_inf_mass)
//! resources/hull.xml                       when the hull is known
//! documentation/index.html                 summary
//! ```
//!
//! The GUID is derived from the resources ([`hydrofmu::model::Resources::guid`]), so two
//! hulls (or two networks, or two flag sets) never share one, and the FMU checks it at
//! instantiation.

use crate::pipeline::{self, Built, HullInfo};
use crate::scene::SceneText;
use crate::sweep_cmd::HullSweepArgs;
use hydrofmu::fmu::description::FIXED_XML;
use hydrofmu::fmu::{DescriptionInfo, Extent, Layout, Resources};
use hydrofmu::model::{Model, ModelOptions};
use hydrofmu::network::Network;
use hydrofmu::scene::{Band, Scene, SceneReport};
use hydrofmu::sweep::ExcitationPart;
use hydrofmu::xml::escape;
use std::fmt;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// Why packing or inspecting failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PackError(pub String);

impl fmt::Display for PackError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PackError {}

impl From<String> for PackError {
    fn from(s: String) -> Self {
        PackError(s)
    }
}

impl From<&str> for PackError {
    fn from(s: &str) -> Self {
        PackError(s.to_string())
    }
}

/// Arguments of `fmu-pack pack`.
#[derive(clap::Args, Debug, Clone)]
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
    /// Network order.
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
    /// Output archive (.fmu).
    #[arg(short = 'o', long)]
    pub output: PathBuf,
    /// The hydrofmu shared library to pack (default: HYDROFMU_BINARY, then next to
    /// fmu-pack, building it if fmu-pack runs from this workspace).
    #[arg(long)]
    pub binary: Option<PathBuf>,
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

/// Where and how an archive is written.
#[derive(Clone, Copy, Debug)]
pub struct Target<'a> {
    /// The hydrofmu shared library to pack.
    pub binary: &'a Path,
    /// modelIdentifier (the binary's name in the archive).
    pub model_identifier: &'a str,
    /// The archive.
    pub output: &'a Path,
    /// Its FMI version.
    pub fmi: FmiVersion,
}

/// Arguments of `fmu-pack inspect`.
#[derive(clap::Args, Debug, Clone)]
pub struct InspectArgs {
    /// The archive to inspect.
    pub fmu: PathBuf,
}

/// What was packed.
#[derive(Clone, Debug, PartialEq)]
pub struct PackSummary {
    /// Archive written.
    pub path: PathBuf,
    /// modelIdentifier.
    pub model_identifier: String,
    /// GUID.
    pub guid: String,
    /// DOF names.
    pub dofs: Vec<String>,
    /// Network states: the length of the network's state vector (see
    /// [`Model::network_states`]).
    pub states: usize,
    /// Whether A_inf is kept inside.
    pub keep_inf_mass: bool,
    /// Fit summary, when the network was computed.
    pub fit: Option<String>,
    /// What the scene's FMU leaves out, when the network was computed.
    pub scene: Option<String>,
    /// The OSP model description written beside the archive.
    pub osp: Option<PathBuf>,
}

/// A network computed for the archive: the pipeline's products and the scene report.
pub struct Fitted {
    /// Sweep and fit.
    pub built: Built,
    /// What was left out and the error it causes.
    pub scene: SceneReport,
}

impl fmt::Display for PackSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "wrote {}", self.path.display())?;
        writeln!(f, "  modelIdentifier  {}", self.model_identifier)?;
        writeln!(f, "  GUID             {}", self.guid)?;
        writeln!(f, "  DOFs             {}", self.dofs.join(" "))?;
        writeln!(f, "  network states   {}", self.states)?;
        write!(
            f,
            "  A_inf            {}",
            if self.keep_inf_mass {
                "inside (acceleration inputs)"
            } else {
                "outside (add added_mass_inf to the hull's mass)"
            }
        )?;
        if let Some(osp) = &self.osp {
            write!(f, "\n  OSP description  {}", osp.display())?;
        }
        if let Some(fit) = &self.fit {
            write!(f, "\n  fit              {fit}")?;
        }
        if let Some(scene) = &self.scene {
            write!(f, "\n  scene")?;
            for line in scene.lines() {
                write!(f, "\n    {line}")?;
            }
        }
        Ok(())
    }
}

/// `fmu-pack pack`.
pub fn pack(args: &PackArgs) -> Result<PackSummary, PackError> {
    // The archive's folder, before the sweep and the fit.
    crate::output::check_folder(&args.output)?;
    if crate::ship_cmd::is_ship_file(&args.sweep.hull) {
        return crate::ship_cmd::pack(args);
    }
    if crate::database_cmd::is_database_file(&args.sweep.hull) {
        return crate::database_cmd::pack(args);
    }
    let (resolved, sweep_params) = args.sweep.resolve()?;
    let hull = HullInfo::new(&resolved);
    let mut report = None;
    let network = match &args.network {
        Some(path) => {
            if args.band.is_some()
                || args.tol.is_some()
                || args.order.is_some()
                || args.max_step.is_some()
                || args.allow_tolerance_miss
            {
                return Err(PackError(
                    "--band, --tol, --order, --max-step and --allow-tolerance-miss shape a \
                     computed network; they cannot apply to --network FILE"
                        .into(),
                ));
            }
            let text = hydrofmu::input::read_bounded_text(
                path,
                hydrofmu::xml::MAX_INPUT_BYTES as u64,
                "MAX_INPUT_BYTES",
            )
            .map_err(|e| format!("cannot read the network {}: {e}", path.display()))?;
            PackedNetwork::from_text(text, &path.display().to_string())?
        }
        None => {
            let band = match &args.band {
                Some(text) => pipeline::parse_band(text)?,
                None => Band::default(),
            };
            // Swept whole: the report states what the left-out DOFs would have coupled.
            let whole = HullSweepArgs {
                dofs: None,
                ..args.sweep.clone()
            };
            let (whole_hull, _) = whole.resolve()?;
            let scene = Scene {
                dofs: Some(hull.dofs.iter().map(|d| d.name.clone()).collect()),
                band,
                tolerance: args.tol,
                order: args.order,
                form: None,
                max_step: args.max_step,
                sweep: sweep_params,
                ..Scene::new(whole_hull)
            };
            let built = pipeline::build_network(scene)?;
            if !built.fit.tolerance_met && !args.allow_tolerance_miss {
                return Err(PackError(tolerance_missed(&built)));
            }
            let scene = built.report();
            let network = PackedNetwork::from_network(built.fit.network.clone());
            report = Some(Fitted { built, scene });
            network
        }
    };
    let binary = locate_binary(args.binary.as_deref())?;
    let identifier = match &args.model_identifier {
        Some(id) => id.clone(),
        None => identifier_from_path(&args.output),
    };
    let target = Target {
        binary: &binary,
        model_identifier: &identifier,
        output: &args.output,
        fmi: args.fmi,
    };
    pack_network(
        &hull,
        &network,
        args.keep_inf_mass,
        &target,
        report.as_ref(),
    )
}

/// Why a fit that misses its tolerance is not packed, and what to do.
fn tolerance_missed(built: &Built) -> String {
    let fit = &built.fit;
    format!(
        "the fit misses the tolerance: largest error {:.2} % of sqrt(|A_ii A_jj|) against the \
         tolerance {:.2} % (--tol) with the {} network, order {}, {} states; no archive \
         written. Try another --order or a narrower --band, raise --tol, or pass \
         --allow-tolerance-miss to pack it anyway",
        100.0 * fit.max_relative_error,
        100.0 * fit.tolerance,
        fit.network.form,
        fit.order,
        fit.states
    )
}

/// The network to pack and the text of its `resources/network.xml`.
pub struct PackedNetwork {
    network: Network,
    xml: String,
}

impl PackedNetwork {
    /// A network file's text, parsed once and packed verbatim (`source` names it in errors).
    pub fn from_text(xml: String, source: &str) -> Result<PackedNetwork, PackError> {
        let network = Network::from_xml_str(&xml, source).map_err(|e| e.to_string())?;
        Ok(PackedNetwork { network, xml })
    }

    /// A computed network, packed in its canonical text.
    pub fn from_network(network: Network) -> PackedNetwork {
        let xml = network.to_xml_string();
        PackedNetwork { network, xml }
    }
}

/// The scene report inside the archive (plain text; `fmu-pack inspect` prints it).
pub const SCENE_FILE: &str = "documentation/scene.txt";
/// Largest FMU library accepted (256 MiB; the release build is under 1 MB, a debug build 17 MB).
const MAX_BINARY_BYTES: u64 = 256 << 20;

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

/// Packs a network for a hull into `output` (the lower-level entry point).
pub fn pack_network(
    hull: &HullInfo,
    network: &PackedNetwork,
    keep_inf_mass: bool,
    target: &Target,
    fit: Option<&Fitted>,
) -> Result<PackSummary, PackError> {
    let Target {
        binary,
        model_identifier,
        output,
        fmi,
    } = *target;
    // The exciting force table of the sweep, for the network's DOFs (a network packed from a
    // file has no sweep: its FMU models calm water only).
    let excitation = match fit {
        Some(fitted) => {
            let names: Vec<&str> = network
                .network
                .dof_names
                .iter()
                .map(String::as_str)
                .collect();
            let sweep = fitted.built.sweep.select_dofs(&names).ok_or_else(|| {
                format!(
                    "the sweep has no exciting force for the DOFs {}",
                    names.join(" ")
                )
            })?;
            let mut text = Vec::new();
            sweep
                .write_excitation_csv(&mut text, ExcitationPart::Total)
                .map_err(|e| format!("cannot format the excitation table: {e}"))?;
            Some(String::from_utf8_lossy(&text).into_owned())
        }
        None => hull.excitation_csv.clone(),
    };
    let resources = Resources::with_options(network.xml.clone(), hull.xml.clone(), keep_inf_mass)
        .with_excitation(excitation)
        .with_hydrostatics(hull.hydrostatics_csv.clone());
    // The GUID is that of the packed texts.
    let options = ModelOptions {
        keep_inf_mass,
        guid: Some(resources.guid()),
    };
    let model = Model::new(&network.network, options).map_err(|e| e.to_string())?;
    let mut units = Vec::new();
    for name in model.dof_names() {
        let unit = hull.dofs.iter().find(|d| &d.name == name).ok_or_else(|| {
            format!(
                "the network's DOF '{name}' is not a DOF of hull '{}' ({})",
                hull.name,
                hull.dofs
                    .iter()
                    .map(|d| d.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })?;
        units.push(unit.clone());
    }
    let layout =
        Layout::with_extent(units, keep_inf_mass, hull.extent).map_err(|e| e.to_string())?;
    let guid = resources.guid();
    let system = model.system();
    let model_name = format!("hydrofmu {}", hull.name);
    let osp = crate::osp::model_description(&layout);
    let info = DescriptionInfo {
        model_identifier: model_identifier.to_string(),
        guid: guid.clone(),
        model_name: Some(model_name.clone()),
        description: Some(format!(
            "Hydrodynamic radiation forces on hull '{}' (DOFs {}), equivalent mass-spring-damper network with {} states",
            hull.name,
            model.dof_names().join(", "),
            model.network_states()
        )),
        damping_direct: Some(system.damping_direct().clone()),
        added_mass_inf: Some(system.added_mass_inf().clone()),
    };
    let description = match fmi {
        FmiVersion::V2 => layout.model_description(FIXED_XML, &info),
        FmiVersion::V3 => layout.model_description_fmi3(FIXED_XML, &info),
    }
    .map_err(|e| e.to_string())?;
    let platform = match fmi {
        FmiVersion::V2 => "linux64",
        FmiVersion::V3 => "x86_64-linux",
    };
    let library = hydrofmu::input::read_bounded(binary, MAX_BINARY_BYTES, "MAX_BINARY_BYTES")
        .map_err(|e| format!("cannot read the binary {}: {e}", binary.display()))?;
    let mut documentation = documentation(hull, &layout, &model, &guid, keep_inf_mass);
    if let Some(report) = &hull.report {
        let section = format!("<h2>Fit report</h2>\n<pre>{}</pre>\n", escape(report));
        documentation = match documentation.rfind("</body>") {
            Some(at) => format!("{}{section}{}", &documentation[..at], &documentation[at..]),
            None => documentation + &section,
        };
    }
    let mut plot_entries = Vec::new();
    let mut scene_entry = hull.report.clone();
    if let Some(Fitted { built, scene }) = fit {
        let scene_text = SceneText(scene).to_string();
        let mut section = format!(
            "<h2>Scene: what this FMU models and leaves out</h2>\n<pre>{}</pre>\n\
             <h2>Fit report</h2>\n<pre>{}</pre>\n",
            escape(&scene_text),
            escape(&crate::fit_cmd::text(built))
        );
        scene_entry = Some(scene_text);
        for (name, svg) in crate::fit_cmd::plots(built) {
            section += &format!("<p><img src=\"plots/{name}\" alt=\"{name}\"></p>\n");
            plot_entries.push((format!("documentation/plots/{name}"), svg.into_bytes()));
        }
        documentation = match documentation.rfind("</body>") {
            Some(at) => format!("{}{section}{}", &documentation[..at], &documentation[at..]),
            None => documentation + &section,
        };
    }

    let mut entries: Vec<(String, Vec<u8>)> = vec![
        ("modelDescription.xml".into(), description.into_bytes()),
        (
            format!("binaries/{platform}/{model_identifier}.so"),
            library,
        ),
        (
            format!("resources/{}", Resources::NETWORK_FILE),
            resources.network_xml.clone().into_bytes(),
        ),
        (
            format!("resources/{}", Resources::OPTIONS_FILE),
            resources.options_xml.clone().into_bytes(),
        ),
    ];
    if let Some(h) = &resources.hull_xml {
        entries.push((
            format!("resources/{}", Resources::HULL_FILE),
            h.clone().into_bytes(),
        ));
    }
    if let Some(x) = &resources.excitation_csv {
        entries.push((
            format!("resources/{}", Resources::EXCITATION_FILE),
            x.clone().into_bytes(),
        ));
    }
    if let Some(c) = &resources.hydrostatics_csv {
        entries.push((
            format!("resources/{}", Resources::HYDROSTATICS_FILE),
            c.clone().into_bytes(),
        ));
    }
    entries.push((
        "documentation/index.html".into(),
        documentation.into_bytes(),
    ));
    entries.extend(plot_entries);
    if let Some(text) = &scene_entry {
        entries.push((SCENE_FILE.into(), format!("{text}\n").into_bytes()));
    }
    if let Some(name) = crate::osp::file_name(&model_name) {
        let path = format!("{}/{name}", crate::osp::ARCHIVE_DIR);
        entries.push((path, osp.clone().into_bytes()));
    }
    // What the archive holds must instantiate: load its resources as an instance does.
    Model::from_resources(&resources).map_err(|e| {
        PackError(format!(
            "not written: {} would not instantiate: {e}",
            output.display()
        ))
    })?;
    // The archive and the OSP description beside it are written together, or neither.
    let archive = zip_archive(output, &entries)?;
    let mut outputs = crate::output::Outputs::new();
    outputs.bytes(output, &archive)?;
    let osp = crate::osp::stage_beside(&mut outputs, output, &model_name, &osp)?;
    outputs.commit()?;
    Ok(PackSummary {
        path: output.to_path_buf(),
        model_identifier: model_identifier.to_string(),
        guid,
        dofs: model.dof_names().to_vec(),
        states: model.network_states(),
        keep_inf_mass,
        osp,
        scene: scene_entry,
        fit: fit.map(|Fitted { built: b, .. }| {
            format!(
                "{} auxiliary DOFs, largest error {:.2} % of sqrt(|A_ii A_jj|) (tolerance {:.2} %, {}), sweep {:.2} s, fit {:.2} s",
                b.fit.aux_dofs,
                100.0 * b.fit.max_relative_error,
                100.0 * b.fit.tolerance,
                if b.fit.tolerance_met { "met" } else { "NOT met" },
                b.sweep_time.as_secs_f64(),
                b.fit_time.as_secs_f64()
            )
        }),
    })
}

/// The archive's bytes. `output` only names it in errors, and a name that standard output
/// would take (`-`) is refused: the summary goes there.
fn zip_archive(output: &Path, entries: &[(String, Vec<u8>)]) -> Result<Vec<u8>, PackError> {
    use zip::write::SimpleFileOptions;
    if output.as_os_str() == "-" {
        return Err(PackError(
            "-o -: an archive is written to a file, not to standard output (which carries the \
             summary); name a file"
                .into(),
        ));
    }
    let err = |e: &dyn fmt::Display| PackError(format!("writing {}: {e}", output.display()));
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644)
        .large_file(false);
    for (path, bytes) in entries {
        if path.contains('\\') || path.starts_with('/') || path.contains("..") {
            return Err(PackError(format!("bad archive path {path}")));
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
    hull: &HullInfo,
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
        name = escape(&hull.name),
        body = match hull.extent {
            Extent::PerUnitLength => "hull section",
            Extent::WholeBody => "whole ship (strip theory, docs/SHIPS.md)",
        },
        extent = hull.extent.words(),
        axes = match hull.extent {
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

/// The hydrofmu shared library: `--binary`, else `HYDROFMU_BINARY`, else, for a release build
/// of fmu-pack, the library cargo built with it (`release/deps/libhydrofmu.so`: building
/// fmu-pack builds the library's cdylib there, only `cargo build -p hydrofmu` copies it up),
/// else `libhydrofmu.so` next to this executable. If none is there and this executable lives
/// in this workspace's target directory, the release library is built with cargo.
pub fn locate_binary(explicit: Option<&Path>) -> Result<PathBuf, PackError> {
    if let Some(p) = explicit {
        return existing(p, "--binary");
    }
    if let Some(p) = std::env::var_os("HYDROFMU_BINARY") {
        return existing(Path::new(&p), "HYDROFMU_BINARY");
    }
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate fmu-pack: {e}"))?;
    let exe_dir = exe
        .parent()
        .ok_or("fmu-pack has no parent directory")?
        .to_path_buf();
    let target_dir = exe_dir.parent().map(Path::to_path_buf);
    let in_cargo_target = target_dir
        .as_ref()
        .is_some_and(|t| t.join("CACHEDIR.TAG").is_file());
    let built_with_this = exe_dir.join("deps").join("libhydrofmu.so");
    if in_cargo_target && exe_dir.ends_with("release") && built_with_this.is_file() {
        return Ok(built_with_this);
    }
    let beside = exe_dir.join("libhydrofmu.so");
    if beside.is_file() {
        return Ok(beside);
    }
    let manifest = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../Cargo.toml"));
    if let (true, true, Some(target_dir)) = (manifest.is_file(), in_cargo_target, target_dir) {
        crate::output::stderr_line(&format!(
            "fmu-pack: {} is missing; building it: cargo build --release -p hydrofmu --lib",
            beside.display()
        ));
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let status = std::process::Command::new(cargo)
            .args([
                "build",
                "--release",
                "-p",
                "hydrofmu",
                "--lib",
                "--manifest-path",
            ])
            .arg(manifest)
            .env("CARGO_TARGET_DIR", &target_dir)
            .status()
            .map_err(|e| format!("cannot run cargo: {e}"))?;
        if !status.success() {
            return Err(PackError(format!("building hydrofmu failed ({status})")));
        }
        let built = target_dir.join("release").join("libhydrofmu.so");
        return existing(&built, "the release build");
    }
    Err(PackError(format!(
        "cannot find libhydrofmu.so: pass --binary PATH, set HYDROFMU_BINARY, or put it next to {} \
         (cargo build --release -p hydrofmu --lib)",
        exe.display()
    )))
}

fn existing(p: &Path, source: &str) -> Result<PathBuf, PackError> {
    if p.is_file() {
        Ok(p.to_path_buf())
    } else {
        Err(PackError(format!(
            "{source}: {} is not a file",
            p.display()
        )))
    }
}

/// What `inspect` found in an archive.
#[derive(Clone, Debug, PartialEq)]
pub struct Inspection {
    /// modelName.
    pub model_name: String,
    /// fmiVersion (`2.0` or `3.0`).
    pub fmi_version: String,
    /// modelIdentifier.
    pub model_identifier: String,
    /// GUID in the model description.
    pub guid: String,
    /// GUID implied by the resources.
    pub resources_guid: String,
    /// DOF names with their velocity units.
    pub dofs: Vec<(String, String)>,
    /// Number of scalar variables.
    pub variables: usize,
    /// Network states: the length of the network's state vector (see
    /// [`Model::network_states`]).
    pub states: usize,
    /// A_inf kept inside.
    pub keep_inf_mass: bool,
    /// Archive entries.
    pub entries: Vec<String>,
    /// The scene report, when the network was computed by fmu-pack.
    pub scene: Option<String>,
}

impl fmt::Display for Inspection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "model             {}", self.model_name)?;
        writeln!(f, "FMI version       {}", self.fmi_version)?;
        writeln!(f, "modelIdentifier   {}", self.model_identifier)?;
        writeln!(
            f,
            "GUID              {} ({})",
            self.guid,
            if self.guid == self.resources_guid {
                "matches the resources"
            } else {
                "DOES NOT match the resources"
            }
        )?;
        writeln!(f, "DOFs              {}", self.dofs.len())?;
        for (name, unit) in &self.dofs {
            writeln!(f, "  {name:<10} velocity in {unit}")?;
        }
        writeln!(f, "variables         {}", self.variables)?;
        writeln!(f, "network states    {}", self.states)?;
        writeln!(
            f,
            "A_inf             {}",
            if self.keep_inf_mass {
                "inside"
            } else {
                "outside"
            }
        )?;
        match &self.scene {
            Some(scene) => {
                writeln!(f, "scene")?;
                for line in scene.lines() {
                    writeln!(f, "  {line}")?;
                }
            }
            None => writeln!(
                f,
                "scene             not recorded (network given as a file)"
            )?,
        }
        writeln!(f, "entries")?;
        for e in &self.entries {
            writeln!(f, "  {e}")?;
        }
        Ok(())
    }
}

fn read_entry<R: Read + std::io::Seek>(
    archive: &mut zip::ZipArchive<R>,
    name: &str,
) -> Result<Option<String>, PackError> {
    let file = match archive.by_name(name) {
        Ok(f) => f,
        Err(zip::result::ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(PackError(format!("{name}: {e}"))),
    };
    let limit = hydrofmu::xml::MAX_INPUT_BYTES;
    let mut text = String::new();
    file.take(limit as u64 + 1)
        .read_to_string(&mut text)
        .map_err(|e| format!("{name}: {e}"))?;
    if text.len() > limit {
        return Err(PackError(format!(
            "{name}: larger than the limit MAX_INPUT_BYTES = {limit} bytes"
        )));
    }
    Ok(Some(text))
}

/// `fmu-pack inspect`. Every error starts with the archive's path.
pub fn inspect(path: &Path) -> Result<Inspection, PackError> {
    inspect_archive(path).map_err(|e| PackError(format!("{}: {e}", path.display())))
}

fn inspect_archive(path: &Path) -> Result<Inspection, PackError> {
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) && path.exists() {
        return Err(PackError(
            "not a regular file (a named pipe, a device or a folder): only regular files are read"
                .into(),
        ));
    }
    let file = std::fs::File::open(path).map_err(|e| format!("cannot open the archive: {e}"))?;
    let mut archive = zip::ZipArchive::new(file).map_err(|e| format!("not a zip archive: {e}"))?;
    let entries: Vec<String> = archive.file_names().map(str::to_string).collect();
    let description = read_entry(&mut archive, "modelDescription.xml")?
        .ok_or("no modelDescription.xml in the archive")?;
    let missing = |n: &str| PackError(format!("no resources/{n} in the archive"));
    let network = read_entry(
        &mut archive,
        &format!("resources/{}", Resources::NETWORK_FILE),
    )?
    .ok_or_else(|| missing(Resources::NETWORK_FILE))?;
    let options = read_entry(
        &mut archive,
        &format!("resources/{}", Resources::OPTIONS_FILE),
    )?
    .ok_or_else(|| missing(Resources::OPTIONS_FILE))?;
    let hull = read_entry(&mut archive, &format!("resources/{}", Resources::HULL_FILE))?;
    let excitation = read_entry(
        &mut archive,
        &format!("resources/{}", Resources::EXCITATION_FILE),
    )?;
    let hydrostatics = read_entry(
        &mut archive,
        &format!("resources/{}", Resources::HYDROSTATICS_FILE),
    )?;
    let scene = read_entry(&mut archive, SCENE_FILE)?;
    let resources = Resources::new(network, hull, options)
        .map_err(|e| e.to_string())?
        .with_excitation(excitation)
        .with_hydrostatics(hydrostatics);
    let model = Model::from_resources(&resources).map_err(|e| e.to_string())?;

    let mut out = Inspection {
        model_name: String::new(),
        fmi_version: String::new(),
        model_identifier: String::new(),
        guid: String::new(),
        resources_guid: resources.guid(),
        dofs: Vec::new(),
        variables: 0,
        states: model.network_states(),
        keep_inf_mass: resources.keep_inf_mass,
        entries,
        scene,
    };
    let root =
        hydrofmu::xml::parse(&description).map_err(|e| format!("modelDescription.xml: {e}"))?;
    let mut current_name = String::new();
    for e in root.descendants() {
        let attr = |key: &str| e.attribute(key).map(str::to_string);
        match e.name.as_str() {
            "fmiModelDescription" => {
                out.model_name = attr("modelName").unwrap_or_default();
                out.fmi_version = attr("fmiVersion").unwrap_or_default();
                // FMI 3.0 calls the GUID the instantiation token.
                out.guid = attr("guid")
                    .or_else(|| attr("instantiationToken"))
                    .unwrap_or_default();
            }
            "CoSimulation" => out.model_identifier = attr("modelIdentifier").unwrap_or_default(),
            "ScalarVariable" => {
                out.variables += 1;
                current_name = attr("name").unwrap_or_default();
            }
            "Real" => {
                if let Some(dof) = current_name.strip_prefix("velocity.") {
                    out.dofs
                        .push((dof.to_string(), attr("unit").unwrap_or_default()));
                }
            }
            // FMI 3.0: one element per variable, the unit on it.
            "Float64" | "Int32" => {
                out.variables += 1;
                let name = attr("name").unwrap_or_default();
                if let Some(dof) = name.strip_prefix("velocity.") {
                    out.dofs
                        .push((dof.to_string(), attr("unit").unwrap_or_default()));
                }
            }
            _ => {}
        }
    }
    if out.dofs.len() != model.dof_count() {
        return Err(PackError(format!(
            "modelDescription.xml has {} velocity inputs, the network {} DOFs",
            out.dofs.len(),
            model.dof_count()
        )));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hydrofmu::fmu::DofUnit;

    /// The seed paper's 2-DOF network (the shipped example file).
    const SEED: &str = include_str!("../../examples/networks/seed_2dof.xml");

    fn temp_dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("fmu-pack-test-{}-{tag}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// An FMI 2.0 target.
    fn to<'a>(binary: &'a Path, model_identifier: &'a str, output: &'a Path) -> Target<'a> {
        Target {
            binary,
            model_identifier,
            output,
            fmi: FmiVersion::V2,
        }
    }

    fn hull() -> HullInfo {
        HullInfo {
            name: "Test hull".into(),
            dofs: vec![
                DofUnit::builtin("sway").unwrap(),
                DofUnit::builtin("roll").unwrap(),
            ],
            xml: Some(
                hydrofmu::hull::Hull::semicircle(1.0)
                    .unwrap()
                    .select_dofs(&["sway", "roll"])
                    .unwrap()
                    .to_xml_string(),
            ),
            extent: Extent::PerUnitLength,
            hydrostatics_csv: None,
            excitation_csv: None,
            report: None,
        }
    }

    fn net(text: &str) -> PackedNetwork {
        PackedNetwork::from_text(text.to_string(), "test network").unwrap()
    }

    #[test]
    fn the_archive_has_the_fmi_layout_and_matching_guid() {
        let dir = temp_dir("layout");
        let binary = dir.join("libfake.so");
        std::fs::write(&binary, b"\x7fELF fake").unwrap();
        let out = dir.join("Seed-1.fmu");
        let id = identifier_from_path(&out);
        assert_eq!(id, "Seed_1");
        let summary =
            pack_network(&hull(), &net(SEED), false, &to(&binary, &id, &out), None).unwrap();
        assert_eq!(summary.dofs, vec!["sway".to_string()]);
        assert_eq!(summary.states, 4);
        let found = inspect(&out).unwrap();
        assert_eq!(found.guid, summary.guid);
        assert_eq!(found.resources_guid, summary.guid);
        assert_eq!(found.model_identifier, "Seed_1");
        assert_eq!(found.dofs, vec![("sway".to_string(), "m/s".to_string())]);
        let osp_name = format!("{}_OspModelDescription.xml", found.model_name);
        let mut names = found.entries.clone();
        names.sort();
        assert_eq!(
            names,
            vec![
                "binaries/linux64/Seed_1.so",
                "documentation/index.html",
                &format!("extra/com.open-simulation-platform/{osp_name}"),
                "modelDescription.xml",
                "resources/hull.xml",
                "resources/network.xml",
                "resources/options.xml",
            ]
        );
        // The OSP model description beside the archive is the one inside it.
        let beside = summary.osp.clone().unwrap();
        assert_eq!(beside, dir.join(&osp_name));
        let inside = read_entry(
            &mut zip::ZipArchive::new(std::fs::File::open(&out).unwrap()).unwrap(),
            &format!("extra/com.open-simulation-platform/{osp_name}"),
        )
        .unwrap();
        assert_eq!(inside, Some(std::fs::read_to_string(&beside).unwrap()));
        let mut archive = zip::ZipArchive::new(std::fs::File::open(&out).unwrap()).unwrap();
        for i in 0..archive.len() {
            let f = archive.by_index(i).unwrap();
            assert_eq!(f.compression(), zip::CompressionMethod::Deflated);
            assert!(!f.name().contains('\\'));
            assert!(!f.is_symlink());
        }
        // The binary is a byte copy.
        let mut so = Vec::new();
        archive
            .by_name("binaries/linux64/Seed_1.so")
            .unwrap()
            .read_to_end(&mut so)
            .unwrap();
        assert_eq!(so, b"\x7fELF fake");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn an_fmi3_archive_has_the_fmi3_layout_and_the_same_guid() {
        let dir = temp_dir("fmi3");
        let binary = dir.join("libfake.so");
        std::fs::write(&binary, b"\x7fELF fake").unwrap();
        let (two, three) = (dir.join("Two.fmu"), dir.join("Three.fmu"));
        let s2 = pack_network(&hull(), &net(SEED), false, &to(&binary, "M", &two), None).unwrap();
        let target = Target {
            fmi: FmiVersion::V3,
            ..to(&binary, "M", &three)
        };
        let s3 = pack_network(&hull(), &net(SEED), false, &target, None).unwrap();
        assert_eq!(s3.guid, s2.guid);
        let found = inspect(&three).unwrap();
        assert_eq!(found.fmi_version, "3.0");
        assert_eq!(inspect(&two).unwrap().fmi_version, "2.0");
        assert_eq!(found.guid, s3.guid);
        assert_eq!(found.dofs, vec![("sway".to_string(), "m/s".to_string())]);
        assert!(found
            .entries
            .contains(&"binaries/x86_64-linux/M.so".to_string()));
        assert!(!found.entries.iter().any(|e| e.contains("linux64")));
        // time, 10 fixed parameters, velocity, force, power, energy, 3 arrays, the waves'
        // force_radiation, force_excitation and wave.elevation.
        assert_eq!(found.variables, 1 + 10 + 4 + 3 + 3);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn guids_differ_between_networks_hulls_and_flags() {
        let dir = temp_dir("guid");
        let binary = dir.join("lib.so");
        std::fs::write(&binary, b"x").unwrap();
        let pack = |net: &str, h: &HullInfo, keep: bool, name: &str| {
            pack_network(
                h,
                &self::net(net),
                keep,
                &to(&binary, "M", &dir.join(name)),
                None,
            )
            .unwrap()
            .guid
        };
        let other_net = SEED.replace("0.1153", "0.1154");
        let mut other_hull = hull();
        other_hull.xml = Some(
            hydrofmu::hull::Hull::semicircle(2.0)
                .unwrap()
                .select_dofs(&["sway", "roll"])
                .unwrap()
                .to_xml_string(),
        );
        let a = pack(SEED, &hull(), false, "a.fmu");
        assert_eq!(a, pack(SEED, &hull(), false, "a2.fmu"));
        assert_ne!(a, pack(&other_net, &hull(), false, "b.fmu"));
        assert_ne!(a, pack(SEED, &other_hull, false, "c.fmu"));
        assert_ne!(a, pack(SEED, &hull(), true, "d.fmu"));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn mistakes_are_reported_clearly() {
        let dir = temp_dir("errors");
        let binary = dir.join("lib.so");
        std::fs::write(&binary, b"x").unwrap();
        let out = dir.join("x.fmu");
        let mut h = hull();
        h.dofs.remove(0);
        let e = pack_network(&h, &net(SEED), false, &to(&binary, "X", &out), None).unwrap_err();
        assert!(e.0.contains("'sway' is not a DOF"), "{e}");
        let e = PackedNetwork::from_text("<nonsense".into(), "network.xml")
            .err()
            .unwrap();
        assert!(e.0.contains("network"), "{e}");
        let e = pack_network(
            &hull(),
            &net(SEED),
            false,
            &to(&dir.join("missing.so"), "X", &out),
            None,
        )
        .unwrap_err();
        assert!(e.0.contains("cannot read the binary"), "{e}");
        assert!(!out.exists());
        assert!(locate_binary(Some(&dir.join("missing.so"))).is_err());
        assert!(inspect(&binary).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
