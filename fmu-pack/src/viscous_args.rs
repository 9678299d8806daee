//! `fmu-pack pack --viscous`: viscous damping and current in the FMU (docs/CURRENT.md).
//!
//! `--damping-linear` takes entries `DOF=B` (a diagonal entry, by DOF name or 1-based index)
//! or `I,J=B` (any entry, names or indices), comma-separated: `sway=2,roll=0.5,sway,roll=0.1`.
//! `--damping-quadratic` takes `DOF=B`. An entry given twice, an unknown DOF, or a value that
//! is not a finite number is an error naming it.
//!
//! Entries not given: a section's estimate ([`section_estimate`], docs/VISCOUS.md "As the
//! FMU's default"): its roll DOF Ikeda's roll damping, linear `B_l` = friction + the keels'
//! linear parts at `--roll-frequency` (default: the roll natural frequency of the hull file's
//! `<mass>`, else `sqrt(g / R)`, R the half-beam) and `--roll-amplitude` (default 10 deg),
//! quadratic `B_q` = eddy making + the keels' normal force; its sway and heave DOFs the
//! cross-flow drag `B_q = 0.5 rho C_D T` (sway), `0.5 rho C_D B` (heave), at the reference
//! rho. A ship: its sections' roll estimates integrated along its stations
//! ([`ship_estimate`]), and its cross-flow strips (`resources/crossflow.csv`, docs/CURRENT.md)
//! for the drag of sway, heave, pitch and yaw, whose per-DOF `B_q` are then 0.
//! Every other entry, an imported database's, and all with `--no-estimate`: 0.

use clap::Args;
use hydrofmu::fmu::description::{DEFAULT_G, DEFAULT_RHO};
use hydrofmu::fmu::Body;
use hydrofmu::hull::Hull;
use hydrofmu::viscous::{self, CrossFlow};
use nalgebra::{DMatrix, DVector};

/// The default roll amplitude of the estimate, degrees.
pub const DEFAULT_ROLL_AMPLITUDE_DEG: f64 = 10.0;

/// Linear (n x n) and quadratic (n) damping.
type Coefficients = (DMatrix<f64>, DVector<f64>);

/// The most entries one option may list.
const MAX_ENTRIES: usize = 1_000_000;

/// The viscous damping options of `fmu-pack pack`.
#[derive(Args, Debug, Clone, Default)]
pub struct ViscousArgs {
    /// Give the FMU viscous damping and a current (docs/CURRENT.md): parameters
    /// `damping_linear[i,j]` and `damping_quadratic[i]` (start values from
    /// --damping-linear and --damping-quadratic; a section's entries not given from its
    /// geometry: Ikeda's roll damping, the cross-flow drag of sway and heave, docs/VISCOUS.md;
    /// else 0), inputs `current.speed` (m/s) and `current.heading` (deg), outputs
    /// `force_viscous.<dof>` (in `force`).
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
    /// Roll amplitude (deg) at which the roll estimate's friction and bilge keels' linear
    /// parts are taken (default 10).
    #[arg(long, value_name = "DEG", requires = "viscous")]
    pub roll_amplitude: Option<f64>,
    /// Frequency (rad/s) at which the roll estimate's linear parts are taken (default: the
    /// roll natural frequency of the hull file's <mass>, else sqrt(g/R), R the half-beam).
    #[arg(long, value_name = "RAD/S", requires = "viscous")]
    pub roll_frequency: Option<f64>,
    /// Pack only the entries given (the others 0), not the section's estimate from its
    /// geometry (Ikeda's roll damping, the cross-flow drag of sway and heave).
    #[arg(long, requires = "viscous")]
    pub no_estimate: bool,
}

/// A section's estimated defaults: `(B_l, B_q)` over the hull's DOFs and the lines that say
/// where they come from.
pub struct Estimate {
    /// The coefficients, over the hull's DOFs in its order.
    pub coefficients: Coefficients,
    /// The hull's DOF names.
    pub names: Vec<String>,
    /// Source, inputs, values and validity warnings, one per line.
    pub lines: Vec<String>,
    /// A ship's cross-flow strips (empty for a section).
    pub strips: Vec<hydrofmu::model::crossflow::Strip>,
}

