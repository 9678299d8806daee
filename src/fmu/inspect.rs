//! Reading an archive back: its model description, resources and scene report, checked
//! against each other (the GUID against the resources, the velocity inputs against the
//! network's DOFs).

use super::archive::{ArchiveError, SCENE_FILE};
use super::Resources;
use crate::model::Model;
use std::fmt;
use std::io::Read;
use std::path::Path;

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
    /// Packed with a drift table (`resources/drift.csv`: `wave.drift`, `force_drift.<dof>`).
    pub drift: bool,
    /// Packed with viscous damping (`resources/viscous.csv`: `damping_linear`,
    /// `damping_quadratic`, `current.speed`, `current.heading`, `force_viscous.<dof>`).
    pub viscous: bool,
    /// The water depth the tables were computed for (`depth`; deep water without one).
    pub depth: crate::units::WaterDepth,
    /// A ship's cross-flow strips (`resources/crossflow.csv`, `crossflow.drag_scale`): their
    /// count, sway `C_D` range and lateral area.
    pub crossflow: Option<String>,
    /// The platforms with a binary: the folders under `binaries/`, in archive order.
    pub platforms: Vec<String>,
    /// Archive entries.
    pub entries: Vec<String>,
    /// The scene report, when a scene or a fit computed the network.
    pub scene: Option<String>,
}

impl fmt::Display for Inspection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "model             {}", self.model_name)?;
        writeln!(f, "FMI version       {}", self.fmi_version)?;
        writeln!(f, "modelIdentifier   {}", self.model_identifier)?;
        writeln!(f, "platforms         {}", self.platforms.join(", "))?;
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
        match self.depth {
            crate::units::WaterDepth::Finite(h) => {
                writeln!(f, "water depth       {h} m (the fixed parameter depth)")?
            }
            crate::units::WaterDepth::Infinite => {
                writeln!(f, "water depth       infinite (deep water)")?
            }
        }
        if self.drift {
            writeln!(
                f,
                "drift             mean drift table (wave.drift 1 mean, 2 slow drift; force_drift.<dof>)"
            )?;
        }
        if self.viscous {
            writeln!(
                f,
                "viscous           damping_linear, damping_quadratic; current.speed, current.heading; force_viscous.<dof>"
            )?;
        }
        if let Some(strips) = &self.crossflow {
            writeln!(f, "  cross-flow      {strips}; crossflow.drag_scale")?;
        }
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

pub(crate) fn read_entry<R: Read + std::io::Seek>(
    archive: &mut zip::ZipArchive<R>,
    name: &str,
) -> Result<Option<String>, ArchiveError> {
    let file = match archive.by_name(name) {
        Ok(f) => f,
        Err(zip::result::ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(ArchiveError(format!("{name}: {e}"))),
    };
    let limit = crate::xml::MAX_INPUT_BYTES;
    let mut text = String::new();
    file.take(limit as u64 + 1)
        .read_to_string(&mut text)
        .map_err(|e| format!("{name}: {e}"))?;
    if text.len() > limit {
        return Err(ArchiveError(format!(
            "{name}: larger than the limit MAX_INPUT_BYTES = {limit} bytes"
        )));
    }
    Ok(Some(text))
}

/// Reads and checks the archive at `path`. Every error starts with the archive's path.
pub fn inspect(path: &Path) -> Result<Inspection, ArchiveError> {
    inspect_archive(path).map_err(|e| ArchiveError(format!("{}: {e}", path.display())))
}

/// The folders under `binaries/` that hold a file, each once, in the order of `entries`.
fn platforms(entries: &[String]) -> Vec<String> {
    let mut found: Vec<String> = Vec::new();
    for entry in entries {
        let Some((platform, file)) = entry
            .strip_prefix("binaries/")
            .and_then(|rest| rest.split_once('/'))
        else {
            continue;
        };
        if !file.is_empty() && !found.iter().any(|p| p == platform) {
            found.push(platform.to_string());
        }
    }
    found
}

fn inspect_archive(path: &Path) -> Result<Inspection, ArchiveError> {
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) && path.exists() {
        return Err(ArchiveError(
            "not a regular file (a named pipe, a device or a folder): only regular files are read"
                .into(),
        ));
    }
    let file = std::fs::File::open(path).map_err(|e| format!("cannot open the archive: {e}"))?;
    let mut archive = zip::ZipArchive::new(file).map_err(|e| format!("not a zip archive: {e}"))?;
    let entries: Vec<String> = archive.file_names().map(str::to_string).collect();
    let description = read_entry(&mut archive, "modelDescription.xml")?
        .ok_or("no modelDescription.xml in the archive")?;
    let missing = |n: &str| ArchiveError(format!("no resources/{n} in the archive"));
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
    let drift = read_entry(
        &mut archive,
        &format!("resources/{}", Resources::DRIFT_FILE),
    )?;
    let viscous = read_entry(
        &mut archive,
        &format!("resources/{}", Resources::VISCOUS_FILE),
    )?;
    let crossflow = read_entry(
        &mut archive,
        &format!("resources/{}", Resources::CROSSFLOW_FILE),
    )?;
    let scene = read_entry(&mut archive, SCENE_FILE)?;
    let resources = Resources::new(network, hull, options)
        .map_err(|e| e.to_string())?
        .with_excitation(excitation)
        .with_hydrostatics(hydrostatics)
        .with_drift(drift)
        .with_viscous(viscous)
        .with_crossflow(crossflow);
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
        drift: resources.drift_csv.is_some(),
        viscous: resources.viscous_csv.is_some(),
        depth: model.depth(),
        crossflow: model
            .viscous()
            .and_then(|v| v.crossflow())
            .map(|c| crate::model::crossflow::describe(c.strips())),
        platforms: platforms(&entries),
        entries,
        scene,
    };
    let root = crate::xml::parse(&description).map_err(|e| format!("modelDescription.xml: {e}"))?;
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
        return Err(ArchiveError(format!(
            "modelDescription.xml has {} velocity inputs, the network {} DOFs",
            out.dofs.len(),
            model.dof_count()
        )));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::platforms;

    #[test]
    fn platforms_are_the_binaries_folders_in_archive_order() {
        let entries: Vec<String> = [
            "modelDescription.xml",
            "binaries/linux64/M.so",
            "binaries/win64/M.dll",
            "binaries/win64/extra.txt",
            "binaries/empty/",
            "resources/binaries/x/y",
            "resources/network.xml",
        ]
        .map(String::from)
        .to_vec();
        assert_eq!(platforms(&entries), ["linux64", "win64"]);
        assert!(platforms(&entries[..1]).is_empty());
    }
}
