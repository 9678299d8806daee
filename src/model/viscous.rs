//! Viscous damping and current (`resources/viscous.csv`, docs/CURRENT.md).
//!
//! ```text
//! F_visc = -B_l v_r - B_q |v_r| v_r      (B_q diagonal: one coefficient per DOF)
//! v_r    = v - c,   c_i = U (a_i cos(psi) + b_i sin(psi))
//! dF_visc/dv = -B_l - 2 diag(B_q |v_r|)
//! ```
//!
//! `U` is `current.speed` (m/s), `psi` is `current.heading` (deg, 0 towards +x). The current
//! moves the rigid translations of known direction ([`Frame`]): a section's `sway` is along the
//! current's x axis (a = 1: a section's current is along its sway axis); a whole body's (ship,
//! database) `surge` is along x (a = 1) and its `sway` along y (b = 1). Every other DOF (heave,
//! rotations, elastic modes) sees no current. `B_l` needs a positive semidefinite symmetric
//! part, `B_q >= 0`.
//!
//! `resources/viscous.csv`: `#` comment lines, a line `frame,section` or `frame,body`, a header
//! `dof,quadratic,<dof_1>,..,<dof_n>`, then one row per DOF in the network's order:
//! `<dof_i>,B_q[i],B_l[i,1],..,B_l[i,n]`. Without the frame line, `sway` is along y when the
//! DOFs include `surge`, else along x.
//!
//! A ship packed with its cross-flow strips (`resources/crossflow.csv`, [`super::crossflow`])
//! adds their drag: `F_visc` gains the strips' force, which couples sway with yaw and heave
//! with pitch and scales with `rho`; the Jacobian and the current's derivatives gain theirs.

use super::crossflow::{check_scale, Crossflow};
use crate::fmu::variables::Quantity;
use nalgebra::{DMatrix, DVector};

/// The most DOFs `viscous.csv` may declare.
const MAX_DOFS: usize = 1000;

/// Linear and quadratic viscous damping with the current the DOFs see.
#[derive(Clone, Debug, PartialEq)]
pub struct Viscous {
    /// `B_l` (n x n).
    pub(super) linear: DMatrix<f64>,
    /// `B_q` (n).
    pub(super) quadratic: DVector<f64>,
    /// `(a_i, b_i)`: the DOF's share of the current along x and along y.
    axes: Vec<(f64, f64)>,
    /// `current.speed` (m/s).
    pub(super) speed: f64,
    /// `current.heading` (deg).
    pub(super) heading: f64,
    /// The current's velocity `c` along every DOF.
    current: DVector<f64>,
    /// Scratch: `v_r`.
    relative: DVector<f64>,
    /// `B_l` is diagonal (the usual case: the force costs n products, not n^2).
    diagonal: bool,
    /// A ship's cross-flow strips, if packed.
    crossflow: Option<Crossflow>,
    /// `U sin(psi)`: the current across a ship's strips.
    lateral_current: f64,
}

/// Where a body's translations point, for the current.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frame {
    /// A 2D section: `sway` along x.
    Section,
    /// A whole body (ship, database): `surge` along x, `sway` along y.
    Body,
}

impl Frame {
    /// The word in `viscous.csv`.
    pub fn word(self) -> &'static str {
        match self {
            Frame::Section => "section",
            Frame::Body => "body",
        }
    }

    /// The frame of a `viscous.csv` without its frame line: a body when the DOFs include
    /// `surge`.
    fn guessed(names: &[String]) -> Frame {
        if names.iter().any(|n| n == "surge") {
            Frame::Body
        } else {
            Frame::Section
        }
    }
}

/// `(a, b)` of a DOF (module docs).
fn current_axis(name: &str, frame: Frame) -> (f64, f64) {
    match (name, frame) {
        ("surge", _) => (1.0, 0.0),
        ("sway", Frame::Body) => (0.0, 1.0),
        ("sway", Frame::Section) => (1.0, 0.0),
        _ => (0.0, 0.0),
    }
}

