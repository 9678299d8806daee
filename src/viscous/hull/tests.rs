//! Ikeda's input from hulls, the natural frequency, the drag and the equivalent damping.

use super::super::{bilge_keel, equivalent_roll_damping, friction, BilgeKeels, RollDampingParams};
use super::*;

/// A box of breadth 20 m and draft 6 m with bilges of radius 1.5 m (24 points per arc), rigid
/// sway, heave and roll about the origin, then `extra`.
fn rounded_box(extra: &str) -> Hull {
    let (half, draft, radius) = (10.0, 6.0, 1.5);
    let mut points = vec![[-half, 0.0]];
    for (cx, start) in [(-half + radius, PI), (half - radius, 1.5 * PI)] {
        for k in 0..=24 {
            let angle = start + 0.5 * PI * k as f64 / 24.0;
            let centre_y = -draft + radius;
            points.push([cx + radius * angle.cos(), centre_y + radius * angle.sin()]);
        }
    }
    points.push([half, 0.0]);
    let contour: String = points
        .iter()
        .map(|p| format!("    <point x=\"{}\" y=\"{}\"/>\n", p[0], p[1]))
        .collect();
    let text = format!(
        "<hull name=\"box\" half_beam=\"10\">\n  <contour>\n{contour}  </contour>\n  \
         <rigid name=\"sway\" kind=\"sway\"/>\n  <rigid name=\"heave\" kind=\"heave\"/>\n  \
         <rigid name=\"roll\" kind=\"roll\"/>\n{extra}</hull>\n"
    );
    Hull::from_xml_str(&text, "box.xml").unwrap()
}

#[test]
fn a_semicircle_gives_its_breadth_draft_area_and_radius() {
    let roll = roll_params(&Hull::semicircle(2.0).unwrap(), 1025.0).unwrap();
    let p = roll.params;
    assert!((p.breadth - 4.0).abs() < 1e-9 && (p.draft - 2.0).abs() < 1e-9);
    assert!((p.area_coefficient - PI / 4.0).abs() < 1e-6);
    assert!((p.bilge_radius - 2.0).abs() < 1e-6, "{}", p.bilge_radius);
    assert_eq!(
        (p.roll_axis_height, roll.axis),
        (0.0, RollAxis::ReferencePoint)
    );
    assert_eq!(roll.dof, 2);
    assert!(p.bilge_keels.is_none());
}

#[test]
fn a_rounded_box_gives_its_bilge_radius_axis_and_keels() {
    let extra = "  <mass value=\"displaced\" x=\"0\" y=\"1.2\" radius_of_gyration=\"7\"/>\n  \
                 <bilge_keels breadth=\"0.4\" length_fraction=\"0.5\"/>\n";
    let hull = rounded_box(extra);
    let roll = roll_params(&hull, 1025.0).unwrap();
    let p = roll.params;
    assert!((p.breadth - 20.0).abs() < 1e-12 && (p.draft - 6.0).abs() < 1e-12);
    // The polygon's bilges miss a little more area than the arcs: R within 1 %.
    assert!((p.bilge_radius - 1.5).abs() < 0.015, "{}", p.bilge_radius);
    assert_eq!(p.roll_axis_height, -1.2);
    assert_eq!(roll.axis, RollAxis::CentreOfGravity);
    assert_eq!(
        p.bilge_keels,
        Some(BilgeKeels {
            breadth: 0.4,
            length_fraction: 0.5
        })
    );
    // The components are those of the parameters by hand.
    let (_, damping) = hull_roll_damping(&hull, 1025.0, 0.5, 0.1).unwrap();
    let by_hand = RollDampingParams {
        roll_axis_height: -1.2,
        bilge_keels: p.bilge_keels,
        ..RollDampingParams::new(20.0, 6.0, p.area_coefficient, p.bilge_radius)
    };
    assert_eq!(damping, roll_damping(&by_hand, 0.5, 0.1).unwrap());
    assert!(damping.bilge_keel.quadratic > 0.0 && damping.eddy_making.quadratic > 0.0);
}

#[test]
fn hulls_without_roll_or_waterline_are_refused_clearly() {
    let no_roll = Hull::semicircle(1.0)
        .unwrap()
        .select_dofs(&["sway", "heave"])
        .unwrap();
    let e = roll_params(&no_roll, 1025.0).unwrap_err().to_string();
    assert!(
        e.contains("no rigid roll DOF (its DOFs: sway heave)"),
        "{e}"
    );
    let submerged = Hull::circle(1.0, 2.0).unwrap();
    let e = section_estimate(&submerged, 1025.0, 1.0, 0.1)
        .unwrap_err()
        .to_string();
    assert!(e.contains("the contour is closed"), "{e}");
    // The axis at the keel: Ikeda's formulas refuse it, naming the field.
    let deep = rounded_box("  <mass value=\"1\" x=\"0\" y=\"-7\" radius_of_gyration=\"1\"/>\n");
    let e = roll_params(&deep, 1025.0).unwrap_err().to_string();
    assert!(e.contains("roll_axis_height = 7"), "{e}");
    // Without a roll DOF the estimate is the drag alone.
    let estimate = section_estimate(&no_roll, 1025.0, 1.0, 0.1).unwrap();
    assert!(estimate.roll.is_none() && estimate.drag.len() == 2);
}

