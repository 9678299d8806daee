//! The `<bilge_keels>` element: reading, canonical writing, the fingerprints, its errors.

use super::super::Hull;

/// The semicircle of radius 1 m with rigid DOFs and `extra` after them (line 6 onwards).
fn keeled(extra: &str) -> String {
    format!(
        "<hull name=\"keeled\" half_beam=\"1\">\n  <circle radius=\"1\" depth=\"0\"/>\n  \
         <rigid name=\"sway\" kind=\"sway\"/>\n  <rigid name=\"heave\" kind=\"heave\"/>\n  \
         <rigid name=\"roll\" kind=\"roll\"/>\n{extra}</hull>\n"
    )
}

const KEELS: &str = "  <bilge_keels breadth=\"0.05\" length_fraction=\"0.4\"/>\n";

#[test]
fn keels_are_read_written_canonically_and_read_back_the_same() {
    let hull = Hull::from_xml_str(&keeled(KEELS), "keeled.xml").unwrap();
    let keels = hull.bilge_keels().expect("the file has <bilge_keels>");
    assert_eq!((keels.breadth, keels.length_fraction), (0.05, 0.4));
    let text = hull.to_xml_string();
    assert!(text.contains(KEELS), "{text}");
    let again = Hull::from_xml_str(&text, "again.xml").unwrap();
    assert_eq!(again.bilge_keels(), hull.bilge_keels());
    assert_eq!(again.to_xml_string(), text);
    // Kept through a selection of DOFs, and with a <mass> in either order.
    assert_eq!(
        hull.select_dofs(&["roll"]).unwrap().bilge_keels(),
        Some(keels)
    );
    let mass = "  <mass value=\"displaced\" x=\"0\" y=\"0\" radius_of_gyration=\"0.3\"/>\n";
    let both = Hull::from_xml_str(&keeled(&format!("{KEELS}{mass}")), "k.xml").unwrap();
    let reversed = Hull::from_xml_str(&keeled(&format!("{mass}{KEELS}")), "k.xml").unwrap();
    assert_eq!(both.to_xml_string(), reversed.to_xml_string());
    assert!(both.mass().is_some() && both.bilge_keels().is_some());
}

#[test]
fn keels_leave_the_geometry_fingerprint_and_a_file_without_them_unchanged() {
    let bare = Hull::from_xml_str(&keeled(""), "keeled.xml").unwrap();
    let with = Hull::from_xml_str(&keeled(KEELS), "keeled.xml").unwrap();
    assert!(bare.bilge_keels().is_none());
    assert!(!bare.to_xml_string().contains("bilge_keels"));
    assert_eq!(bare.geometry_fingerprint(), with.geometry_fingerprint());
    assert_ne!(bare.fingerprint(), with.fingerprint());
}

#[test]
fn bad_keels_are_refused_with_their_line_and_field() {
    let cases = [
        (
            "<bilge_keels breadth=\"-0.1\" length_fraction=\"0.4\"/>\n",
            "keeled.xml:6: breadth=\"-0.1\" in <bilge_keels> must be > 0 m",
        ),
        (
            "<bilge_keels breadth=\"NaN\" length_fraction=\"0.4\"/>\n",
            "keeled.xml:6: breadth=\"NaN\" in <bilge_keels>",
        ),
        (
            "<bilge_keels breadth=\"0.1\" length_fraction=\"1.5\"/>\n",
            "length_fraction=\"1.5\" in <bilge_keels> must be in (0, 1]",
        ),
        (
            "<bilge_keels breadth=\"0.1\" length_fraction=\"0\"/>\n",
            "length_fraction=\"0\" in <bilge_keels> must be in (0, 1]",
        ),
        (
            "<bilge_keels breadth=\"0.1\"/>\n",
            "missing the attribute length_fraction",
        ),
        (
            "<bilge_keels breadth=\"2e6\" length_fraction=\"0.5\"/>\n",
            "breadth in <bilge_keels> = 2000000 m is outside",
        ),
        (
            "<bilge_keels breadth=\"0.1\" length_fraction=\"0.5\" depth=\"1\"/>\n",
            "unknown attribute depth in <bilge_keels>",
        ),
        (
            "<bilge_keels breadth=\"0.1\" length_fraction=\"0.5\"/>\n\
             <bilge_keels breadth=\"0.2\" length_fraction=\"0.5\"/>\n",
            "keeled.xml:7: second <bilge_keels>: the keels are already given on line 6",
        ),
    ];
    for (extra, expected) in cases {
        let message = Hull::from_xml_str(&keeled(extra), "keeled.xml")
            .unwrap_err()
            .to_string();
        assert!(message.contains(expected), "{extra}: {message}");
    }
}
