//! Equivalent mass-spring-damper networks: transfer function, augmented matrices, state space,
//! and the network XML file.
//!
//! # The network
//!
//! The water around the hull is replaced by a mechanical network (seed, section 4, Figure 5).
//! The hull has `n` generalized coordinates `q` (one per DOF). Rigidly attached to them is the
//! mass matrix `m0 = A_inf` (n x n, symmetric positive semi-definite). Further there is a set of
//! *branches*. Branch `b` acts along a direction `d_b` (an n-vector; a unit vector `e_j` for the
//! single-DOF forms) and is a chain of stages: stage 1 is a spring `k_1` in parallel with a
//! damper `c_1` between the hull coordinate `x_0 = d_b^T q` and the auxiliary mass `m_1`; stage
//! `j` connects `m_(j-1)` to `m_j` through `k_j`, `c_j`. The hull feels `d_b f_b`, with `f_b` the
//! force of the first spring and damper.
//!
//! * Series chain ([`NetworkForm::SeriesChain`]): one DOF, one branch with a chain of K masses.
//! * Parallel bank ([`NetworkForm::ParallelBank`]): one DOF, K branches of one mass each.
//! * Coupled ([`NetworkForm::Coupled`]): n DOFs, branches along general directions `d_b`.
//!
//! # Transfer function
//!
//! With the Laplace variable `s` (time factor `exp(+i omega t)`, so `s = i omega`), a chain seen
//! from its attachment point has the dynamic mass `G(s) = f / (s^2 x_0)` (force the attachment
//! point applies to the chain over its acceleration), computed from the far end:
//!
//! ```text
//! G_(K+1) = 0,   M_j = m_j + G_(j+1),   Z_j = k_j + c_j s,   G_j = M_j Z_j / (Z_j + s^2 M_j),
//! H(s) = A_inf + sum_b d_b d_b^T G_b,1(s).
//! ```
//!
//! `H(s)` is the seed's `H~(s) = F / (s^2 x_0)` (eq. 16) for every DOF pair: the force on the
//! hull by the water is `F = -s^2 H(s) q`, and in the time domain (Cummins)
//! `F(t) = -A_inf q'' - int_0^t K(t - tau) q'(tau) dtau`. So `H(i omega)` is the network's complex
//! added mass `A~(omega) = a - i b / omega`. Limits: `H(inf) = A_inf` (the springs decouple the
//! masses) and `H(0) = A_inf + sum_b d_b d_b^T sum_j m_b,j` (everything moves rigidly). For the
//! seed's one-mass chain, `H_1(s) = m_0 + m_1 (k_1 + c_1 s) / (m_1 s^2 + c_1 s + k_1)`, equal to
//! eq. 16. As `s -> inf`, `H - A_inf -> (sum_b c_b,1 d_b d_b^T) / s`: the first dampers act as a
//! direct velocity feedthrough (`damping_direct`, the `omega -> inf` limit of the damping `b`).
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
//! # Augmented matrices (seed eq. 19 layout)
//!
//! [`Network::augmented_matrices`]: coordinates `[q (n); aux masses (branch by branch, stage by
//! stage)]`; the hull block of the mass matrix holds `m0 = A_inf` (the body's own mass is NOT
//! included: the master adds it). Seed eq. 19: `diag(m + m0, m1, m2)`, the chain's `C` and `K`.
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
//! # Scaling to other rho and g
//!
//! Hydrodynamic coefficients of a hull of fixed size depend on `omega` through
//! `k R = omega^2 R / g` only and are proportional to `rho`, so
//! `A~_new(omega) = (rho / rho0) A~_old(omega sqrt(g0 / g))`. The network maps exactly:
//! masses and `A_inf` scale with `rho`, springs with `rho g`, dampers with `rho sqrt(g)`
//! ([`Network::scaled`]).
//!
//! # Network XML file
//!
//! ```xml
//! <?xml version="1.0" encoding="UTF-8"?>
//! <network format_version="1" form="series_chain" rho="1025" g="9.81">
//!   <dof name="sway"/>
//!   <added_mass_inf>
//!     <row>230.5</row>
//!   </added_mass_inf>
//!   <branch>
//!     <direction>1</direction>
//!     <stage mass="512.3" stiffness="2100.7" damping="880.1"/>
//!     <stage mass="101.9" stiffness="4000.2" damping="120.4"/>
//!   </branch>
//! </network>
//! ```
//!
//! * `network`: attributes `format_version` (must be `1`), `form` (`series_chain`,
//!   `parallel_bank` or `coupled`), `rho` and `g` (the water density and gravity the values were
//!   made for; [`Network::scaled`] moves them). Children in this order: `dof` elements, one
//!   `added_mass_inf`, then zero or more `branch` elements.
//! * `dof name="..."`: one per hull DOF, in the order of the matrix rows.
//! * `added_mass_inf`: n `row` elements of n whitespace-separated numbers (symmetric PSD).
//! * `branch`: one `direction` (n numbers), then one or more `stage` elements with attributes
//!   `mass`, `stiffness`, `damping` (all finite and > 0), listed from the hull outwards.
//!
//! Units: SI per unit hull length; a DOF's generalized units carry into the matrices. Comments
//! are allowed anywhere; anything else unknown (elements, attributes, text) is an error that
//! names the file and line. The full description is `docs/NETWORK_FORMAT.md`.

use std::fmt;
use std::path::Path;

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// Version written to and required in the `format_version` attribute of network files.
pub const NETWORK_FORMAT_VERSION: u32 = 1;

