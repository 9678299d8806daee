//! Free-free hull-girder modes from the ship's mass and stiffness distributions.
//!
//! The girder is a beam along x on the stations' grid (one finite element between two
//! stations, each element with the mean of its two stations' data):
//!
//! ```text
//! vertical bending:    (EI_v w'')'' + m w_tt = 0        Hermite cubic elements (w, w')
//! horizontal bending:  (EI_h v'')'' + m v_tt = 0        the same, with EI_h
//! torsion:             (GJ theta')' - I_x theta_tt = 0  linear elements
//! ```
//!
//! with free ends (no support: the water and the master's model carry the ship). The
//! generalized eigenproblem `K phi = omega^2 M phi` (consistent mass) is solved through the
//! Cholesky factor of `M`; the rigid-body solutions (2 for bending: translation and rotation,
//! 1 for torsion) come first and are skipped. Each elastic mode is scaled to a largest
//! displacement of 1 m at the stations (1 rad for torsion), sign chosen so that it is positive
//! at the stern. Euler-Bernoulli, no shear deflection or rotary inertia, no coupling of
//! bending and torsion through a shear centre off the centreline: a first model of the
//! girder, for a scene that needs its lowest wet modes.

use nalgebra::{DMatrix, DVector};
use std::fmt;

/// One computed mode: shape at the stations and its dry modal properties.
#[derive(Clone, Debug, PartialEq)]
pub struct GirderMode {
    /// The displacement (m, or rad for torsion) at each station per unit amplitude.
    pub shape: Vec<f64>,
    /// Dry natural frequency, rad/s.
    pub natural_frequency: f64,
    /// Modal mass `phi^T M phi` (kg for bending, kg m^2 for torsion, per unit amplitude^2).
    pub modal_mass: f64,
    /// Modal stiffness `phi^T K phi = omega^2 modal_mass`.
    pub modal_stiffness: f64,
}

/// Which girder motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GirderKind {
    /// Vertical bending (w, along z).
    Vertical,
    /// Horizontal bending (v, along y).
    Horizontal,
    /// Torsion (theta, about x).
    Torsion,
}

/// Why [`modes`] found no modes.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum GirderError {
    /// Not one inertia and one stiffness per station.
    DataLength,
    /// A station's inertia or stiffness is not positive and finite.
    BadStation {
        /// 1-based station.
        station: usize,
        /// Its position, m.
        x: f64,
    },
    /// More modes asked than the stations carry.
    TooManyModes {
        /// The motion.
        kind: GirderKind,
        /// Modes asked.
        count: usize,
        /// Stations given.
        stations: usize,
        /// The most elastic modes they carry.
        most: usize,
    },
    /// The consistent mass matrix has no Cholesky factor.
    MassNotPositiveDefinite,
    /// Its Cholesky factor cannot be inverted.
    MassSingular,
    /// An elastic eigenvalue is not positive and finite.
    EigenvalueNotPositive {
        /// The motion.
        kind: GirderKind,
        /// 1-based elastic mode.
        mode: usize,
        /// The eigenvalue `omega^2`.
        eigenvalue: f64,
    },
}

impl fmt::Display for GirderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GirderError::DataLength => {
                f.write_str("one inertia and one stiffness per station are needed")
            }
            GirderError::BadStation { station, x } => write!(
                f,
                "station {station} at x = {x} m: the structural data must be positive and finite"
            ),
            GirderError::TooManyModes {
                kind,
                count,
                stations,
                most,
            } => write!(
                f,
                "{count} {kind:?} modes asked, but {stations} stations carry at most {most}"
            ),
            GirderError::MassNotPositiveDefinite => {
                f.write_str("the girder's mass matrix is not positive definite")
            }
            GirderError::MassSingular => f.write_str("the girder's mass matrix is singular"),
            GirderError::EigenvalueNotPositive {
                kind,
                mode,
                eigenvalue,
            } => write!(
                f,
                "{kind:?} mode {mode}: eigenvalue {eigenvalue} is not positive"
            ),
        }
    }
}

impl std::error::Error for GirderError {}

impl From<GirderError> for String {
    fn from(error: GirderError) -> String {
        error.to_string()
    }
}

