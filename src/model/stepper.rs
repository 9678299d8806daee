//! Exact stepping of the network state with the inputs held or ramped over the step.
//!
//! ```text
//! z(t + h) = Phi z + Gamma0 (P v) + Gamma1 (P v'),   Phi = exp(A h)   (per branch block)
//! ```
//!
//! The time after k equal steps is `anchor + k h` (no drift from repeated additions), for k up
//! to [`MAX_STEPS_SINCE_ANCHOR`] (then a new anchor); a step must start at the component's
//! time within [`TIME_TOLERANCE`], and end within the f64 range and not past the stop time
//! (the same tolerance).

use super::{ModelError, ModelState, RadiationSystem, MAX_STEPS_SINCE_ANCHOR, TIME_TOLERANCE};
use crate::discretize::BlockDiscretizationCache;
use nalgebra::{DMatrix, DVector};
use std::ops::Not;

/// True when no entry is NaN or infinite (all exponent bits set). One pass of integer
/// operations without an early exit, so it vectorizes.
fn all_finite(values: &[f64]) -> bool {
    const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
    values
        .iter()
        .fold(false, |bad, x| bad | (x.to_bits() & EXPONENT == EXPONENT))
        .not()
}

/// The state scales that balance each block before its exponential: `sqrt(P_ii)` of the
/// diagonal energy weight P (energy coordinates, in which a block's flow is a contraction).
fn balancing_scale(energy_weight: &DMatrix<f64>) -> Vec<f64> {
    energy_weight.diagonal().iter().map(|p| p.sqrt()).collect()
}

/// Steps a [`ModelState`] exactly; holds the discretization cache and scratch memory.
///
/// The branches see the hull only through their speeds `s = P v`, so the stepper
/// discretizes `z' = A z + B_r s` and one step is `z+ = [Phi | Gamma0 | Gamma1] [z; P v; P v']`
/// with block-diagonal `Phi` (one block per branch): O(r n + states) work.
#[derive(Clone, Debug)]
pub struct Stepper {
    cache: BlockDiscretizationCache,
    projection: DMatrix<f64>,
    next: DVector<f64>,
    speed: DVector<f64>,
    rate: DVector<f64>,
}

impl Stepper {
    /// A stepper for this system.
    pub fn new(system: &RadiationSystem) -> Result<Stepper, ModelError> {
        let r = system.branch_count();
        Ok(Stepper {
            cache: BlockDiscretizationCache::new(
                &system.a,
                &system.b_branch,
                &system.branch_states,
                &system.branch_inputs,
                &balancing_scale(&system.energy_weight),
            )?,
            projection: system.branch_projection.clone(),
            next: DVector::zeros(system.state_size()),
            speed: DVector::zeros(r),
            rate: DVector::zeros(r),
        })
    }

