//! Writing a [`Database`] as WAMIT files (`.1`, `.3`, `.9`, `.hst`; the inverse of
//! [`super::read`] and [`super::read_drift`]).

use super::{mode_indices, Database};

/// The three files of a database in WAMIT's format, ULEN = 1 m.
#[derive(Clone, Debug, PartialEq)]
pub struct WamitFiles {
    /// `NAME.1`: the `A_inf` rows (PER = 0), then every frequency, ascending period.
    pub radiation: String,
    /// `NAME.3`; `None` when the database has no exciting force.
    pub excitation: Option<String>,
    /// `NAME.9`, the mean drift of one wave direction (`BETA1 = BETA2`); `None` when the
    /// database has none.
    pub drift: Option<String>,
    /// `NAME.hst`.
    pub hydrostatics: String,
}

/// Writes `database` as WAMIT files (the inverse of [`super::read`] with ULEN = 1 m and the
/// database's rho and g): `Abar = A / rho`, `Bbar = B / (rho omega) = -Im A~ / rho`,
/// `Xbar = X / (rho g)`, `Dbar = D / (rho g)`, `Cbar = C / (rho g)`, 10 significant digits. One header line names
/// the modes (`modes: 3=heave 5=pitch 7=vb1`), so that [`super::read`] gives the names back; other
/// readers skip it (or read the files without it: WAMIT writes one with NUMHDR = 1).
pub fn write(database: &Database) -> WamitFiles {
    let index = mode_indices(&database.dof_names);
    let names: Vec<String> = index
        .iter()
        .zip(&database.dof_names)
        .map(|(k, name)| format!("{k}={name}"))
        .collect();
    let header = |what: &str| {
        format!(
            " hydrofmu {what} of {} (ULEN = 1 m, rho = {} kg/m^3, g = {} m/s^2; {}) modes: {}\n",
            database.name,
            database.rho,
            database.g,
            database.source,
            names.join(" ")
        )
    };
    let number = |x: f64| format!("{:.9E}", x + 0.0);
    let n = database.dof_names.len();
    let (rho, g) = (database.rho, database.g);
    let mut radiation = header("added mass and damping");
    for i in 0..n {
        for j in 0..n {
            radiation.push_str(&format!(
                "{} {} {} {}\n",
                number(0.0),
                index[i],
                index[j],
                number(database.added_mass_inf[(i, j)] / rho)
            ));
        }
    }
    let order: Vec<usize> = (0..database.omega.len()).rev().collect();
    for &k in &order {
        let period = 2.0 * std::f64::consts::PI / database.omega[k];
        let a = &database.added_mass[k];
        for i in 0..n {
            for j in 0..n {
                radiation.push_str(&format!(
                    "{} {} {} {} {}\n",
                    number(period),
                    index[i],
                    index[j],
                    number(a[(i, j)].re / rho),
                    number(-a[(i, j)].im / rho)
                ));
            }
        }
    }
    let excitation = (!database.excitation.is_empty()).then(|| {
        let mut text = header("exciting force");
        for &k in &order {
            let period = 2.0 * std::f64::consts::PI / database.omega[k];
            for (h, heading) in database.headings.iter().enumerate() {
                for (i, mode) in index.iter().enumerate() {
                    let x = database.excitation[k][(i, h)] / (rho * g);
                    text.push_str(&format!(
                        "{} {} {mode} {} {} {} {}\n",
                        number(period),
                        number(*heading),
                        number(x.norm()),
                        number(x.im.atan2(x.re).to_degrees()),
                        number(x.re),
                        number(x.im)
                    ));
                }
            }
        }
        text
    });
    let drift = (!database.drift.is_empty()).then(|| {
        let mut text = header("mean drift");
        for &k in &order {
            let period = 2.0 * std::f64::consts::PI / database.omega[k];
            for (h, heading) in database.drift_headings.iter().enumerate() {
                for (i, mode) in index.iter().enumerate() {
                    let d = database.drift[k][(i, h)] / (rho * g);
                    text.push_str(&format!(
                        "{} {} {} {mode} {} {} {} {}\n",
                        number(period),
                        number(*heading),
                        number(*heading),
                        number(d.abs()),
                        number(if d < 0.0 { 180.0 } else { 0.0 }),
                        number(d),
                        number(0.0)
                    ));
                }
            }
        }
        text
    });
    let mut hydrostatics = header("hydrostatic restoring");
    for i in 0..n {
        for j in 0..n {
            hydrostatics.push_str(&format!(
                "{} {} {}\n",
                index[i],
                index[j],
                number(database.stiffness_hydrostatic[(i, j)] / (rho * g))
            ));
        }
    }
    WamitFiles {
        radiation,
        excitation,
        drift,
        hydrostatics,
    }
}
