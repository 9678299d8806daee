//! `fmu-pack pack --viscous`: viscous damping and current in the FMU (docs/CURRENT.md).
//!
//! `--damping-linear` takes entries `DOF=B` (a diagonal entry, by DOF name or 1-based index)
//! or `I,J=B` (any entry, names or indices), comma-separated: `sway=2,roll=0.5,sway,roll=0.1`.
//! `--damping-quadratic` takes `DOF=B`. Entries not given are 0; an entry given twice, an
//! unknown DOF, or a value that is not a finite number is an error naming it.

use clap::Args;
use hydrofmu::fmu::Body;
use nalgebra::{DMatrix, DVector};

/// Linear (n x n) and quadratic (n) damping.
type Coefficients = (DMatrix<f64>, DVector<f64>);

/// The most entries one option may list.
const MAX_ENTRIES: usize = 1_000_000;

/// The viscous damping options of `fmu-pack pack`.
#[derive(Args, Debug, Clone, Default)]
pub struct ViscousArgs {
    /// Give the FMU viscous damping and a current (docs/CURRENT.md): parameters
    /// `damping_linear[i,j]` and `damping_quadratic[i]` (start values from
    /// --damping-linear and --damping-quadratic, else 0), inputs `current.speed` (m/s) and
    /// `current.heading` (deg), outputs `force_viscous.<dof>` (in `force`).
    #[arg(long)]
    pub viscous: bool,
    /// Linear viscous damping B_l: `DOF=B` (diagonal) or `I,J=B` entries, comma-separated
    /// (DOF names or 1-based indices; SI units of damping_direct).
    #[arg(
        long,
        value_name = "DOF=B,..|I,J=B,..",
        requires = "viscous",
        allow_hyphen_values = true
    )]
    pub damping_linear: Option<String>,
    /// Quadratic viscous damping B_q: `DOF=B`, comma-separated (force / velocity^2).
    #[arg(
        long,
        value_name = "DOF=B,..",
        requires = "viscous",
        allow_hyphen_values = true
    )]
    pub damping_quadratic: Option<String>,
}

/// The 0-based index of a DOF given by name or 1-based index.
fn dof_index(token: &str, names: &[String], option: &str) -> Result<usize, String> {
    if let Some(i) = names.iter().position(|n| n == token) {
        return Ok(i);
    }
    match token.parse::<usize>() {
        Ok(i) if (1..=names.len()).contains(&i) => Ok(i - 1),
        _ => Err(format!(
            "{option}: '{token}' is not a DOF of the body ({}) nor an index 1..{}",
            names.join(", "),
            names.len()
        )),
    }
}

/// The entries of a list `K=B,K,K=B,..`: the keys (one or two tokens) with their values.
fn entries(text: &str, option: &str) -> Result<Vec<(Vec<String>, f64)>, String> {
    let mut out = Vec::new();
    let mut key: Vec<String> = Vec::new();
    for token in text.split(',').map(str::trim).filter(|t| !t.is_empty()) {
        if out.len() >= MAX_ENTRIES {
            return Err(format!("{option}: more than {MAX_ENTRIES} entries"));
        }
        match token.split_once('=') {
            Some((last, value)) => {
                key.push(last.trim().to_string());
                let number = value
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        format!(
                            "{option}: '{}' for {} is not a finite number",
                            value.trim(),
                            key.join(",")
                        )
                    })?;
                out.push((std::mem::take(&mut key), number));
            }
            None => key.push(token.to_string()),
        }
    }
    if !key.is_empty() {
        return Err(format!("{option}: '{}' has no '=VALUE'", key.join(",")));
    }
    Ok(out)
}

impl ViscousArgs {
    /// The coefficients `(B_l, B_q)` for the body's DOFs `names` (`None` without --viscous).
    pub fn coefficients(&self, names: &[String]) -> Result<Option<Coefficients>, String> {
        if !self.viscous {
            return Ok(None);
        }
        let n = names.len();
        let mut linear = DMatrix::zeros(n, n);
        let mut quadratic = DVector::zeros(n);
        let mut given = std::collections::BTreeSet::new();
        let option = "--damping-linear";
        for (key, value) in entries(self.damping_linear.as_deref().unwrap_or(""), option)? {
            let (i, j) = match key.as_slice() {
                [d] if !d.is_empty() => {
                    let i = dof_index(d, names, option)?;
                    (i, i)
                }
                [a, b] => (dof_index(a, names, option)?, dof_index(b, names, option)?),
                _ => return Err(format!("{option}: '{}' is not DOF or I,J", key.join(","))),
            };
            if !given.insert((i, j)) {
                return Err(format!("{option}: entry {},{} given twice", i + 1, j + 1));
            }
            linear[(i, j)] = value;
        }
        let option = "--damping-quadratic";
        let mut given = std::collections::BTreeSet::new();
        for (key, value) in entries(self.damping_quadratic.as_deref().unwrap_or(""), option)? {
            let i = match key.as_slice() {
                [d] if !d.is_empty() => dof_index(d, names, option)?,
                _ => return Err(format!("{option}: '{}' is not one DOF", key.join(","))),
            };
            if !given.insert(i) {
                return Err(format!("{option}: DOF {} given twice", names[i]));
            }
            quadratic[i] = value;
        }
        Ok(Some((linear, quadratic)))
    }

    /// `body` with the viscous damping of these options (unchanged without --viscous).
    pub fn apply(&self, body: Body) -> Result<Body, String> {
        let names: Vec<String> = body.dofs.iter().map(|d| d.name.clone()).collect();
        match self.coefficients(&names)? {
            Some((linear, quadratic)) => body
                .with_viscous(linear, quadratic)
                .map_err(|e| format!("--viscous: {e}")),
            None => Ok(body),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names() -> Vec<String> {
        vec!["sway".into(), "heave".into(), "roll".into()]
    }

    fn args(linear: &str, quadratic: &str) -> ViscousArgs {
        ViscousArgs {
            viscous: true,
            damping_linear: Some(linear.into()),
            damping_quadratic: Some(quadratic.into()),
        }
    }

    #[test]
    fn entries_by_name_and_index_fill_the_matrices() {
        let (l, q) = args("sway=2, 3=0.5, sway,roll=0.1, 3,1=0.1", "roll=4,1=1e3")
            .coefficients(&names())
            .unwrap()
            .unwrap();
        assert_eq!(
            (l[(0, 0)], l[(2, 2)], l[(0, 2)], l[(2, 0)]),
            (2.0, 0.5, 0.1, 0.1)
        );
        assert_eq!(l[(1, 1)], 0.0);
        assert_eq!(q.as_slice(), &[1e3, 0.0, 4.0]);
        let off = ViscousArgs::default().coefficients(&names()).unwrap();
        assert!(off.is_none());
    }

    #[test]
    fn bad_entries_name_the_option_and_the_entry() {
        let cases = [
            (args("yaw=1", ""), "'yaw' is not a DOF"),
            (
                args("sway=nan", ""),
                "'nan' for sway is not a finite number",
            ),
            (args("sway=1,sway=2", ""), "given twice"),
            (args("sway", ""), "has no '=VALUE'"),
            (args("1,2,3=1", ""), "is not DOF or I,J"),
            (args("", "sway,roll=1"), "--damping-quadratic"),
            (args("", "4=1"), "index 1..3"),
        ];
        for (a, expected) in cases {
            let e = a.coefficients(&names()).unwrap_err();
            assert!(e.contains(expected), "{e}");
        }
    }
}