/// The DOFs whose drag a ship's cross-flow strips carry.
const STRIP_DOFS: [&str; 4] = ["sway", "heave", "pitch", "yaw"];

/// The frequency of the estimate's linear parts and where it comes from.
fn roll_frequency(args: &ViscousArgs, hull: &Hull) -> Result<(f64, String), String> {
    if args.roll_frequency.is_some() {
        return checked_frequency(args);
    }
    if let Some(omega) = viscous::roll_natural_frequency(hull, DEFAULT_RHO, DEFAULT_G) {
        return Ok((
            omega,
            "the roll natural frequency of <mass>, dry inertia".into(),
        ));
    }
    let r = hull.reference_half_beam();
    Ok((
        (DEFAULT_G / r).sqrt(),
        format!("sqrt(g/R), R = {r} m: no <mass> with roll restoring"),
    ))
}

/// The estimate of a ship (module docs; [`viscous::ship_estimate`]): at `--roll-frequency`,
/// default `sqrt(g / R)` with R the largest section half-beam.
pub fn ship_estimate(args: &ViscousArgs, ship: &hydrofmu::ship::Ship) -> Result<Estimate, String> {
    let degrees = roll_amplitude(args)?;
    let r = ship
        .sections()
        .iter()
        .map(|h| h.reference_half_beam())
        .fold(0.0, f64::max);
    let (omega, source) = match args.roll_frequency {
        Some(_) => checked_frequency(args)?,
        None => (
            (DEFAULT_G / r).sqrt(),
            format!("sqrt(g/R), R = {r} m, the largest section half-beam"),
        ),
    };
    let estimate = viscous::ship_estimate(ship, DEFAULT_RHO, omega, degrees.to_radians())
        .map_err(|e| format!("--viscous: {e}; pass --no-estimate and give the entries"))?;
    let names: Vec<String> = ship.dof_names().iter().map(|d| d.to_string()).collect();
    let n = names.len();
    let (mut linear, mut quadratic) = (DMatrix::zeros(n, n), DVector::zeros(n));
    let strips = match names.iter().any(|n| STRIP_DOFS.contains(&n.as_str())) {
        true => estimate.strips,
        false => Vec::new(),
    };
    let mut lines = vec![format!(
        "ship: its sections' estimates integrated along the stations (docs/VISCOUS.md), roll at \
         {omega:.4} rad/s ({source}) and {degrees} deg, drag as a section's"
    )];
    for (name, damping) in &estimate.dofs {
        let Some(i) = names.iter().position(|d| d == name) else {
            continue;
        };
        linear[(i, i)] = damping.linear;
        if STRIP_DOFS.contains(name) && !strips.is_empty() {
            lines.push(format!(
                "{name}: B_q 0, the strips' drag (alone: B_q {:.6e})",
                damping.quadratic
            ));
            continue;
        }
        quadratic[i] = damping.quadratic;
        lines.push(format!(
            "{name}: B_l {:.6e}, B_q {:.6e}",
            damping.linear, damping.quadratic
        ));
    }
    if !strips.is_empty() {
        lines.push(format!(
            "cross-flow strips (resources/crossflow.csv; sway-yaw and heave-pitch coupled, the \
             current's yaw moment; scaled by crossflow.drag_scale): {}",
            hydrofmu::model::crossflow::describe(&strips)
        ));
    }
    let mut warned = std::collections::BTreeSet::new();
    for (x, w) in &estimate.warnings {
        if warned.insert(w.field) {
            lines.push(format!(
                "warning: {w} (station x = {x} m, first of its kind): Ikeda's method \
                 extrapolates"
            ));
        }
    }
    lines.push(format!(
        "estimates at rho {DEFAULT_RHO} kg/m^3; entries given with --damping-linear and \
         --damping-quadratic replace them"
    ));
    Ok(Estimate {
        coefficients: (linear, quadratic),
        names,
        lines,
        strips,
    })
}

