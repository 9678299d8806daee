//! # hydrofmu
//!
//! Hydrodynamic radiation forces on a partially submerged, flexible 2D hull section, as an
//! FMI 2.0 co-simulation unit, following Schilder et al., "Hydro-elasticity in flexible
//! multibody dynamics".
//!
//! The data flow runs one way, one module per stage:
//!
//! ```text
//! hull -> panels -> green -> bem -> sweep -> identify -> network -> realize -> discretize -> model
//! ```
//!
//! - [`hull`]: the section contour and its DOFs ([`Hull`]);
//! - [`panels`]: the body and lid panels ([`PanelParams`]);
//! - [`green`]: the free-surface Green function;
//! - [`bem`]: the radiation problem at one frequency;
//! - [`sweep`]: added mass and damping over a frequency grid ([`SweepParams`], [`SweepResult`]);
//! - [`identify`]: fits a passive network to the response ([`FrequencyResponse`],
//!   [`FitParams`], [`FitReport`]);
//! - [`network`]: the mass-spring-damper network and its file format ([`Network`]);
//! - [`realize`]: its matrices and first-order state space ([`StateSpace`]);
//! - [`discretize`]: the exact step over one communication interval (input held or ramped);
//! - [`model`]: the component that steps in time ([`Model`], [`ModelOptions`]).
//!
//! Beside the chain: [`hydrostatics`] gives the linear restoring of every DOF
//! ([`Hydrostatics`]), and [`waves`] the incident sea and its exciting force in the time domain,
//! from the exciting forces the sweep computes with the added mass.
//!
//! [`scene`] drives hull to identify for one hull, DOF set and band ([`Scene`], [`Band`],
//! [`SceneReport`]). [`fmu`] (variables, model descriptions, resources, GUID) and [`fmi`] (the
//! exported C functions of FMI 2.0 and of FMI 3.0, over one instance) make the FMU. [`units`] and [`xml`] support every stage.
//!
//! Conventions (every module): 2D, per unit length of hull, SI units; x to the right, y up,
//! mean free surface y = 0, fluid in y < 0, infinite depth; time factor `exp(+i omega t)`;
//! wavenumber `k = omega^2 / g`; unit normal pointing out of the fluid into the body; complex
//! added mass `A~_ij(omega) = rho * integral n_i phi_j ds = a_ij - i b_ij / omega`.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod bem;
pub mod database;
pub mod discretize;
pub mod fmi;
pub mod fmu;
pub mod green;
pub mod hull;
pub mod hydrostatics;
pub mod identify;
pub mod input;
pub mod model;
pub mod motion;
pub mod network;
pub(crate) mod numerics;
pub mod panels;
pub mod passivity;
pub mod realize;
pub mod scene;
pub mod ship;
pub mod source;
pub mod sweep;
pub mod units;
pub mod waves;
pub mod xml;

pub use bem::BemError;
pub use discretize::DiscretizeError;
pub use fmu::{Resources, ResourcesError, VariablesError};
pub use green::GreenError;
pub use hull::{Hull, HullError};
pub use hydrostatics::{Hydrostatics, HydrostaticsError};
pub use identify::{FitParams, FitReport, FrequencyResponse, IdentifyError};
pub use model::{Model, ModelError, ModelOptions};
pub use network::{Branch, Network, NetworkError, NetworkForm, Stage};
pub use panels::{PanelError, PanelParams};
pub use realize::StateSpace;
pub use scene::{Band, Scene, SceneError, SceneReport};
pub use sweep::{SweepError, SweepParams, SweepResult};
pub use xml::XmlError;
