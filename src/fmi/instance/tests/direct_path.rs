//! The direct get/set path (value references resolved at instantiation) against the general
//! path.

use super::*;

#[test]
fn the_direct_path_gives_the_general_paths_forces_bit_for_bit() {
    // Instance `direct` is driven by calls that only set inputs or only get forces (the
    // direct path); `general` through the model's own set_value and value, as the general
    // path does. Both keep the accelerations (keep_inf_mass) so that every input is used.
    let mut direct = ready(TWO_DOF_NETWORK, true);
    let mut general = ready(TWO_DOF_NETWORK, true);
    let reference = |inst: &Instance, q: Quantity| inst.layout.value_reference(q).unwrap();
    let inputs: Vec<u32> = (0..2)
        .flat_map(|k| [Quantity::Velocity(k), Quantity::Acceleration(k)])
        .map(|q| reference(&direct, q))
        .collect();
    let forces: Vec<u32> = (0..2)
        .map(|k| reference(&direct, Quantity::Force(k)))
        .collect();
    let mut forces_and_power = forces.clone();
    forces_and_power.push(reference(&direct, Quantity::Power));
    for n in 0..300 {
        let t = 0.01 * n as f64;
        let values = [
            (2.1 * t).sin(),
            2.1 * (2.1 * t).cos(),
            0.3 * (0.7 * t).cos(),
            -0.21 * (0.7 * t).sin(),
        ];
        assert_eq!(direct.set_real(&inputs, &values), Status::Ok);
        for (r, x) in inputs.iter().zip(values) {
            let quantity = general.layout.quantity(*r).unwrap();
            general.model.set_value(quantity, x).unwrap();
        }
        assert_eq!(direct.do_step(t, 0.01, true), Status::Ok);
        assert_eq!(general.do_step(t, 0.01, true), Status::Ok);
        let fast = get(&mut direct, &forces);
        // With the power among them, the call takes the general path.
        let slow = get(&mut direct, &forces_and_power);
        for (k, f) in fast.iter().enumerate() {
            let expected = general.model.value(Quantity::Force(k)).unwrap();
            assert_eq!(f.to_bits(), expected.to_bits(), "step {n}, force {k}");
            assert_eq!(f.to_bits(), slow[k].to_bits(), "step {n}, force {k}");
        }
    }
    assert!(direct.take_messages().is_empty());
}
