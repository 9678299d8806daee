//! What makes the component an FMU: its variables and value references, their units, the
//! `modelDescription.xml` writer with the fixed parameters of `modelDescription/fixed.xml`,
//! the files of `resources/`, and the GUID.
//!
//! ```text
//! units -> variables (Layout: value references) -> description (modelDescription.xml)
//! resources (network.xml, options.xml, hull.xml) -> guid (content hash)
//! ```
//!
//! [`fmi3`] gives the same variables the FMI 3.0 way (matrices as arrays, `time`).
//!
//! [`archive`] packs them, with a network, a binary and the documentation, into the `.fmu`
//! zip ([`Archive`]), with the OSP model description of [`osp`] inside and beside it;
//! [`inspect()`] reads an archive back.

pub mod archive;
pub mod description;
pub mod fmi3;
pub mod guid;
pub mod inspect;
pub mod osp;
pub mod resources;
pub mod units;
pub mod variables;

pub use archive::{
    identifier_from_path, read_binary, Archive, ArchiveError, Body, FmiVersion, Packed,
    PackedNetwork, SceneDocumentation, SCENE_FILE,
};
pub use description::DescriptionInfo;
pub use fmi3::{ArrayVariable, Fmi3Reference, VR_TIME};
pub use guid::content_guid;
pub use inspect::{inspect, Inspection};
pub use resources::{Resources, ResourcesError};
pub use units::{DofUnit, Extent};
pub use variables::{Causality, Layout, Quantity, Variable, VariablesError};
