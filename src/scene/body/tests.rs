use super::*;
use crate::database::import::{self, ImportParams};
use std::path::Path;

/// The WAMIT v7.2 hemisphere of tests/data/wamit (6 DOFs, 7 frequencies).
fn sphere() -> Database {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/wamit/sphere.1");
    import::import(&path, &ImportParams::new()).unwrap()
}

fn scene(dofs: &[&str]) -> BodyScene {
    BodyScene {
        dofs: Some(dofs.iter().map(|d| d.to_string()).collect()),
        ..BodyScene::new(sphere())
    }
}

#[test]
fn a_new_scene_covers_every_frequency_of_the_database() {
    let database = sphere();
    let (first, last) = (database.omega[0], *database.omega.last().unwrap());
    let scene = BodyScene::new(database);
    let Band::RadPerSecond(lo, hi) = scene.band else {
        panic!("{:?}", scene.band);
    };
    assert!(lo < first && first - lo < 1e-9 * first, "{lo} {first}");
    assert!(hi > last && hi - last < 1e-9 * last, "{hi} {last}");
    assert_eq!(scene.description, "sphere");
}

#[test]
fn the_fit_of_two_dofs_reports_the_four_left_out() {
    let fitted = scene(&["heave", "surge"]).fit().unwrap();
    assert_eq!(fitted.database.dof_names, ["heave", "surge"]);
    assert_eq!(fitted.fit.network.dof_names, ["heave", "surge"]);
    let report = &fitted.report;
    assert_eq!(report.dofs, ["heave", "surge"]);
    let left_out: Vec<&str> = report.left_out.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(left_out, ["sway", "roll", "pitch", "yaw"]);
    // A hemisphere: surge couples to pitch, nothing else to the kept DOFs.
    let coupling = |name: &str| {
        report
            .left_out
            .iter()
            .find(|l| l.name == name)
            .unwrap()
            .coupling
    };
    assert!(coupling("pitch") > 0.01, "{report:?}");
    assert!(coupling("sway") < 1e-6, "{report:?}");
    assert_eq!(report.nyquist_cut, None);
    assert_eq!(report.tolerance_met, fitted.fit.tolerance_met);
    assert_eq!(report.states, fitted.fit.network.state_count());
    let text = fitted.scene_text();
    assert!(
        text.starts_with("DOFs modelled      heave surge\nDOFs left out      4"),
        "{text}"
    );
    assert!(
        text.contains("\n\nsphere\nDOFs heave surge\nband "),
        "{text}"
    );
    assert!(text.contains("\nlargest error "), "{text}");
}

#[test]
fn a_max_step_cuts_the_band_and_the_report_says_so() {
    let database = sphere();
    let middle = database.omega[database.omega.len() - 2];
    // pi / h between the last two frequencies: the last one falls out.
    let max_step = std::f64::consts::PI / (middle * 1.001);
    let fitted = BodyScene {
        max_step: Some(max_step),
        ..scene(&["heave"])
    }
    .fit()
    .unwrap();
    let nyquist = fitted.report.nyquist_cut.unwrap();
    assert!((nyquist - middle * 1.001).abs() < 1e-12 * nyquist);
    assert_eq!(fitted.band.1, nyquist);
    assert!(fitted.report.above.is_some(), "{:?}", fitted.report);
    assert!(fitted
        .report
        .to_string()
        .contains("(cut at the Nyquist frequency"));
}

#[test]
fn the_form_is_the_one_asked_for_and_one_dof_forms_need_one_dof() {
    let fitted = BodyScene {
        form: Some(NetworkForm::Coupled),
        ..scene(&["heave"])
    }
    .fit()
    .unwrap();
    assert_eq!(fitted.fit.network.form, NetworkForm::Coupled);
    let chain = BodyScene {
        form: Some(NetworkForm::SeriesChain),
        ..scene(&["heave"])
    }
    .fit()
    .unwrap();
    assert_eq!(chain.fit.network.form, NetworkForm::SeriesChain);
    let e = BodyScene {
        form: Some(NetworkForm::SeriesChain),
        ..scene(&["heave", "surge"])
    }
    .fit()
    .unwrap_err();
    assert_eq!(
        e,
        WholeBodyError::FormNeedsOneDof {
            form: NetworkForm::SeriesChain,
            dofs: 2
        }
    );
}

#[test]
fn a_refused_scene_names_its_reason() {
    let e = scene(&["heave", "bow"]).fit().unwrap_err();
    assert!(
        matches!(&e, WholeBodyError::UnknownDof { name, .. } if name == "bow"),
        "{e}"
    );
    let e = BodyScene {
        tolerance: Some(-1.0),
        ..scene(&["heave"])
    }
    .fit()
    .unwrap_err();
    assert_eq!(e, WholeBodyError::InvalidTolerance(-1.0));
    let omega = sphere().omega;
    let e = BodyScene {
        band: Band::RadPerSecond(omega[0], omega[1]),
        ..scene(&["heave"])
    }
    .fit()
    .unwrap_err();
    assert!(
        matches!(e, WholeBodyError::TooFewFrequencies { inside: 2, .. }),
        "{e}"
    );
}