impl Viscous {
    /// Damping for the DOFs `names` of a body in `frame` (no current yet); the coefficients
    /// are checked ([`Viscous::check`]).
    pub fn new(
        names: &[String],
        frame: Frame,
        linear: DMatrix<f64>,
        quadratic: DVector<f64>,
    ) -> Result<Viscous, String> {
        let n = names.len();
        if linear.shape() != (n, n) || quadratic.len() != n {
            return Err(format!(
                "viscous damping: {}x{} linear and {} quadratic coefficients for {n} DOFs",
                linear.nrows(),
                linear.ncols(),
                quadratic.len()
            ));
        }
        let mut viscous = Viscous {
            linear,
            quadratic,
            ..Viscous::zeros(names, frame)
        };
        viscous.diagonal = is_diagonal(&viscous.linear);
        viscous.check()?;
        Ok(viscous)
    }

    /// Zero coefficients for the DOFs `names` of a body in `frame`.
    pub fn zeros(names: &[String], frame: Frame) -> Viscous {
        let n = names.len();
        Viscous {
            linear: DMatrix::zeros(n, n),
            quadratic: DVector::zeros(n),
            axes: names.iter().map(|n| current_axis(n, frame)).collect(),
            speed: 0.0,
            heading: 0.0,
            current: DVector::zeros(n),
            relative: DVector::zeros(n),
            diagonal: true,
            crossflow: None,
            lateral_current: 0.0,
        }
    }

    /// Refuses a coefficient that is not finite or negative (`damping_quadratic[i]`, a
    /// diagonal `damping_linear[i,i]`), and a `damping_linear` whose symmetric part has a
    /// negative eigenvalue.
    pub fn check(&self) -> Result<(), String> {
        let n = self.quadratic.len();
        for i in 0..n {
            check_quadratic(i, self.quadratic[i])?;
            for j in 0..n {
                check_linear(i, j, self.linear[(i, j)])?;
            }
        }
        let symmetric = (&self.linear + self.linear.transpose()) * 0.5;
        let scale = symmetric.amax();
        let lowest = symmetric.symmetric_eigenvalues().min();
        if n > 0 && lowest < -1e-12 * scale {
            return Err(format!(
                "damping_linear: its symmetric part is not positive semidefinite (eigenvalue \
                 {lowest:e}): the damping would feed energy into the hull"
            ));
        }
        Ok(())
    }

    /// Sets `B_q[i]`, if it is finite and not negative.
    pub fn set_quadratic(&mut self, i: usize, value: f64) -> Result<(), String> {
        check_quadratic(i, value)?;
        self.quadratic[i] = value;
        Ok(())
    }

    /// Sets `B_l[i,j]`, if it is finite (and not negative on the diagonal); the matrix as a
    /// whole is checked by [`Viscous::check`].
    pub fn set_linear(&mut self, i: usize, j: usize, value: f64) -> Result<(), String> {
        check_linear(i, j, value)?;
        self.linear[(i, j)] = value;
        self.diagonal = is_diagonal(&self.linear);
        Ok(())
    }

    /// Sets the current (speed in m/s, heading in deg), if both are finite.
    pub fn set_current(&mut self, speed: f64, heading: f64) -> Result<(), String> {
        if !speed.is_finite() {
            return Err(format!("current.speed = {speed}: not finite"));
        }
        if !heading.is_finite() {
            return Err(format!("current.heading = {heading}: not finite"));
        }
        self.speed = speed;
        self.heading = heading;
        let (sin, cos) = heading.to_radians().sin_cos();
        for (c, (a, b)) in self.current.iter_mut().zip(&self.axes) {
            *c = speed * (a * cos + b * sin);
        }
        self.lateral_current = speed * sin;
        Ok(())
    }

    /// The same damping with a ship's cross-flow strips.
    pub fn with_crossflow(self, crossflow: Crossflow) -> Viscous {
        Viscous {
            crossflow: Some(crossflow),
            ..self
        }
    }