/// `--roll-amplitude` (default [`DEFAULT_ROLL_AMPLITUDE_DEG`]), checked.
fn roll_amplitude(args: &ViscousArgs) -> Result<f64, String> {
    let degrees = args.roll_amplitude.unwrap_or(DEFAULT_ROLL_AMPLITUDE_DEG);
    if !(degrees.is_finite() && degrees > 0.0 && degrees < 90.0) {
        return Err(format!(
            "--roll-amplitude {degrees}: expected an amplitude in (0, 90) deg"
        ));
    }
    Ok(degrees)
}

/// `--roll-frequency` (given), checked.
fn checked_frequency(args: &ViscousArgs) -> Result<(f64, String), String> {
    let omega = args.roll_frequency.unwrap_or(f64::NAN);
    if !(omega.is_finite() && omega > 0.0) {
        return Err(format!(
            "--roll-frequency {omega}: expected a finite frequency > 0 rad/s"
        ));
    }
    Ok((omega, "--roll-frequency".into()))
}

/// The estimate of a section hull (module docs).
pub fn section_estimate(args: &ViscousArgs, hull: &Hull) -> Result<Estimate, String> {
    let degrees = roll_amplitude(args)?;
    let (omega, source) = roll_frequency(args, hull)?;
    let no_estimate = "; give the entries with --damping-linear and --damping-quadratic and \
                       pass --no-estimate";
    let estimate = viscous::section_estimate(hull, DEFAULT_RHO, omega, degrees.to_radians())
        .map_err(|e| format!("--viscous: {e}{no_estimate}"))?;
    let names: Vec<String> = hull.dof_names().iter().map(|d| d.to_string()).collect();
    let n = names.len();
    let (mut linear, mut quadratic) = (DMatrix::zeros(n, n), DVector::zeros(n));
    let mut lines = Vec::new();
    if let Some((roll, damping)) = &estimate.roll {
        let p = &roll.params;
        let total = damping.total();
        linear[(roll.dof, roll.dof)] = total.linear;
        quadratic[roll.dof] = total.quadratic;
        let keels = p.bilge_keels.map_or("no bilge keels".to_string(), |k| {
            format!(
                "bilge keels {} m on {} of the length",
                k.breadth, k.length_fraction
            )
        });
        lines.push(format!(
            "{}: Ikeda at zero speed, B {:.4} m, T {:.4} m, sigma {:.4}, bilge radius {:.4} m \
             (from sigma), OG {:.4} m ({}), {keels}",
            names[roll.dof],
            p.breadth,
            p.draft,
            p.area_coefficient,
            p.bilge_radius,
            p.roll_axis_height,
            roll.axis.describe()
        ));
        lines.push(format!(
            "  at {omega:.4} rad/s ({source}) and {degrees} deg: B_l {:.6e} (friction {:.6e}, \
             keels {:.6e}) N.m.s/rad per m, B_q {:.6e} (eddy {:.6e}, keels {:.6e}) \
             N.m.s2/rad2 per m",
            total.linear,
            damping.friction.linear,
            damping.bilge_keel.linear,
            total.quadratic,
            damping.eddy_making.quadratic,
            damping.bilge_keel.quadratic
        ));
        for w in &damping.warnings {
            lines.push(format!(
                "  warning: {w}: Ikeda's method extrapolates (docs/VISCOUS.md)"
            ));
        }
    }
    for drag in &estimate.drag {
        quadratic[drag.dof] = drag.quadratic;
        let (formula, projected) = match drag.flow {
            CrossFlow::Sway => ("0.5 rho C_D T", "T"),
            CrossFlow::Heave => ("0.5 rho C_D B", "B"),
        };
        lines.push(format!(
            "{}: cross-flow drag, C_D {:.4} (rounded rectangle on {projected}), B_q = {formula} \
             = {:.6e} kg/m2",
            names[drag.dof], drag.drag_coefficient, drag.quadratic
        ));
    }
    lines.push(format!(
        "estimates at rho {DEFAULT_RHO} kg/m^3; entries given with --damping-linear and \
         --damping-quadratic replace them"
    ));
    Ok(Estimate {
        coefficients: (linear, quadratic),
        names,
        lines,
        strips: Vec::new(),
    })
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
    /// The coefficients `(B_l, B_q)` for the body's DOFs `names` (`None` without --viscous):
    /// the entries given, the others from `defaults` (matched by DOF name) or 0.
    pub fn coefficients(
        &self,
        names: &[String],
        defaults: Option<&Estimate>,
    ) -> Result<Option<Coefficients>, String> {
        if !self.viscous {
            return Ok(None);
        }
        let n = names.len();
        let mut linear = DMatrix::zeros(n, n);
        let mut quadratic = DVector::zeros(n);
        if let Some(estimate) = defaults {
            let (l, q) = &estimate.coefficients;
            let at = |name: &String| estimate.names.iter().position(|m| m == name);
            for (i, a) in names.iter().enumerate() {
                let Some(k) = at(a) else { continue };
                quadratic[i] = q[k];
                for (j, b) in names.iter().enumerate() {
                    if let Some(m) = at(b) {
                        linear[(i, j)] = l[(k, m)];
                    }
                }
            }
        }
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

    /// The estimate of a section `hull` for these options: `None` without --viscous or with
    /// --no-estimate.
    pub fn estimate(&self, hull: &Hull) -> Result<Option<Estimate>, String> {
        if !self.viscous {
            return Ok(None);
        }
        if self.no_estimate {
            self.refuse_estimate_options()?;
            return Ok(None);
        }
        section_estimate(self, hull).map(Some)
    }

    /// Refuses the estimate's options for a body without an estimate (an imported database,
    /// or --no-estimate), whose entries are the ones given.
    pub fn refuse_estimate_options(&self) -> Result<(), String> {
        if self.roll_amplitude.is_some() || self.roll_frequency.is_some() {
            return Err(
                "--roll-amplitude and --roll-frequency shape the estimate from a section's \
                 or a ship's geometry; here the viscous damping is the entries given \
                 (docs/VISCOUS.md)"
                    .into(),
            );
        }
        Ok(())
    }

    /// `body` with the viscous damping of these options (unchanged without --viscous), the
    /// entries not given from `defaults`, and the defaults' cross-flow strips.
    pub fn apply(&self, body: Body, defaults: Option<&Estimate>) -> Result<Body, String> {
        let names: Vec<String> = body.dofs.iter().map(|d| d.name.clone()).collect();
        let Some((linear, quadratic)) = self.coefficients(&names, defaults)? else {
            return Ok(body);
        };
        let body = body
            .with_viscous(linear, quadratic)
            .map_err(|e| format!("--viscous: {e}"))?;
        match defaults {
            Some(estimate) if !estimate.strips.is_empty() => body
                .with_crossflow(&estimate.strips)
                .map_err(|e| format!("--viscous: {e}")),
            _ => Ok(body),
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
            ..ViscousArgs::default()
        }
    }

    #[test]
    fn entries_by_name_and_index_fill_the_matrices() {
        let (l, q) = args("sway=2, 3=0.5, sway,roll=0.1, 3,1=0.1", "roll=4,1=1e3")
            .coefficients(&names(), None)
            .unwrap()
            .unwrap();
        assert_eq!(
            (l[(0, 0)], l[(2, 2)], l[(0, 2)], l[(2, 0)]),
            (2.0, 0.5, 0.1, 0.1)
        );
        assert_eq!(l[(1, 1)], 0.0);
        assert_eq!(q.as_slice(), &[1e3, 0.0, 4.0]);
        let off = ViscousArgs::default().coefficients(&names(), None).unwrap();
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
            let e = a.coefficients(&names(), None).unwrap_err();
            assert!(e.contains(expected), "{e}");
        }
    }
}
