//! Substructures: the general passive, reciprocal mechanical element of a network, in which
//! a rational fit with poles common to every DOF is realized ([`crate::identify::synthesis`]).
//!
//! # The element
//!
//! `Nm` auxiliary bodies of unit mass (velocities `u`) and `Ns` springs of unit stiffness
//! (elongations `e`), attached to the hull coordinates `q` (velocities `v = q'`):
//!
//! ```text
//! e' = -R e + E [u; v]                        springs: elongation rate, relaxation R
//! u' = -E_u^T e - (C_uu u + C_uv v)           aux bodies: spring and damper forces
//! F  = -E_v^T e - (C_vu u + C_vv v)           the force on the hull by the water (without -A_inf q'')
//! ```
//!
//! `E = [E_u  E_v]` (`Ns x (Nm + n)`, `spring_incidence`) says how the velocities of the aux
//! bodies and the hull stretch each spring; `C = [[C_uu, C_uv], [C_vu, C_vv]]` (`damping`,
//! symmetric PSD, `(Nm + n)^2`) is a damping matrix over `[u; v]`; `R` (`spring_relaxation`,
//! symmetric PSD) is a damper in series with the springs (a Maxwell element; zero when every
//! spring acts alone). Energy and dissipation:
//!
//! ```text
//! E = 1/2 |e|^2 + 1/2 |u|^2,   dE/dt = -F . v - e^T R e - [u; v]^T C [u; v]  <=  -F . v,
//! ```
//!
//! so a substructure is passive for every `E` and every PSD `R`, `C`; its transfer function is
//! symmetric (reciprocal) because `C` and `R` are. Unit masses and springs lose no generality:
//! a body of mass `m` is the unit body at `sqrt(m)` times its velocity, a spring `k` the unit
//! spring at `sqrt(k)` times its elongation.
//!
//! Added-mass contribution (`s = i omega`): with the impedance
//! `Z(s) = C_Z (sI - A)^-1 B + C_vv` (force per hull velocity), states `[e; u]`,
//!
//! ```text
//! A = [[-R, E_u], [-E_u^T, -C_uu]],  B = [E_v; -C_uv],  C_Z = [E_v^T, C_vu],  G(s) = Z(s) / s,
//! ```
//!
//! `H(s) = A_inf + sum_branches + sum_substructures G(s)`.
//!
//! # Scaling to other rho and g
//!
//! `A~_new(omega) = (rho / rho0) A~_old(omega sqrt(g0 / g))` holds with `gamma = sqrt(g / g0)`
//! and `r = rho / rho0` when `R`, `E_u`, `C_uu` scale with `gamma`, `E_v`, `C_uv` with
//! `sqrt(r) gamma`, `C_vv` with `r gamma` (the states are energy coordinates, so `E` at a
//! fixed state does not change with rho and g).

use nalgebra::DMatrix;
use num_complex::Complex64;

/// A passive mechanical substructure (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Substructure {
    /// Number of auxiliary unit masses `Nm`.
    pub masses: usize,
    /// `E = [E_u E_v]`: elongation rate of each unit spring per velocity of `[aux masses; hull
    /// DOFs]` (`Ns x (Nm + n)`).
    pub spring_incidence: DMatrix<f64>,
    /// `R`: relaxation of the springs (`Ns x Ns`, symmetric PSD).
    pub spring_relaxation: DMatrix<f64>,
    /// `C`: damping over `[aux velocities; hull velocities]` (`(Nm + n)^2`, symmetric PSD).
    pub damping: DMatrix<f64>,
}

/// The impedance realization `(A, B, C_Z, D_Z)` of a substructure (module docs).
pub struct ImpedanceRealization {
    /// State matrix over `[e; u]`.
    pub a: DMatrix<f64>,
    /// Input matrix (hull velocity).
    pub b: DMatrix<f64>,
    /// Output matrix of the impedance (force the hull exerts on the water).
    pub c: DMatrix<f64>,
    /// Direct feedthrough `C_vv`.
    pub d: DMatrix<f64>,
}

impl Substructure {
    /// Number of springs `Ns`.
    pub fn spring_count(&self) -> usize {
        self.spring_incidence.nrows()
    }

    /// Number of states `Ns + Nm`.
    pub fn state_count(&self) -> usize {
        self.spring_count() + self.masses
    }

