//! Equivalent mass-spring-damper networks: the type `identify` produces and `realize` turns
//! into matrices, its rules, its transfer function and its scaling to other rho and g. The
//! file format is in `file.rs` ([`Network::to_xml_string`], [`Network::from_xml_str`]).
//!
//! # The network
//!
//! The water around the hull is replaced by a mechanical network (Schilder et al., section 4, Figure 5).
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
//! `H(s)` is Schilder et al.'s `H~(s) = F / (s^2 x_0)` (eq. 16) for every DOF pair: the force on the
//! hull by the water is `F = -s^2 H(s) q`, and in the time domain (Cummins)
//! `F(t) = -A_inf q'' - int_0^t K(t - tau) q'(tau) dtau`. So `H(i omega)` is the network's complex
//! added mass `A~(omega) = a - i b / omega`. Limits: `H(inf) = A_inf` (the springs decouple the
//! masses) and `H(0) = A_inf + sum_b d_b d_b^T sum_j m_b,j` (everything moves rigidly). For the
//! seed's one-mass chain, `H_1(s) = m_0 + m_1 (k_1 + c_1 s) / (m_1 s^2 + c_1 s + k_1)`, equal to
//! eq. 16. As `s -> inf`, `H - A_inf -> (sum_b c_b,1 d_b d_b^T) / s`: the first dampers act as a
//! direct velocity feedthrough (`damping_direct` of the state space in `realize`, the
//! `omega -> inf` limit of the damping `b`).
//!
//! # Scaling to other rho and g
//!
//! Hydrodynamic coefficients of a hull of fixed size depend on `omega` through
//! `k R = omega^2 R / g` only and are proportional to `rho`, so
//! `A~_new(omega) = (rho / rho0) A~_old(omega sqrt(g0 / g))`. The network maps exactly:
//! masses and `A_inf` scale with `rho`, springs with `rho g`, dampers with `rho sqrt(g)`
//! ([`Network::scaled`]).

mod file;
mod substructure;

pub use substructure::{ImpedanceRealization, Substructure};

use std::fmt;

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// Version written to and required in the `format_version` attribute of network files.
pub(crate) const NETWORK_FORMAT_VERSION: u32 = 1;

/// Most hull DOFs of a network: a ship's rigid motions with hundreds of girder or generalized
/// modes fit; `added_mass_inf` then holds a million numbers (8 MB), and the file reader refuses
/// more before anything of that size is allocated.
pub const MAX_NETWORK_DOFS: usize = 1000;

/// Most stages (auxiliary masses) of one branch. A chain is stepped as one block whose new
/// step size costs an exponential of twice its stages (cubic); fits use 1 to 12.
pub(crate) const MAX_BRANCH_STAGES: usize = 64;

/// Most states of a whole network (twice the branch stages plus the substructures' springs
/// and masses). The component keeps dense matrices of this size (32 MB at the limit), and a new
/// step size costs one exponential per block: at most 2048 / 512 blocks of the largest
/// substructure ([`MAX_SUBSTRUCTURE_STATES`]), measured in docs/STABILITY.md.
pub const MAX_NETWORK_STATES: usize = 2048;

/// Most states of one substructure (springs + masses): a step costs the square of its states,
/// a new step size their cube (about 0.1 s at this limit, docs/STABILITY.md); fits have tens.
pub const MAX_SUBSTRUCTURE_STATES: usize = 512;

/// Relative tolerance for the symmetry and positive semi-definiteness of `A_inf`.
const MATRIX_TOLERANCE: f64 = 1e-9;

/// The shape of an equivalent network.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NetworkForm {
    /// One DOF, one branch: a chain of masses (Schilder et al., Figure 5).
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
#[non_exhaustive]
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
    /// The substructures (form `coupled` only; see [`Substructure`]).
    pub substructures: Vec<Substructure>,
    /// Water density the values were made for.
    pub rho: f64,
    /// Gravity the values were made for.
    pub g: f64,
    /// Shape tag.
    pub form: NetworkForm,
}

impl Network {
    /// A coupled network of `A_inf` and substructures (what the rational fit gives).
    pub fn from_substructures(
        dof_names: Vec<String>,
        added_mass_inf: DMatrix<f64>,
        substructures: Vec<Substructure>,
        rho: f64,
        g: f64,
    ) -> Network {
        Network {
            dof_names,
            added_mass_inf,
            branches: Vec::new(),
            substructures,
            rho,
            g,
            form: NetworkForm::Coupled,
        }
    }

    /// Number of hull DOFs.
    pub fn dof_count(&self) -> usize {
        self.dof_names.len()
    }

    /// Number of auxiliary masses (each adds one spring).
    pub fn aux_dof_count(&self) -> usize {
        self.branches.iter().map(|b| b.stages.len()).sum::<usize>()
            + self.substructures.iter().map(|s| s.masses).sum::<usize>()
    }

    /// Number of states of the realized network: two per stage (elongation and velocity),
    /// and each substructure's springs and masses.
    pub fn state_count(&self) -> usize {
        2 * self.branches.iter().map(|b| b.stages.len()).sum::<usize>()
            + self
                .substructures
                .iter()
                .map(Substructure::state_count)
                .sum::<usize>()
    }

