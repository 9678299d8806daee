//! # hydrofmu
//!
//! Hydrodynamic radiation forces on a partially submerged, flexible 2D hull section, as an
//! FMI 2.0 co-simulation unit, following Schilder et al., "Hydro-elasticity in flexible
//! multibody dynamics".
//!
//! The data flow runs one way, one module per stage:
//!
//! ```text
//! hull -> panels -> green -> bem -> sweep -> identify -> realize -> discretize -> model -> fmi2
//! ```
//!
//! Conventions (every module): 2D, per unit length of hull, SI units; x to the right, y up,
//! mean free surface y = 0, fluid in y < 0, infinite depth; time factor `exp(+i omega t)`;
//! wavenumber `k = omega^2 / g`; unit normal pointing out of the fluid into the body; complex
//! added mass `A~_ij(omega) = rho * integral n_i phi_j ds = a_ij - i b_ij / omega`.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod bem;
pub mod discretize;
pub mod fmi2;
pub mod fmu;
pub mod green;
pub mod hull;
pub mod identify;
pub mod model;
/// The fixed part of the FMU interface (now [`fmu::description`]; this path is kept).
pub mod model_description {
    pub use crate::fmu::description::*;
}
pub mod network;
pub mod numerics;
pub mod panels;
pub mod realize;
pub mod scene;
pub mod sweep;
pub mod units;
/// The per-hull FMU variables, units and GUID (now in [`fmu`]; this path is kept).
pub mod variables {
    pub use crate::fmu::description::DescriptionInfo;
    pub use crate::fmu::guid::{content_guid, sha256};
    pub use crate::fmu::units::DofUnit;
    pub use crate::fmu::variables::*;
}
pub mod xml;
