//! Network rules, transfer function limits, scaling and the file format.

use super::*;
use std::path::Path;

/// Schilder et al.'s 2-DOF chain (after eq. 19), nondimensional.
pub(crate) fn seed_network() -> Network {
    Network {
        substructures: Vec::new(),
        dof_names: vec!["sway".into()],
        added_mass_inf: DMatrix::from_element(1, 1, 0.1153),
        branches: vec![Branch {
            direction: DVector::from_element(1, 1.0),
            stages: vec![
                Stage {
                    mass: 0.5434,
                    stiffness: 0.2339,
                    damping: 0.9962,
                },
                Stage {
                    mass: 0.1877,
                    stiffness: 0.5522,
                    damping: 0.2453,
                },
            ],
        }],
        rho: 1.0,
        g: 1.0,
        form: NetworkForm::SeriesChain,
    }
}

/// A 3-DOF coupled network with chains along mixed directions.
pub(crate) fn coupled_network() -> Network {
    let a_inf = DMatrix::from_row_slice(3, 3, &[2.0, 0.3, -0.1, 0.3, 1.5, 0.2, -0.1, 0.2, 1.0]);
    let stage = |m, k, c| Stage {
        mass: m,
        stiffness: k,
        damping: c,
    };
    Network {
        substructures: Vec::new(),
        dof_names: vec!["sway".into(), "heave".into(), "roll".into()],
        added_mass_inf: a_inf,
        branches: vec![
            Branch {
                direction: DVector::from_vec(vec![1.0, 0.2, -0.5]),
                stages: vec![stage(0.8, 2.0, 0.6), stage(0.3, 1.1, 0.2)],
            },
            Branch {
                direction: DVector::from_vec(vec![0.0, 1.0, 0.3]),
                stages: vec![stage(1.2, 0.7, 0.9)],
            },
            Branch {
                direction: DVector::from_vec(vec![0.4, -0.6, 1.0]),
                stages: vec![stage(0.5, 3.0, 0.4)],
            },
        ],
        rho: 1025.0,
        g: 9.81,
        form: NetworkForm::Coupled,
    }
}

pub(crate) fn max_abs_diff(a: &DMatrix<Complex64>, b: &DMatrix<Complex64>) -> f64 {
    (a - b).iter().map(|x| x.norm()).fold(0.0, f64::max)
}

#[test]
fn seed_chain_limits_match_eq16() {
    let net = seed_network();
    net.validate().unwrap();
    // H(inf) = m0, H(0) = m0 + m1 + m2 (1e-6: the large-s limit converges like 1/s).
    let big = net.added_mass_at(Complex64::new(0.0, 1e8))[(0, 0)];
    assert!((big - 0.1153).norm() < 1e-6, "{big}");
    let zero = net.added_mass_zero()[(0, 0)];
    assert!((zero - (0.1153 + 0.5434 + 0.1877)).abs() < 1e-14);
    // One-stage chain equals Schilder et al.'s closed form (16) at an arbitrary s.
    let (m0, m1, k1, c1) = (0.1153, 0.5434, 0.2339, 0.9962);
    let one = Network {
        branches: vec![Branch {
            direction: DVector::from_element(1, 1.0),
            stages: vec![Stage {
                mass: m1,
                stiffness: k1,
                damping: c1,
            }],
        }],
        ..seed_network()
    };
    let s = Complex64::new(0.3, 0.7);
    let f = (m0 + m1) / (m0 * m1);
    let eq16 = m0 * (s * s + f * c1 * s + f * k1) / (s * s + c1 / m1 * s + k1 / m1);
    assert!((one.added_mass_at(s)[(0, 0)] - eq16).norm() < 1e-13);
}

#[test]
fn damping_is_positive_and_tf_symmetric() {
    let net = coupled_network();
    net.validate().unwrap();
    for &omega in &[0.01, 0.3, 1.0, 3.0, 30.0] {
        let h = net.added_mass_tf(omega);
        // Reciprocity: symmetric to rounding.
        assert!(max_abs_diff(&h, &h.transpose()) < 1e-14);
        // Damping matrix b = -omega Im H is PSD.
        let b = h.map(|x| -omega * x.im);
        assert!(b.symmetric_eigenvalues().min() > -1e-12);
    }
}

