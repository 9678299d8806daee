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
pub mod green;
pub mod hull;
pub mod identify;
pub mod model;
pub mod model_description;
pub mod panels;
pub mod realize;
pub mod sweep;
pub mod variables;
