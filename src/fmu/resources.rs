//! The files of an FMU's `resources/` folder and their texts.
//!
//! ```text
//! resources/network.xml   the equivalent network (crate::realize, docs/NETWORK_FORMAT.md)
//! resources/options.xml   <hydrofmu_options format="1" keep_inf_mass="true|false"/>
//! resources/hull.xml      the hull, when known (the FMU computes its hydrostatics from it)
//! resources/excitation.csv  the exciting force table (docs/WAVES.md), when packed with one
//! resources/hydrostatics.csv  the restoring C / (rho g) of a body without a hull file (a ship)
//! resources/drift.csv     the mean drift table (docs/WAVES.md), when packed with one
//! resources/viscous.csv   the viscous damping coefficients (docs/CURRENT.md), when packed with them
//! resources/crossflow.csv a ship's cross-flow strips (docs/CURRENT.md), with viscous.csv
//! ```
//!
//! The GUID of an FMU is the content hash of these texts ([`Resources::guid`]).

use crate::fmu::guid::content_guid;
use crate::network::Network;
use std::fmt;
use std::path::{Path, PathBuf};

/// Why the resources could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ResourcesError {
    /// A file cannot be read.
    Read {
        /// The file.
        path: PathBuf,
        /// What the system said.
        reason: String,
    },
    /// `options.xml` is malformed.
    Options(String),
}

impl ResourcesError {
    /// The message without the leading `resources:`.
    pub fn detail(&self) -> String {
        match self {
            ResourcesError::Read { path, reason } => {
                format!("cannot read {}: {reason}", path.display())
            }
            ResourcesError::Options(m) => m.clone(),
        }
    }
}

impl fmt::Display for ResourcesError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "resources: {}", self.detail())
    }
}

impl std::error::Error for ResourcesError {}

/// The files in an FMU's `resources/` folder.
#[derive(Clone, Debug, PartialEq)]
pub struct Resources {
    /// Text of `network.xml`.
    pub network_xml: String,
    /// Text of `hull.xml`, when the hull is known.
    pub hull_xml: Option<String>,
    /// Text of `options.xml`.
    pub options_xml: String,
    /// Whether the force includes `-A_inf a` (from `options.xml`).
    pub keep_inf_mass: bool,
    /// Text of `excitation.csv`, when the FMU models waves.
    pub excitation_csv: Option<String>,
    /// Text of `hydrostatics.csv`, the restoring of a body packed without a hull file.
    pub hydrostatics_csv: Option<String>,
    /// Text of `drift.csv`, the mean drift table, when the FMU models the drift force.
    pub drift_csv: Option<String>,
    /// Text of `viscous.csv`, the viscous damping, when the FMU models it.
    pub viscous_csv: Option<String>,
    /// Text of `crossflow.csv`, a ship's cross-flow strips, when packed with them.
    pub crossflow_csv: Option<String>,
}

impl Resources {
    /// The network file.
    pub const NETWORK_FILE: &'static str = "network.xml";
    /// The hull file (optional).
    pub const HULL_FILE: &'static str = "hull.xml";
    /// The options file.
    pub const OPTIONS_FILE: &'static str = "options.xml";
    /// The exciting force table (optional).
    pub const EXCITATION_FILE: &'static str = "excitation.csv";
    /// The restoring table (optional; `crate::hydrostatics::Table`).
    pub const HYDROSTATICS_FILE: &'static str = "hydrostatics.csv";
    /// The mean drift table (optional; `crate::waves::DriftTable`).
    pub const DRIFT_FILE: &'static str = "drift.csv";
    /// The viscous damping coefficients (optional).
    pub const VISCOUS_FILE: &'static str = "viscous.csv";
    /// A ship's cross-flow strips (optional; `crate::model::crossflow`).
    pub const CROSSFLOW_FILE: &'static str = "crossflow.csv";

    /// The same resources with the cross-flow strips `text`, or without them.
    pub fn with_crossflow(self, text: Option<String>) -> Resources {
        Resources {
            crossflow_csv: text,
            ..self
        }
    }

    /// The same resources with the viscous damping `text`, or without one.
    pub fn with_viscous(self, text: Option<String>) -> Resources {
        Resources {
            viscous_csv: text,
            ..self
        }
    }