/// The lowest `count` elastic free-free modes of a girder on stations `x` (increasing) with
/// per-station `inertia` (mass per length, or torsional inertia per length) and `stiffness`
/// (EI, or GJ).
///
/// # Errors
/// [`GirderError`]: fewer than 2 stations for torsion or 3 for bending (not enough elements for the modes
/// asked), more modes than the discretization has, data not positive and finite, or an
/// eigenproblem that fails.
pub fn modes(
    kind: GirderKind,
    x: &[f64],
    inertia: &[f64],
    stiffness: &[f64],
    count: usize,
) -> Result<Vec<GirderMode>, GirderError> {
    let n = x.len();
    if inertia.len() != n || stiffness.len() != n {
        return Err(GirderError::DataLength);
    }
    if let Some(k) = (0..n).find(|&k| {
        !(inertia[k].is_finite()
            && inertia[k] > 0.0
            && stiffness[k].is_finite()
            && stiffness[k] > 0.0)
    }) {
        return Err(GirderError::BadStation {
            station: k + 1,
            x: x[k],
        });
    }
    let (k_matrix, m_matrix, rigid, per_node) = match kind {
        GirderKind::Torsion => {
            let (k, m) = torsion_matrices(x, inertia, stiffness);
            (k, m, 1, 1)
        }
        _ => {
            let (k, m) = bending_matrices(x, inertia, stiffness);
            (k, m, 2, 2)
        }
    };
    let size = k_matrix.nrows();
    if count + rigid > size {
        return Err(GirderError::TooManyModes {
            kind,
            count,
            stations: n,
            most: size - rigid,
        });
    }
    let cholesky = m_matrix
        .clone()
        .cholesky()
        .ok_or(GirderError::MassNotPositiveDefinite)?;
    let l_inverse = cholesky
        .l()
        .try_inverse()
        .ok_or(GirderError::MassSingular)?;
    let reduced = &l_inverse * &k_matrix * l_inverse.transpose();
    let eigen = crate::numerics::symmetric_eigen(&reduced);
    let mut order: Vec<usize> = (0..size).collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let mut out = Vec::with_capacity(count);
    for &k in order.iter().skip(rigid).take(count) {
        let lambda = eigen.eigenvalues[k];
        if !(lambda.is_finite() && lambda > 0.0) {
            return Err(GirderError::EigenvalueNotPositive {
                kind,
                mode: out.len() + 1,
                eigenvalue: lambda,
            });
        }
        let phi: DVector<f64> = l_inverse.transpose() * eigen.eigenvectors.column(k);
        let mut shape: Vec<f64> = (0..n).map(|i| phi[i * per_node]).collect();
        let largest = shape.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let sign = if shape[0] < 0.0 { -1.0 } else { 1.0 };
        let scale = sign / largest;
        for v in &mut shape {
            *v *= scale;
        }
        let phi = phi * scale;
        let modal_mass = phi.dot(&(&m_matrix * &phi));
        let modal_stiffness = phi.dot(&(&k_matrix * &phi));
        out.push(GirderMode {
            shape,
            natural_frequency: lambda.sqrt(),
            modal_mass,
            modal_stiffness,
        });
    }
    Ok(out)
}

