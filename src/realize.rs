//! Realizations of an equivalent network ([`Network`], defined in [`crate::network`]):
//! augmented matrices and a first-order state space.
//!
//! # Passive and reciprocal by construction
//!
//! With `x = [q; aux displacements]` the network has the energy function
//! `E = 1/2 sum_i m_i x_i'^2 + 1/2 sum_j k_j e_j^2` (`e_j` the elongation of spring `j`) and the
//! dissipation `D = sum_j c_j e_j'^2 >= 0`. Every spring and damper adds `k e e^T`, `c e e^T`
//! (`e` its incidence vector) to the augmented stiffness and damping matrices, so `M`, `C`, `K`
//! are symmetric positive semi-definite when all `m, k, c > 0` and `A_inf` is PSD. Then
//! `dE/dt = -F . q' - D`: the water network can never return more energy to the hull than the
//! hull put in (passivity), and the symmetric matrices give `H(s) = H(s)^T` (reciprocity).
//!
//! # Augmented matrices (Schilder et al., eq. 19 layout)
//!
//! [`Network::augmented_matrices`]: coordinates `[q (n); aux masses (branch by branch, stage by
//! stage)]`; the hull block of the mass matrix holds `m0 = A_inf` (the body's own mass is NOT
//! included: the master adds it). Schilder et al., eq. 19: `diag(m + m0, m1, m2)`, the chain's `C` and `K`.
//!
//! # State space (without the drifting hull coordinate)
//!
//! [`Network::state_space`]: state `z = [e (one elongation per spring); u (aux velocities)]`,
//! input the hull velocity `v = q'` (n), output the force on the hull by the water EXCLUDING
//! `-A_inf q''`. With `e = E_q q + E_x x_aux` (incidence), `K_s = diag(k)`, `C_s = diag(c)`,
//! `M_a = diag(m)`:
//!
//! ```text
//! e' = E_x u + E_q v
//! u' = -M_a^-1 E_x^T (K_s e + C_s (E_x u + E_q v))
//! F  = -E_q^T (K_s e + C_s (E_x u + E_q v))
//! ```
//!
//! so `A = [0, E_x; -M_a^-1 E_x^T K_s, -M_a^-1 E_x^T C_s E_x]`, `B = [E_q; -M_a^-1 E_x^T C_s E_q]`,
//! `C = [-E_q^T K_s, -E_q^T C_s E_x]`, `D = -E_q^T C_s E_q`. The transfer function is
//! `F(s) / v(s) = C (sI - A)^-1 B + D = -s (H(s) - A_inf)`. Stored energy `E = 1/2 z^T P z`,
//! `P = diag(K_s, M_a)`; `dE/dt = -F . v - e'^T C_s e'`. `damping_direct = -D` (symmetric PSD).
//! `A` is Hurwitz (every mode of the network clamped at the hull is damped).
//!
//! Substructures ([`crate::network::Substructure`]) follow the branches: their states are their
//! energy coordinates divided by `sqrt(rho)` (so that, as for the branches, `P` and, at a fixed
//! state, `C` and `D` are proportional to rho), `P = rho I` on them, and their inputs are the
//! n hull velocities (n rows of the identity in `branch_directions`).

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use crate::network::{Network, NetworkError, Stage};

/// Augmented mass, damping and stiffness matrices (Schilder et al., eq. 19 layout, hull DOFs first).
#[derive(Clone, Debug, PartialEq)]
pub struct AugmentedMatrices {
    /// `diag(A_inf, aux masses)`.
    pub mass: DMatrix<f64>,
    /// Sum of `c e e^T` over the dampers.
    pub damping: DMatrix<f64>,
    /// Sum of `k e e^T` over the springs.
    pub stiffness: DMatrix<f64>,
}