    /// The same resources with the drift table `text`, or without one.
    pub fn with_drift(self, text: Option<String>) -> Resources {
        Resources {
            drift_csv: text,
            ..self
        }
    }

    /// The same resources with the restoring table `text`, or without one.
    pub fn with_hydrostatics(self, text: Option<String>) -> Resources {
        Resources {
            hydrostatics_csv: text,
            ..self
        }
    }

    /// The same resources with the exciting force table `text` (docs/DESIGN.md's excitation
    /// table), or without one.
    pub fn with_excitation(self, text: Option<String>) -> Resources {
        Resources {
            excitation_csv: text,
            ..self
        }
    }

    /// The options file text for these flags.
    pub fn options_text(keep_inf_mass: bool) -> String {
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<hydrofmu_options format=\"1\" keep_inf_mass=\"{keep_inf_mass}\"/>\n"
        )
    }

    /// Resources from their texts (checks the options file).
    pub fn new(
        network_xml: String,
        hull_xml: Option<String>,
        options_xml: String,
    ) -> Result<Resources, ResourcesError> {
        let keep_inf_mass = parse_options(&options_xml)?;
        Ok(Resources {
            network_xml,
            hull_xml,
            options_xml,
            keep_inf_mass,
            excitation_csv: None,
            hydrostatics_csv: None,
            drift_csv: None,
            viscous_csv: None,
            crossflow_csv: None,
        })
    }

    /// Reads the resources folder.
    /// Each file is refused, before it is read, if it is longer than
    /// [`crate::xml::MAX_INPUT_BYTES`] (64 MiB, far above any real resource).
    pub fn read(dir: &Path) -> Result<Resources, ResourcesError> {
        let read = |name: &str| {
            read_bounded(&dir.join(name), crate::xml::MAX_INPUT_BYTES).map_err(|reason| {
                ResourcesError::Read {
                    path: dir.join(name),
                    reason,
                }
            })
        };
        let network = read(Self::NETWORK_FILE)?;
        let options = read(Self::OPTIONS_FILE)?;
        let optional = |name: &str| {
            if dir.join(name).exists() {
                read(name).map(Some)
            } else {
                Ok(None)
            }
        };
        let hull = optional(Self::HULL_FILE)?;
        let excitation = optional(Self::EXCITATION_FILE)?;
        let hydrostatics = optional(Self::HYDROSTATICS_FILE)?;
        let drift = optional(Self::DRIFT_FILE)?;
        let viscous = optional(Self::VISCOUS_FILE)?;
        let crossflow = optional(Self::CROSSFLOW_FILE)?;
        Ok(Resources::new(network, hull, options)?
            .with_excitation(excitation)
            .with_hydrostatics(hydrostatics)
            .with_drift(drift)
            .with_viscous(viscous)
            .with_crossflow(crossflow))
    }

    /// Resources from the network text and the flags (the options text is written, not
    /// read back).
    pub fn with_options(
        network_xml: String,
        hull_xml: Option<String>,
        keep_inf_mass: bool,
    ) -> Resources {
        Resources {
            network_xml,
            hull_xml,
            options_xml: Self::options_text(keep_inf_mass),
            keep_inf_mass,
            excitation_csv: None,
            hydrostatics_csv: None,
            drift_csv: None,
            viscous_csv: None,
            crossflow_csv: None,
        }
    }

    /// The resources of a network, with its canonical text ([`Network::to_xml_string`]).
    pub fn for_network(
        network: &Network,
        hull_xml: Option<String>,
        keep_inf_mass: bool,
    ) -> Resources {
        Self::with_options(network.to_xml_string(), hull_xml, keep_inf_mass)
    }

    /// The GUID these resources imply ([`content_guid`]).
    pub fn guid(&self) -> String {
        let mut parts: Vec<(&str, &[u8])> = vec![(Self::NETWORK_FILE, self.network_xml.as_bytes())];
        if let Some(h) = &self.hull_xml {
            parts.push((Self::HULL_FILE, h.as_bytes()));
        }
        parts.push((Self::OPTIONS_FILE, self.options_xml.as_bytes()));
        // Absent: the GUID of an FMU without waves stays what it was.
        if let Some(x) = &self.excitation_csv {
            parts.push((Self::EXCITATION_FILE, x.as_bytes()));
        }
        if let Some(c) = &self.hydrostatics_csv {
            parts.push((Self::HYDROSTATICS_FILE, c.as_bytes()));
        }
        // Absent: the GUID of an FMU without drift stays what it was.
        if let Some(d) = &self.drift_csv {
            parts.push((Self::DRIFT_FILE, d.as_bytes()));
        }
        // Absent: the GUID of an FMU without viscous damping stays what it was.
        if let Some(v) = &self.viscous_csv {
            parts.push((Self::VISCOUS_FILE, v.as_bytes()));
        }
        // Absent: the GUID of an FMU without strips stays what it was.
        if let Some(c) = &self.crossflow_csv {
            parts.push((Self::CROSSFLOW_FILE, c.as_bytes()));
        }
        content_guid(&parts)
    }
}