#[test]
fn scaling_maps_the_transfer_function() {
    let net = coupled_network();
    let (rho, g) = (998.0, 9.80665);
    let new = net.scaled(rho, g);
    new.validate().unwrap();
    for &omega in &[0.1, 0.8, 2.0, 7.0] {
        let lhs = new.added_mass_tf(omega);
        let rhs =
            net.added_mass_tf(omega * (net.g / g).sqrt()) * Complex64::new(rho / net.rho, 0.0);
        assert!(max_abs_diff(&lhs, &rhs) < 1e-12 * lhs.camax().max(1.0));
    }
    assert!(net.scaled(-1.0, 9.81).validate().is_err());
}

#[test]
fn validation_names_the_problem() {
    let mut net = coupled_network();
    net.branches[1].stages[0].stiffness = -1.0;
    let e = net.validate().unwrap_err().to_string();
    assert!(e.contains("branch 2, stage 1: stiffness"), "{e}");
    let mut net = coupled_network();
    net.branches[0].stages[1].mass = f64::NAN;
    assert!(net.validate().unwrap_err().to_string().contains("mass"));
    let mut net = coupled_network();
    net.branches[2].direction = DVector::from_vec(vec![1.0, 2.0]);
    assert!(net
        .validate()
        .unwrap_err()
        .to_string()
        .contains("direction has 2"));
    let mut net = coupled_network();
    net.added_mass_inf[(0, 1)] = 0.5;
    assert!(net
        .validate()
        .unwrap_err()
        .to_string()
        .contains("not symmetric"));
    let mut net = coupled_network();
    net.added_mass_inf[(2, 2)] = -3.0;
    assert!(net
        .validate()
        .unwrap_err()
        .to_string()
        .contains("positive semi-definite"));
    let mut net = coupled_network();
    net.branches[0].stages[0].damping = 0.0;
    assert!(net.validate().is_err());
    let mut net = seed_network();
    net.dof_names = vec!["two words".into()];
    assert!(net.validate().is_err());
}

#[test]
fn xml_round_trip_is_exact() {
    for net in [seed_network(), coupled_network()] {
        let text = net.to_xml_string();
        let back = Network::from_xml_str(&text, "memory").unwrap();
        assert_eq!(back, net);
    }
    let mut odd = coupled_network();
    odd.dof_names[0] = "a&b<c>".into();
    odd.branches[0].stages[0].mass = 1.234_567_890_123_456_7e-17;
    odd.branches[0].stages[0].stiffness = 3.3e12;
    let back = Network::from_xml_str(&odd.to_xml_string(), "memory").unwrap();
    assert_eq!(back, odd);
    let with_substructure = Network::from_xml_str(
        &crate::model::tests::two_dof_substructure_network(),
        "memory",
    )
    .unwrap()
    .scaled(1025.0, 9.81);
    let back = Network::from_xml_str(&with_substructure.to_xml_string(), "memory").unwrap();
    assert_eq!(back, with_substructure);
}