/// Relative tolerance for the symmetry and positive semi-definiteness of `A_inf`.
const MATRIX_TOLERANCE: f64 = 1e-9;

/// The shape of an equivalent network.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NetworkForm {
    /// One DOF, one branch: a chain of masses (seed Figure 5).
    SeriesChain,
    /// One DOF, several branches of one mass each.
    ParallelBank,
    /// Several DOFs, branches along general directions in DOF space.
    Coupled,
}

impl NetworkForm {
    /// The name used in files: `series_chain`, `parallel_bank`, `coupled`.
    pub fn name(self) -> &'static str {
        match self {
            NetworkForm::SeriesChain => "series_chain",
            NetworkForm::ParallelBank => "parallel_bank",
            NetworkForm::Coupled => "coupled",
        }
    }

    /// Inverse of [`NetworkForm::name`].
    pub fn from_name(name: &str) -> Option<NetworkForm> {
        match name {
            "series_chain" => Some(NetworkForm::SeriesChain),
            "parallel_bank" => Some(NetworkForm::ParallelBank),
            "coupled" => Some(NetworkForm::Coupled),
            _ => None,
        }
    }

    /// True for the forms that describe a single DOF.
    pub fn is_single_dof(self) -> bool {
        !matches!(self, NetworkForm::Coupled)
    }
}

impl fmt::Display for NetworkForm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Errors of network validation and of network files.
#[derive(Clone, Debug, PartialEq)]
pub enum NetworkError {
    /// The network's values break a rule of [`Network::validate`].
    Invalid(String),
    /// A network file could not be read or understood.
    File {
        /// File name (or the source name given to [`Network::from_xml_str`]).
        source: String,
        /// 1-based line of the problem, where known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
}

impl fmt::Display for NetworkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NetworkError::Invalid(message) => write!(f, "invalid network: {message}"),
            NetworkError::File {
                source,
                line: Some(line),
                message,
            } => write!(f, "{source}:{line}: {message}"),
            NetworkError::File {
                source,
                line: None,
                message,
            } => write!(f, "{source}: {message}"),
        }
    }
}

impl std::error::Error for NetworkError {}

/// One stage of a chain: spring and damper in parallel from the previous node to a mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stage {
    /// Auxiliary mass `m_j`.
    pub mass: f64,
    /// Spring `k_j` between the previous node and `m_j`.
    pub stiffness: f64,
    /// Damper `c_j` in parallel with the spring.
    pub damping: f64,
}

/// A chain of stages attached to the hull along `direction`.
#[derive(Clone, Debug, PartialEq)]
pub struct Branch {
    /// Direction `d` in DOF space: the chain is attached to the coordinate `d^T q`.
    pub direction: DVector<f64>,
    /// Stages from the hull outwards.
    pub stages: Vec<Stage>,
}

impl Branch {
    /// Dynamic mass `G(s)` of the chain: force applied at the attachment over its acceleration.
    pub fn dynamic_mass(&self, s: Complex64) -> Complex64 {
        let s2 = s * s;
        let mut beyond = Complex64::new(0.0, 0.0);
        for stage in self.stages.iter().rev() {
            let node = beyond + stage.mass;
            let spring = Complex64::new(stage.stiffness, 0.0) + s * stage.damping;
            beyond = node * spring / (spring + s2 * node);
        }
        beyond
    }
}

/// Equivalent mass-spring-damper network of the water around a hull.
#[derive(Clone, Debug, PartialEq)]
pub struct Network {
    /// Names of the hull DOFs (matrix row order).
    pub dof_names: Vec<String>,
    /// `m0 = A_inf`, rigidly attached to the hull (n x n, symmetric PSD).
    pub added_mass_inf: DMatrix<f64>,
    /// The branches.
    pub branches: Vec<Branch>,
    /// Water density the values were made for.
    pub rho: f64,
    /// Gravity the values were made for.
    pub g: f64,
    /// Shape tag.
    pub form: NetworkForm,
}

/// Augmented mass, damping and stiffness matrices (seed eq. 19 layout, hull DOFs first).
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
    /// The states of each branch (its elongations, then its aux velocities). `A` couples no
    /// two branches, and column (row) b of `b_branch` (`c_branch`) is zero outside branch b.
    pub branch_states: Vec<Vec<usize>>,
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
        let n = self.state_count();
        let d = self.d.map(|x| Complex64::new(x, 0.0));
        if n == 0 {
            return d;
        }
        let mut shifted = self.a.map(|x| Complex64::new(-x, 0.0));
        for i in 0..n {
            shifted[(i, i)] += s;
        }
        let b = self.b.map(|x| Complex64::new(x, 0.0));
        let c = self.c.map(|x| Complex64::new(x, 0.0));
        match shifted.lu().solve(&b) {
            Some(x) => c * x + d,
            None => DMatrix::from_element(d.nrows(), d.ncols(), Complex64::new(f64::NAN, 0.0)),
        }
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

    /// Dissipated power `e'^T diag(c) e'` (>= 0).
    pub fn dissipation(&self, z: &DVector<f64>, v: &DVector<f64>) -> f64 {
        let rates = self.derivative(z, v);
        self.elongation_damping
            .iter()
            .enumerate()
            .map(|(j, c)| c * rates[j] * rates[j])
            .sum()
    }
}

impl Network {
    /// Number of hull DOFs.
    pub fn dof_count(&self) -> usize {
        self.dof_names.len()
    }