/// The text of the regular file `path` if it holds at most `limit` bytes
/// ([`crate::input::read_bounded_text`]).
fn read_bounded(path: &Path, limit: usize) -> Result<String, String> {
    Ok(crate::input::read_bounded_text(
        path,
        limit as u64,
        "MAX_INPUT_BYTES",
    )?)
}

/// `keep_inf_mass` of `options.xml`: the root `<hydrofmu_options format="1" keep_inf_mass="true|false"/>`.
fn parse_options(text: &str) -> Result<bool, ResourcesError> {
    let fail = |message: String| ResourcesError::Options(format!("options.xml: {message}"));
    let root = crate::xml::parse(text).map_err(|e| fail(e.to_string()))?;
    if root.name != "hydrofmu_options" {
        return Err(ResourcesError::Options(
            "options.xml has no <hydrofmu_options>".into(),
        ));
    }
    let format = root.attribute("format");
    if format != Some("1") {
        return Err(fail(format!("format {format:?}, expected \"1\"")));
    }
    match root.attribute("keep_inf_mass") {
        Some("true") => Ok(true),
        Some("false") => Ok(false),
        other => Err(fail(format!(
            "keep_inf_mass = {other:?}, expected true or false"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SEED_NETWORK: &str = include_str!("../../examples/networks/seed_2dof.xml");

    fn resources(keep_inf_mass: bool) -> Resources {
        Resources::new(
            SEED_NETWORK.into(),
            None,
            Resources::options_text(keep_inf_mass),
        )
        .unwrap()
    }

    #[test]
    fn options_are_checked() {
        assert!(Resources::new(SEED_NETWORK.into(), None, "<x/>".into()).is_err());
        assert!(Resources::new(
            SEED_NETWORK.into(),
            None,
            "<hydrofmu_options format=\"1\" keep_inf_mass=\"yes\"/>".into()
        )
        .is_err());
        assert!(resources(true).keep_inf_mass);
        assert!(!resources(false).keep_inf_mass);
        assert_ne!(resources(false).guid(), resources(true).guid());
        // An excitation table is part of the content; without one the GUID is unchanged.
        let plain = resources(false);
        let waves = plain
            .clone()
            .with_excitation(Some("kR,j,heading,re,im\n".into()));
        assert_ne!(plain.guid(), waves.guid());
        assert_eq!(plain.clone().with_excitation(None).guid(), plain.guid());
        // So are a ship's strips.
        let strips = plain.clone().with_crossflow(Some("x,weight\n".into()));
        assert_ne!(plain.guid(), strips.guid());
        assert_eq!(plain.clone().with_crossflow(None).guid(), plain.guid());
    }

    #[test]
    fn a_network_gives_its_canonical_text() {
        let network = Network::from_xml_str(SEED_NETWORK, "seed.xml").unwrap();
        let from_network = Resources::for_network(&network, None, true);
        let text = network.to_xml_string();
        let from_text = Resources::new(text, None, Resources::options_text(true)).unwrap();
        assert_eq!(from_network, from_text);
        let given = Resources::with_options(network.to_xml_string(), None, true);
        assert_eq!(given, from_text);
        assert_eq!(from_network.guid(), from_text.guid());
        let with_hull = Resources::for_network(&network, Some("<hull/>".into()), true);
        assert_ne!(with_hull.guid(), from_network.guid());
    }
}
