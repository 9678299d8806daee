//! What makes the component an FMU: its variables and value references, their units, the
//! `modelDescription.xml` writer with the fixed parameters of `modelDescription/fixed.xml`,
//! the files of `resources/`, and the GUID.
//!
//! ```text
//! units -> variables (Layout: value references) -> description (modelDescription.xml)
//! resources (network.xml, options.xml, hull.xml) -> guid (content hash)
//! ```

pub mod description;
pub mod guid;
pub mod resources;
pub mod units;
pub mod variables;

pub use description::DescriptionInfo;
pub use guid::content_guid;
pub use resources::{Resources, ResourcesError};
pub use units::{DofUnit, Extent};
pub use variables::{Causality, Layout, Quantity, Variable, VariablesError};