/// Hermite cubic beam elements, DOFs (w_i, w'_i) per node.
fn bending_matrices(x: &[f64], mass: &[f64], stiffness: &[f64]) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = x.len();
    let mut k = DMatrix::zeros(2 * n, 2 * n);
    let mut m = DMatrix::zeros(2 * n, 2 * n);
    for e in 0..n - 1 {
        let l = x[e + 1] - x[e];
        let ei = (stiffness[e] + stiffness[e + 1]) / 2.0;
        let mu = (mass[e] + mass[e + 1]) / 2.0;
        let ke = [
            [12.0, 6.0 * l, -12.0, 6.0 * l],
            [6.0 * l, 4.0 * l * l, -6.0 * l, 2.0 * l * l],
            [-12.0, -6.0 * l, 12.0, -6.0 * l],
            [6.0 * l, 2.0 * l * l, -6.0 * l, 4.0 * l * l],
        ];
        let me = [
            [156.0, 22.0 * l, 54.0, -13.0 * l],
            [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
            [54.0, 13.0 * l, 156.0, -22.0 * l],
            [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
        ];
        for a in 0..4 {
            for b in 0..4 {
                let (i, j) = (2 * e + a, 2 * e + b);
                k[(i, j)] += ei / (l * l * l) * ke[a][b];
                m[(i, j)] += mu * l / 420.0 * me[a][b];
            }
        }
    }
    (k, m)
}

/// Linear torsion elements, one rotation per node.
fn torsion_matrices(x: &[f64], inertia: &[f64], stiffness: &[f64]) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = x.len();
    let mut k = DMatrix::zeros(n, n);
    let mut m = DMatrix::zeros(n, n);
    for e in 0..n - 1 {
        let l = x[e + 1] - x[e];
        let gj = (stiffness[e] + stiffness[e + 1]) / 2.0;
        let ix = (inertia[e] + inertia[e + 1]) / 2.0;
        for (a, b, ks, ms) in [
            (0, 0, 1.0, 2.0),
            (0, 1, -1.0, 1.0),
            (1, 0, -1.0, 1.0),
            (1, 1, 1.0, 2.0),
        ] {
            k[(e + a, e + b)] += gj / l * ks;
            m[(e + a, e + b)] += ix * l / 6.0 * ms;
        }
    }
    (k, m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn uniform(n: usize, length: f64) -> Vec<f64> {
        (0..n)
            .map(|k| -length / 2.0 + length * k as f64 / (n - 1) as f64)
            .collect()
    }

    /// The uniform free-free beam: omega_n = (beta_n L)^2 sqrt(EI / (m L^4)), beta_1 L = 4.7300,
    /// beta_2 L = 7.8532; the shape cosh + cos - s (sinh + sin). Hermite elements converge at
    /// h^4 in frequency: 40 elements give 1e-6.
    #[test]
    fn a_uniform_beam_has_the_textbook_free_free_modes() {
        let (length, mass, ei) = (100.0, 2.0e4, 5.0e11);
        let x = uniform(41, length);
        let found = modes(GirderKind::Vertical, &x, &[mass; 41], &[ei; 41], 2).unwrap();
        for (mode, beta_l) in found
            .iter()
            .zip([4.730_040_744_862_704, 7.853_204_624_095_838])
        {
            let exact = beta_l * beta_l * (ei / (mass * length.powi(4))).sqrt();
            assert!(
                (mode.natural_frequency / exact - 1.0).abs() < 1e-5,
                "{} vs {exact}",
                mode.natural_frequency
            );
            assert!(
                (mode.modal_stiffness / mode.modal_mass - exact * exact).abs()
                    < 1e-4 * exact * exact
            );
        }
        // Shape of mode 1 against the analytic one (scaled to 1 at the ends).
        let beta_l = 4.730_040_744_862_704_f64;
        let s = (beta_l.cosh() - beta_l.cos()) / (beta_l.sinh() - beta_l.sin());
        let shape = |z: f64| z.cosh() + z.cos() - s * (z.sinh() + z.sin());
        for (xi, w) in x.iter().zip(&found[0].shape) {
            let exact = shape(beta_l * (xi / length + 0.5)) / shape(0.0);
            assert!((w - exact).abs() < 1e-5, "x = {xi}: {w} vs {exact}");
        }
        // Orthogonal to the rigid motions (uniform mass): no net force, no net moment.
        let h = length / 40.0;
        let trapezoid = |f: &dyn Fn(usize) -> f64| {
            (0..41)
                .map(|k| f(k) * if k == 0 || k == 40 { h / 2.0 } else { h })
                .sum::<f64>()
        };
        assert!(trapezoid(&|k| found[0].shape[k]).abs() < 1e-3 * length);
        assert!(trapezoid(&|k| found[0].shape[k] * x[k]).abs() < 1e-3 * length * length);
    }

    #[test]
    fn a_uniform_shaft_has_the_textbook_torsion_modes() {
        let (length, inertia, gj) = (100.0, 3.0e5, 1.0e12);
        let x = uniform(81, length);
        let found = modes(GirderKind::Torsion, &x, &[inertia; 81], &[gj; 81], 2).unwrap();
        for (n, mode) in found.iter().enumerate() {
            let exact = (n + 1) as f64 * PI / length * (gj / inertia).sqrt();
            // Linear elements: error (n pi h / L)^2 / 12 about, 2e-4 for mode 2 on 80 elements.
            assert!(
                (mode.natural_frequency / exact - 1.0).abs() < 3e-4,
                "{} vs {exact}",
                mode.natural_frequency
            );
            assert!((mode.shape[0] - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn bad_structural_data_names_the_station() {
        let x = uniform(5, 10.0);
        let e = modes(
            GirderKind::Vertical,
            &x,
            &[1.0, 1.0, f64::NAN, 1.0, 1.0],
            &[1.0; 5],
            1,
        )
        .unwrap_err();
        assert_eq!(e, GirderError::BadStation { station: 3, x: 0.0 });
        assert!(e.to_string().contains("station 3 at x = 0 m"), "{e}");
        let e = modes(GirderKind::Torsion, &x, &[1.0; 5], &[1.0; 5], 5).unwrap_err();
        assert!(
            matches!(e, GirderError::TooManyModes { most: 4, .. }),
            "{e:?}"
        );
        assert_eq!(
            String::from(e),
            "5 Torsion modes asked, but 5 stations carry at most 4"
        );
    }
}
