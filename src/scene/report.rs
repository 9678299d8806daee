//! What a scene's FMU leaves out, and the error this causes.
//!
//! A scene asks for DOFs, a band (cut at the Nyquist frequency `pi / max_step`) and a
//! tolerance; the pipeline fits the smallest network that meets them. This report states the
//! price, measured against the panel method's data on the whole sweep grid, with the fit's own
//! scale `sqrt(s_i s_j)` (`s_i`: the largest `|A~_ii|` in the band):
//!
//! ```text
//! error(omega) = max_ij |H_ij(i omega) - A~_ij(omega)| / sqrt(s_i s_j)
//! ```
//!
//! in the band, below it and above it; and, for DOFs left out, the largest coupling
//! `|A~_ij| / sqrt(s_i s_j)` between a left-out DOF j and the kept DOFs i in the band: the
//! force on the kept DOFs that motion in DOF j would cause and that the FMU does not model.

use super::EDGE;
use crate::identify::{self, FitReport, FrequencyResponse};
use std::fmt;

/// Largest error over a frequency range.
#[derive(Clone, Debug, PartialEq)]
pub struct RangeError {
    /// Frequency range (rad/s).
    pub omega: (f64, f64),
    /// Largest normalized error.
    pub error: f64,
    /// The matrix entry (DOF names) where it occurs.
    pub entry: (String, String),
}

/// A left-out DOF and its largest normalized coupling to the kept ones in the band.
#[derive(Clone, Debug, PartialEq)]
pub struct LeftOut {
    /// DOF name.
    pub name: String,
    /// `max |A~_ij| / sqrt(s_i s_j)` over the band and the kept DOFs i.
    pub coupling: f64,
}

/// The scene's FMU: what it models, what it leaves out, and the error.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneReport {
    /// Kept DOFs.
    pub dofs: Vec<String>,
    /// DOFs of the hull left out (empty when unknown or none).
    pub left_out: Vec<LeftOut>,
    /// The band asked for, after the `max_step` cut (rad/s).
    pub band: (f64, f64),
    /// The sweep frequencies the fit used: the first and last inside the band (rad/s).
    pub fitted: (f64, f64),
    /// The Nyquist frequency of the master's largest step, when it cut the band (rad/s).
    pub nyquist_cut: Option<f64>,
    /// Tolerance.
    pub tolerance: f64,
    /// Whether the fit met the tolerance.
    pub tolerance_met: bool,
    /// Error in the band (the fit's own measure).
    pub in_band: f64,
    /// Error below the band, on the sweep grid (None: no grid points there).
    pub below: Option<RangeError>,
    /// Error above the band, on the sweep grid.
    pub above: Option<RangeError>,
    /// Network states: the length of the fitted network's state vector
    /// ([`crate::network::Network::state_count`]: spring elongations, auxiliary velocities,
    /// substructure coordinates; the hull's positions and velocities are not among them).
    /// The FMU steps exactly these.
    pub states: usize,
}

impl SceneReport {
    /// The report of `fit` against `data` (the fitted DOFs); `full` is the response of all
    /// the hull's DOFs when some were left out. `band` is the band asked for (rad/s) and
    /// `nyquist_cut` the Nyquist frequency when it cut the band.
    pub fn new(
        data: &FrequencyResponse,
        full: Option<&FrequencyResponse>,
        fit: &FitReport,
        band: (f64, f64),
        nyquist_cut: Option<f64>,
    ) -> SceneReport {
        let scale = &fit.error_scale;
        let mut below: Option<RangeError> = None;
        let mut above: Option<RangeError> = None;
        for (k, &omega) in data.omega.iter().enumerate() {
            let side = if omega < fit.band.0 * (1.0 - EDGE) {
                &mut below
            } else if omega > fit.band.1 * (1.0 + EDGE) {
                &mut above
            } else {
                continue;
            };
            let model = fit.network.added_mass_tf(omega);
            let mut worst = (0.0f64, 0, 0);
            for i in 0..model.nrows() {
                for j in 0..model.ncols() {
                    if scale[(i, j)] > 0.0 {
                        let e = (model[(i, j)] - data.added_mass[k][(i, j)]).norm() / scale[(i, j)];
                        if e > worst.0 {
                            worst = (e, i, j);
                        }
                    }
                }
            }
            let names = &data.dof_names;
            let entry = side.get_or_insert(RangeError {
                omega: (omega, omega),
                error: 0.0,
                entry: (names[0].clone(), names[0].clone()),
            });
            entry.omega.0 = entry.omega.0.min(omega);
            entry.omega.1 = entry.omega.1.max(omega);
            if worst.0 > entry.error {
                entry.error = worst.0;
                entry.entry = (names[worst.1].clone(), names[worst.2].clone());
            }
        }
        let dofs = fit.network.dof_names.clone();
        let left_out = full
            .map(|f| left_out(f, &dofs, fit.band))
            .unwrap_or_default();
        SceneReport {
            dofs,
            left_out,
            band,
            fitted: fit.band,
            nyquist_cut,
            tolerance: fit.tolerance,
            tolerance_met: fit.tolerance_met,
            in_band: fit.max_relative_error,
            below,
            above,
            states: fit.network.state_count(),
        }
    }
}

/// Couplings of the DOFs of `full` not in `kept` to the kept ones, in the band.
fn left_out(full: &FrequencyResponse, kept: &[String], band: (f64, f64)) -> Vec<LeftOut> {
    let in_band: Vec<usize> = (0..full.omega.len())
        .filter(|&k| {
            full.omega[k] >= band.0 * (1.0 - EDGE) && full.omega[k] <= band.1 * (1.0 + EDGE)
        })
        .collect();
    let n = full.dof_names.len();
    let band_data: Vec<_> = in_band
        .iter()
        .map(|&k| full.added_mass[k].clone())
        .collect();
    let Some(s) = identify::dof_scales(&band_data) else {
        return Vec::new();
    };
    let kept_index: Vec<usize> = (0..n)
        .filter(|&i| kept.contains(&full.dof_names[i]))
        .collect();
    let mut result = Vec::new();
    for j in (0..n).filter(|j| !kept_index.contains(j)) {
        let mut coupling = 0.0f64;
        for &i in &kept_index {
            for &k in &in_band {
                let x = full.added_mass[k][(i, j)].norm() / (s[i] * s[j]).sqrt();
                if x.is_finite() {
                    coupling = coupling.max(x);
                }
            }
        }
        result.push(LeftOut {
            name: full.dof_names[j].clone(),
            coupling,
        });
    }
    result
}

/// The report in words, as packed in `documentation/scene.txt`: one line per item, the DOFs
/// left out indented under their count; a Nyquist cut names the step as `--max-step`.
impl fmt::Display for SceneReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let report = self;
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
        assert_eq!(report.to_string(), expected);
    }
}
