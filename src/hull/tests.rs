//! Hull files: reading, validation messages with their lines, canonical writing, and DOF
//! selection.

use super::validate::sub;
use super::*;
use std::path::Path;

/// A 5-point open section; lines: hull 2, contour 3, points 4..=8, rigid 10..=12, mode 13.
const BOX: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<hull name="box" half_beam="2" units="m">
  <contour closed="false">
    <point x="-2" y="0"/>
    <point x="-2" y="-1"/>
    <point x="0" y="-1.5"/>
    <point x="2" y="-1"/>
    <point x="2" y="0"/>
  </contour>
  <rigid name="sway" kind="sway"/>
  <rigid name="heave" kind="heave"/>
  <rigid name="roll" kind="roll" x="0.5" y="-0.5"/>
  <mode name="bottom">
    <u x="0" y="0"/>
    <u x="0.25" y="0"/>
    <u x="0" y="1"/>
    <u x="-0.25" y="0"/>
    <u x="0" y="0"/>
  </mode>
</hull>
"#;

/// File text with the given points (contour on line 2, points from line 3) and a mode.
fn hull_xml(points: &[Point], closed: bool) -> String {
    let mut text = String::from("<hull name=\"t\" half_beam=\"1\">\n");
    text.push_str(&format!("<contour closed=\"{closed}\">\n"));
    for p in points {
        text.push_str(&format!("<point x=\"{}\" y=\"{}\"/>\n", p[0], p[1]));
    }
    text.push_str("</contour>\n<rigid name=\"heave\" kind=\"heave\"/>\n<mode name=\"m\">\n");
    for (i, _) in points.iter().enumerate() {
        text.push_str(&format!("<u x=\"{i}\" y=\"1\"/>\n"));
    }
    text.push_str("</mode>\n</hull>\n");
    text
}

fn expect_error(text: &str, line: Option<usize>, words: &str) -> HullError {
    let e = Hull::from_xml_str(text, "test.xml").expect_err("should be rejected");
    let shown = e.to_string();
    assert!(shown.starts_with("test.xml:"), "{shown}");
    assert_eq!(e.line(), line, "{shown}");
    assert!(shown.contains(words), "'{shown}' lacks '{words}'");
    e
}