    /// Advances `state` from `current` (must match `state.time`) by h. On error the state
    /// is unchanged.
    pub fn step(&mut self, state: &mut ModelState, current: f64, h: f64) -> Result<(), ModelError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(ModelError::Step(format!(
                "step size {h} must be finite and > 0"
            )));
        }
        if !current.is_finite()
            || (current - state.time).abs() > TIME_TOLERANCE * state.time.abs().max(h)
        {
            return Err(ModelError::Step(format!(
                "communication point {current} does not match the component's time {}",
                state.time
            )));
        }
        // The time at the end: the count of equal steps goes on while it stays exact.
        let (anchor, steps) = if h.to_bits() == state.last_step.to_bits()
            && (1..MAX_STEPS_SINCE_ANCHOR).contains(&state.steps_since_anchor)
        {
            (state.time_anchor, state.steps_since_anchor + 1)
        } else {
            (current, 1)
        };
        let time = anchor + steps as f64 * h;
        if !time.is_finite() {
            return Err(ModelError::Step(format!(
                "the step from time {current:e} by {h:e} ends at {time}, beyond the f64 range"
            )));
        }
        if let Some(stop) = state.stop_time {
            if time > stop + TIME_TOLERANCE * stop.abs().max(h) {
                return Err(ModelError::Step(format!(
                    "the step from time {current} by {h} ends at {time}, past the stop time \
                     {stop} set at initialization (fmi2SetupExperiment, fmi3EnterInitializationMode)"
                )));
            }
        }
        // The network state is checked through `next` below; the inputs here.
        let inputs = [
            &state.velocity,
            &state.velocity_derivative,
            &state.acceleration,
            &state.acceleration_derivative,
        ];
        if inputs.iter().any(|v| !all_finite(v.as_slice())) {
            return Err(ModelError::Step("non-finite input".into()));
        }
        let d = self.cache.get(h)?;
        // Per branch b: next_b = Phi_b z_b + Gamma0_b (d_b . v) + Gamma1_b (d_b . v').
        self.speed.gemv(1.0, &self.projection, &state.velocity, 0.0);
        let ramp = state
            .velocity_derivative
            .as_slice()
            .iter()
            .any(|x| *x != 0.0);
        if ramp {
            self.rate
                .gemv(1.0, &self.projection, &state.velocity_derivative, 0.0);
        } else {
            self.rate.fill(0.0);
        }
        d.apply(
            state.network.as_slice(),
            self.speed.as_slice(),
            self.rate.as_slice(),
            self.next.as_mut_slice(),
        );
        if !all_finite(self.next.as_slice()) {
            return Err(ModelError::Step(
                "the network state is not finite after the step".into(),
            ));
        }
        let acceleration_ramp = state
            .acceleration_derivative
            .as_slice()
            .iter()
            .any(|x| *x != 0.0);
        let ramp_ok = |x: &DVector<f64>, dx: &DVector<f64>| {
            x.iter()
                .zip(dx.iter())
                .all(|(x, dx)| (x + dx * h).is_finite())
        };
        if (ramp && !ramp_ok(&state.velocity, &state.velocity_derivative))
            || (acceleration_ramp && !ramp_ok(&state.acceleration, &state.acceleration_derivative))
        {
            return Err(ModelError::Step(
                "the extrapolated inputs are not finite".into(),
            ));
        }
        std::mem::swap(&mut state.network, &mut self.next);
        if ramp {
            state.velocity.axpy(h, &state.velocity_derivative, 1.0);
        }
        if acceleration_ramp {
            state
                .acceleration
                .axpy(h, &state.acceleration_derivative, 1.0);
        }
        state.time_anchor = anchor;
        state.last_step = h;
        state.steps_since_anchor = steps;
        state.time = time;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::fmu::variables::Quantity;
    use crate::model::tests::seed;

    #[test]
    fn result_is_independent_of_the_step_split_with_first_order_hold() {
        // A ramp input: one step of 0.8 s equals 8 steps of 0.1 s (exact discretization).
        let run = |steps: usize| {
            let mut m = seed(1025.0, 9.81);
            m.set_value(Quantity::Velocity(0), 0.3).unwrap();
            m.set_input_derivative(Quantity::Velocity(0), -0.7).unwrap();
            let h = 0.8 / steps as f64;
            for k in 0..steps {
                m.step(k as f64 * h, h).unwrap();
            }
            (m.value(Quantity::Force(0)).unwrap(), m.state().clone())
        };
        let (f1, s1) = run(1);
        let (f8, s8) = run(8);
        assert!((f1 - f8).abs() < 1e-10 * f1.abs().max(1.0));
        assert!((s1.velocity[0] - s8.velocity[0]).abs() < 1e-14);
        assert!((s1.network - s8.network).amax() < 1e-10);
    }

    #[test]
    fn time_does_not_drift_over_many_equal_steps() {
        let mut m = seed(1.0, 1.0);
        let h = 0.1;
        let mut t = 0.0;
        for _ in 0..10_000 {
            m.step(t, h).unwrap();
            t += h; // a master that accumulates (drifts by ~1e-10 after 1e4 steps)
        }
        assert_eq!(m.time(), 10_000.0 * h);
        assert!((t - m.time()).abs() < 1e-9);
    }

    /// A one-DOF network of one branch with one stage, at rho = g = 1.
    fn one_stage(mass: f64, stiffness: f64, damping: f64) -> crate::model::Model {
        let text = format!(
            r#"<network format_version="1" form="series_chain" rho="1" g="1">
  <dof name="heave"/>
  <added_mass_inf><row>1</row></added_mass_inf>
  <branch><direction>1</direction>
    <stage mass="{mass:e}" stiffness="{stiffness:e}" damping="{damping:e}"/>
  </branch>
</network>"#
        );
        let mut m = crate::model::tests::model(&text, false);
        m.set_parameters(1.0, 1.0).unwrap();
        m
    }

    /// The exact step of one stage, `e' = r`, `m r' = -(k e + c r)` with `r = w - v` and v
    /// held: the new `(e, w)` from `(e, w)`, in closed form from the eigenvalues.
    fn exact_stage_step(
        (mass, stiffness, damping): (f64, f64, f64),
        (e, w): (f64, f64),
        v: f64,
        h: f64,
    ) -> (f64, f64) {
        let r = w - v;
        let sigma = damping / (2.0 * mass);
        let omega2 = stiffness / mass;
        let (e_new, r_new) = if sigma * sigma < omega2 {
            // Underdamped: e = exp(-sigma t) (e cos(wd t) + (r + sigma e) / wd sin(wd t)).
            let wd = (omega2 - sigma * sigma).sqrt();
            let (sin, cos) = (wd * h).sin_cos();
            let decay = (-sigma * h).exp();
            let b = (r + sigma * e) / wd;
            let e_new = decay * (e * cos + b * sin);
            let r_new = decay * ((b * wd - sigma * e) * cos - (e * wd + sigma * b) * sin);
            (e_new, r_new)
        } else {
            // Overdamped: real roots fast = -sigma - sqrt(..), slow = omega^2 / fast.
            let fast = -sigma - (sigma * sigma - omega2).sqrt();
            let slow = omega2 / fast;
            let (x_fast, x_slow) = ((fast * h).exp(), (slow * h).exp());
            let gap = slow - fast;
            let (a_fast, a_slow) = ((e * slow - r) / gap, (r - fast * e) / gap);
            (
                a_fast * x_fast + a_slow * x_slow,
                a_fast * fast * x_fast + a_slow * slow * x_slow,
            )
        };
        (e_new, r_new + v)
    }

    /// Largest error of steps of the stage against [`exact_stage_step`] from the same state,
    /// over a few steps with changing inputs: of the new state in the energy norm, of the
    /// energy and of the force, each relative to the size of the step's data (the states
    /// before and after, in the energy norm, and the input velocity: a state that decays to
    /// nothing keeps the scale it came from).
    fn stage_step_error(mass: f64, stiffness: f64, damping: f64, h: f64) -> f64 {
        let mut model = one_stage(mass, stiffness, damping);
        let mut worst: f64 = 0.0;
        let energy_norm = |e: f64, w: f64| (stiffness * e * e + mass * w * w).sqrt();
        for (k, v) in [1.0, -0.5, 2.0, 0.25, 0.0].into_iter().enumerate() {
            let start = &model.state().network;
            let start = (start[0], start[1]);
            model.set_value(Quantity::Velocity(0), v).unwrap();
            model.step(k as f64 * h, h).unwrap();
            let before = energy_norm(start.0, start.1);
            let exact = exact_stage_step((mass, stiffness, damping), start, v, h);
            let after = energy_norm(exact.0, exact.1);
            let size = before + after + mass.sqrt() * v.abs();
            let z = &model.state().network;
            let state_error = energy_norm(z[0] - exact.0, z[1] - exact.1) / size;
            // |E - E_exact| <= |z - z_exact|_P (|z|_P + |z_exact|_P) / 2.
            let energy = model.value(Quantity::Energy).unwrap();
            let energy_error = (energy - 0.5 * after * after).abs() / (size * size);
            // |k e| <= sqrt(k) |z|_P, |c (w - v)| <= c (|z|_P / sqrt(m) + |v|).
            let force = model.value(Quantity::ForceRadiation(0)).unwrap();
            let exact_force = stiffness * exact.0 + damping * (exact.1 - v);
            let force_size = stiffness.sqrt() * size + damping * (size / mass.sqrt() + v.abs());
            let force_error = (force - exact_force).abs() / force_size;
            worst = worst.max(state_error).max(energy_error).max(force_error);
        }
        worst
    }

    #[test]
    fn badly_scaled_stages_step_exactly() {
        // (mass, stiffness, damping, step, tolerance): sqrt(k / m) h from 1e-11 to 1e10 rad,
        // under- and overdamped; each tolerance about 2.5 times the error measured. The
        // error grows with the phase a mode turns through within the step (about 0.5 unit
        // roundoffs per radian; none once the mode has decayed), and with c h / m for an
        // overdamped stage (1.6e-8 at 5e18). Before the stages were balanced, k = 1e12 (1e6
        // rad a step) gave the energy 0.530 against 0.116 and a force of the wrong sign, k =
        // 1e20 at h = 2^-7 the energy 1e134 against 0.097, k = 1e4 an error of 6.5e-13.
        let cases = [
            (1.0, 1.0, 0.3, 0.1, 5e-16),
            (1.0, 1e4, 3.0, 0.1, 1e-15),
            (1.0, 1e12, 1.0, 1.0, 1e-10),
            (1.0, 1e20, 1.0, 0.0078125, 2e-9),
            (1.0, 1e18, 1.0, 0.5, 2e-8),
            (1.0, 1e20, 1e2, 1.0, 2e-15),
            (1.0, 1e20, 1e10, 1.0, 1e-15),
            (1.0, 1e-20, 1e-10, 0.1, 5e-16),
            (1e-20, 1e-8, 1e-20, 0.1, 2e-11),
            (1e20, 1e32, 1e20, 0.1, 2e-12),
            (1e-20, 1.0, 1.0, 0.05, 4e-8),
            (1.0, 1e12, 1e7, 0.1, 3e-15),
        ];
        for (mass, stiffness, damping, h, tolerance) in cases {
            let error = stage_step_error(mass, stiffness, damping, h);
            assert!(
                error < tolerance,
                "m {mass:e} k {stiffness:e} c {damping:e} h {h}: error {error:.3e}"
            );
        }
    }

    #[test]
    fn a_step_beyond_the_phase_limit_is_refused_and_a_shorter_one_taken() {
        // sqrt(k / m) = 1e10 rad/s: 1e10 rad in a step of 1 s.
        let mut model = one_stage(1.0, 1e20, 1.0);
        model.set_value(Quantity::Velocity(0), 1.0).unwrap();
        let before = model.state().clone();
        let message = model.step(0.0, 1.0).unwrap_err().to_string();
        for part in ["MAX_PHASE_PER_STEP", "beyond 1e9 rad", "at most 1"] {
            assert!(message.contains(part), "{part}: {message}");
        }
        assert_eq!(model.state(), &before);
        model.step(0.0, 0.1).unwrap();
        assert!(model.value(Quantity::Energy).unwrap() > 0.0);
    }
}