#[test]
fn the_natural_frequency_of_a_semicircle_is_the_weight_over_the_dry_inertia() {
    let text = "<hull name=\"float\" half_beam=\"1\">\n  <circle radius=\"1\" depth=\"0\"/>\n  \
                <rigid name=\"roll\" kind=\"roll\"/>\n  \
                <mass value=\"displaced\" x=\"0\" y=\"0.2\" radius_of_gyration=\"0.3\"/>\n\
                </hull>\n";
    let hull = Hull::from_xml_str(text, "float.xml").unwrap();
    // A semicircle about its centre has no buoyancy restoring in roll: C = -m g y_G < 0 with G
    // above the centre; below it, C = m g |y_G| and I = m (k^2 + y_G^2).
    assert_eq!(roll_natural_frequency(&hull, 1025.0, 9.81), None);
    let below = Hull::from_xml_str(&text.replace("y=\"0.2\"", "y=\"-0.2\""), "f.xml").unwrap();
    let omega = roll_natural_frequency(&below, 1025.0, 9.81).unwrap();
    let by_hand: f64 = (9.81 * 0.2 / (0.09 + 0.04_f64)).sqrt();
    assert!(
        (omega - by_hand).abs() < 1e-6 * by_hand,
        "{omega} vs {by_hand}"
    );
    assert_eq!(
        roll_natural_frequency(&Hull::semicircle(1.0).unwrap(), 1025.0, 9.81),
        None
    );
}

#[test]
fn the_drag_of_a_semicircle_is_half_rho_cd_times_its_projection() {
    let drag = section_drag(&Hull::semicircle(1.0).unwrap(), 1025.0).unwrap();
    assert_eq!(drag.len(), 2);
    // Double body 2 x 2 m, a circle: the square's 2.05 halved by the rounding.
    let sway = drag[0];
    assert_eq!((sway.dof, sway.flow), (0, CrossFlow::Sway));
    assert!((sway.drag_coefficient - 1.025).abs() < 1e-6);
    assert!((sway.quadratic - 0.5 * 1025.0 * sway.drag_coefficient * 1.0).abs() < 1e-9);
    let heave = drag[1];
    assert_eq!((heave.dof, heave.flow), (1, CrossFlow::Heave));
    assert!((heave.quadratic - 0.5 * 1025.0 * heave.drag_coefficient * 2.0).abs() < 1e-9);
}

#[test]
fn the_equivalent_damping_is_the_components_and_friction_alone_at_zero_amplitude() {
    let mut p = RollDampingParams::new(20.0, 6.0, 0.95, 1.5);
    let (omega, phi_a) = (0.5, 0.1);
    let total = roll_damping(&p, omega, phi_a).unwrap().total();
    let equivalent = equivalent_roll_damping(&p, omega, phi_a).unwrap();
    assert!((equivalent - total.equivalent_linear(omega, phi_a)).abs() < 1e-9 * equivalent);
    let still = equivalent_roll_damping(&p, omega, 0.0).unwrap();
    assert_eq!(still, friction(&p, omega, 0.0).linear);
    assert!(still < 0.1 * equivalent, "{still} vs {equivalent}");
    // With keels the vanishing amplitude keeps their linear parts, finite.
    p.bilge_keels = Some(BilgeKeels {
        breadth: 0.4,
        length_fraction: 0.5,
    });
    let keels = bilge_keel(&p, omega, 0.0);
    assert!(keels.linear.is_finite() && keels.linear > 0.0);
    let with_keels = equivalent_roll_damping(&p, omega, 0.0).unwrap();
    assert!((with_keels - still - keels.linear).abs() < 1e-9 * with_keels);
    let near = bilge_keel(&p, omega, 1e-9);
    assert!((near.linear - keels.linear).abs() < 1e-6 * keels.linear);
}

#[test]
fn a_semicircle_rolling_off_its_centre_gets_no_negative_eddy_damping() {
    let mut p = RollDampingParams::new(2.0, 1.0, PI / 4.0, 1.0);
    p.roll_axis_height = 0.3;
    let c_r = super::super::eddy_coefficient(&p).unwrap();
    assert!(c_r < 0.0, "{c_r}");
    assert_eq!(super::super::eddy_making(&p).unwrap().quadratic, 0.0);
}
