//! Checks shared by the identification tests.

use hydrofmu::fmu::variables::Quantity;
use hydrofmu::network::Network;

/// Passive by the exact check, stable, and 300 s after a 1 s unit velocity pulse in any DOF
/// every force is below 1e-3 of its peak (no spurious slow mode).
pub fn assert_passive_and_forgets_a_pulse(network: &Network) {
    let check = hydrofmu::passivity::check(&network.state_space().unwrap(), 1e-9);
    assert!(check.passive && check.stable, "{check:?}");
    let n = network.dof_count();
    for dof in 0..n {
        let mut model = hydrofmu::Model::new(
            network,
            hydrofmu::ModelOptions {
                keep_inf_mass: false,
                guid: None,
            },
        )
        .unwrap();
        let h = 0.05;
        let (mut peak, mut last): (f64, f64) = (0.0, 0.0);
        for k in 0..(301.0 / h) as usize {
            let t = k as f64 * h;
            let v = if t < 1.0 - 1e-9 { 1.0 } else { 0.0 };
            model.set_value(Quantity::Velocity(dof), v).unwrap();
            let largest = (0..n)
                .map(|j| model.value(Quantity::Force(j)).unwrap().abs())
                .fold(0.0, f64::max);
            peak = peak.max(largest);
            model.step(model.time(), h).unwrap();
            last = (0..n)
                .map(|j| model.value(Quantity::Force(j)).unwrap().abs())
                .fold(0.0, f64::max);
        }
        assert!(last < 1e-3 * peak, "DOF {dof}: {last:e} of a peak {peak:e}");
    }
}
