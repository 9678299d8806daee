//! Ikeda's zero-speed components of one section (equations in the parent module).

use super::{Damping, RollDampingParams, ViscousError};
use std::f64::consts::PI;

/// The Lewis form of a section: `x = M((1+a1) sin t - a3 sin 3t)`,
/// `y = -M((1-a1) cos t + a3 cos 3t)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LewisForm {
    /// a_1.
    pub a1: f64,
    /// a_3.
    pub a3: f64,
    /// Scale M (m).
    pub scale: f64,
    /// Half-beam to draft ratio H_0 = B / (2 T).
    pub h0: f64,
}

impl LewisForm {
    /// Radius from the origin at the mapping angle `psi` (m).
    pub fn radius(&self, psi: f64) -> f64 {
        let (a1, a3) = (self.a1, self.a3);
        let x = (1.0 + a1) * psi.sin() - a3 * (3.0 * psi).sin();
        let y = (1.0 - a1) * psi.cos() + a3 * (3.0 * psi).cos();
        self.scale * x.hypot(y)
    }
}

/// The Lewis form of breadth B, draft T and area coefficient sigma (von Kerczek and Tuck).
pub fn lewis_form(breadth: f64, draft: f64, sigma: f64) -> Result<LewisForm, ViscousError> {
    let h0 = breadth / (2.0 * draft);
    let ratio = ((h0 - 1.0) / (h0 + 1.0)).powi(2);
    let c1 = (3.0 + 4.0 * sigma / PI) + (1.0 - 4.0 * sigma / PI) * ratio;
    let discriminant = 9.0 - 2.0 * c1;
    if discriminant < 0.0 || c1 == 0.0 {
        return Err(ViscousError::new(
            "area_coefficient",
            sigma,
            "no Lewis form for this breadth/draft",
        ));
    }
    let a3 = (-c1 + 3.0 + discriminant.sqrt()) / c1;
    let a1 = (1.0 + a3) * (h0 - 1.0) / (h0 + 1.0);
    Ok(LewisForm {
        a1,
        a3,
        scale: breadth / (2.0 * (1.0 + a1 + a3)),
        h0,
    })
}

/// Kato's skin friction, linear at `omega` (rad/s) and amplitude `phi_a` (rad).
pub fn friction(p: &RollDampingParams, omega: f64, phi_a: f64) -> Damping {
    let girth = 1.7 * p.draft + p.area_coefficient * p.breadth;
    let r_f = ((0.887 + 0.145 * p.area_coefficient) * girth - 2.0 * p.roll_axis_height) / PI;
    let reynolds = r_f * r_f * phi_a * phi_a * omega / p.nu;
    Damping {
        linear: 0.787
            * p.rho
            * girth
            * r_f
            * r_f
            * (omega * p.nu).sqrt()
            * (1.0 + 0.00814 * reynolds.powf(0.386)),
        quadratic: 0.0,
    }
}

/// Ikeda's eddy-making moment coefficient C_R of the naked section.
pub fn eddy_coefficient(p: &RollDampingParams) -> Result<f64, ViscousError> {
    let (t, og, sigma, r) = (
        p.draft,
        p.roll_axis_height,
        p.area_coefficient,
        p.bilge_radius,
    );
    if og >= sigma * t {
        return Err(ViscousError::new(
            "roll_axis_height",
            og,
            "at or above sigma T: Ikeda's sigma' is not positive",
        ));
    }
    let lewis = lewis_form(p.breadth, t, sigma)?;
    let (a1, a3, m) = (lewis.a1, lewis.a3, lewis.scale);
    let mut psi = 0.0;
    if a3 != 0.0 {
        let argument = a1 * (1.0 + a3) / (4.0 * a3);
        if argument.abs() <= 1.0 {
            let psi2 = 0.5 * argument.acos();
            if lewis.radius(psi2) > lewis.radius(0.0) {
                psi = psi2;
            }
        }
    }
    let r_max = lewis.radius(psi);
    let b0 = -2.0 * a3 * (5.0 * psi).sin()
        + a1 * (1.0 - a3) * (3.0 * psi).sin()
        + ((6.0 + 3.0 * a1) * a3 * a3 + (3.0 * a1 + a1 * a1) * a3 + a1 * a1) * psi.sin();
    let a0 = -2.0 * a3 * (5.0 * psi).cos()
        + a1 * (1.0 - a3) * (3.0 * psi).cos()
        + ((6.0 - 3.0 * a1) * a3 * a3 + (a1 * a1 - 3.0 * a1) * a3 + a1 * a1) * psi.cos();
    let h = 1.0 + a1 * a1 + 9.0 * a3 * a3 + 2.0 * a1 * (1.0 - 3.0 * a3) * (2.0 * psi).cos()
        - 6.0 * a3 * (4.0 * psi).cos();
    let f1 = 0.5 * (1.0 + (20.0 * (sigma - 0.7)).tanh());
    let f2 = 0.5 * (1.0 - (PI * sigma).cos())
        - 1.5 * (1.0 - (-5.0 * (1.0 - sigma)).exp()) * (PI * sigma).sin().powi(2);
    let f3 = 1.0 + 4.0 * (-1.65e5 * (1.0 - sigma).powi(2)).exp();
    let h0_prime = lewis.h0 * t / (t - og);
    let sigma_prime = (sigma * t - og) / (t - og);
    let gamma = PI.sqrt() * f3 * (r_max + 2.0 * m / h * a0.hypot(b0))
        / (2.0 * t * (1.0 - og / t) * (h0_prime * sigma_prime).sqrt());
    let c_p = 0.5 * (0.87 * (-gamma).exp() - 4.0 * (-0.187 * gamma).exp() + 3.0);
    let bilge = f1 * r / t;
    let arm = (1.0 - bilge) * (1.0 - og / t - bilge) + f2 * (lewis.h0 - bilge).powi(2);
    Ok((r_max / t).powi(2) * c_p * arm)
}

