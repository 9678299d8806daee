//! The floating section of a command: the hull file's `<mass>` element with the command line's
//! `--mass`, `--cog`, `--gyradius`, `--mooring` and `--mooring-damping` replacing its fields,
//! or none (`--fixed`, or neither given).

use crate::args::FloatingArgs;
use hydrofmu::fmu::description::{DEFAULT_G, DEFAULT_RHO};
use hydrofmu::hull::{DofKind, Hull};
use hydrofmu::motion::{Floating, MassProperties};
use nalgebra::DMatrix;

/// A floating section: its equation of motion and the line that describes it in tables.
pub type FloatingSection = (Floating, String);

/// The floating section of `hull` with `args` at the reference rho and g; `None` when it is
/// held fixed. `wanted` names what needs a floating section (e.g. `--rao`), an error when the
/// section is fixed.
pub fn resolve(
    hull: &Hull,
    args: &FloatingArgs,
    wanted: Option<&str>,
) -> Result<Option<FloatingSection>, String> {
    if args.fixed {
        if args.given() {
            return Err(
                "--fixed holds the section; --mass, --cog, --gyradius and --mooring make it \
                 float: give one or the other"
                    .to_string(),
            );
        }
        if let Some(what) = wanted {
            return Err(format!(
                "{what} is the motion of a floating section; --fixed holds it"
            ));
        }
        return Ok(None);
    }
    let file = match hull.mass() {
        Some(mass) => Some(
            mass.properties(hull, DEFAULT_RHO)
                .map_err(|e| e.to_string())?,
        ),
        None => None,
    };
    if file.is_none() && !args.given() && wanted.is_none() {
        return Ok(None);
    }
    let missing = |option: &str| {
        format!(
            "a floating section needs {option} (or the hull file's <mass> element, \
             docs/HULL_FORMAT.md)"
        )
    };
    let statics = hydrofmu::hydrostatics::stiffness(hull).map_err(|e| e.to_string())?;
    let mass = match (&args.mass, &file) {
        (Some(text), _) if text == "displaced" => DEFAULT_RHO * statics.submerged_area,
        (Some(text), _) => text
            .parse()
            .map_err(|_| format!("--mass '{text}': expected kg/m or 'displaced'"))?,
        (None, Some(file)) => file.mass,
        (None, None) => return Err(missing("--mass")),
    };
    let centre_of_gravity = match (&args.cog, &file) {
        (Some(cog), _) => {
            let centre = match cog.split(',').map(str::trim).collect::<Vec<_>>()[..] {
                [x, y] => [x, y].map(|v| v.parse::<f64>().ok()),
                _ => [None, None],
            };
            let [Some(x), Some(y)] = centre else {
                return Err(format!("--cog '{cog}': expected X,Y in m"));
            };
            [x, y]
        }
        (None, Some(file)) => file.centre_of_gravity,
        (None, None) => return Err(missing("--cog")),
    };
    let radius_of_gyration = match (args.gyradius, &file) {
        (Some(k), _) => k,
        (None, Some(file)) => file.radius_of_gyration,
        (None, None) => return Err(missing("--gyradius")),
    };
    let rigid: Vec<&str> = (0..hull.dof_count())
        .filter(|&j| matches!(hull.dof_kind(j), Some(DofKind::Rigid { .. })))
        .map(|j| hull.dof_names()[j])
        .collect();
    let diagonal =
        |option: &str, text: &Option<String>, file: Option<&DMatrix<f64>>| match (text, file) {
            (Some(text), _) => diagonal(option, text, &rigid),
            (None, Some(file)) => Ok(file.clone()),
            (None, None) => Ok(DMatrix::zeros(0, 0)),
        };
    let properties = MassProperties {
        mass,
        centre_of_gravity,
        radius_of_gyration,
        stiffness: diagonal(
            "--mooring",
            &args.mooring,
            file.as_ref().map(|f| &f.stiffness),
        )?,
        damping: diagonal(
            "--mooring-damping",
            &args.mooring_damping,
            file.as_ref().map(|f| &f.damping),
        )?,
    };
    let floating = Floating::new(hull, &statics, &properties, DEFAULT_RHO, DEFAULT_G)
        .map_err(|e| format!("{}: {e}", hull.name()))?;
    let line = format!("{properties}; rho {DEFAULT_RHO} kg/m^3, g {DEFAULT_G} m/s^2");
    Ok(Some((floating, line)))
}

/// The diagonal matrix over the `rigid` DOFs of `DOF=VALUE,...`.
fn diagonal(option: &str, text: &str, rigid: &[&str]) -> Result<DMatrix<f64>, String> {
    let mut matrix = DMatrix::zeros(rigid.len(), rigid.len());
    for entry in text.split(',') {
        let (name, value) = entry.split_once('=').ok_or_else(|| {
            format!(
                "{option} '{entry}': expected DOF=VALUE (DOFs: {})",
                rigid.join(" ")
            )
        })?;
        let k = rigid
            .iter()
            .position(|d| *d == name.trim())
            .ok_or_else(|| {
                format!(
                    "{option}: '{}' is not a rigid DOF of the section (its rigid DOFs: {})",
                    name.trim(),
                    rigid.join(" ")
                )
            })?;
        matrix[(k, k)] = value
            .trim()
            .parse()
            .map_err(|_| format!("{option} '{entry}': '{value}' is not a number"))?;
    }
    Ok(matrix)
}