    /// The cross-flow strips, if packed.
    pub fn crossflow(&self) -> Option<&Crossflow> {
        self.crossflow.as_ref()
    }

    /// Sets `crossflow.drag_scale` (finite, not negative) of an FMU with strips.
    pub fn set_crossflow_scale(&mut self, value: f64) -> Result<(), String> {
        match self.crossflow.as_mut() {
            Some(c) => c.set_scale(value),
            None => Err("crossflow.drag_scale: this FMU has no cross-flow strips".into()),
        }
    }

    /// `B_l`.
    pub fn linear(&self) -> &DMatrix<f64> {
        &self.linear
    }

    /// `B_q`.
    pub fn quadratic(&self) -> &DVector<f64> {
        &self.quadratic
    }

    /// The current's velocity along every DOF.
    pub fn current(&self) -> &DVector<f64> {
        &self.current
    }

    /// `F_visc` at velocity `v` into `force`, in water of density `rho` (the strips').
    pub fn force(&mut self, velocity: &DVector<f64>, rho: f64, force: &mut DVector<f64>) {
        self.relative.copy_from(velocity);
        self.relative -= &self.current;
        if self.diagonal {
            // The same sums as the product below without its zero terms.
            for (i, f) in force.iter_mut().enumerate() {
                *f = -(self.linear[(i, i)] * self.relative[i]);
            }
        } else {
            force.gemv(-1.0, &self.linear, &self.relative, 0.0);
        }
        for ((f, b), v) in force.iter_mut().zip(&self.quadratic).zip(&self.relative) {
            *f -= b * v.abs() * v;
        }
        if let Some(crossflow) = &self.crossflow {
            crossflow.add_force(
                velocity.as_slice(),
                rho,
                self.lateral_current,
                force.as_mut_slice(),
            );
        }
    }

    /// `dF_visc/dv` at velocity `v`: `-B_l - 2 diag(B_q |v_r|)`, plus the strips'.
    pub fn jacobian(&self, velocity: &DVector<f64>, rho: f64) -> DMatrix<f64> {
        let mut jacobian = self.per_dof_jacobian(velocity);
        if let Some(crossflow) = &self.crossflow {
            let n = velocity.len();
            let (mut unused_speed, mut unused_degree) = (DVector::zeros(n), DVector::zeros(n));
            crossflow.add_derivatives(
                velocity.as_slice(),
                rho,
                (self.speed, self.heading),
                &mut jacobian,
                &mut unused_speed,
                &mut unused_degree,
            );
        }
        jacobian
    }

    /// `-B_l - 2 diag(B_q |v_r|)`.
    fn per_dof_jacobian(&self, velocity: &DVector<f64>) -> DMatrix<f64> {
        let mut jacobian = -&self.linear;
        for i in 0..velocity.len() {
            let relative = velocity[i] - self.current[i];
            jacobian[(i, i)] -= 2.0 * self.quadratic[i] * relative.abs();
        }
        jacobian
    }

    /// `dF_visc/dU` and `dF_visc/dpsi` (per deg) at velocity `v`: `-J dc/dU`, `-J dc/dpsi`
    /// with the per-DOF `J`, plus the strips'.
    pub fn current_derivatives(
        &self,
        velocity: &DVector<f64>,
        rho: f64,
    ) -> (DVector<f64>, DVector<f64>) {
        let jacobian = self.per_dof_jacobian(velocity);
        let (sin, cos) = self.heading.to_radians().sin_cos();
        let per_speed = DVector::from_iterator(
            self.axes.len(),
            self.axes.iter().map(|(a, b)| a * cos + b * sin),
        );
        let per_degree = DVector::from_iterator(
            self.axes.len(),
            self.axes
                .iter()
                .map(|(a, b)| self.speed * (b * cos - a * sin) * std::f64::consts::PI / 180.0),
        );
        let mut per_speed = -(&jacobian * per_speed);
        let mut per_degree = -(&jacobian * per_degree);
        if let Some(crossflow) = &self.crossflow {
            let mut unused = DMatrix::zeros(velocity.len(), velocity.len());
            crossflow.add_derivatives(
                velocity.as_slice(),
                rho,
                (self.speed, self.heading),
                &mut unused,
                &mut per_speed,
                &mut per_degree,
            );
        }
        (per_speed, per_degree)
    }