/// First-order realization without the hull coordinate (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct StateSpace {
    /// State matrix (2N x 2N), N auxiliary masses.
    pub a: DMatrix<f64>,
    /// Input matrix (2N x n), input the hull velocity.
    pub b: DMatrix<f64>,
    /// Output matrix (n x 2N), output the force on the hull (without `-A_inf q''`).
    pub c: DMatrix<f64>,
    /// Direct feedthrough (n x n), `-damping_direct`.
    pub d: DMatrix<f64>,
    /// `P` in `E = 1/2 z^T P z`.
    pub energy_weight: DMatrix<f64>,
    /// Damper of each spring (elongation order), for the dissipation `e'^T diag(c) e'`.
    pub elongation_damping: DVector<f64>,
    /// Branch directions as rows (r x n, r branches). A branch feels the hull only through
    /// `d_b . v`, so `B = b_branch * branch_directions` and `C = branch_directions^T *
    /// c_branch`: a step then costs O(r n + nonzeros of A) instead of O(2N n).
    pub branch_directions: DMatrix<f64>,
    /// Input matrix per branch speed `d_b . v` (2N x r).
    pub b_branch: DMatrix<f64>,
    /// Force along each branch direction (r x 2N).
    pub c_branch: DMatrix<f64>,
    /// The states of each branch (its elongations, then its aux velocities), then of each
    /// substructure. `A` couples no two of these groups, and column (row) r of `b_branch`
    /// (`c_branch`) is zero outside the group whose `branch_inputs` hold r.
    pub branch_states: Vec<Vec<usize>>,
    /// The inputs (rows of `branch_directions`) of each group: one per branch; for a
    /// substructure, the hull velocities along an orthonormal basis of the motions it acts on.
    pub branch_inputs: Vec<std::ops::Range<usize>>,
    /// The substructures, each with its first state and the factor from the state to its
    /// energy coordinates (`sqrt(rho)`).
    pub substructures: Vec<(usize, crate::network::Substructure, f64)>,
}

/// Singular values of a substructure's coupling below this fraction of the largest are
/// directions of hull motion it does not act on.
const SUBSTRUCTURE_SPAN: f64 = 1e-12;

/// An orthonormal basis (n x k) of the hull motions a substructure acts on: the column space
/// of `[B^T C]` (equal spaces for a reciprocal substructure). Its inputs are the k velocities
/// `Q^T v` and its force `Q f`, so a step costs `m (m + k)`, not `m (m + n)`; the columns
/// left out carry below [`SUBSTRUCTURE_SPAN`] of the coupling. For a mirror-symmetric hull,
/// each of the rational fit's parts acts on the symmetric or the antisymmetric motions only.
fn acted_on(b: &DMatrix<f64>, c: &DMatrix<f64>) -> DMatrix<f64> {
    let n = c.nrows();
    let mut coupling = DMatrix::zeros(n, b.nrows() + c.ncols());
    coupling
        .view_mut((0, 0), (n, b.nrows()))
        .copy_from(&b.transpose());
    coupling
        .view_mut((0, b.nrows()), (n, c.ncols()))
        .copy_from(c);
    // No decomposition (the bounded iteration stopped): every motion, exact at a higher cost.
    let Some(svd) = crate::numerics::svd(coupling, true, false) else {
        return DMatrix::identity(n, n);
    };
    let largest = svd.singular_values.amax();
    let u = svd.u.expect("the SVD was asked for U");
    let kept: Vec<usize> = (0..svd.singular_values.len())
        .filter(|&i| largest > 0.0 && svd.singular_values[i] > SUBSTRUCTURE_SPAN * largest)
        .collect();
    DMatrix::from_fn(n, kept.len(), |i, c| u[(i, kept[c])])
}

/// `C (sI - A)^-1 B + D` of any real state-space model (NaN entries when `sI - A` is
/// singular).
pub fn transfer_function(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    c: &DMatrix<f64>,
    d: &DMatrix<f64>,
    s: Complex64,
) -> DMatrix<Complex64> {
    let n = a.nrows();
    let d = d.map(|x| Complex64::new(x, 0.0));
    if n == 0 {
        return d;
    }
    let mut shifted = a.map(|x| Complex64::new(-x, 0.0));
    for i in 0..n {
        shifted[(i, i)] += s;
    }
    let b = b.map(|x| Complex64::new(x, 0.0));
    let c = c.map(|x| Complex64::new(x, 0.0));
    match shifted.lu().solve(&b) {
        Some(x) => c * x + d,
        None => DMatrix::from_element(d.nrows(), d.ncols(), Complex64::new(f64::NAN, 0.0)),
    }
}