/// Ikeda's eddy making at zero speed, quadratic: `B_q = rho T^4 C_R / 2`, with a negative
/// `C_R` (near-circular sections rolling off their centre, where the fit dips below zero)
/// taken as 0: eddies do not feed energy into the roll.
pub fn eddy_making(p: &RollDampingParams) -> Result<Damping, ViscousError> {
    let c_r = eddy_coefficient(p)?.max(0.0);
    Ok(Damping {
        linear: 0.0,
        quadratic: 0.5 * p.rho * p.draft.powi(4) * c_r,
    })
}

/// Bilge keels: normal force (linear and quadratic parts) and hull pressure (equivalent
/// linear at the amplitude); zero without keels.
pub fn bilge_keel(p: &RollDampingParams, omega: f64, phi_a: f64) -> Damping {
    let Some(keels) = p.bilge_keels else {
        return Damping::default();
    };
    let b = keels.breadth;
    if b == 0.0 || keels.length_fraction == 0.0 {
        return Damping::default();
    }
    let (t, og, r, sigma) = (
        p.draft,
        p.roll_axis_height,
        p.bilge_radius,
        p.area_coefficient,
    );
    let h0 = p.breadth / (2.0 * t);
    let corner = (1.0 - 0.5 * 2f64.sqrt()) * r / t;
    let l = t * (h0 - corner).hypot(1.0 - og / t - corner);
    let f = 1.0 + 0.3 * (-160.0 * (1.0 - sigma)).exp();
    let normal_linear = 60.0 * p.rho * l * l * b * b * omega / (PI * PI);
    let normal_quadratic = 2.4 * p.rho * l.powi(3) * b * f;
    // Hull pressure (Ikeda 1978; ITTC 7.5-02-07-04.5).
    let s0 = (0.3 * PI * l * phi_a * f / b + 1.95) * b;
    let m1 = r / t;
    let m2 = og / t;
    let m3 = 1.0 - m1 - m2;
    let m4 = h0 - m1;
    let denominator = (h0 - 0.215 * m1) * (1.0 - 0.215 * m1);
    let m5 = (0.414 * h0 + 0.0651 * m1 * m1 - (0.382 * h0 + 0.0106) * m1) / denominator;
    let m6 = (0.414 * h0 + 0.0651 * m1 * m1 - (0.382 + 0.0106 * h0) * m1) / denominator;
    let (m7, m8) = if s0 > 0.25 * PI * r {
        let m7 = s0 / t - 0.25 * PI * m1;
        (m7, m7 + 0.414 * m1)
    } else {
        let angle = if r > 0.0 { s0 / r } else { 0.0 };
        (0.0, 1.414 * m1 * (1.0 - angle.cos()))
    };
    let a = (m3 + m4) * m8 - m7 * m7;
    let bb = m2 * m2 / (3.0 * (h0 - 0.215 * m1))
        + (1.0 - m1).powi(2) * (2.0 * m3 - m2) / (6.0 * (1.0 - 0.215 * m1))
        + m1 * (m3 * m5 + m4 * m6);
    // phi_a (-a C_P- + bb C_P+) with C_P- = -22.5 b/(pi l phi_a f) - 1.2, C_P+ = 1.2, written
    // so that it stays finite at phi_a = 0.
    let pressure_factor = a * (22.5 * b / (PI * l * f) + 1.2 * phi_a) + 1.2 * bb * phi_a;
    let pressure = 4.0 / (3.0 * PI) * p.rho * l * l * omega * t * t * pressure_factor;
    Damping {
        linear: keels.length_fraction * (normal_linear + pressure.max(0.0)),
        quadratic: keels.length_fraction * normal_quadratic,
    }
}