    /// The explicit step bound `h < 2 m_i / (B_l[i,i] + 2 B_q[i] |v_r|)` of DOF `i` for its
    /// mass (plus added mass) `mass` (infinite where the DOF has no damping).
    pub fn step_bound(&self, i: usize, mass: f64, velocity: f64) -> f64 {
        let rate =
            self.linear[(i, i)] + 2.0 * self.quadratic[i] * (velocity - self.current[i]).abs();
        if rate > 0.0 {
            2.0 * mass / rate
        } else {
            f64::INFINITY
        }
    }
}

/// Refuses a value `quantity` (a viscous coefficient or the current) cannot take, and a
/// coefficient set after initialization (`initializing` false), naming it (the positive
/// semidefinite `damping_linear` is checked as a whole when initialization ends).
pub fn check_value(quantity: Quantity, value: f64, initializing: bool) -> Result<(), String> {
    match quantity {
        Quantity::DampingLinear(i, j) if !initializing => Err(format!(
            "damping_linear[{},{}] is a fixed parameter: set it before initialization mode ends",
            i + 1,
            j + 1
        )),
        Quantity::DampingQuadratic(i) if !initializing => Err(format!(
            "damping_quadratic[{}] is a fixed parameter: set it before initialization mode ends",
            i + 1
        )),
        Quantity::CrossflowDragScale if !initializing => Err(
            "crossflow.drag_scale is a fixed parameter: set it before initialization mode ends"
                .into(),
        ),
        Quantity::CrossflowDragScale => check_scale(value),
        Quantity::DampingLinear(i, j) => check_linear(i, j, value),
        Quantity::DampingQuadratic(i) => check_quadratic(i, value),
        Quantity::CurrentSpeed if !value.is_finite() => {
            Err(format!("current.speed = {value}: not finite"))
        }
        Quantity::CurrentHeading if !value.is_finite() => {
            Err(format!("current.heading = {value}: not finite"))
        }
        _ => Ok(()),
    }
}

/// Whether every off-diagonal entry is zero.
fn is_diagonal(matrix: &DMatrix<f64>) -> bool {
    let n = matrix.nrows();
    (0..n).all(|i| (0..n).all(|j| i == j || matrix[(i, j)] == 0.0))
}

fn check_quadratic(i: usize, value: f64) -> Result<(), String> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(format!(
            "damping_quadratic[{}] = {value}: must be finite and not negative",
            i + 1
        ))
    }
}

fn check_linear(i: usize, j: usize, value: f64) -> Result<(), String> {
    if !value.is_finite() || (i == j && value < 0.0) {
        let what = if i == j {
            "finite and not negative"
        } else {
            "finite"
        };
        return Err(format!(
            "damping_linear[{},{}] = {value}: must be {what}",
            i + 1,
            j + 1
        ));
    }
    Ok(())
}