impl StateSpace {
    /// Number of states (2 x auxiliary masses).
    pub fn state_count(&self) -> usize {
        self.a.nrows()
    }

    /// Number of hull DOFs.
    pub fn input_count(&self) -> usize {
        self.b.ncols()
    }

    /// Transfer function `F(s) / v(s) = C (sI - A)^-1 B + D`.
    pub fn transfer(&self, s: Complex64) -> DMatrix<Complex64> {
        transfer_function(&self.a, &self.b, &self.c, &self.d, s)
    }

    /// Direct velocity feedthrough as a damping matrix: `-D` (symmetric PSD).
    pub fn damping_direct(&self) -> DMatrix<f64> {
        -&self.d
    }

    /// Stored energy `1/2 z^T P z`.
    pub fn energy(&self, z: &DVector<f64>) -> f64 {
        0.5 * z.dot(&(&self.energy_weight * z))
    }

    /// Force on the hull (without `-A_inf q''`) for state `z` and hull velocity `v`.
    pub fn force(&self, z: &DVector<f64>, v: &DVector<f64>) -> DVector<f64> {
        &self.c * z + &self.d * v
    }

    /// Time derivative of the state.
    pub fn derivative(&self, z: &DVector<f64>, v: &DVector<f64>) -> DVector<f64> {
        &self.a * z + &self.b * v
    }

    /// Dissipated power (>= 0): `e'^T diag(c) e'` of the branches' dampers, and per
    /// substructure `e^T R e + [u; v]^T C [u; v]`.
    pub fn dissipation(&self, z: &DVector<f64>, v: &DVector<f64>) -> f64 {
        let rates = self.derivative(z, v);
        let branches: f64 = self
            .elongation_damping
            .iter()
            .enumerate()
            .map(|(j, c)| c * rates[j] * rates[j])
            .sum();
        let substructures: f64 = self
            .substructures
            .iter()
            .map(|(first, sub, factor)| {
                let ns = sub.spring_count();
                let e = z.rows(*first, ns) * *factor;
                let mut uv = DVector::zeros(sub.damping.nrows());
                uv.rows_mut(0, sub.masses)
                    .copy_from(&(z.rows(first + ns, sub.masses) * *factor));
                uv.rows_mut(sub.masses, v.len()).copy_from(v);
                e.dot(&(&sub.spring_relaxation * &e)) + uv.dot(&(&sub.damping * &uv))
            })
            .sum();
        branches + substructures
    }
}

impl Network {
    /// Incidence rows of all springs over `[q; aux]` and their (stiffness, damping, mass).
    fn springs(&self) -> (DMatrix<f64>, Vec<Stage>) {
        let n = self.dof_count();
        let na: usize = self.branches.iter().map(|b| b.stages.len()).sum();
        let mut incidence = DMatrix::zeros(na, n + na);
        let mut stages = Vec::with_capacity(na);
        let mut row = 0;
        for branch in &self.branches {
            for (j, stage) in branch.stages.iter().enumerate() {
                if j == 0 {
                    for i in 0..n.min(branch.direction.len()) {
                        incidence[(row, i)] = -branch.direction[i];
                    }
                } else {
                    incidence[(row, n + row - 1)] = -1.0;
                }
                incidence[(row, n + row)] = 1.0;
                stages.push(*stage);
                row += 1;
            }
        }
        (incidence, stages)
    }

