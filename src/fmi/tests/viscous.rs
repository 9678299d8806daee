//! Viscous damping and current through the fmi2 C functions.

use super::*;
use crate::fmu::variables::Quantity;
use crate::model::tests::TWO_DOF_NETWORK;
use crate::model::viscous::{write_csv, Frame};
use nalgebra::{DMatrix, DVector};

#[test]
fn the_viscous_variables_work_through_the_c_functions() {
    let names = vec!["sway".to_string(), "roll".to_string()];
    let linear = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1.0]);
    let quadratic = DVector::from_vec(vec![3.0, 0.5]);
    let csv = write_csv(&names, Frame::Section, &linear, &quadratic);
    let fmu = Unpacked::with_files(
        TWO_DOF_NETWORK,
        false,
        "resources",
        &[(Resources::VISCOUS_FILE, &csv)],
    );
    let layout = crate::fmu::Layout::new(
        names
            .iter()
            .map(|d| crate::fmu::DofUnit::new(d, 0, false))
            .collect(),
        false,
    )
    .unwrap()
    .with_viscous(&linear, &quadratic)
    .unwrap();
    let vr = |q| layout.value_reference(q).unwrap();
    let log = Log::default();
    let functions = callbacks(&log);
    let c = instantiate(&fmu, &fmu.uri(), &functions, false);
    assert!(!c.is_null());
    // SAFETY: see the module docs.
    unsafe {
        set(c, &[VR_RHO, VR_G], &[1.0, 1.0]);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
        // The master replaces the packed quadratic damping of sway.
        set(c, &[vr(Quantity::DampingQuadratic(0))], &[4.0]);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2OK);
        let packed = get(c, &[vr(Quantity::DampingLinear(0, 0))]);
        assert_eq!(packed, vec![2.0]);
        set(
            c,
            &[vr(Quantity::CurrentSpeed), vr(Quantity::CurrentHeading)],
            &[1.0, 180.0],
        );
        set(c, &[vr(Quantity::Velocity(0))], &[0.5]);
        assert_eq!(fmi2DoStep(c, 0.0, 0.1, 1), fmi2OK);
        let parts = [
            vr(Quantity::Force(0)),
            vr(Quantity::ForceRadiation(0)),
            vr(Quantity::ForceViscous(0)),
            vr(Quantity::ForceViscous(1)),
        ];
        let values = get(c, &parts);
        // v_r = 0.5 - (-1) = 1.5: F = -2 * 1.5 - 4 * 1.5^2.
        assert!((values[2] + 12.0).abs() < 1e-12, "{values:?}");
        assert_eq!(values[0], values[1] + values[2]);
        assert_eq!(values[3], 0.0);
        let mut derivative = [0.0];
        let status = fmi2GetDirectionalDerivative(
            c,
            &parts[0],
            1,
            &vr(Quantity::Velocity(0)),
            1,
            &1.0,
            derivative.as_mut_ptr(),
        );
        assert_eq!(status, fmi2OK);
        let direct = get(c, &[vr(Quantity::DampingDirect(0, 0))])[0];
        assert!(
            (derivative[0] - (-direct - 2.0 - 2.0 * 4.0 * 1.5)).abs() < 1e-12,
            "{derivative:?}"
        );
        // A current that is not finite: refused, naming it.
        let speed = vr(Quantity::CurrentSpeed);
        let status = fmi2SetReal(c, &speed, 1, &f64::NAN);
        assert_eq!(status, fmi2Error);
        fmi2FreeInstance(c);
    }
    let messages = log.lock().unwrap();
    assert!(
        messages.iter().any(|(_, _, m)| m.contains("current.speed")),
        "{messages:?}"
    );
}
