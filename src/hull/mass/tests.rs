//! The `<mass>` element: reading, canonical writing, its errors with their lines, and the
//! mass properties it resolves to.

use super::*;

/// The semicircle of radius 1 m with rigid DOFs and `mass` after them (line 6 onwards).
fn floating(mass: &str) -> String {
    format!(
        "<hull name=\"float\" half_beam=\"1\">\n  <circle radius=\"1\" depth=\"0\"/>\n  \
         <rigid name=\"sway\" kind=\"sway\"/>\n  <rigid name=\"heave\" kind=\"heave\"/>\n  \
         <rigid name=\"roll\" kind=\"roll\"/>\n{mass}</hull>\n"
    )
}

const MOORED: &str =
    "  <mass value=\"displaced\" x=\"0\" y=\"-0.2\" radius_of_gyration=\"0.3\">\n    \
     <mooring dof=\"sway\" stiffness=\"1000\" damping=\"50\"/>\n    \
     <mooring dof=\"roll\" damping=\"7\"/>\n  </mass>\n";

fn error(text: &str) -> String {
    Hull::from_xml_str(text, "float.xml")
        .unwrap_err()
        .to_string()
}

#[test]
fn a_mass_element_is_read_written_canonically_and_read_back_the_same() {
    let hull = Hull::from_xml_str(&floating(MOORED), "float.xml").unwrap();
    let mass = hull.mass().expect("the file has <mass>");
    assert_eq!(mass.mass, SectionMass::Displaced);
    assert_eq!(mass.centre_of_gravity, [0.0, -0.2]);
    assert_eq!(mass.radius_of_gyration, 0.3);
    assert_eq!(
        mass.mooring,
        vec![
            Mooring {
                dof: "sway".into(),
                stiffness: 1000.0,
                damping: 50.0
            },
            Mooring {
                dof: "roll".into(),
                stiffness: 0.0,
                damping: 7.0
            }
        ]
    );
    let text = hull.to_xml_string();
    let again = Hull::from_xml_str(&text, "again.xml").unwrap();
    assert_eq!(again.mass(), hull.mass());
    assert_eq!(again.to_xml_string(), text);
    let given = Hull::from_xml_str(
        &floating("<mass value=\"812.5\" x=\"0.1\" y=\"-0.3\" radius_of_gyration=\"0\"/>\n"),
        "float.xml",
    )
    .unwrap();
    assert_eq!(given.mass().unwrap().mass, SectionMass::PerLength(812.5));
    assert!(given.mass().unwrap().mooring.is_empty());
}

#[test]
fn mass_leaves_the_geometry_fingerprint_and_a_massless_file_unchanged() {
    let fixed = Hull::from_xml_str(&floating(""), "float.xml").unwrap();
    let moored = Hull::from_xml_str(&floating(MOORED), "float.xml").unwrap();
    assert!(fixed.mass().is_none());
    assert!(!fixed.to_xml_string().contains("<mass"));
    // Same geometry and DOFs solve to the same tables; the whole file differs.
    assert_eq!(fixed.geometry_fingerprint(), moored.geometry_fingerprint());
    assert_ne!(fixed.fingerprint(), moored.fingerprint());
    assert_eq!(
        Hull::semicircle(1.0).unwrap().fingerprint(),
        Hull::from_file(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/hulls/semicircle.xml"
        )))
        .unwrap()
        .fingerprint()
    );
}

#[test]
fn selecting_dofs_drops_the_moorings_of_the_dofs_left_out() {
    let hull = Hull::from_xml_str(&floating(MOORED), "float.xml").unwrap();
    let kept = hull.select_dofs(&["heave", "roll"]).unwrap();
    let mooring = &kept.mass().unwrap().mooring;
    assert_eq!(mooring.len(), 1);
    assert_eq!(mooring[0].dof, "roll");
    // The canonical text of the selection reads back.
    Hull::from_xml_str(&kept.to_xml_string(), "kept.xml").unwrap();
}