    /// Number of auxiliary masses (each adds one spring).
    pub fn aux_dof_count(&self) -> usize {
        self.branches.iter().map(|b| b.stages.len()).sum()
    }

    /// Checks every rule of the network; the error says which value breaks which rule.
    pub fn validate(&self) -> Result<(), NetworkError> {
        let bad = |m: String| Err(NetworkError::Invalid(m));
        let n = self.dof_names.len();
        if n == 0 {
            return bad("the network has no DOFs".into());
        }
        for (i, name) in self.dof_names.iter().enumerate() {
            if name.is_empty() || name.chars().any(|c| c.is_whitespace() || c.is_control()) {
                return bad(format!(
                    "DOF {} has an empty name or one with whitespace: {name:?}",
                    i + 1
                ));
            }
            if self.dof_names[..i].contains(name) {
                return bad(format!("DOF name {name:?} appears twice"));
            }
        }
        if !(self.rho.is_finite() && self.rho > 0.0) {
            return bad(format!("rho must be finite and > 0, got {}", self.rho));
        }
        if !(self.g.is_finite() && self.g > 0.0) {
            return bad(format!("g must be finite and > 0, got {}", self.g));
        }
        let a = &self.added_mass_inf;
        if a.nrows() != n || a.ncols() != n {
            return bad(format!(
                "added_mass_inf is {} x {}, expected {n} x {n} (one row and column per DOF)",
                a.nrows(),
                a.ncols()
            ));
        }
        if let Some((k, x)) = a.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return bad(format!(
                "added_mass_inf[{},{}] is not finite: {x}",
                k % n + 1,
                k / n + 1
            ));
        }
        let scale = a.amax();
        for i in 0..n {
            for j in 0..i {
                if (a[(i, j)] - a[(j, i)]).abs() > MATRIX_TOLERANCE * scale {
                    return bad(format!(
                        "added_mass_inf is not symmetric: [{},{}] = {} but [{},{}] = {}",
                        i + 1,
                        j + 1,
                        a[(i, j)],
                        j + 1,
                        i + 1,
                        a[(j, i)]
                    ));
                }
            }
        }
        let min_eigen = a.clone().symmetric_eigenvalues().min();
        if min_eigen < -MATRIX_TOLERANCE * scale {
            return bad(format!(
                "added_mass_inf is not positive semi-definite (smallest eigenvalue {min_eigen:e})"
            ));
        }
        match self.form {
            NetworkForm::SeriesChain | NetworkForm::ParallelBank if n != 1 => {
                return bad(format!("form {} needs exactly one DOF, got {n}", self.form));
            }
            NetworkForm::SeriesChain if self.branches.len() != 1 => {
                return bad(format!(
                    "form series_chain needs exactly one branch, got {}",
                    self.branches.len()
                ));
            }
            _ => {}
        }
        for (ib, branch) in self.branches.iter().enumerate() {
            let ib = ib + 1;
            if branch.direction.len() != n {
                return bad(format!(
                    "branch {ib}: direction has {} entries, expected {n} (one per DOF)",
                    branch.direction.len()
                ));
            }
            if branch.direction.iter().any(|x| !x.is_finite()) {
                return bad(format!("branch {ib}: direction has a non-finite entry"));
            }
            if branch.direction.amax() == 0.0 {
                return bad(format!("branch {ib}: direction is zero"));
            }
            if branch.stages.is_empty() {
                return bad(format!("branch {ib}: has no stages"));
            }
            if self.form == NetworkForm::ParallelBank && branch.stages.len() != 1 {
                return bad(format!(
                    "branch {ib}: form parallel_bank needs one stage per branch, got {}",
                    branch.stages.len()
                ));
            }
            for (is, stage) in branch.stages.iter().enumerate() {
                for (what, value) in [
                    ("mass", stage.mass),
                    ("stiffness", stage.stiffness),
                    ("damping", stage.damping),
                ] {
                    if !(value.is_finite() && value > 0.0) {
                        return bad(format!(
                            "branch {ib}, stage {}: {what} must be finite and > 0, got {value}",
                            is + 1
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// The same network for water density `rho` and gravity `g` (exact; see the module docs).
    /// Non-positive or non-finite values give a network that [`Network::validate`] rejects.
    pub fn scaled(&self, rho: f64, g: f64) -> Network {
        let mass_factor = rho / self.rho;
        let frequency_factor = (g / self.g).sqrt();
        let branches = self
            .branches
            .iter()
            .map(|b| Branch {
                direction: b.direction.clone(),
                stages: b
                    .stages
                    .iter()
                    .map(|s| Stage {
                        mass: s.mass * mass_factor,
                        stiffness: s.stiffness * mass_factor * frequency_factor * frequency_factor,
                        damping: s.damping * mass_factor * frequency_factor,
                    })
                    .collect(),
            })
            .collect();
        Network {
            dof_names: self.dof_names.clone(),
            added_mass_inf: &self.added_mass_inf * mass_factor,
            branches,
            rho,
            g,
            form: self.form,
        }
    }

    /// `H(s)` for a complex Laplace variable `s`.
    pub fn added_mass_at(&self, s: Complex64) -> DMatrix<Complex64> {
        let mut h = self.added_mass_inf.map(|x| Complex64::new(x, 0.0));
        let n = h.nrows();
        for branch in &self.branches {
            if branch.direction.len() != n {
                continue;
            }
            let g = branch.dynamic_mass(s);
            for j in 0..n {
                for i in 0..n {
                    h[(i, j)] += g * (branch.direction[i] * branch.direction[j]);
                }
            }
        }
        h
    }

    /// The network's complex added mass `A~(omega) = H(i omega)` (omega in rad/s).
    pub fn added_mass_tf(&self, omega: f64) -> DMatrix<Complex64> {
        self.added_mass_at(Complex64::new(0.0, omega))
    }

    /// Zero-frequency added mass `H(0) = A_inf + sum_b d_b d_b^T sum_j m_b,j`.
    pub fn added_mass_zero(&self) -> DMatrix<f64> {
        self.added_mass_at(Complex64::new(0.0, 0.0)).map(|x| x.re)
    }

    /// Incidence rows of all springs over `[q; aux]` and their (stiffness, damping, mass).
    fn springs(&self) -> (DMatrix<f64>, Vec<Stage>) {
        let n = self.dof_count();
        let na = self.aux_dof_count();
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

    /// Augmented `M`, `C`, `K` over `[q; aux masses]` (seed eq. 19; body mass not included).
    pub fn augmented_matrices(&self) -> AugmentedMatrices {
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
        AugmentedMatrices {
            mass,
            damping,
            stiffness,
        }
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
        })
    }

    /// The network as an XML file (format in the module docs). Numbers round-trip exactly.
    pub fn to_xml_string(&self) -> String {
        let mut out = String::new();
        out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        out.push_str(
            "<!-- Equivalent mass-spring-damper network (hydrofmu), SI units per unit hull \
             length; format: docs/NETWORK_FORMAT.md -->\n",
        );
        out.push_str(&format!(
            "<network format_version=\"{NETWORK_FORMAT_VERSION}\" form=\"{}\" rho=\"{}\" g=\"{}\">\n",
            self.form.name(),
            format_number(self.rho),
            format_number(self.g)
        ));
        for name in &self.dof_names {
            out.push_str(&format!("  <dof name=\"{}\"/>\n", escape_xml(name)));
        }
        out.push_str("  <added_mass_inf>\n");
        for i in 0..self.added_mass_inf.nrows() {
            let row: Vec<String> = self
                .added_mass_inf
                .row(i)
                .iter()
                .map(|&x| format_number(x))
                .collect();
            out.push_str(&format!("    <row>{}</row>\n", row.join(" ")));
        }
        out.push_str("  </added_mass_inf>\n");
        for branch in &self.branches {
            out.push_str("  <branch>\n");
            let direction: Vec<String> =
                branch.direction.iter().map(|&x| format_number(x)).collect();
            out.push_str(&format!(
                "    <direction>{}</direction>\n",
                direction.join(" ")
            ));
            for stage in &branch.stages {
                out.push_str(&format!(
                    "    <stage mass=\"{}\" stiffness=\"{}\" damping=\"{}\"/>\n",
                    format_number(stage.mass),
                    format_number(stage.stiffness),
                    format_number(stage.damping)
                ));
            }
            out.push_str("  </branch>\n");
        }
        out.push_str("</network>\n");
        out
    }

    /// Writes [`Network::to_xml_string`] to `path`.
    pub fn write_file(&self, path: impl AsRef<Path>) -> Result<(), NetworkError> {
        let path = path.as_ref();
        std::fs::write(path, self.to_xml_string()).map_err(|e| NetworkError::File {
            source: path.display().to_string(),
            line: None,
            message: format!("cannot write: {e}"),
        })
    }

    /// Reads a network file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Network, NetworkError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| NetworkError::File {
            source: path.display().to_string(),
            line: None,
            message: format!("cannot read: {e}"),
        })?;
        Network::from_xml_str(&text, &path.display().to_string())
    }

    /// Parses and validates network XML; `source_name` names the text in error messages.
    pub fn from_xml_str(text: &str, source_name: &str) -> Result<Network, NetworkError> {
        let fail = |offset: Option<usize>, message: String| NetworkError::File {
            source: source_name.to_string(),
            line: offset.map(|o| line_of(text, o)),
            message,
        };
        let root = parse_tree(text).map_err(|(offset, message)| fail(Some(offset), message))?;
        let network =
            network_from_tree(&root).map_err(|(offset, message)| fail(Some(offset), message))?;
        network.validate().map_err(|e| fail(None, e.to_string()))?;
        Ok(network)
    }
}

/// Shortest round-trip text of a number, with an exponent only for very large or small values.
fn format_number(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || (1e-4..1e9).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

fn escape_xml(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            _ => out.push(c),
        }
    }
    out
}

fn unescape_xml(s: &str) -> Result<String, String> {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(amp) = rest.find('&') {
        out.push_str(&rest[..amp]);
        let tail = &rest[amp..];
        let semi = tail
            .find(';')
            .ok_or_else(|| format!("unterminated entity in {s:?}"))?;
        let entity = &tail[1..semi];
        let c = match entity {
            "amp" => '&',
            "lt" => '<',
            "gt" => '>',
            "quot" => '"',
            "apos" => '\'',
            _ => {
                let code = if let Some(hex) = entity.strip_prefix("#x") {
                    u32::from_str_radix(hex, 16).ok()
                } else if let Some(dec) = entity.strip_prefix('#') {
                    dec.parse::<u32>().ok()
                } else {
                    None
                };
                code.and_then(char::from_u32)
                    .ok_or_else(|| format!("unknown entity &{entity}; in {s:?}"))?
            }
        };
        out.push(c);
        rest = &tail[semi + 1..];
    }
    out.push_str(rest);
    Ok(out)
}

fn line_of(text: &str, offset: usize) -> usize {
    let end = offset.min(text.len());
    text.as_bytes()[..end]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// Raw bytes of a quick-xml value (a `str` or a `[u8]`, depending on the quick-xml version).
fn raw_bytes<T: AsRef<[u8]> + ?Sized>(x: &T) -> &[u8] {
    x.as_ref()
}

/// A parsed XML element: name, attributes, child elements, text, byte offset of its start.
struct Element {
    name: String,
    attributes: Vec<(String, String)>,
    children: Vec<Element>,
    text: String,
    offset: usize,
}

type TreeError = (usize, String);

fn parse_tree(text: &str) -> Result<Element, TreeError> {
    use quick_xml::events::{BytesStart, Event};
    use quick_xml::Reader;

    fn element(e: &BytesStart, offset: usize) -> Result<Element, TreeError> {
        let name = String::from_utf8_lossy(raw_bytes(e.name().into_inner())).into_owned();
        let mut attributes: Vec<(String, String)> = Vec::new();
        for attribute in e.attributes() {
            let attribute = attribute.map_err(|err| (offset, format!("bad attribute: {err}")))?;
            let key = String::from_utf8_lossy(raw_bytes(attribute.key.into_inner())).into_owned();
            let raw = String::from_utf8_lossy(raw_bytes(&*attribute.value)).into_owned();
            let value = unescape_xml(&raw).map_err(|m| (offset, m))?;
            if attributes.iter().any(|(k, _)| *k == key) {
                return Err((
                    offset,
                    format!("attribute {key:?} appears twice in <{name}>"),
                ));
            }
            attributes.push((key, value));
        }
        Ok(Element {
            name,
            attributes,
            children: Vec::new(),
            text: String::new(),
            offset,
        })
    }

    let mut reader = Reader::from_str(text);
    let mut stack: Vec<Element> = Vec::new();
    let mut root: Option<Element> = None;
    loop {
        let offset = reader.buffer_position() as usize;
        let event = reader
            .read_event()
            .map_err(|e| (reader.error_position() as usize, format!("XML error: {e}")))?;
        let finished = match event {
            Event::Start(e) => {
                stack.push(element(&e, offset)?);
                None
            }
            Event::Empty(e) => Some(element(&e, offset)?),
            Event::End(_) => stack.pop(),
            Event::Text(t) => {
                let raw = String::from_utf8_lossy(raw_bytes(&*t)).into_owned();
                match stack.last_mut() {
                    Some(top) => top.text.push_str(&raw),
                    None if raw.trim().is_empty() => {}
                    None => return Err((offset, "text outside the root element".into())),
                }
                None
            }
            Event::CData(t) => {
                let raw = String::from_utf8_lossy(raw_bytes(&*t)).into_owned();
                match stack.last_mut() {
                    Some(top) => top.text.push_str(&raw),
                    None => return Err((offset, "CDATA outside the root element".into())),
                }
                None
            }
            Event::Comment(_) | Event::Decl(_) | Event::PI(_) | Event::DocType(_) => None,
            Event::Eof => break,
            #[allow(unreachable_patterns)]
            _ => {
                return Err((
                    offset,
                    "unsupported XML construct (entity reference?)".into(),
                ))
            }
        };
        if let Some(done) = finished {
            match stack.last_mut() {
                Some(parent) => parent.children.push(done),
                None if root.is_none() => root = Some(done),
                None => return Err((done.offset, "more than one root element".into())),
            }
        }
    }
    if let Some(open) = stack.last() {
        return Err((
            open.offset,
            format!("element <{}> is not closed", open.name),
        ));
    }
    root.ok_or_else(|| (0, "no root element".into()))
}

impl Element {
    fn check_attributes(&self, allowed: &[&str]) -> Result<(), TreeError> {
        for (key, _) in &self.attributes {
            if !allowed.contains(&key.as_str()) {
                return Err((
                    self.offset,
                    format!(
                        "unknown attribute {key:?} on <{}> (allowed: {})",
                        self.name,
                        allowed.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    fn attribute(&self, key: &str) -> Result<&str, TreeError> {
        self.attributes
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
            .ok_or_else(|| {
                (
                    self.offset,
                    format!("<{}> is missing the attribute {key:?}", self.name),
                )
            })
    }

    fn number_attribute(&self, key: &str) -> Result<f64, TreeError> {
        let value = self.attribute(key)?;
        parse_number(value).map_err(|m| (self.offset, format!("<{}> {key}: {m}", self.name)))
    }

    fn no_text(&self) -> Result<(), TreeError> {
        if self.text.trim().is_empty() {
            Ok(())
        } else {
            Err((
                self.offset,
                format!("unexpected text {:?} in <{}>", self.text.trim(), self.name),
            ))
        }
    }

    fn leaf(&self) -> Result<(), TreeError> {
        match self.children.first() {
            Some(child) => Err((
                child.offset,
                format!("unexpected element <{}> in <{}>", child.name, self.name),
            )),
            None => Ok(()),
        }
    }

    fn numbers(&self, expected: usize) -> Result<Vec<f64>, TreeError> {
        self.leaf()?;
        self.check_attributes(&[])?;
        let values = self
            .text
            .split_whitespace()
            .map(parse_number)
            .collect::<Result<Vec<f64>, String>>()
            .map_err(|m| (self.offset, format!("<{}>: {m}", self.name)))?;
        if values.len() != expected {
            return Err((
                self.offset,
                format!(
                    "<{}> has {} numbers, expected {expected} (one per DOF)",
                    self.name,
                    values.len()
                ),
            ));
        }
        Ok(values)
    }
}

fn parse_number(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(format!("{text:?} is not a finite number")),
        Err(_) => Err(format!("{text:?} is not a number")),
    }
}

fn network_from_tree(root: &Element) -> Result<Network, TreeError> {
    if root.name != "network" {
        return Err((
            root.offset,
            format!("root element is <{}>, expected <network>", root.name),
        ));
    }
    root.check_attributes(&["format_version", "form", "rho", "g"])?;
    root.no_text()?;
    let version = root.attribute("format_version")?;
    if version.trim() != NETWORK_FORMAT_VERSION.to_string() {
        return Err((
            root.offset,
            format!("format_version {version:?} is not supported (this reader knows {NETWORK_FORMAT_VERSION})"),
        ));
    }
    let form_name = root.attribute("form")?;
    let form = NetworkForm::from_name(form_name.trim()).ok_or_else(|| {
        (
            root.offset,
            format!("unknown form {form_name:?} (series_chain, parallel_bank or coupled)"),
        )
    })?;
    let rho = root.number_attribute("rho")?;
    let g = root.number_attribute("g")?;

    let mut dof_names = Vec::new();
    let mut added_mass_inf: Option<DMatrix<f64>> = None;
    let mut branches = Vec::new();
    // Order: dof*, added_mass_inf, branch*.
    let mut phase = 0;
    for child in &root.children {
        match child.name.as_str() {
            "dof" => {
                if phase > 0 {
                    return Err((
                        child.offset,
                        "<dof> must come before <added_mass_inf>".into(),
                    ));
                }
                child.check_attributes(&["name"])?;
                child.leaf()?;
                child.no_text()?;
                dof_names.push(child.attribute("name")?.to_string());
            }
            "added_mass_inf" => {
                if phase > 0 {
                    return Err((child.offset, "more than one <added_mass_inf>".into()));
                }
                if dof_names.is_empty() {
                    return Err((child.offset, "<added_mass_inf> before any <dof>".into()));
                }
                phase = 1;
                child.check_attributes(&[])?;
                child.no_text()?;
                let n = dof_names.len();
                let mut matrix = DMatrix::zeros(n, n);
                let mut rows = 0;
                for row in &child.children {
                    if row.name != "row" {
                        return Err((
                            row.offset,
                            format!("unexpected element <{}> in <added_mass_inf>", row.name),
                        ));
                    }
                    if rows == n {
                        return Err((
                            row.offset,
                            format!("<added_mass_inf> has more than {n} rows"),
                        ));
                    }
                    let values = row.numbers(n)?;
                    for (j, v) in values.into_iter().enumerate() {
                        matrix[(rows, j)] = v;
                    }
                    rows += 1;
                }
                if rows != n {
                    return Err((
                        child.offset,
                        format!("<added_mass_inf> has {rows} rows, expected {n}"),
                    ));
                }
                added_mass_inf = Some(matrix);
            }
            "branch" => {
                if phase == 0 {
                    return Err((child.offset, "<branch> before <added_mass_inf>".into()));
                }
                child.check_attributes(&[])?;
                child.no_text()?;
                let n = dof_names.len();
                let mut direction = None;
                let mut stages = Vec::new();
                for part in &child.children {
                    match part.name.as_str() {
                        "direction" => {
                            if direction.is_some() || !stages.is_empty() {
                                return Err((
                                    part.offset,
                                    "one <direction> per branch, before its stages".into(),
                                ));
                            }
                            direction = Some(DVector::from_vec(part.numbers(n)?));
                        }
                        "stage" => {
                            part.check_attributes(&["mass", "stiffness", "damping"])?;
                            part.leaf()?;
                            part.no_text()?;
                            stages.push(Stage {
                                mass: part.number_attribute("mass")?,
                                stiffness: part.number_attribute("stiffness")?,
                                damping: part.number_attribute("damping")?,
                            });
                        }
                        other => {
                            return Err((
                                part.offset,
                                format!("unexpected element <{other}> in <branch>"),
                            ))
                        }
                    }
                }
                let direction = direction
                    .ok_or_else(|| (child.offset, "<branch> has no <direction>".to_string()))?;
                if stages.is_empty() {
                    return Err((child.offset, "<branch> has no <stage>".into()));
                }
                branches.push(Branch { direction, stages });
            }
            other => {
                return Err((
                    child.offset,
                    format!("unexpected element <{other}> in <network>"),
                ))
            }
        }
    }
    let added_mass_inf = added_mass_inf
        .ok_or_else(|| (root.offset, "<network> has no <added_mass_inf>".to_string()))?;
    Ok(Network {
        dof_names,
        added_mass_inf,
        branches,
        rho,
        g,
        form,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The seed's 2-DOF chain (after eq. 19), nondimensional.
    fn seed_network() -> Network {
        Network {
            dof_names: vec!["sway".into()],
            added_mass_inf: DMatrix::from_element(1, 1, 0.1153),
            branches: vec![Branch {
                direction: DVector::from_element(1, 1.0),
                stages: vec![
                    Stage {
                        mass: 0.5434,
                        stiffness: 0.2339,
                        damping: 0.9962,
                    },
                    Stage {
                        mass: 0.1877,
                        stiffness: 0.5522,
                        damping: 0.2453,
                    },
                ],
            }],
            rho: 1.0,
            g: 1.0,
            form: NetworkForm::SeriesChain,
        }
    }

    /// A 3-DOF coupled network with chains along mixed directions.
    fn coupled_network() -> Network {
        let a_inf = DMatrix::from_row_slice(3, 3, &[2.0, 0.3, -0.1, 0.3, 1.5, 0.2, -0.1, 0.2, 1.0]);
        let stage = |m, k, c| Stage {
            mass: m,
            stiffness: k,
            damping: c,
        };
        Network {
            dof_names: vec!["sway".into(), "heave".into(), "roll".into()],
            added_mass_inf: a_inf,
            branches: vec![
                Branch {
                    direction: DVector::from_vec(vec![1.0, 0.2, -0.5]),
                    stages: vec![stage(0.8, 2.0, 0.6), stage(0.3, 1.1, 0.2)],
                },
                Branch {
                    direction: DVector::from_vec(vec![0.0, 1.0, 0.3]),
                    stages: vec![stage(1.2, 0.7, 0.9)],
                },
                Branch {
                    direction: DVector::from_vec(vec![0.4, -0.6, 1.0]),
                    stages: vec![stage(0.5, 3.0, 0.4)],
                },
            ],
            rho: 1025.0,
            g: 9.81,
            form: NetworkForm::Coupled,
        }
    }

    fn max_abs_diff(a: &DMatrix<Complex64>, b: &DMatrix<Complex64>) -> f64 {
        (a - b).iter().map(|x| x.norm()).fold(0.0, f64::max)
    }

    #[test]
    fn seed_chain_limits_match_eq16() {
        let net = seed_network();
        net.validate().unwrap();
        // H(inf) = m0, H(0) = m0 + m1 + m2 (1e-6: the large-s limit converges like 1/s).
        let big = net.added_mass_at(Complex64::new(0.0, 1e8))[(0, 0)];
        assert!((big - 0.1153).norm() < 1e-6, "{big}");
        let zero = net.added_mass_zero()[(0, 0)];
        assert!((zero - (0.1153 + 0.5434 + 0.1877)).abs() < 1e-14);
        // One-stage chain equals the seed's closed form (16) at an arbitrary s.
        let (m0, m1, k1, c1) = (0.1153, 0.5434, 0.2339, 0.9962);
        let one = Network {
            branches: vec![Branch {
                direction: DVector::from_element(1, 1.0),
                stages: vec![Stage {
                    mass: m1,
                    stiffness: k1,
                    damping: c1,
                }],
            }],
            ..seed_network()
        };
        let s = Complex64::new(0.3, 0.7);
        let f = (m0 + m1) / (m0 * m1);
        let eq16 = m0 * (s * s + f * c1 * s + f * k1) / (s * s + c1 / m1 * s + k1 / m1);
        assert!((one.added_mass_at(s)[(0, 0)] - eq16).norm() < 1e-13);
    }

    #[test]
    fn damping_is_positive_and_tf_symmetric() {
        let net = coupled_network();
        net.validate().unwrap();
        for &omega in &[0.01, 0.3, 1.0, 3.0, 30.0] {
            let h = net.added_mass_tf(omega);
            // Reciprocity: symmetric to rounding.
            assert!(max_abs_diff(&h, &h.transpose()) < 1e-14);
            // Damping matrix b = -omega Im H is PSD.
            let b = h.map(|x| -omega * x.im);
            assert!(b.symmetric_eigenvalues().min() > -1e-12);
        }
    }

    #[test]
    fn state_space_transfer_matches_network() {
        for net in [seed_network(), coupled_network()] {
            let ss = net.state_space().unwrap();
            assert_eq!(ss.state_count(), 2 * net.aux_dof_count());
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
            // Feedthrough = -(sum of first dampers d d^T), symmetric PSD.
            let dd = ss.damping_direct();
            let mut expected = DMatrix::zeros(net.dof_count(), net.dof_count());
            for b in &net.branches {
                expected += &b.direction * b.direction.transpose() * b.stages[0].damping;
            }
            assert!((dd - expected).amax() < 1e-13);
            // The branch factorization reconstructs B and C (the stepper relies on it).
            let b = &ss.b_branch * &ss.branch_directions;
            let c = ss.branch_directions.transpose() * &ss.c_branch;
            assert!((b - &ss.b).amax() < 1e-14 * ss.b.amax().max(1.0));
            assert!((c - &ss.c).amax() < 1e-14 * ss.c.amax().max(1.0));
            assert_eq!(ss.branch_directions.nrows(), net.branches.len());
            // The branch blocks: A, B_r and C_r have nothing outside them.
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
                for b in 0..net.branches.len() {
                    if owner[i] != b {
                        assert_eq!(ss.b_branch[(i, b)], 0.0);
                        assert_eq!(ss.c_branch[(b, i)], 0.0);
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
        let aug = net.augmented_matrices();
        let (k1, k2, c1, c2) = (0.2339, 0.5522, 0.9962, 0.2453);
        let k = DMatrix::from_row_slice(3, 3, &[k1, -k1, 0.0, -k1, k1 + k2, -k2, 0.0, -k2, k2]);
        let c = DMatrix::from_row_slice(3, 3, &[c1, -c1, 0.0, -c1, c1 + c2, -c2, 0.0, -c2, c2]);
        assert!((aug.stiffness - k).amax() < 1e-15);
        assert!((aug.damping - c).amax() < 1e-15);
        assert_eq!(
            aug.mass,
            DMatrix::from_diagonal(&DVector::from_vec(vec![0.1153, 0.5434, 0.1877]))
        );
        let aug = coupled_network().augmented_matrices();
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
        // Seed eq. 19 with body mass m = 1 and a unit impulse on the body.
        let net = seed_network();
        let aug = net.augmented_matrices();
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

    #[test]
    fn scaling_maps_the_transfer_function() {
        let net = coupled_network();
        let (rho, g) = (998.0, 9.80665);
        let new = net.scaled(rho, g);
        new.validate().unwrap();
        for &omega in &[0.1, 0.8, 2.0, 7.0] {
            let lhs = new.added_mass_tf(omega);
            let rhs =
                net.added_mass_tf(omega * (net.g / g).sqrt()) * Complex64::new(rho / net.rho, 0.0);
            assert!(max_abs_diff(&lhs, &rhs) < 1e-12 * lhs.camax().max(1.0));
        }
        assert!(net.scaled(-1.0, 9.81).validate().is_err());
    }

    #[test]
    fn validation_names_the_problem() {
        let mut net = coupled_network();
        net.branches[1].stages[0].stiffness = -1.0;
        let e = net.validate().unwrap_err().to_string();
        assert!(e.contains("branch 2, stage 1: stiffness"), "{e}");
        let mut net = coupled_network();
        net.branches[0].stages[1].mass = f64::NAN;
        assert!(net.validate().unwrap_err().to_string().contains("mass"));
        let mut net = coupled_network();
        net.branches[2].direction = DVector::from_vec(vec![1.0, 2.0]);
        assert!(net
            .validate()
            .unwrap_err()
            .to_string()
            .contains("direction has 2"));
        let mut net = coupled_network();
        net.added_mass_inf[(0, 1)] = 0.5;
        assert!(net
            .validate()
            .unwrap_err()
            .to_string()
            .contains("not symmetric"));
        let mut net = coupled_network();
        net.added_mass_inf[(2, 2)] = -3.0;
        assert!(net
            .validate()
            .unwrap_err()
            .to_string()
            .contains("positive semi-definite"));
        let mut net = coupled_network();
        net.branches[0].stages[0].damping = 0.0;
        assert!(net.validate().is_err());
        let mut net = seed_network();
        net.dof_names = vec!["two words".into()];
        assert!(net.validate().is_err());
    }

    #[test]
    fn xml_round_trip_is_exact() {
        for net in [seed_network(), coupled_network()] {
            let text = net.to_xml_string();
            let back = Network::from_xml_str(&text, "memory").unwrap();
            assert_eq!(back, net);
        }
        let mut odd = coupled_network();
        odd.dof_names[0] = "a&b<c>".into();
        odd.branches[0].stages[0].mass = 1.234_567_890_123_456_7e-17;
        odd.branches[0].stages[0].stiffness = 3.3e12;
        let back = Network::from_xml_str(&odd.to_xml_string(), "memory").unwrap();
        assert_eq!(back, odd);
    }

    #[test]
    fn xml_errors_name_file_line_and_problem() {
        let good = seed_network().to_xml_string();
        let cases = [
            (
                good.replace("damping=\"0.9962\"", "damping=\"-0.9962\""),
                "damping must be",
            ),
            (
                good.replace("mass=\"0.5434\"", "mass=\"abc\""),
                "not a number",
            ),
            (
                good.replace("mass=\"0.5434\"", "mass=\"NaN\""),
                "not a finite number",
            ),
            (
                good.replace(
                    "<stage mass=\"0.5434\"",
                    "<stage colour=\"red\" mass=\"0.5434\"",
                ),
                "unknown attribute",
            ),
            (
                good.replace("<direction>1</direction>", "<direction>1 2</direction>"),
                "expected 1",
            ),
            (
                good.replace("<direction>1</direction>", ""),
                "no <direction>",
            ),
            (
                good.replace("format_version=\"1\"", "format_version=\"7\""),
                "not supported",
            ),
            (good.replace("series_chain", "ladder"), "unknown form"),
            (
                good.replace("</branch>", "</branch><extra/>"),
                "unexpected element <extra>",
            ),
            (good.replace("</network>", ""), "not closed"),
            (
                good.replace("<row>0.1153</row>", "<row>0.1153</row><row>1</row>"),
                "more than 1 rows",
            ),
            (good.replace(" g=\"1\"", ""), "missing the attribute \"g\""),
        ];
        for (text, needle) in cases {
            let e = Network::from_xml_str(&text, "net.xml")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("net.xml"), "{e}");
            assert!(e.contains(needle), "expected {needle:?} in {e}");
        }
        let e = Network::from_xml_str(&good.replace("mass=\"0.1877\"", "mass=\"x\""), "f.xml")
            .unwrap_err();
        // The second stage is on line 11 of the written file.
        assert!(
            matches!(e, NetworkError::File { line: Some(11), .. }),
            "{e}"
        );
        let e = Network::from_file("/nonexistent/net.xml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/nonexistent/net.xml") && e.contains("cannot read"),
            "{e}"
        );
    }

    #[test]
    fn seed_example_file_holds_the_seed_network() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../main/examples/networks/seed_2dof.xml"
        );
        let path = if Path::new(path).exists() {
            path.to_string()
        } else {
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/examples/networks/seed_2dof.xml"
            )
            .to_string()
        };
        let net = Network::from_file(&path).unwrap();
        assert_eq!(net, seed_network());
    }
}