/// Parses `viscous.csv` (module docs) for the DOFs `names`: the frame, `B_l` and `B_q`.
pub fn parse_csv(
    text: &str,
    names: &[String],
) -> Result<(Frame, DMatrix<f64>, DVector<f64>), String> {
    let source = "resources/viscous.csv";
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .peekable();
    let frame = match rows
        .peek()
        .and_then(|(line, l)| Some((*line, l.strip_prefix("frame,")?)))
    {
        Some((line, word)) => {
            let frame = [Frame::Section, Frame::Body]
                .into_iter()
                .find(|f| f.word() == word.trim())
                .ok_or(format!(
                    "{source}:{line}: frame '{}': expected section or body",
                    word.trim()
                ))?;
            rows.next();
            frame
        }
        None => Frame::guessed(names),
    };
    let (line, header) = rows.next().ok_or(format!("{source}: no header"))?;
    let fields: Vec<&str> = header.split(',').map(str::trim).collect();
    let n = names.len();
    if n > MAX_DOFS || fields.len() != n + 2 || fields[..2] != ["dof", "quadratic"] {
        return Err(format!(
            "{source}:{line}: header must be 'dof,quadratic,' then the {n} DOFs {}",
            names.join(",")
        ));
    }
    if fields[2..].iter().zip(names).any(|(f, n)| f != n) {
        return Err(format!(
            "{source}:{line}: DOFs {} differ from the network's {}",
            fields[2..].join(","),
            names.join(",")
        ));
    }
    let mut linear = DMatrix::zeros(n, n);
    let mut quadratic = DVector::zeros(n);
    for (i, name) in names.iter().enumerate() {
        let (line, row) = rows
            .next()
            .ok_or(format!("{source}: no row for DOF {name}"))?;
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        if fields.len() != n + 2 || fields[0] != name {
            return Err(format!(
                "{source}:{line}: expected '{name},' then {} numbers",
                n + 1
            ));
        }
        let number = |k: usize| {
            fields[k]
                .parse::<f64>()
                .map_err(|_| format!("{source}:{line}: '{}' is not a number", fields[k]))
        };
        quadratic[i] = number(1)?;
        for j in 0..n {
            linear[(i, j)] = number(j + 2)?;
        }
    }
    if let Some((line, _)) = rows.next() {
        return Err(format!("{source}:{line}: more rows than DOFs"));
    }
    Ok((frame, linear, quadratic))
}

/// The cross-flow strips of `crossflow.csv` ([`super::crossflow`]) for the network's DOFs
/// `names` of a body in `frame` (a whole body only: a section has no stations).
pub fn crossflow_of(text: &str, names: &[String], frame: Frame) -> Result<Crossflow, String> {
    if frame != Frame::Body {
        return Err(
            "resources/crossflow.csv: cross-flow strips need a whole body (frame body)".into(),
        );
    }
    Ok(Crossflow::new(super::crossflow::parse_csv(text)?, names))
}

/// The text of `viscous.csv` for these coefficients of a body in `frame` (exact: shortest
/// round-trip numbers).
pub fn write_csv(
    names: &[String],
    frame: Frame,
    linear: &DMatrix<f64>,
    quadratic: &DVector<f64>,
) -> String {
    let mut text = String::from(
        "# hydrofmu viscous damping: F = -B_l v_r - B_q |v_r| v_r (docs/CURRENT.md)\n",
    );
    text.push_str(&format!("frame,{}\n", frame.word()));
    text.push_str("dof,quadratic");
    for name in names {
        text.push(',');
        text.push_str(name);
    }
    text.push('\n');
    for (i, name) in names.iter().enumerate() {
        text.push_str(&format!("{name},{:?}", quadratic[i]));
        for j in 0..names.len() {
            text.push_str(&format!(",{:?}", linear[(i, j)]));
        }
        text.push('\n');
    }
    text
}

impl super::Model {
    /// Replaces the viscous damping (`None`: none; the FMU then has no viscous variables).
    pub fn set_viscous(&mut self, viscous: Option<Viscous>) {
        self.viscous = viscous;
        self.outputs_valid = false;
    }

    /// The viscous damping the FMU was packed with, if any.
    pub fn viscous(&self) -> Option<&Viscous> {
        self.viscous.as_ref()
    }

    /// The viscous force on every DOF (zeros without viscous damping).
    pub fn force_viscous(&mut self) -> &DVector<f64> {
        self.refresh();
        &self.outputs.viscous
    }