    /// Augmented `M`, `C`, `K` over `[q; aux masses]` (Schilder et al., eq. 19; body mass not included),
    /// for the branches; a network with substructures is refused (a relaxed spring has no
    /// place in `M`, `C`, `K`).
    pub fn augmented_matrices(&self) -> Result<AugmentedMatrices, NetworkError> {
        if !self.substructures.is_empty() {
            return Err(NetworkError::Invalid(
                "augmented matrices cover branches only; this network has substructures".into(),
            ));
        }
        let n = self.dof_count();
        let (incidence, stages) = self.springs();
        let total = incidence.ncols();
        let mut mass = DMatrix::zeros(total, total);
        mass.view_mut((0, 0), (n, n))
            .copy_from(&self.added_mass_inf.view((0, 0), (n, n)));
        let mut damping = DMatrix::zeros(total, total);
        let mut stiffness = DMatrix::zeros(total, total);
        for (j, stage) in stages.iter().enumerate() {
            mass[(n + j, n + j)] = stage.mass;
            let e = incidence.row(j);
            let outer = e.transpose() * e;
            damping += &outer * stage.damping;
            stiffness += &outer * stage.stiffness;
        }
        Ok(AugmentedMatrices {
            mass,
            damping,
            stiffness,
        })
    }

    /// First-order realization (see the module docs). Validates the network first.
    pub fn state_space(&self) -> Result<StateSpace, NetworkError> {
        self.validate()?;
        let n = self.dof_count();
        let (incidence, stages) = self.springs();
        let na = stages.len();
        let e_q = incidence.columns(0, n).into_owned();
        let e_x = incidence.columns(n, na).into_owned();
        let k_s = DVector::from_iterator(na, stages.iter().map(|s| s.stiffness));
        let c_s = DVector::from_iterator(na, stages.iter().map(|s| s.damping));
        let inv_m = DVector::from_iterator(na, stages.iter().map(|s| 1.0 / s.mass));
        let k_diag = DMatrix::from_diagonal(&k_s);
        let c_diag = DMatrix::from_diagonal(&c_s);
        let inv_m_diag = DMatrix::from_diagonal(&inv_m);

        let mut a = DMatrix::zeros(2 * na, 2 * na);
        a.view_mut((0, na), (na, na)).copy_from(&e_x);
        let ext_k = e_x.transpose() * &k_diag;
        let ext_c = e_x.transpose() * &c_diag;
        a.view_mut((na, 0), (na, na))
            .copy_from(&(-&inv_m_diag * &ext_k));
        a.view_mut((na, na), (na, na))
            .copy_from(&(-&inv_m_diag * &ext_c * &e_x));
        let mut b = DMatrix::zeros(2 * na, n);
        b.view_mut((0, 0), (na, n)).copy_from(&e_q);
        b.view_mut((na, 0), (na, n))
            .copy_from(&(-&inv_m_diag * &ext_c * &e_q));
        let eqt_c = e_q.transpose() * &c_diag;
        let mut c = DMatrix::zeros(n, 2 * na);
        c.view_mut((0, 0), (n, na))
            .copy_from(&(-(e_q.transpose() * &k_diag)));
        c.view_mut((0, na), (n, na)).copy_from(&(-&eqt_c * &e_x));
        let mut d = -&eqt_c * &e_q;
        // Exact symmetry of the feedthrough (it is c d d^T summed).
        d = (&d + d.transpose()) * 0.5;
        let mut energy_weight = DMatrix::zeros(2 * na, 2 * na);
        for j in 0..na {
            energy_weight[(j, j)] = k_s[j];
            energy_weight[(na + j, na + j)] = stages[j].mass;
        }
        // e_q = S P: the first spring of branch b has the hull row -d_b^T.
        let r = self.branches.len();
        let mut branch_directions = DMatrix::zeros(r, n);
        let mut select = DMatrix::zeros(na, r);
        let mut branch_states = Vec::with_capacity(r);
        let mut row = 0;
        for (b_index, branch) in self.branches.iter().enumerate() {
            for i in 0..n.min(branch.direction.len()) {
                branch_directions[(b_index, i)] = branch.direction[i];
            }
            select[(row, b_index)] = -1.0;
            let stages = row..row + branch.stages.len();
            branch_states.push(stages.clone().chain(stages.map(|j| na + j)).collect());
            row += branch.stages.len();
        }
        let mut b_branch = DMatrix::zeros(2 * na, r);
        b_branch.view_mut((0, 0), (na, r)).copy_from(&select);
        b_branch
            .view_mut((na, 0), (na, r))
            .copy_from(&(-&inv_m_diag * &ext_c * &select));
        let mut c_branch = DMatrix::zeros(r, 2 * na);
        c_branch
            .view_mut((0, 0), (r, na))
            .copy_from(&(-(select.transpose() * &k_diag)));
        c_branch
            .view_mut((0, na), (r, na))
            .copy_from(&(-(select.transpose() * &c_diag) * &e_x));
        let mut branch_inputs: Vec<std::ops::Range<usize>> = (0..r).map(|j| j..j + 1).collect();
        // Substructures: their states after the branches', their inputs the hull velocities
        // in the subspace the substructure acts on.
        let extra: usize = self.substructures.iter().map(|sub| sub.state_count()).sum();
        let root_rho = self.rho.sqrt();
        let realizations: Vec<_> = self
            .substructures
            .iter()
            .map(|sub| {
                let z = sub.impedance_realization();
                let (b_sub, c_sub) = (&z.b / root_rho, -&z.c * root_rho);
                let span = acted_on(&b_sub, &c_sub);
                (z, b_sub, c_sub, span)
            })
            .collect();
        let (total, inputs) = (
            2 * na + extra,
            r + realizations.iter().map(|x| x.3.ncols()).sum::<usize>(),
        );
        let grow = |m: &DMatrix<f64>, rows: usize, cols: usize| {
            let mut out = DMatrix::zeros(rows, cols);
            out.view_mut((0, 0), (m.nrows(), m.ncols())).copy_from(m);
            out
        };
        let mut a = grow(&a, total, total);
        let mut b = grow(&b, total, n);
        let mut c = grow(&c, n, total);
        let mut energy_weight = grow(&energy_weight, total, total);
        let mut branch_directions = grow(&branch_directions, inputs, n);
        let mut b_branch = grow(&b_branch, total, inputs);
        let mut c_branch = grow(&c_branch, inputs, total);
        let mut substructures = Vec::with_capacity(self.substructures.len());
        let (mut first, mut input) = (2 * na, r);
        // State = energy coordinates / sqrt(rho) (module docs).
        for (sub, (z, b_sub, c_sub, span)) in self.substructures.iter().zip(&realizations) {
            let (m, k) = (sub.state_count(), span.ncols());
            a.view_mut((first, first), (m, m)).copy_from(&z.a);
            b.view_mut((first, 0), (m, n)).copy_from(b_sub);
            c.view_mut((0, first), (n, m)).copy_from(c_sub);
            d -= &z.d;
            energy_weight
                .view_mut((first, first), (m, m))
                .copy_from(&DMatrix::from_diagonal_element(m, m, self.rho));
            branch_directions
                .view_mut((input, 0), (k, n))
                .copy_from(&span.transpose());
            b_branch
                .view_mut((first, input), (m, k))
                .copy_from(&(b_sub * span));
            c_branch
                .view_mut((input, first), (k, m))
                .copy_from(&(span.transpose() * c_sub));
            branch_states.push((first..first + m).collect());
            branch_inputs.push(input..input + k);
            substructures.push((first, sub.clone(), root_rho));
            first += m;
            input += k;
        }
        let d = (&d + d.transpose()) * 0.5;
        Ok(StateSpace {
            a,
            b,
            c,
            d,
            energy_weight,
            elongation_damping: c_s,
            branch_directions,
            b_branch,
            c_branch,
            branch_states,
            branch_inputs,
            substructures,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::tests::{coupled_network, max_abs_diff, seed_network};

    #[test]
    fn state_space_transfer_matches_network() {
        let with_substructure = Network::from_xml_str(
            &crate::model::tests::two_dof_substructure_network(),
            "substructure.xml",
        )
        .unwrap()
        .scaled(1025.0, 9.81);
        for net in [seed_network(), coupled_network(), with_substructure] {
            let ss = net.state_space().unwrap();
            assert_eq!(ss.state_count(), net.state_count());
            for &omega in &[0.05, 0.4, 1.0, 2.5, 10.0] {
                let s = Complex64::new(0.0, omega);
                let from_ss = ss.transfer(s);
                let h = net.added_mass_at(s);
                let a_inf = net.added_mass_inf.map(|x| Complex64::new(x, 0.0));
                let expected = (h - a_inf) * (-s);
                let scale = expected.iter().map(|x| x.norm()).fold(0.0, f64::max);
                // Two evaluations of one rational function: agree to rounding.
                assert!(max_abs_diff(&from_ss, &expected) < 1e-11 * scale.max(1.0));
            }
            // Feedthrough = -(sum of first dampers d d^T and the substructures' C_vv),
            // symmetric PSD.
            let dd = ss.damping_direct();
            let n = net.dof_count();
            let mut expected = DMatrix::zeros(n, n);
            for b in &net.branches {
                expected += &b.direction * b.direction.transpose() * b.stages[0].damping;
            }
            for sub in &net.substructures {
                expected += sub.damping.view((sub.masses, sub.masses), (n, n));
            }
            assert!((dd - &expected).amax() < 1e-13 * expected.amax());
            // The branch factorization reconstructs B and C (the stepper relies on it).
            let b = &ss.b_branch * &ss.branch_directions;
            let c = ss.branch_directions.transpose() * &ss.c_branch;
            assert!((b - &ss.b).amax() < 1e-14 * ss.b.amax().max(1.0));
            assert!((c - &ss.c).amax() < 1e-14 * ss.c.amax().max(1.0));
            assert_eq!(
                ss.branch_directions.nrows(),
                net.branches.len() + n * net.substructures.len()
            );
            // The blocks: A, B_r and C_r have nothing outside them.
            let mut owner = vec![usize::MAX; ss.state_count()];
            for (b, states) in ss.branch_states.iter().enumerate() {
                for &i in states {
                    assert_eq!(owner[i], usize::MAX, "state {i} in two branches");
                    owner[i] = b;
                }
            }
            for i in 0..ss.state_count() {
                for j in 0..ss.state_count() {
                    if owner[i] != owner[j] {
                        assert_eq!(ss.a[(i, j)], 0.0);
                    }
                }
                for (b, inputs) in ss.branch_inputs.iter().enumerate() {
                    for r in inputs.clone() {
                        if owner[i] != b {
                            assert_eq!(ss.b_branch[(i, r)], 0.0);
                            assert_eq!(ss.c_branch[(r, i)], 0.0);
                        }
                    }
                }
            }
            // Every mode decays.
            let eig = ss.a.complex_eigenvalues();
            assert!(eig.iter().all(|l| l.re < 0.0), "{eig}");
        }
    }

    #[test]
    fn augmented_matrices_match_eq19_and_are_psd() {
        let net = seed_network();
        let aug = net.augmented_matrices().unwrap();
        let (k1, k2, c1, c2) = (0.2339, 0.5522, 0.9962, 0.2453);
        let k = DMatrix::from_row_slice(3, 3, &[k1, -k1, 0.0, -k1, k1 + k2, -k2, 0.0, -k2, k2]);
        let c = DMatrix::from_row_slice(3, 3, &[c1, -c1, 0.0, -c1, c1 + c2, -c2, 0.0, -c2, c2]);
        assert!((aug.stiffness - k).amax() < 1e-15);
        assert!((aug.damping - c).amax() < 1e-15);
        assert_eq!(
            aug.mass,
            DMatrix::from_diagonal(&DVector::from_vec(vec![0.1153, 0.5434, 0.1877]))
        );
        let aug = coupled_network().augmented_matrices().unwrap();
        for m in [&aug.mass, &aug.damping, &aug.stiffness] {
            assert!((m - m.transpose()).amax() < 1e-15);
            assert!(m.clone().symmetric_eigenvalues().min() > -1e-12);
        }
    }

    /// RK4 on y' = f(y).
    fn rk4<F: Fn(&DVector<f64>) -> DVector<f64>>(f: &F, y: &DVector<f64>, h: f64) -> DVector<f64> {
        let k1 = f(y);
        let k2 = f(&(y + &k1 * (h / 2.0)));
        let k3 = f(&(y + &k2 * (h / 2.0)));
        let k4 = f(&(y + &k3 * h));
        y + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
    }

    #[test]
    fn seed_impulse_response_reaches_common_velocity() {
        // Schilder et al., eq. 19 with body mass m = 1 and a unit impulse on the body.
        let net = seed_network();
        let aug = net.augmented_matrices().unwrap();
        let mut mass = aug.mass.clone();
        mass[(0, 0)] += 1.0;
        let inv_m = mass.clone().try_inverse().unwrap();
        let nt = 3;
        let f = |y: &DVector<f64>| {
            let x = y.rows(0, nt);
            let v = y.rows(nt, nt);
            let acc = &inv_m * (-(&aug.damping * v) - &aug.stiffness * x);
            let mut out = DVector::zeros(2 * nt);
            out.rows_mut(0, nt).copy_from(&v);
            out.rows_mut(nt, nt).copy_from(&acc);
            out
        };
        let mut y = DVector::zeros(2 * nt);
        y[nt] = 1.0 / (1.0 + 0.1153);
        // Same motion from the state space: (m + A_inf) v' = F_ss, z' = A z + B v.
        let ss = net.state_space().unwrap();
        let nz = ss.state_count();
        let g = |w: &DVector<f64>| {
            let z = w.rows(0, nz).into_owned();
            let v = w.rows(nz, 1).into_owned();
            let mut out = DVector::zeros(nz + 1);
            out.rows_mut(0, nz).copy_from(&ss.derivative(&z, &v));
            out[nz] = ss.force(&z, &v)[0] / (1.0 + 0.1153);
            out
        };
        let mut w = DVector::zeros(nz + 1);
        w[nz] = 1.0 / (1.0 + 0.1153);
        let h = 0.01;
        let mut max_gap: f64 = 0.0;
        for _ in 0..30_000 {
            y = rk4(&f, &y, h);
            w = rk4(&g, &w, h);
            max_gap = max_gap.max((y[nt] - w[nz]).abs());
        }
        let expected = 1.0 / (1.0 + 0.1153 + 0.5434 + 0.1877);
        for i in 0..nt {
            // After t = 300 every mode has decayed far below 1e-9.
            assert!(
                (y[nt + i] - expected).abs() < 1e-9,
                "{} vs {expected}",
                y[nt + i]
            );
        }
        // Both realizations integrate the same ODE with RK4 at h = 0.01.
        assert!(max_gap < 1e-8, "{max_gap}");
        // Momentum is conserved exactly by the augmented system.
        let momentum = (&mass * y.rows(nt, nt)).sum();
        assert!((momentum - 1.0).abs() < 1e-12);
    }

    #[test]
    fn energy_identity_by_finite_differences() {
        let net = coupled_network();
        let ss = net.state_space().unwrap();
        let velocity = |t: f64| {
            DVector::from_vec(vec![
                (1.3 * t).sin() + 0.2,
                (0.7 * t + 1.0).cos(),
                0.5 * (2.1 * t).sin() * (0.3 * t).cos(),
            ])
        };
        let nz = ss.state_count();
        let f = |y: &DVector<f64>| {
            let z = y.rows(0, nz).into_owned();
            let v = velocity(y[nz]);
            let mut out = DVector::zeros(nz + 1);
            out.rows_mut(0, nz).copy_from(&ss.derivative(&z, &v));
            out[nz] = 1.0;
            out
        };
        let h = 1e-3;
        let mut y = DVector::zeros(nz + 1);
        let mut history = Vec::new();
        for _ in 0..6000 {
            history.push(y.clone());
            y = rk4(&f, &y, h);
        }
        for k in (100..5900).step_by(500) {
            let e = |y: &DVector<f64>| ss.energy(&y.rows(0, nz).into_owned());
            let de_dt = (e(&history[k + 1]) - e(&history[k - 1])) / (2.0 * h);
            let z = history[k].rows(0, nz).into_owned();
            let v = velocity(history[k][nz]);
            let rhs = -ss.force(&z, &v).dot(&v) - ss.dissipation(&z, &v);
            // Central difference of a smooth trajectory: O(h^2) ~ 1e-6 relative.
            assert!(
                (de_dt - rhs).abs() < 1e-5 * (1.0 + rhs.abs()),
                "{de_dt} vs {rhs}"
            );
        }
    }
}
