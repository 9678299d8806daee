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

pub mod description;
pub mod fmi3;
pub mod guid;
pub mod resources;
pub mod units;
pub mod variables;

pub use description::DescriptionInfo;
pub use fmi3::{ArrayVariable, Fmi3Reference, VR_TIME};
pub use guid::content_guid;
pub use resources::{Resources, ResourcesError};
pub use units::{DofUnit, Extent};
pub use variables::{Causality, Layout, Quantity, Variable, VariablesError};
