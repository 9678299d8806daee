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
}
