//! A floating section's motion per unit wave amplitude from a sweep, for the report generators:
//! [`hydrofmu::motion::Floating`] at heading 0, with extra roll damping.

use hydrofmu::hull::{DofKind, Hull, RigidKind};
use hydrofmu::motion::{Floating, MassProperties};
use hydrofmu::sweep::SweepResult;
use nalgebra::DMatrix;
use num_complex::Complex64;

/// The motion per unit amplitude of every DOF of `hull` (elastic ones held at zero) at each
/// frequency of `sweep`, heading 0, with `extra_roll_damping` (N m s per m) added to every roll
/// DOF: m per m for a translation, rad per m for a rotation.
pub fn motions(
    hull: &Hull,
    properties: &MassProperties,
    sweep: &SweepResult,
    rho: f64,
    g: f64,
    extra_roll_damping: f64,
) -> Vec<Vec<Complex64>> {
    let rigid: Vec<RigidKind> = (0..hull.dof_count())
        .filter_map(|j| match hull.dof_kind(j) {
            Some(DofKind::Rigid { kind, .. }) => Some(kind),
            _ => None,
        })
        .collect();
    let n = rigid.len();
    let mut properties = properties.clone();
    if properties.damping.is_empty() {
        properties.damping = DMatrix::zeros(n, n);
    }
    for (a, kind) in rigid.iter().enumerate() {
        if *kind == RigidKind::Roll {
            properties.damping[(a, a)] += extra_roll_damping;
        }
    }
    let statics = hydrofmu::hydrostatics::stiffness(hull).expect("hydrostatics");
    let floating = Floating::new(hull, &statics, &properties, rho, g).expect("mass properties");
    floating
        .sweep_raos(sweep)
        .expect("a regular equation of motion")
        .iter()
        .map(|rao| rao.column(0).iter().copied().collect())
        .collect()
}