#[test]
fn the_properties_resolve_the_displaced_mass_and_the_moorings_over_the_rigid_dofs() {
    let hull = Hull::from_xml_str(&floating(MOORED), "float.xml").unwrap();
    let properties = hull.mass().unwrap().properties(&hull, 1025.0).unwrap();
    // Semicircle of R = 1 m: A = pi / 2.
    let displaced = 1025.0 * std::f64::consts::FRAC_PI_2;
    assert!((properties.mass - displaced).abs() <= 1e-9 * displaced);
    assert_eq!(properties.stiffness[(0, 0)], 1000.0);
    assert_eq!(properties.damping[(0, 0)], 50.0);
    assert_eq!(properties.damping[(2, 2)], 7.0);
    assert_eq!(
        properties.stiffness.iter().filter(|&&v| v != 0.0).count(),
        1
    );
    let free = Hull::from_xml_str(
        &floating("<mass value=\"100\" x=\"0\" y=\"-0.2\" radius_of_gyration=\"0.3\"/>\n"),
        "float.xml",
    )
    .unwrap();
    let properties = free.mass().unwrap().properties(&free, 1025.0).unwrap();
    assert_eq!(properties.mass, 100.0);
    assert_eq!(properties.stiffness.len(), 0, "no mooring, no matrix");
}

#[test]
fn bad_mass_elements_are_refused_with_their_line_and_field() {
    let cases = [
        (
            "<mass value=\"-5\" x=\"0\" y=\"0\" radius_of_gyration=\"1\"/>\n",
            "float.xml:6: value=\"-5\" in <mass> must be > 0 kg/m",
        ),
        (
            "<mass value=\"heavy\" x=\"0\" y=\"0\" radius_of_gyration=\"1\"/>\n",
            "must be a mass per unit length in kg/m or \"displaced\"",
        ),
        (
            "<mass value=\"NaN\" x=\"0\" y=\"0\" radius_of_gyration=\"1\"/>\n",
            "must be a mass per unit length",
        ),
        (
            "<mass value=\"1\" x=\"0\" y=\"1e9\" radius_of_gyration=\"1\"/>\n",
            "centre of gravity (0, 1e9) has a component beyond",
        ),
        (
            "<mass value=\"1\" x=\"0\" y=\"0\" radius_of_gyration=\"-1\"/>\n",
            "radius_of_gyration=\"-1\" in <mass> must be >= 0",
        ),
        (
            "<mass value=\"1\" x=\"0\" radius_of_gyration=\"1\"/>\n",
            "missing the attribute y",
        ),
        (
            "<mass value=\"1\" x=\"0\" y=\"0\" radius_of_gyration=\"1\" cog=\"1\"/>\n",
            "unknown attribute cog",
        ),
        (
            "<mass value=\"1\" x=\"0\" y=\"0\" radius_of_gyration=\"1\">\n<mooring dof=\"bend\" stiffness=\"1\"/>\n</mass>\n",
            "float.xml:7: <mooring dof=\"bend\">: not a rigid DOF of the hull (its rigid DOFs: sway heave roll)",
        ),
        (
            "<mass value=\"1\" x=\"0\" y=\"0\" radius_of_gyration=\"1\">\n<mooring dof=\"sway\" stiffness=\"-1\"/>\n</mass>\n",
            "stiffness=\"-1\" in <mooring> must be >= 0",
        ),
        (
            "<mass value=\"1\" x=\"0\" y=\"0\" radius_of_gyration=\"1\">\n<mooring dof=\"sway\"/>\n</mass>\n",
            "needs stiffness or damping",
        ),
        (
            "<mass value=\"1\" x=\"0\" y=\"0\" radius_of_gyration=\"1\">\n<mooring dof=\"sway\" damping=\"1\"/>\n<mooring dof=\"sway\" damping=\"2\"/>\n</mass>\n",
            "float.xml:8: <mooring dof=\"sway\"> is given twice",
        ),
        (
            "<mass value=\"1\" x=\"0\" y=\"0\" radius_of_gyration=\"1\">\n<spring dof=\"sway\"/>\n</mass>\n",
            "unknown element <spring> in <mass>",
        ),
        (
            "<mass value=\"1\" x=\"0\" y=\"0\" radius_of_gyration=\"1\"/>\n<mass value=\"2\" x=\"0\" y=\"0\" radius_of_gyration=\"1\"/>\n",
            "float.xml:7: second <mass>: the mass properties are already given on line 6",
        ),
    ];
    for (mass, expected) in cases {
        let message = error(&floating(mass));
        assert!(message.contains(expected), "{mass}: {message}");
        assert!(message.contains("float.xml"), "{message}");
    }
}