#[test]
fn substructure_errors_name_file_line_and_problem() {
    let good = crate::model::tests::two_dof_substructure_network();
    let good = good.as_str();
    assert!(Network::from_xml_str(good, "net.xml").is_ok());
    let cases = [
        (
            good.replace("springs=\"2\"", "springs=\"1000000000\""),
            "not a count from 0 to 512",
        ),
        (
            good.replace(
                "springs=\"2\" masses=\"1\"",
                "springs=\"300\" masses=\"300\"",
            ),
            "600 states",
        ),
        (
            good.replace(
                "<row>0.2 0.05</row><row>0.05 0.1</row></spring_relaxation>",
                "<row>0.2 0.05</row></spring_relaxation>",
            ),
            "<spring_relaxation> has 1 rows, expected 2",
        ),
        (
            good.replace("<row>1 -0.7 0.2</row>", "<row>1 -0.7</row>"),
            "has 2 numbers, expected 3",
        ),
        (
            good.replace("<row>0.5 -0.2 0.1</row>", "<row>-0.5 -0.2 0.1</row>"),
            "substructure 1: damping is not positive semi-definite",
        ),
        (
            good.replace(
                "<row>0.2 0.05</row><row>0.05 0.1</row></spring_relaxation>",
                "<row>0.2 0.06</row><row>0.05 0.1</row></spring_relaxation>",
            ),
            "substructure 1: spring_relaxation is not symmetric",
        ),
        (
            good.replace("<damping><row>", "<dampers><row>")
                .replace("</damping>", "</dampers>"),
            "in this order",
        ),
        (
            good.replace("form=\"coupled\"", "form=\"parallel_bank\""),
            "needs exactly one DOF",
        ),
    ];
    for (text, needle) in cases {
        let e = Network::from_xml_str(&text, "net.xml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("net.xml"), "{e}");
        assert!(e.contains(needle), "expected {needle:?} in {e}");
    }
}

#[test]
fn xml_errors_name_file_line_and_problem() {
    let good = seed_network().to_xml_string();
    let cases = [
        (
            good.replace("damping=\"0.9962\"", "damping=\"-0.9962\""),
            "damping must be",
        ),
        (
            good.replace("mass=\"0.5434\"", "mass=\"abc\""),
            "not a number",
        ),
        (
            good.replace("mass=\"0.5434\"", "mass=\"NaN\""),
            "not a finite number",
        ),
        (
            good.replace(
                "<stage mass=\"0.5434\"",
                "<stage colour=\"red\" mass=\"0.5434\"",
            ),
            "unknown attribute",
        ),
        (
            good.replace("<direction>1</direction>", "<direction>1 2</direction>"),
            "expected 1",
        ),
        (
            good.replace("<direction>1</direction>", ""),
            "no <direction>",
        ),
        (
            good.replace("format_version=\"1\"", "format_version=\"7\""),
            "not supported",
        ),
        (good.replace("series_chain", "ladder"), "unknown form"),
        (
            good.replace("</branch>", "</branch><extra/>"),
            "unexpected element <extra>",
        ),
        (good.replace("</network>", ""), "not closed"),
        (
            good.replace("<row>0.1153</row>", "<row>0.1153</row><row>1</row>"),
            "more than 1 rows",
        ),
        (good.replace(" g=\"1\"", ""), "missing the attribute g"),
    ];
    for (text, needle) in cases {
        let e = Network::from_xml_str(&text, "net.xml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("net.xml"), "{e}");
        assert!(e.contains(needle), "expected {needle:?} in {e}");
    }
    let e =
        Network::from_xml_str(&good.replace("mass=\"0.1877\"", "mass=\"x\""), "f.xml").unwrap_err();
    // The second stage is on line 11 of the written file.
    assert!(
        matches!(e, NetworkError::File { line: Some(11), .. }),
        "{e}"
    );
    let e = Network::from_file("/nonexistent/net.xml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("/nonexistent/net.xml") && e.contains("cannot read"),
        "{e}"
    );
}

#[test]
fn seed_example_file_holds_the_seed_network() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../main/examples/networks/seed_2dof.xml"
    );
    let path = if Path::new(path).exists() {
        path.to_string()
    } else {
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/networks/seed_2dof.xml"
        )
        .to_string()
    };
    let net = Network::from_file(&path).unwrap();
    assert_eq!(net, seed_network());
}

#[test]
fn coefficients_beyond_the_magnitude_limit_are_refused_naming_them() {
    // One stage of Schilder et al.'s network form, with one number replaced.
    let text = |m: &str, k: &str, c: &str, a_inf: &str, direction: &str, rho: &str| {
        format!(
            r#"<network format_version="1" form="series_chain" rho="{rho}" g="1">
  <dof name="sway"/>
  <added_mass_inf><row>{a_inf}</row></added_mass_inf>
  <branch><direction>{direction}</direction><stage mass="{m}" stiffness="{k}" damping="{c}"/></branch>
</network>"#
        )
    };
    let cases = [
        (text("1e154", "1", "1", "1", "1", "1"), "mass"),
        (text("1", "1e250", "1", "1", "1", "1"), "stiffness"),
        (text("1", "1", "1e154", "1", "1", "1"), "damping"),
        (text("1", "1", "1", "1e250", "1", "1"), "added_mass_inf"),
        (text("1", "1", "1", "1", "-1e154", "1"), "direction"),
        (text("1", "1", "1", "1", "1", "1e-300"), "rho"),
    ];
    // A diagonal entry of a substructure's damping (symmetric, positive definite).
    let substructure = crate::model::tests::two_dof_substructure_network()
        .replace("<row>0.5 -0.2 0.1</row>", "<row>1e200 -0.2 0.1</row>");
    let cases = cases
        .into_iter()
        .chain([(substructure, "substructure 1: damping[1,1]")]);
    for (network, expected) in cases {
        let err = Network::from_xml_str(&network, "n.xml")
            .unwrap_err()
            .to_string();
        assert!(err.contains(expected) && err.contains("1e100"), "{err}");
    }
    // At the limit, accepted.
    let edge = text("1e100", "1e-100", "1e100", "1e100", "1e100", "1e100");
    Network::from_xml_str(&edge, "n.xml").unwrap();
}
