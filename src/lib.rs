//! # hydrofmu
//!
//! Hydrodynamic radiation and wave forces on partially submerged, flexible hulls, as an FMI 2.0
//! or FMI 3.0 co-simulation unit, following Schilder et al., "Hydro-elasticity in flexible
//! multibody dynamics". Its sources: 2D sections by the panel method (per unit length), ships
//! by zero-speed strip theory over their sections, and imported WAMIT or Capytaine 3D
//! databases. The FMU steps an equivalent mass-spring-damper network, and the incident waves
//! with their exciting force.
//!
//! ## The pipeline
//!
//! One stage a line, each with the module it lives in:
//!
//! ```text
//! source::Source        what the user names: a section, a ship file or a database file
//!   section:  hull::Hull -> sweep (panel method) -> database::section::SectionDatabase
//!   ship:     ship::Ship -> ship::strip::run (strip theory)
//!   database: database::import::import (WAMIT NAME.1, Capytaine NAME.nc)
//! database::Database    whole-body coefficients in SI; Database::response for the fit
//! identify::fit         a passive network fitted to the added mass over a band
//! network::Network      the mass-spring-damper network and its file format
//! fmu::Archive          the .fmu: model description, resources, binary, documentation
//! ```
//!
//! The types of every stage are re-exported here ([`Source`], [`Hull`], [`Ship`],
//! [`Database`], [`FitParams`], [`FitReport`], [`Network`], [`Archive`], [`Body`]). A section
//! may also go the short way through a [`Scene`] (hull, DOFs, band: sweep, response and fit in
//! one), a ship or an imported database through a [`scene::BodyScene`] (its database, DOFs,
//! band, tolerance and form: the checks, the fit and the scene report in one). The [`fmu::archive`] module documentation holds a compiled example of the whole
//! chain: it packs the built-in semicircle and `tests/data/wamit/sphere.1` into FMUs.
//!
//! The first two stages, from a file name to the data a fit takes:
//!
//! ```
//! use hydrofmu::database::import::{import, ImportParams};
//! use hydrofmu::{Database, Source};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let source = Source::from_argument("tests/data/wamit/sphere.1")?;
//! let database: Database = match &source {
//!     Source::Wamit(path) | Source::Capytaine(path) => import(path, &ImportParams::new())?,
//!     other => return Err(format!("not a database: {other:?}").into()),
//! };
//! let response = database.response();
//! assert_eq!(response.dof_names, database.dof_names);
//! assert!(!source.is_section() && source.is_import());
//! # Ok(())
//! # }
//! ```
//!
//! ## The modules
//!
//! - [`hull`]: the section contour and its DOFs ([`Hull`]);
//! - [`panels`]: the body and lid panels ([`PanelParams`]);
//! - [`green`]: the free-surface Green function;
//! - [`bem`]: the radiation problem at one frequency;
//! - [`sweep`]: added mass and damping over a frequency grid ([`SweepParams`], [`SweepResult`]);
//! - [`ship`]: ship files and strip theory ([`Ship`], [`ShipSweepParams`]);
//! - [`database`]: whole-body coefficients, WAMIT and Capytaine files ([`Database`]);
//! - [`identify`]: fits a passive network to the response ([`FrequencyResponse`],
//!   [`FitParams`], [`FitReport`]);
//! - [`network`]: the mass-spring-damper network and its file format ([`Network`]);
//! - [`realize`]: its matrices and first-order state space ([`StateSpace`]);
//! - [`discretize`]: the exact step over one communication interval (input held or ramped);
//! - [`model`]: the component that steps in time ([`Model`], [`ModelOptions`]).
//!
//! Beside the chain: [`hydrostatics`] gives the linear restoring of every DOF
//! ([`Hydrostatics`]), and [`waves`] the incident sea and its exciting force in the time domain,
//! from the exciting forces the sweep computes with the added mass. [`passivity`] checks a
//! network's passivity. A section's mean wave drift comes with every wave solve
//! ([`bem::Drift`]: far field and pressure integration, fixed section), [`motion`] gives a
//! floating section's rigid motion in regular waves from its mass properties (and with it the
//! floating sway drift), and the FMU adds the mean or slow drift force of its sea
//! ([`waves::DriftTable`]) from a section's or an imported database's drift table.
//!
//! [`scene`] drives hull to identify for one hull, DOF set and band ([`Scene`], [`Band`],
//! [`SceneReport`]). [`fmu`] (variables, model descriptions, resources, GUID, the archive) and
//! [`fmi`] (the exported C functions of FMI 2.0 and of FMI 3.0, over one instance) make the
//! FMU. [`input`] reads the user's files within bounds ([`FileError`], [`ReadError`]);
//! [`units`] and [`xml`] support every stage. [`viscous`] gives a section's roll damping by
//! Ikeda's components and its cross-flow drag.
//!
//! Conventions of a section (docs/DESIGN.md; ships and databases: [`database`]): 2D, per unit
//! length of hull, SI units; x to the right, y up, mean free surface y = 0, fluid in y < 0,
//! infinite depth; time factor `exp(+i omega t)`; wavenumber `k = omega^2 / g`; unit normal
//! pointing out of the fluid into the body; complex added mass
//! `A~_ij(omega) = rho * integral n_i phi_j ds = a_ij - i b_ij / omega`.
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
pub mod viscous;
pub mod waves;
pub mod xml;

pub use bem::BemError;
pub use database::{Database, DatabaseError};
pub use discretize::DiscretizeError;
pub use fmu::{
    Archive, ArchiveError, Body, FmiVersion, PackedNetwork, Resources, ResourcesError,
    VariablesError,
};
pub use green::GreenError;
pub use hull::{Hull, HullError};
pub use hydrostatics::{Hydrostatics, HydrostaticsError};
pub use identify::{FitParams, FitReport, FrequencyResponse, IdentifyError};
pub use input::{FileError, ReadError};
pub use model::{Model, ModelError, ModelOptions};
pub use network::{Branch, Network, NetworkError, NetworkForm, Stage};
pub use panels::{PanelError, PanelParams};
pub use realize::StateSpace;
pub use scene::{Band, Scene, SceneError, SceneReport};
pub use ship::{Ship, ShipError, ShipSweepParams};
pub use source::{Source, SourceError};
pub use sweep::{SweepError, SweepParams, SweepResult};
pub use xml::XmlError;
