//! The HULL argument shared by every subcommand: `semicircle`, `circle` or a hull file.

use hydrofmu::hull::Hull;
use hydrofmu::source::Source;

/// Default centre depth over radius of the built-in `circle` when `--depth` is not given.
pub const DEFAULT_CIRCLE_DEPTH: f64 = 2.0;

/// Resolves `spec` (a section, [`Source::from_argument`]) into a hull, keeping only `dofs` when given. `depth` is the centre depth
/// over radius H/R of the built-in circle (the hull knows it: [`Hull::depth_ratio`]).
pub fn resolve(
    spec: &str,
    radius: f64,
    depth: Option<f64>,
    dofs: Option<&str>,
) -> Result<Hull, String> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(format!(
            "--radius {radius}: the radius must be finite and > 0"
        ));
    }
    let hull = match Source::from_argument(spec).map_err(|e| e.to_string())? {
        Source::Semicircle => {
            if let Some(d) = depth.filter(|d| *d != 0.0) {
                return Err(format!(
                    "--depth {d} applies to the circle; the semicircle has H/R = 0"
                ));
            }
            Hull::semicircle(radius).map_err(|e| e.to_string())?
        }
        Source::Circle => {
            let d = depth.unwrap_or(DEFAULT_CIRCLE_DEPTH);
            let hull = if d == 0.0 {
                Hull::semicircle(radius)
            } else {
                Hull::circle(radius, d)
            };
            hull.map_err(|e| e.to_string())?
        }
        Source::HullFile(path) => {
            if depth.is_some() {
                return Err("--depth applies to the built-in circle only".into());
            }
            Hull::from_file(&path).map_err(|e| e.to_string())?
        }
        _ => return Err(format!("'{spec}' is a whole body, not a section")),
    };
    match dofs {
        Some(list) => {
            let names: Vec<&str> = list.split(',').map(str::trim).collect();
            hull.select_dofs(&names).map_err(|e| e.to_string())
        }
        None => Ok(hull),
    }
}

/// Parses `MIN:MAX` into a pair.
pub fn parse_range(text: &str, what: &str) -> Result<(f64, f64), String> {
    let parts: Vec<&str> = text.split(':').collect();
    let [min, max] = parts.as_slice() else {
        return Err(format!("{what} '{text}': expected MIN:MAX"));
    };
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .map_err(|_| format!("{what} '{text}': '{s}' is not a number"))
    };
    Ok((number(min)?, number(max)?))
}