fn close(a: Point, b: Point, tol: f64) -> bool {
    (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol
}

#[test]
fn file_contour_fields() {
    let h = Hull::from_xml_str(BOX, "box.xml").unwrap();
    assert_eq!(h.name(), "box");
    assert!(h.notes().is_empty());
    assert!(!h.is_closed());
    assert_eq!(h.dof_names(), ["sway", "heave", "roll", "bottom"]);
    assert_eq!(h.dof_kind(3), Some(DofKind::Elastic));
    assert_eq!(
        h.dof_kind(2),
        Some(DofKind::Rigid {
            kind: RigidKind::Roll,
            reference: [0.5, -0.5]
        })
    );
    let side = 0.5_f64.hypot(2.0);
    let length = 2.0 + 2.0 * side;
    assert!((h.contour_length() - length).abs() < 1e-14);
    let knots = h.breakpoints();
    let expected = [0.0, 1.0, 1.0 + side, 1.0 + 2.0 * side, length].map(|k| k / length);
    assert!(knots
        .iter()
        .zip(expected)
        .all(|(a, b)| (a - b).abs() < 1e-15));
    let vertices = [
        [-2.0, 0.0],
        [-2.0, -1.0],
        [0.0, -1.5],
        [2.0, -1.0],
        [2.0, 0.0],
    ];
    for (k, v) in knots.iter().zip(vertices) {
        assert!(close(h.point(*k), v, 1e-14));
    }
    // s proportional to arc length inside a segment; linear mode interpolation.
    let (s0, s1) = (
        knots[1] + 0.1 * (knots[2] - knots[1]),
        knots[1] + 0.7 * (knots[2] - knots[1]),
    );
    let d = sub(h.point(s1), h.point(s0));
    assert!((d[0].hypot(d[1]) - (s1 - s0) * length).abs() < 1e-14);
    assert!(close(h.displacement(3, s0), [0.25 * 0.9, 0.1], 1e-14));
    assert!(close(h.displacement(3, knots[2]), [0.0, 1.0], 1e-14));
    // Normal into the body: up on the bottom, right on the left side.
    assert!(close(
        h.normal(0.5 * (knots[0] + knots[1])),
        [1.0, 0.0],
        1e-15
    ));
    assert!(h.normal(s0)[1] > 0.9);
    let p = h.point(0.3);
    assert!(close(
        h.displacement(2, 0.3),
        [-(p[1] + 0.5), p[0] - 0.5],
        1e-15
    ));
    assert!(close(h.displacement(0, 0.3), [1.0, 0.0], 0.0));
    assert!(close(h.displacement(1, 0.3), [0.0, 1.0], 0.0));
    // Out-of-range s clamps.
    assert!(close(h.point(-1.0), [-2.0, 0.0], 0.0));
    assert!(close(h.point(2.0), [2.0, 0.0], 0.0));
}

#[test]
fn closed_file_contour() {
    let square = [[-1.0, -2.0], [1.0, -2.0], [1.0, -1.0], [-1.0, -1.0]];
    let h = Hull::from_xml_str(&hull_xml(&square, true), "sq.xml").unwrap();
    assert!(h.is_closed());
    assert!(h.notes().is_empty());
    let expected = [0.0, 2.0, 3.0, 5.0, 6.0].map(|k| k / 6.0);
    assert!(h
        .breakpoints()
        .iter()
        .zip(expected)
        .all(|(a, b)| (a - b).abs() < 1e-15));
    assert!(close(h.point(1.0), square[0], 0.0));
    assert!(close(h.point(11.0 / 12.0), [-1.0, -1.5], 1e-15));
    // Mode vectors wrap: between the last point (x = 3) and the first (x = 0).
    assert!(close(h.displacement(1, 11.0 / 12.0), [1.5, 1.0], 1e-15));
    assert!(close(h.normal(1.0 / 6.0), [0.0, 1.0], 1e-15));
    assert!(close(h.normal(11.0 / 12.0), [1.0, 0.0], 1e-15));
}

#[test]
fn clockwise_contours_are_reversed_with_a_note() {
    let ccw = Hull::from_xml_str(BOX, "box.xml").unwrap();
    // The same section written right-to-left, with the mode vectors in the same order.
    let mut lines: Vec<&str> = BOX.lines().collect();
    lines[3..8].reverse();
    lines[13..18].reverse();
    let cw = Hull::from_xml_str(&lines.join("\n"), "box.xml").unwrap();
    assert_eq!(cw.notes().len(), 1);
    assert!(cw.notes()[0].contains("reversed"), "{:?}", cw.notes());
    assert!(ccw.notes().is_empty());
    assert_eq!(cw.fingerprint(), ccw.fingerprint());
    assert_eq!(cw.to_xml_string(), ccw.to_xml_string());

    let square = [[-1.0, -2.0], [-1.0, -1.0], [1.0, -1.0], [1.0, -2.0]];
    let h = Hull::from_xml_str(&hull_xml(&square, true), "sq.xml").unwrap();
    assert_eq!(h.notes().len(), 1);
    // Start point kept, order reversed; vectors follow their points.
    assert!(close(h.point(0.0), [-1.0, -2.0], 0.0));
    assert!(close(h.point(1.0 / 3.0), [1.0, -2.0], 1e-15));
    assert!(close(h.displacement(1, 1.0 / 3.0), [3.0, 1.0], 1e-15));
    assert!(close(h.normal(1.0 / 6.0), [0.0, 1.0], 1e-15));
}

#[test]
fn waterline_points_snap_within_tolerance() {
    let text = BOX.replace(r#"<point x="2" y="0"/>"#, r#"<point x="2" y="1e-9"/>"#);
    let h = Hull::from_xml_str(&text, "box.xml").unwrap();
    assert_eq!(h.point(1.0), [2.0, 0.0]);
    assert!(h.notes()[0].contains("line 8"), "{:?}", h.notes());
    // 4 m wide section: tolerance 4 micrometres.
    let text = BOX.replace(r#"<point x="2" y="0"/>"#, r#"<point x="2" y="1e-5"/>"#);
    expect_error(&text, Some(8), "above the free surface");
}

#[test]
fn rejects_points_above_the_free_surface() {
    let text = BOX.replace(r#"y="-1.5""#, r#"y="0.3""#);
    expect_error(&text, Some(6), "above the free surface");
}

#[test]
fn rejects_open_ends_off_the_waterline() {
    let text = BOX.replace(r#"<point x="2" y="0"/>"#, r#"<point x="2" y="-0.2"/>"#);
    expect_error(&text, Some(8), "must end on the free surface");
    let text = BOX.replace(r#"<point x="-2" y="0"/>"#, r#"<point x="-2" y="-0.2"/>"#);
    expect_error(&text, Some(4), "first point");
}

#[test]
fn rejects_contours_touching_the_free_surface_inside() {
    let pts = [
        [-2.0, 0.0],
        [-1.0, -1.0],
        [0.0, 0.0],
        [1.0, -1.0],
        [2.0, 0.0],
    ];
    expect_error(&hull_xml(&pts, false), Some(5), "only the two end points");
    let pts = [[-1.0, -2.0], [1.0, -2.0], [0.0, 0.0]];
    expect_error(
        &hull_xml(&pts, true),
        Some(5),
        "must stay below the free surface",
    );
}

#[test]
fn rejects_self_intersection() {
    let pts = [
        [-2.0, 0.0],
        [1.0, -2.0],
        [1.0, -1.0],
        [-1.0, -2.0],
        [2.0, 0.0],
    ];
    expect_error(&hull_xml(&pts, false), Some(6), "intersects itself");
    // A figure of eight (closed) and a touching vertex.
    let pts = [[-1.0, -2.0], [1.0, -1.0], [1.0, -2.0], [-1.0, -1.0]];
    expect_error(&hull_xml(&pts, true), Some(6), "intersects itself");
    let pts = [
        [-2.0, 0.0],
        [0.0, -2.0],
        [1.0, -1.0],
        [0.0, -1.0],
        [0.5, -1.5],
        [2.0, 0.0],
    ];
    expect_error(&hull_xml(&pts, false), Some(7), "intersects itself");
    // Straight back along the previous segment.
    let pts = [
        [-2.0, 0.0],
        [-2.0, -2.0],
        [-2.0, -1.0],
        [2.0, -1.0],
        [2.0, 0.0],
    ];
    expect_error(&hull_xml(&pts, false), Some(4), "turns straight back");
    // A closed contour repeating its first point.
    let pts = [[-1.0, -2.0], [1.0, -2.0], [1.0, -1.0], [-1.0, -2.0]];
    expect_error(
        &hull_xml(&pts, true),
        Some(3),
        "do not repeat the first point",
    );
}

#[test]
fn rejects_too_few_points() {
    expect_error(
        &hull_xml(&[[-1.0, 0.0], [1.0, 0.0]], false),
        Some(2),
        "at least 3",
    );
    expect_error(&hull_xml(&[], true), Some(2), "has 0 points");
}

#[test]
fn rejects_bad_numbers() {
    for (bad, words) in [
        ("NaN", "not a finite number"),
        ("inf", "not a finite number"),
        ("-infinity", "not a finite number"),
        ("1,5", "not a number"),
        ("", "not a number"),
    ] {
        let text = BOX.replace(r#"y="-1.5""#, &format!("y=\"{bad}\""));
        let e = expect_error(&text, Some(6), words);
        assert!(e.message().contains("<point>"), "{e}");
    }
    let text = BOX.replace(r#"half_beam="2""#, r#"half_beam="two""#);
    expect_error(&text, Some(2), "half_beam=\"two\"");
    let text = BOX.replace(r#"<u x="0" y="1"/>"#, r#"<u x="0" y="nan"/>"#);
    expect_error(&text, Some(16), "not a finite number");
    let text = BOX.replace(r#"x="0.5" y="-0.5""#, r#"x="0.5" y="1e999""#);
    expect_error(&text, Some(12), "not a finite number");
}

#[test]
fn rejects_wrong_mode_vector_counts() {
    let text = BOX.replace("    <u x=\"0\" y=\"1\"/>\n", "");
    expect_error(
        &text,
        Some(13),
        "mode 'bottom' has 4 vectors but the contour has 5 points",
    );
    let text = BOX.replace(
        "<u x=\"0\" y=\"1\"/>",
        "<u x=\"0\" y=\"1\"/><u x=\"0\" y=\"1\"/>",
    );
    expect_error(&text, Some(13), "has 6 vectors");
    let text = BOX
        .replace(r#"x="0.25""#, r#"x="0""#)
        .replace(r#"x="-0.25""#, r#"x="0""#)
        .replace(r#"<u x="0" y="1"/>"#, r#"<u x="0" y="0"/>"#);
    expect_error(&text, Some(13), "zero at every point");
}

#[test]
fn rejects_duplicate_and_bad_dof_names() {
    let text = BOX.replace(r#"name="heave""#, r#"name="sway""#);
    expect_error(
        &text,
        Some(11),
        "duplicate DOF name 'sway' (first defined on line 10)",
    );
    let text = BOX.replace(r#"name="bottom""#, r#"name="roll""#);
    expect_error(&text, Some(13), "duplicate DOF name 'roll'");
    let text = BOX.replace(r#"name="bottom""#, r#"name="bottom plate""#);
    expect_error(&text, Some(13), "must start with a letter");
    let text = BOX.replace(r#"kind="heave""#, r#"kind="pitch""#);
    expect_error(&text, Some(11), "kind=\"pitch\"");
}

#[test]
fn rejects_unknown_elements_and_attributes() {
    let text = BOX.replace(
        "  <rigid name=\"sway\"",
        "  <keel/>\n  <rigid name=\"sway\"",
    );
    expect_error(&text, Some(10), "unknown element <keel>");
    let text = BOX.replace(r#"<point x="0" y="-1.5"/>"#, r#"<pt x="0" y="-1.5"/>"#);
    expect_error(&text, Some(6), "unknown element <pt> in <contour>");
    let text = BOX.replace(r#"kind="sway""#, r#"kind="sway" z="1""#);
    expect_error(&text, Some(10), "unknown attribute z in <rigid>");
    let text = BOX.replace(r#"units="m""#, r#"units="m" colour="red""#);
    expect_error(&text, Some(2), "unknown attribute colour in <hull>");
    let text = BOX.replace(r#"units="m""#, r#"units="ft""#);
    expect_error(&text, Some(2), "units=\"ft\"");
    let text = BOX.replace(
        r#"<point x="0" y="-1.5"/>"#,
        r#"<point x="0" y="-1.5">1</point>"#,
    );
    expect_error(&text, Some(6), "unexpected text");
    let text = BOX.replace(
        r#"<point x="0" y="-1.5"/>"#,
        r#"<point x="0" x="1" y="-1.5"/>"#,
    );
    expect_error(&text, Some(6), "bad attribute");
}

#[test]
fn rejects_missing_or_bad_half_beam() {
    let text = BOX.replace(r#" half_beam="2""#, "");
    expect_error(&text, Some(2), "missing the attribute half_beam");
    for bad in ["0", "-3"] {
        let text = BOX.replace(r#"half_beam="2""#, &format!("half_beam=\"{bad}\""));
        expect_error(&text, Some(2), "half_beam must be positive");
    }
}

#[test]
fn rejects_malformed_xml_and_structure() {
    let text = BOX.replace("</mode>", "</mod>");
    expect_error(&text, Some(19), "malformed XML");
    let text = BOX.replace("</hull>\n", "");
    let e = Hull::from_xml_str(&text, "test.xml").unwrap_err();
    assert!(e.to_string().starts_with("test.xml"), "{e}");
    let text = format!("{BOX}<hull name=\"b\" half_beam=\"1\"/>\n");
    expect_error(&text, Some(21), "second top-level element");
    expect_error("<ship/>", Some(1), "expected <hull>");
    expect_error("<hull name=\"a\" half_beam=\"1\"/>", Some(1), "no geometry");
    let text = BOX.replace(
        "  <contour",
        "  <circle radius=\"1\" depth=\"0\"/>\n  <contour",
    );
    expect_error(&text, Some(4), "second geometry");
    let e = Hull::from_file(Path::new("/nonexistent/hull.xml")).unwrap_err();
    assert_eq!(e.source_name(), "/nonexistent/hull.xml");
    assert!(e.message().contains("cannot read"));
}

#[test]
fn circle_elements_in_files() {
    let semi = Hull::semicircle(1.5).unwrap();
    let text = semi.to_xml_string();
    assert!(
        text.contains("<circle radius=\"1.5\" depth=\"0.0\"/>"),
        "{text}"
    );
    let back = Hull::from_xml_str(&text, "semi.xml").unwrap();
    assert_eq!(back.fingerprint(), semi.fingerprint());
    for dof in 0..semi.dof_count() {
        for s in [0.0, 0.13, 0.5, 0.77, 1.0] {
            assert_eq!(back.displacement(dof, s), semi.displacement(dof, s));
        }
    }
    let sub = "<hull name=\"c\" half_beam=\"1\">\n<circle radius=\"1\" depth=\"0.5\"/>\n\
                   <rigid name=\"sway\" kind=\"sway\"/>\n</hull>";
    expect_error(sub, Some(2), "pierces");
    let cb = sub.replace("0.5", "2").replace(
        "<rigid name=\"sway\" kind=\"sway\"/>",
        "<craig_bampton name=\"a\" mode=\"1\"/>",
    );
    expect_error(&cb, Some(3), "needs the semicircle");
    let text = BOX.replace(
        "<rigid name=\"sway\" kind=\"sway\"/>",
        "<craig_bampton name=\"cb1\" mode=\"1\"/>",
    );
    expect_error(&text, Some(10), "needs the built-in semicircle");
    let circle = Hull::circle(2.0, 3.0).unwrap();
    let back = Hull::from_xml_str(&circle.to_xml_string(), "c.xml").unwrap();
    assert_eq!(back.to_xml_string(), circle.to_xml_string());
    assert!(back.is_closed());
}

#[test]
fn xml_round_trip_and_fingerprints() {
    let h = Hull::from_xml_str(BOX, "box.xml").unwrap();
    let text = h.to_xml_string();
    let back = Hull::from_xml_str(&text, "canonical.xml").unwrap();
    assert_eq!(back.to_xml_string(), text);
    assert_eq!(back.fingerprint(), h.fingerprint());
    assert_eq!(h.fingerprint().len(), 16);
    for s in [0.0, 0.2, 0.41, 0.9, 1.0] {
        for dof in 0..4 {
            assert_eq!(back.displacement(dof, s), h.displacement(dof, s));
        }
    }
    // Any change to the hull changes the fingerprint.
    let variants = [
        BOX.replace(r#"y="-1.5""#, r#"y="-1.5000000000000002""#),
        BOX.replace(r#"name="box""#, r#"name="box2""#),
        BOX.replace(r#"half_beam="2""#, r#"half_beam="2.5""#),
        BOX.replace(r#"x="0.5" y="-0.5""#, r#"x="0.5" y="-0.25""#),
        BOX.replace(r#"<u x="0" y="1"/>"#, r#"<u x="0" y="2"/>"#),
        BOX.replace(r#"name="bottom""#, r#"name="bottom1""#),
    ];
    let mut prints = vec![h.fingerprint()];
    for v in &variants {
        prints.push(Hull::from_xml_str(v, "v.xml").unwrap().fingerprint());
    }
    prints.push(
        h.select_dofs(&["heave", "sway", "roll", "bottom"])
            .unwrap()
            .fingerprint(),
    );
    prints.push(Hull::semicircle(1.0).unwrap().fingerprint());
    prints.push(Hull::semicircle(1.0 + 1e-15).unwrap().fingerprint());
    prints.push(Hull::circle(1.0, 2.0).unwrap().fingerprint());
    prints.push(Hull::circle(1.0, 2.5).unwrap().fingerprint());
    let count = prints.len();
    prints.sort();
    prints.dedup();
    assert_eq!(prints.len(), count);
    // Escaped characters and comments are read.
    let text = BOX
        .replace(r#"name="box""#, "name=\"box&#45;a\"")
        .replace("<contour", "<!-- written by hand -->\n  <contour");
    assert_eq!(Hull::from_xml_str(&text, "b.xml").unwrap().name(), "box-a");
}

#[test]
fn select_dofs_keeps_order_and_checks_names() {
    let h = Hull::semicircle(1.0).unwrap();
    let sel = h.select_dofs(&["cb4", "sway", "cb1"]).unwrap();
    assert_eq!(sel.dof_names(), ["cb4", "sway", "cb1"]);
    assert_eq!(sel.displacement(0, 0.3), h.displacement(6, 0.3));
    assert_eq!(sel.dof_kind(0), Some(DofKind::CraigBampton { mode: 4 }));
    for (names, words) in [
        (&["sway", "pitch"][..], "unknown DOF 'pitch'"),
        (&["sway", "sway"][..], "selected twice"),
        (&[][..], "no DOFs selected"),
    ] {
        let e = h.select_dofs(names).unwrap_err();
        assert!(e.message().contains(words), "{e}");
        assert!(
            e.message()
                .contains("sway heave roll cb1 cb2 cb3 cb4 cb5 cb6"),
            "{e}"
        );
        assert_eq!(e.source_name(), "semicircle");
    }
}

#[test]
fn a_contour_of_the_largest_size_is_read_and_a_larger_one_refused() {
    // An open half circle below the free surface, `n` points from waterline to waterline.
    let half_circle = |n: usize| -> Vec<Point> {
        (0..n)
            .map(|k| {
                let t = std::f64::consts::PI * k as f64 / (n - 1) as f64;
                [-t.cos(), if k == 0 || k == n - 1 { 0.0 } else { -t.sin() }]
            })
            .collect()
    };
    // The attack's 40,000 points took 125 s in the pairwise contact check; now refused at
    // once, naming the limit; the largest accepted contour is checked by the grid.
    expect_error(
        &hull_xml(&half_circle(40_000), false),
        Some(2),
        "at most 8192",
    );
    expect_error(
        &hull_xml(&half_circle(MAX_CONTOUR_POINTS + 1), false),
        Some(2),
        "the contour has 8193 points; at most 8192",
    );
    let hull = Hull::from_xml_str(&hull_xml(&half_circle(MAX_CONTOUR_POINTS), false), "t.xml");
    assert!(hull.is_ok(), "{:?}", hull.err());
}

#[test]
fn a_hull_file_nested_200000_deep_is_refused_in_a_small_thread() {
    // Was a stack overflow that aborted fmu-pack.
    let mut text = String::from("<hull name=\"t\" half_beam=\"1\">");
    text.push_str(&"<contour>".repeat(200_000));
    text.push_str(&"</contour>".repeat(200_000));
    text.push_str("</hull>");
    let shown = std::thread::Builder::new()
        .stack_size(512 * 1024)
        .spawn(move || {
            Hull::from_xml_str(&text, "deep.xml")
                .err()
                .map(|e| e.to_string())
        })
        .unwrap()
        .join()
        .unwrap()
        .expect("refused");
    assert!(shown.starts_with("deep.xml:1:"), "{shown}");
    assert!(shown.contains("MAX_DEPTH"), "{shown}");
}

/// BOX with every contour coordinate multiplied by `scale`.
fn scaled_box(scale: f64) -> String {
    let mut text = BOX.to_string();
    for (x, y) in [
        ("-2", "0"),
        ("-2", "-1"),
        ("0", "-1.5"),
        ("2", "-1"),
        ("2", "0"),
    ] {
        let scaled = |v: &str| format!("{:e}", v.parse::<f64>().unwrap() * scale);
        text = text.replace(
            &format!(r#"<point x="{x}" y="{y}"/>"#),
            &format!(r#"<point x="{}" y="{}"/>"#, scaled(x), scaled(y)),
        );
    }
    text
}

#[test]
fn rejects_lengths_that_cannot_give_meaningful_numbers() {
    let half_beam = |v: &str| BOX.replace(r#"half_beam="2""#, &format!("half_beam=\"{v}\""));
    expect_error(
        &half_beam("1e154"),
        Some(2),
        "half_beam = 1e154 m is outside [1e-6, 1000000] m",
    );
    expect_error(&half_beam("1e-7"), Some(2), "half_beam = 1e-7 m is outside");
    // Within the absolute bounds but far from the section's size (4 m).
    expect_error(
        &half_beam("5000"),
        Some(2),
        "more than 1000 times larger or smaller",
    );
    expect_error(
        &half_beam("0.001"),
        Some(2),
        "more than 1000 times larger or smaller",
    );
    // Coordinates near 1e-160: the half-beam first, then the section's size.
    let tiny = scaled_box(1e-160);
    expect_error(&tiny, Some(3), "the section's size");
    expect_error(
        &tiny.replace(r#"half_beam="2""#, r#"half_beam="2e-160""#),
        Some(2),
        "half_beam = 2e-160 m",
    );
    let far = BOX.replace(r#"<point x="0" y="-1.5"/>"#, r#"<point x="0" y="-1e154"/>"#);
    expect_error(
        &far,
        Some(6),
        "point (0, -1e154) has a component beyond 1000000 m",
    );
    let mode = BOX.replace(r#"<u x="0" y="1"/>"#, r#"<u x="0" y="1e154"/>"#);
    expect_error(&mode, Some(16), "displacement (0, 1e154)");
    let faint = BOX
        .replace(r#"<u x="0.25" y="0"/>"#, r#"<u x="2.5e-161" y="0"/>"#)
        .replace(r#"<u x="0" y="1"/>"#, r#"<u x="0" y="1e-160"/>"#)
        .replace(r#"<u x="-0.25" y="0"/>"#, r#"<u x="-2.5e-161" y="0"/>"#);
    expect_error(
        &faint,
        Some(13),
        "mode 'bottom': its largest displacement component 1e-160 m",
    );
    let all_zero = faint.replace("e-161", "e-400").replace("1e-160", "0");
    expect_error(&all_zero, Some(13), "mode 'bottom' is zero at every point");
    let reference = BOX.replace(r#"x="0.5" y="-0.5""#, r#"x="1e154" y="-0.5""#);
    expect_error(&reference, Some(12), "reference point (1e154, -0.5)");
    let circle = |radius: &str, depth: &str| {
        format!(
            "<hull name=\"c\" half_beam=\"1\">\n<circle radius=\"{radius}\" depth=\"{depth}\"/>\n\
             <rigid name=\"sway\" kind=\"sway\"/>\n</hull>"
        )
    };
    expect_error(
        &circle("1e154", "0"),
        Some(2),
        "radius = 1e154 m is outside",
    );
    expect_error(&circle("1", "1e154"), Some(2), "centre (0, -1e154)");
    for e in [
        Hull::semicircle(1e154).unwrap_err(),
        Hull::circle(1e-160, 2.0).unwrap_err(),
    ] {
        assert!(e.message().contains("radius = "), "{e}");
    }
    assert!(Hull::circle(1.0, 1e154).is_err());
    // The bounds themselves are accepted.
    for text in [half_beam("1000"), half_beam("0.004"), scaled_box(2.5e5)] {
        let text = text.replace(r#"half_beam="2""#, r#"half_beam="5e5""#);
        Hull::from_xml_str(&text, "edge.xml").unwrap_or_else(|e| panic!("{e}"));
    }
    Hull::semicircle(1e6).unwrap();
    Hull::semicircle(1e-6).unwrap();
}

#[test]
fn rejects_more_dofs_than_the_limit() {
    let dofs = |count: usize| {
        let rigid: String = (0..count)
            .map(|k| format!("  <rigid name=\"d{k}\" kind=\"sway\"/>\n"))
            .collect();
        BOX.replace("  <rigid name=\"sway\" kind=\"sway\"/>\n", &rigid)
    };
    let at_limit = Hull::from_xml_str(&dofs(256 - 3), "many.xml").unwrap();
    assert_eq!(at_limit.dof_count(), 256);
    expect_error(
        &dofs(256 - 2),
        Some(10 + 256),
        "one more than the 256 a hull may have",
    );
}

#[test]
fn a_hull_past_the_bounds_gives_no_non_finite_number() {
    // The reader refuses these; built directly, the sweep must still not return NaN or inf.
    let good = Hull::from_xml_str(BOX, "box.xml").unwrap();
    let params = crate::sweep::SweepParams {
        kr: vec![0.5, 1.0],
        panels: crate::panels::PanelParams {
            body_panels: 16,
            ..crate::panels::PanelParams::default()
        },
        extrapolation_levels: 2,
        threads: 1,
        ..crate::sweep::SweepParams::default()
    };
    for half_beam in [1e154, 1e-160] {
        let hull = Hull {
            half_beam,
            ..good.clone()
        };
        match crate::sweep::run(&hull, &params, &|_, _| {}) {
            Err(e) => assert!(
                e.to_string().contains("finite") || e.to_string().contains("failed"),
                "{e}"
            ),
            Ok(result) => {
                let finite = |z: &num_complex::Complex64| z.re.is_finite() && z.im.is_finite();
                assert!(
                    result.added_mass.iter().flatten().all(finite),
                    "R = {half_beam:e}"
                );
                assert!(result.added_mass_inf.iter().all(|a| a.is_finite()));
                assert!(result
                    .added_mass_zero
                    .iter()
                    .flatten()
                    .all(|a| a.is_finite()));
                assert!(result
                    .excitation
                    .iter()
                    .all(|w| w.direct.iter().all(finite)));
                assert!(result.excitation_long_wave.iter().all(|x| x.is_finite()));
            }
        }
    }
}