    /// Checks every rule of the network; the error says which value breaks which rule.
    pub fn validate(&self) -> Result<(), NetworkError> {
        let bad = |m: String| Err(NetworkError::Invalid(m));
        let n = self.dof_names.len();
        if n == 0 {
            return bad("the network has no DOFs".into());
        }
        if n > MAX_NETWORK_DOFS {
            return bad(format!(
                "the network has {n} DOFs, at most {MAX_NETWORK_DOFS} are accepted (MAX_NETWORK_DOFS)"
            ));
        }
        if let Some((b, branch)) = self
            .branches
            .iter()
            .enumerate()
            .find(|(_, b)| b.stages.len() > MAX_BRANCH_STAGES)
        {
            return bad(format!(
                "branch {} has {} stages, at most {MAX_BRANCH_STAGES} are accepted (MAX_BRANCH_STAGES)",
                b + 1,
                branch.stages.len()
            ));
        }
        if let Some((k, sub)) = self
            .substructures
            .iter()
            .enumerate()
            .find(|(_, s)| s.state_count() > MAX_SUBSTRUCTURE_STATES)
        {
            return bad(format!(
                "substructure {} has {} states, at most {MAX_SUBSTRUCTURE_STATES} are accepted \
                 (MAX_SUBSTRUCTURE_STATES)",
                k + 1,
                sub.state_count()
            ));
        }
        if self.state_count() > MAX_NETWORK_STATES {
            return bad(format!(
                "the network has {} states, at most {MAX_NETWORK_STATES} are accepted (MAX_NETWORK_STATES)",
                self.state_count()
            ));
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
        if let Err(message) = check_symmetric_psd("added_mass_inf", a, MATRIX_TOLERANCE) {
            return bad(message);
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
        if !self.substructures.is_empty() && self.form != NetworkForm::Coupled {
            return bad(format!(
                "form {} cannot hold substructures (form coupled can)",
                self.form
            ));
        }
        for (k, sub) in self.substructures.iter().enumerate() {
            if let Err(message) = sub.validate(n, MATRIX_TOLERANCE) {
                return bad(format!("substructure {}: {message}", k + 1));
            }
        }
        Ok(())
    }

    /// The same network with the hull DOFs' added mass scaled, `H_ij(s) -> f_i f_j H_ij(s)`
    /// (exact up to rounding): the network in the coordinates `q_i` of a network made for
    /// `q'_i = f_i q_i` (forces `F_i = f_i F'_i`). `A_inf`, the branch directions and the
    /// substructures' hull columns (`spring_incidence`, `damping`) take the factors; stages and
    /// aux masses stay. Refused unless there is one finite positive factor per DOF.
    pub fn with_dof_factors(&self, factors: &[f64]) -> Result<Network, NetworkError> {
        let n = self.dof_count();
        if factors.len() != n || factors.iter().any(|f| !(f.is_finite() && *f > 0.0)) {
            return Err(NetworkError::Invalid(format!(
                "DOF factors {factors:?}: expected {n} finite positive numbers"
            )));
        }
        let mut network = self.clone();
        for j in 0..n {
            for i in 0..n {
                network.added_mass_inf[(i, j)] *= factors[i] * factors[j];
            }
        }
        for branch in &mut network.branches {
            for (d, f) in branch.direction.iter_mut().zip(factors) {
                *d *= f;
            }
        }
        for sub in &mut network.substructures {
            for (i, f) in factors.iter().enumerate() {
                let hull = sub.masses + i;
                sub.spring_incidence.column_mut(hull).scale_mut(*f);
                sub.damping.column_mut(hull).scale_mut(*f);
                sub.damping.row_mut(hull).scale_mut(*f);
            }
        }
        Ok(network)
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
            substructures: self
                .substructures
                .iter()
                .map(|sub| sub.scaled(mass_factor, g / self.g))
                .collect(),
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
        for sub in &self.substructures {
            if sub.dof_count() == n {
                h += sub.dynamic_mass(s);
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
}

/// `m` (finite) must be symmetric and positive semi-definite, both to `tolerance` relative to
/// its largest entry; the error names it.
fn check_symmetric_psd(name: &str, m: &DMatrix<f64>, tolerance: f64) -> Result<(), String> {
    let n = m.nrows();
    let scale = m.amax();
    for i in 0..n {
        for j in 0..i {
            if (m[(i, j)] - m[(j, i)]).abs() > tolerance * scale {
                return Err(format!(
                    "{name} is not symmetric: [{},{}] = {} but [{},{}] = {}",
                    i + 1,
                    j + 1,
                    m[(i, j)],
                    j + 1,
                    i + 1,
                    m[(j, i)]
                ));
            }
        }
    }
    if n == 0 {
        return Ok(());
    }
    let min_eigen = crate::numerics::symmetric_eigen(m).eigenvalues.min();
    // NaN (an eigenvalue computation that overflowed) fails too.
    if min_eigen.is_nan() || min_eigen < -tolerance * scale {
        return Err(format!(
            "{name} is not positive semi-definite (smallest eigenvalue {min_eigen:e})"
        ));
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests;
