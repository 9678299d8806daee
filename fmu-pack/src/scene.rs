//! The scene report as text: what a scene-driven FMU models, what it leaves out, and the
//! error this causes (the numbers: [`hydrofmu::scene::SceneReport`]). Packed as
//! `documentation/scene.txt` and printed by `pack` and `inspect`.

use hydrofmu::scene::SceneReport;
use std::fmt;

/// Displays a [`SceneReport`] in the words of the command line.
pub struct SceneText<'a>(pub &'a SceneReport);

impl fmt::Display for SceneText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let report = self.0;
        let percent = |x: f64| format!("{:.2} %", 100.0 * x);
        writeln!(f, "DOFs modelled      {}", report.dofs.join(" "))?;
        if report.left_out.is_empty() {
            writeln!(f, "DOFs left out      none")?;
        } else {
            writeln!(
                f,
                "DOFs left out      {} (held at zero: no force on them, and their motion \
                 would cause these forces on the modelled DOFs, not modelled):",
                report.left_out.len()
            )?;
            for l in &report.left_out {
                writeln!(
                    f,
                    "  {:<10} coupling to the modelled DOFs up to {} of sqrt(|A_ii A_jj|)",
                    l.name,
                    percent(l.coupling)
                )?;
            }
        }
        write!(
            f,
            "band               {:.4} .. {:.4} rad/s (data points {:.4} .. {:.4})",
            report.band.0, report.band.1, report.fitted.0, report.fitted.1
        )?;
        match report.nyquist_cut {
            Some(w) => writeln!(
                f,
                " (cut at the Nyquist frequency {w:.4} rad/s of --max-step {:.4} s)",
                std::f64::consts::PI / w
            )?,
            None => writeln!(f)?,
        }
        writeln!(
            f,
            "error in the band  {} (tolerance {}, {})",
            percent(report.in_band),
            percent(report.tolerance),
            if report.tolerance_met {
                "met"
            } else {
                "NOT met"
            }
        )?;
        for (what, range) in [
            ("below the band", &report.below),
            ("above the band", &report.above),
        ] {
            match range {
                Some(r) => writeln!(
                    f,
                    "error {what}  {} over {:.4} .. {:.4} rad/s (not fitted; largest in {} {})",
                    percent(r.error),
                    r.omega.0,
                    r.omega.1,
                    r.entry.0,
                    r.entry.1
                )?,
                None => writeln!(f, "error {what}  no data there")?,
            }
        }
        write!(f, "network states     {}", report.states)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hydrofmu::scene::{LeftOut, RangeError};

    #[test]
    fn the_report_reads_as_documented() {
        let report = SceneReport {
            dofs: vec!["sway".into()],
            left_out: vec![LeftOut {
                name: "cb1".into(),
                coupling: 0.25,
            }],
            band: (0.7, std::f64::consts::PI),
            fitted: (0.71, 3.1),
            nyquist_cut: Some(std::f64::consts::PI),
            tolerance: 0.01,
            tolerance_met: true,
            in_band: 0.005,
            below: None,
            above: Some(RangeError {
                omega: (3.2, 9.9),
                error: 0.5,
                entry: ("sway".into(), "sway".into()),
            }),
            states: 4,
        };
        let expected = "\
DOFs modelled      sway
DOFs left out      1 (held at zero: no force on them, and their motion would cause these forces on the modelled DOFs, not modelled):
  cb1        coupling to the modelled DOFs up to 25.00 % of sqrt(|A_ii A_jj|)
band               0.7000 .. 3.1416 rad/s (data points 0.7100 .. 3.1000) (cut at the Nyquist frequency 3.1416 rad/s of --max-step 1.0000 s)
error in the band  0.50 % (tolerance 1.00 %, met)
error below the band  no data there
error above the band  50.00 % over 3.2000 .. 9.9000 rad/s (not fitted; largest in sway sway)
network states     4";
        assert_eq!(SceneText(&report).to_string(), expected);
    }
}