    /// Number of hull DOFs it attaches to.
    pub fn dof_count(&self) -> usize {
        self.damping.nrows().saturating_sub(self.masses)
    }

    /// `(A, B, C_Z, D_Z)` of the module docs.
    pub fn impedance_realization(&self) -> ImpedanceRealization {
        let (ns, nm, n) = (self.spring_count(), self.masses, self.dof_count());
        let e_u = self.spring_incidence.columns(0, nm);
        let e_v = self.spring_incidence.columns(nm, n);
        let c_uu = self.damping.view((0, 0), (nm, nm));
        let c_uv = self.damping.view((0, nm), (nm, n));
        let c_vu = self.damping.view((nm, 0), (n, nm));
        let mut a = DMatrix::zeros(ns + nm, ns + nm);
        a.view_mut((0, 0), (ns, ns))
            .copy_from(&(-&self.spring_relaxation));
        a.view_mut((0, ns), (ns, nm)).copy_from(&e_u);
        a.view_mut((ns, 0), (nm, ns)).copy_from(&(-e_u.transpose()));
        a.view_mut((ns, ns), (nm, nm)).copy_from(&(-c_uu));
        let mut b = DMatrix::zeros(ns + nm, n);
        b.view_mut((0, 0), (ns, n)).copy_from(&e_v);
        b.view_mut((ns, 0), (nm, n)).copy_from(&(-c_uv));
        let mut c = DMatrix::zeros(n, ns + nm);
        c.view_mut((0, 0), (n, ns)).copy_from(&e_v.transpose());
        c.view_mut((0, ns), (n, nm)).copy_from(&c_vu);
        let d = self.damping.view((nm, nm), (n, n)).into_owned();
        ImpedanceRealization { a, b, c, d }
    }

    /// The contribution `G(s) = Z(s) / s` to the added mass transfer function; at `s = 0`
    /// its limit `Z'(0) = -C_Z A^-2 B`, the static added mass (exact when `Z(0) = 0`, nothing
    /// attached to the ground; otherwise the finite part).
    pub fn dynamic_mass(&self, s: Complex64) -> DMatrix<Complex64> {
        let r = self.impedance_realization();
        if s == Complex64::new(0.0, 0.0) {
            let n = r.d.nrows();
            let nan = || DMatrix::from_element(n, n, Complex64::new(f64::NAN, 0.0));
            let lu = r.a.clone().lu();
            let Some(x) = lu.solve(&r.b).and_then(|x| lu.solve(&x)) else {
                return nan();
            };
            return (-&r.c * x).map(|v| Complex64::new(v, 0.0));
        }
        crate::realize::transfer_function(&r.a, &r.b, &r.c, &r.d, s) / s
    }

    /// The substructure in water of density `rho_ratio` times and gravity `gravity_ratio`
    /// times the reference (module docs).
    pub fn scaled(&self, rho_ratio: f64, gravity_ratio: f64) -> Substructure {
        let (nm, n) = (self.masses, self.dof_count());
        let gamma = gravity_ratio.sqrt();
        let mut spring_incidence = &self.spring_incidence * gamma;
        spring_incidence
            .columns_mut(nm, n)
            .scale_mut(rho_ratio.sqrt());
        let weights: Vec<f64> = (0..nm + n)
            .map(|i| if i < nm { 1.0 } else { rho_ratio.sqrt() })
            .collect();
        let damping = DMatrix::from_fn(nm + n, nm + n, |i, j| {
            self.damping[(i, j)] * gamma * weights[i] * weights[j]
        });
        Substructure {
            masses: nm,
            spring_incidence,
            spring_relaxation: &self.spring_relaxation * gamma,
            damping,
        }
    }

