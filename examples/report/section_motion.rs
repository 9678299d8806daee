//! A floating section's motion per unit wave amplitude from a sweep, for the report generators.
//!
//! The equation of motion of `hydrofmu::motion` over the rigid DOFs (heading 0, SI per unit
//! length, `exp(+i omega t)`):
//!
//! ```text
//! [ -omega^2 (M + A~) + i omega B_ext + C + C_G + K_ext ] xi = X
//! ```
//!
//! with `A~ = rho pi R^2 added_mass` (the sweep's table already carries the DOFs' length
//! exponents), `X = rho g a R^(1 + e_j) direct`, `C` the hydrostatic restoring, the weight's roll
//! term `C_G = -m g (y_G - y_P)` and the mass matrix `M_ab = m u_a . u_b (+ m k^2 for roll)`, `u_j`
//! the displacement of G per unit DOF j (sway (1, 0), heave (0, 1), roll about its own reference
//! point P: `(-(y_G - y_P), x_G - x_P)`), so `M` is symmetric for any P.

use hydrofmu::hull::{DofKind, Hull, RigidKind};
use hydrofmu::motion::MassProperties;
use hydrofmu::sweep::SweepResult;
use nalgebra::{DMatrix, DVector};
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
    let rigid: Vec<(usize, RigidKind, [f64; 2])> = (0..hull.dof_count())
        .filter_map(|j| match hull.dof_kind(j) {
            Some(DofKind::Rigid { kind, reference }) => Some((j, kind, reference)),
            _ => None,
        })
        .collect();
    let n = rigid.len();
    let (m, [xg, yg], k) = (
        properties.mass,
        properties.centre_of_gravity,
        properties.radius_of_gyration,
    );
    let of_g = |kind: RigidKind, p: [f64; 2]| match kind {
        RigidKind::Sway => [1.0, 0.0],
        RigidKind::Heave => [0.0, 1.0],
        RigidKind::Roll => [-(yg - p[1]), xg - p[0]],
    };
    let statics = hydrofmu::hydrostatics::stiffness(hull).expect("hydrostatics");
    let external = |matrix: &DMatrix<f64>, a: usize, b: usize| {
        if matrix.is_empty() {
            0.0
        } else {
            matrix[(a, b)]
        }
    };
    let mut mass = DMatrix::zeros(n, n);
    let mut restoring = DMatrix::zeros(n, n);
    let mut damping = DMatrix::zeros(n, n);
    for (a, &(ja, kind_a, pa)) in rigid.iter().enumerate() {
        for (b, &(jb, kind_b, pb)) in rigid.iter().enumerate() {
            let (u, v) = (of_g(kind_a, pa), of_g(kind_b, pb));
            mass[(a, b)] = m * (u[0] * v[0] + u[1] * v[1]);
            restoring[(a, b)] = statics.stiffness_per_rho_g[(ja, jb)] * rho * g
                + external(&properties.stiffness, a, b);
            damping[(a, b)] = external(&properties.damping, a, b);
            if a == b && kind_a == RigidKind::Roll {
                mass[(a, b)] += m * k * k;
                restoring[(a, b)] -= m * g * (yg - pa[1]);
                damping[(a, b)] += extra_roll_damping;
            }
        }
    }
    let r = sweep.reference_half_beam;
    let area = std::f64::consts::PI * r * r;
    sweep
        .kr
        .iter()
        .zip(&sweep.added_mass)
        .zip(&sweep.excitation)
        .map(|((kr, added), forces)| {
            let omega = (kr * g / r).sqrt();
            let system = DMatrix::from_fn(n, n, |a, b| {
                let added = added[(rigid[a].0, rigid[b].0)] * rho * area;
                (added + mass[(a, b)]) * (-omega * omega)
                    + Complex64::new(0.0, omega * damping[(a, b)])
                    + restoring[(a, b)]
            });
            let force = DVector::from_fn(n, |a, _| {
                let j = rigid[a].0;
                forces.direct[(j, 0)] * rho * g * r.powi(1 + i32::from(sweep.length_exponents[j]))
            });
            let solved = system.lu().solve(&force).expect("a regular equation");
            let mut out = vec![Complex64::new(0.0, 0.0); hull.dof_count()];
            for (a, &(j, _, _)) in rigid.iter().enumerate() {
                out[j] = solved[a];
            }
            out
        })
        .collect()
}