    /// The partial derivatives the viscous force adds or owns (`None`: none, the general
    /// rules apply): `dF/dv = -damping_direct + dF_visc/dv`, and those with respect to the
    /// current (only the viscous force depends on it).
    pub(super) fn viscous_partial(
        &self,
        of: Quantity,
        with_respect_to: Quantity,
    ) -> Result<Option<f64>, super::ModelError> {
        let n = self.dof_count();
        let Some(viscous) = &self.viscous else {
            return Ok(None);
        };
        let velocity = &self.state.velocity;
        let rho = self.state.rho;
        let value = match (of, with_respect_to) {
            (Quantity::Force(i), Quantity::Velocity(j)) if i < n && j < n => {
                -self.system.damping_direct[(i, j)] + viscous.jacobian(velocity, rho)[(i, j)]
            }
            (Quantity::ForceViscous(i), Quantity::Velocity(j)) if i < n && j < n => {
                viscous.jacobian(velocity, rho)[(i, j)]
            }
            (Quantity::ForceViscous(i), Quantity::Acceleration(j))
                if i < n && j < n && self.system.keep_inf_mass =>
            {
                0.0
            }
            (
                Quantity::Force(i) | Quantity::ForceViscous(i),
                Quantity::CurrentSpeed | Quantity::CurrentHeading,
            ) if i < n => {
                let (per_speed, per_degree) = viscous.current_derivatives(velocity, rho);
                if with_respect_to == Quantity::CurrentSpeed {
                    per_speed[i]
                } else {
                    per_degree[i]
                }
            }
            (
                Quantity::ForceRadiation(_)
                | Quantity::ForceExcitation(_)
                | Quantity::WaveElevation
                | Quantity::Power
                | Quantity::Energy
                | Quantity::AddedMassInf(..)
                | Quantity::DampingDirect(..)
                | Quantity::StiffnessHydrostatic(..),
                Quantity::CurrentSpeed | Quantity::CurrentHeading,
            ) => 0.0,
            (Quantity::ForceDrift(_), Quantity::CurrentSpeed | Quantity::CurrentHeading)
                if self.drift.is_some() =>
            {
                0.0
            }
            _ => return Ok(None),
        };
        Ok(Some(value))
    }

    /// The strips' force in the DOF of `of` (`force` or `force_viscous`) per unit `rho`: its
    /// derivative with respect to `rho` (`None`: no strips).
    pub(super) fn crossflow_per_rho(&self, of: Quantity) -> Option<f64> {
        let viscous = self.viscous.as_ref()?;
        let crossflow = viscous.crossflow()?;
        let (Quantity::Force(i) | Quantity::ForceViscous(i)) = of else {
            return Some(0.0);
        };
        let velocity = self.state.velocity.as_slice();
        let mut force = vec![0.0; velocity.len()];
        crossflow.add_force(velocity, 1.0, viscous.lateral_current, &mut force);
        force.get(i).copied()
    }

    /// Sets `current.speed`, `current.heading`, `damping_linear[i,j]`,
    /// `damping_quadratic[i]` or `crossflow.drag_scale`; a value refused names the variable and changes nothing.
    pub(super) fn set_viscous_value(
        &mut self,
        quantity: Quantity,
        value: f64,
    ) -> Result<(), super::ModelError> {
        let n = self.dof_count();
        let Some(viscous) = self.viscous.as_mut() else {
            return Err(super::ModelError::Variable(format!(
                "{quantity:?}: this FMU was packed without viscous damping"
            )));
        };
        let result = match quantity {
            Quantity::CurrentSpeed => viscous.set_current(value, viscous.heading),
            Quantity::CurrentHeading => viscous.set_current(viscous.speed, value),
            Quantity::DampingLinear(i, j) if i < n && j < n => viscous.set_linear(i, j, value),
            Quantity::DampingQuadratic(i) if i < n => viscous.set_quadratic(i, value),
            Quantity::CrossflowDragScale => viscous.set_crossflow_scale(value),
            other => Err(format!("{other:?} cannot be set")),
        };
        self.state.current = [viscous.speed, viscous.heading];
        self.outputs_valid = false;
        result.map_err(super::ModelError::Variable)
    }
}