    /// The checks of [`super::Network::validate`] for a substructure on `n` DOFs: shapes,
    /// finite values, `R` and `C` symmetric PSD (relative tolerance `tolerance`).
    pub(super) fn validate(&self, n: usize, tolerance: f64) -> Result<(), String> {
        let (ns, nm) = (self.spring_count(), self.masses);
        if self.spring_incidence.ncols() != nm + n {
            return Err(format!(
                "spring_incidence has {} columns, expected masses + DOFs = {}",
                self.spring_incidence.ncols(),
                nm + n
            ));
        }
        if self.spring_relaxation.shape() != (ns, ns) {
            return Err(format!(
                "spring_relaxation is {}x{}, expected {ns}x{ns} (one row per spring)",
                self.spring_relaxation.nrows(),
                self.spring_relaxation.ncols()
            ));
        }
        if self.damping.shape() != (nm + n, nm + n) {
            return Err(format!(
                "damping is {}x{}, expected (masses + DOFs) = {}",
                self.damping.nrows(),
                self.damping.ncols(),
                nm + n
            ));
        }
        if ns + nm == 0 {
            return Err("it has neither springs nor masses".into());
        }
        for (name, m) in [
            ("spring_incidence", &self.spring_incidence),
            ("spring_relaxation", &self.spring_relaxation),
            ("damping", &self.damping),
        ] {
            if let Some(((i, j), x)) = m.iter().enumerate().find_map(|(k, x)| {
                (!x.is_finite()).then_some(((k % m.nrows() + 1, k / m.nrows() + 1), x))
            }) {
                return Err(format!("{name}[{i},{j}] = {x} is not finite"));
            }
        }
        for (name, m) in [
            ("spring_relaxation", &self.spring_relaxation),
            ("damping", &self.damping),
        ] {
            super::check_symmetric_psd(name, m, tolerance)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One unit spring from the hull (1 DOF) to one unit mass, damper c between them: the
    /// one-stage chain m = k = 1, so `G = (1 + c s) / (s^2 + c s + 1)`.
    fn one_stage(c: f64) -> Substructure {
        // Spring elongation e = x_aux - q: rate u - v.
        Substructure {
            masses: 1,
            spring_incidence: DMatrix::from_row_slice(1, 2, &[1.0, -1.0]),
            spring_relaxation: DMatrix::zeros(1, 1),
            damping: DMatrix::from_row_slice(2, 2, &[c, -c, -c, c]),
        }
    }

    #[test]
    fn a_unit_one_stage_substructure_is_the_one_stage_chain() {
        let sub = one_stage(0.3);
        for omega in [0.01, 0.5, 1.0, 3.0, 40.0] {
            let s = Complex64::new(0.0, omega);
            let expected = (1.0 + s * 0.3) / (s * s + s * 0.3 + 1.0);
            let got = sub.dynamic_mass(s)[(0, 0)];
            assert!((got - expected).norm() < 1e-13 * expected.norm(), "{omega}");
        }
    }

    #[test]
    fn scaling_matches_the_scaling_law_of_the_added_mass() {
        // A 2-DOF substructure with relaxation and coupling; A~_new(w) = r A~_old(w / gamma).
        let sub = Substructure {
            masses: 1,
            spring_incidence: DMatrix::from_row_slice(2, 3, &[1.0, -0.7, 0.2, 0.4, 0.3, -1.1]),
            spring_relaxation: DMatrix::from_row_slice(2, 2, &[0.2, 0.05, 0.05, 0.1]),
            damping: DMatrix::from_row_slice(
                3,
                3,
                &[0.5, -0.2, 0.1, -0.2, 0.3, 0.0, 0.1, 0.0, 0.2],
            ),
        };
        assert!(sub.validate(2, 1e-9).is_ok());
        let (r, gr) = (1025.0, 9.81);
        let scaled = sub.scaled(r, gr);
        for omega in [0.05, 0.7, 2.0, 9.0] {
            let new = scaled.dynamic_mass(Complex64::new(0.0, omega));
            let old =
                sub.dynamic_mass(Complex64::new(0.0, omega / gr.sqrt())) * Complex64::new(r, 0.0);
            assert!((&new - &old).norm() < 1e-12 * old.norm(), "{omega}");
        }
    }

    #[test]
    fn validation_names_the_broken_matrix() {
        let mut sub = one_stage(0.3);
        sub.damping[(0, 0)] = -1.0;
        let err = sub.validate(1, 1e-9).unwrap_err();
        assert!(err.contains("damping"), "{err}");
        let mut sub = one_stage(0.3);
        sub.spring_incidence = DMatrix::zeros(1, 3);
        let err = sub.validate(1, 1e-9).unwrap_err();
        assert!(err.contains("spring_incidence has 3 columns"), "{err}");
        let mut sub = one_stage(0.3);
        sub.spring_relaxation[(0, 0)] = f64::NAN;
        let err = sub.validate(1, 1e-9).unwrap_err();
        assert!(err.contains("spring_relaxation[1,1] = NaN"), "{err}");
    }
}
