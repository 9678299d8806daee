//! Writing a [`Database`] as a Capytaine dataset in NetCDF-3 (the inverse of [`super::read`]).

use super::super::wamit;
use super::Database;
use std::fmt;

/// Why [`write_with`] could not write the dataset; its text names the file.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum WriteError {
    /// The file system refused the file.
    Io {
        /// The file.
        path: String,
        /// The error's kind.
        kind: std::io::ErrorKind,
    },
    /// The NetCDF writer refused the data or its definition.
    NetCdf {
        /// The file.
        path: String,
        /// The writer's words.
        message: String,
        /// Whether the definition (dimensions, variables, attributes) was refused.
        definition: bool,
    },
}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WriteError::Io { path, kind } => {
                write!(f, "cannot write {path}: {}", std::io::Error::from(*kind))
            }
            WriteError::NetCdf {
                path,
                message,
                definition: false,
            } => write!(f, "cannot write {path}: {message}"),
            WriteError::NetCdf { path, message, .. } => write!(f, "{path}: {message}"),
        }
    }
}

impl std::error::Error for WriteError {}

impl From<WriteError> for String {
    fn from(error: WriteError) -> String {
        error.to_string()
    }
}

/// Capytaine's DOF name of ours: `Surge` .. `Yaw` for the rigid modes, others unchanged.
fn capytaine_name(name: &str) -> String {
    match wamit::RIGID_MODES.iter().position(|r| *r == name) {
        Some(_) => {
            let mut c = name.chars();
            c.next()
                .map(|first| first.to_ascii_uppercase().to_string() + c.as_str())
                .unwrap_or_default()
        }
        None => name.to_string(),
    }
}

/// Writes `database` at `path` as a Capytaine dataset in NetCDF-3 (the inverse of [`super::read`]):
/// the variables, dimensions and conventions of the module docs, as
/// `separate_complex_values(dataset).to_netcdf(path, engine="scipy")` writes them, so that
/// `xarray.open_dataset` and `capytaine.io.xarray.merge_complex_values` read it:
/// `omega` holds the database's frequencies then `inf` (the `A_inf` row; damping 0, the
/// exciting force NaN there, as Capytaine's), `added_mass = Re A~`,
/// `radiation_damping = -omega Im A~`, `excitation_force = conj(X)` (Capytaine's
/// `exp(-i omega t)`), `wave_direction` in radians, `hydrostatic_stiffness`, `rho`, `g`,
/// `forward_speed = 0`, `water_depth` (m, `inf` for deep water: [`Database::depth`]).
///
/// # Errors
/// [`WriteError`]: the file cannot be written (its text names the file).
pub fn write(database: &Database, path: &std::path::Path) -> Result<(), WriteError> {
    write_with(database, path, &[])
}

/// The value of a global attribute of [`write_with`].
#[derive(Clone, Debug, PartialEq)]
pub enum Attribute {
    /// Text.
    Text(String),
    /// Numbers (`f64`).
    Numbers(Vec<f64>),
}

/// As [`write()`], with more global attributes.
///
/// # Errors
/// [`WriteError`]: the file cannot be written (its text names the file).
pub fn write_with(
    database: &Database,
    path: &std::path::Path,
    attributes: &[(&str, Attribute)],
) -> Result<(), WriteError> {
    use netcdf3::{DataSet, FileWriter, Version};
    let fail = |e: netcdf3::error::WriteError| match e {
        netcdf3::error::WriteError::IOErrorKind(kind) => WriteError::Io {
            path: path.display().to_string(),
            kind,
        },
        other => WriteError::NetCdf {
            path: path.display().to_string(),
            message: format!("{other:?}"),
            definition: false,
        },
    };
    let define = |e: netcdf3::error::InvalidDataSet| WriteError::NetCdf {
        path: path.display().to_string(),
        message: format!("{e:?}"),
        definition: true,
    };
    let n = database.dof_names.len();
    let count = database.omega.len() + 1;
    let headings = database.headings.len();
    let names: Vec<String> = database
        .dof_names
        .iter()
        .map(|d| capytaine_name(d))
        .collect();
    let width = names.iter().map(String::len).max().unwrap_or(1).max(1);
    let string = format!("string{width}");
    let mut ds = DataSet::new();
    ds.add_fixed_dim("omega", count).map_err(define)?;
    ds.add_fixed_dim("influenced_dof", n).map_err(define)?;
    ds.add_fixed_dim("radiating_dof", n).map_err(define)?;
    ds.add_fixed_dim(&string, width).map_err(define)?;
    ds.add_fixed_dim("complex", 2).map_err(define)?;
    ds.add_fixed_dim("string2", 2).map_err(define)?;
    let has_waves = !database.excitation.is_empty() && headings > 0;
    if has_waves {
        ds.add_fixed_dim("wave_direction", headings)
            .map_err(define)?;
    }
    ds.add_var_f64("omega", &["omega"]).map_err(define)?;
    ds.add_var_f64("period", &["omega"]).map_err(define)?;
    ds.add_var_u8("influenced_dof", &["influenced_dof", &string])
        .map_err(define)?;
    ds.add_var_u8("radiating_dof", &["radiating_dof", &string])
        .map_err(define)?;
    ds.add_var_u8("complex", &["complex", "string2"])
        .map_err(define)?;
    // xarray decodes a character array to text with this attribute (as it writes them).
    for text in ["influenced_dof", "radiating_dof", "complex"] {
        ds.add_var_attr_string(text, "_Encoding", "utf-8")
            .map_err(define)?;
    }
    ds.add_global_attr_string("source", format!("hydrofmu: {}", database.source))
        .map_err(define)?;
    for (name, value) in attributes {
        match value {
            Attribute::Text(text) => ds.add_global_attr_string(name, text),
            Attribute::Numbers(numbers) => ds.add_global_attr_f64(name, numbers.clone()),
        }
        .map_err(define)?;
    }
    for scalar in ["rho", "g", "forward_speed", "water_depth"] {
        ds.add_var_f64::<&str>(scalar, &[]).map_err(define)?;
    }
    for matrix in ["added_mass", "radiation_damping"] {
        ds.add_var_f64(matrix, &["omega", "influenced_dof", "radiating_dof"])
            .map_err(define)?;
    }
    ds.add_var_f64(
        "hydrostatic_stiffness",
        &["influenced_dof", "radiating_dof"],
    )
    .map_err(define)?;
    if has_waves {
        ds.add_var_f64("wave_direction", &["wave_direction"])
            .map_err(define)?;
        ds.add_var_f64(
            "excitation_force",
            &["complex", "omega", "wave_direction", "influenced_dof"],
        )
        .map_err(define)?;
    }
    let mut omega = database.omega.clone();
    omega.push(f64::INFINITY);
    let period: Vec<f64> = omega
        .iter()
        .map(|w| 2.0 * std::f64::consts::PI / w)
        .collect();
    let chars = |list: &[String], w: usize| -> Vec<u8> {
        list.iter()
            .flat_map(|s| {
                let mut b = s.as_bytes().to_vec();
                b.resize(w, 0);
                b
            })
            .collect()
    };
    let mut added = Vec::with_capacity(count * n * n);
    let mut damping = Vec::with_capacity(count * n * n);
    for (k, w) in database.omega.iter().enumerate() {
        let a = &database.added_mass[k];
        for i in 0..n {
            for j in 0..n {
                added.push(a[(i, j)].re);
                damping.push(-a[(i, j)].im * w);
            }
        }
    }
    for i in 0..n {
        for j in 0..n {
            added.push(database.added_mass_inf[(i, j)]);
            damping.push(0.0);
        }
    }
    let stiffness: Vec<f64> = (0..n * n)
        .map(|q| database.stiffness_hydrostatic[(q / n, q % n)])
        .collect();
    let mut writer = FileWriter::open(path).map_err(fail)?;
    writer.set_def(&ds, Version::Offset64Bit, 0).map_err(fail)?;
    writer.write_var_f64("omega", &omega).map_err(fail)?;
    writer.write_var_f64("period", &period).map_err(fail)?;
    writer
        .write_var_u8("influenced_dof", &chars(&names, width))
        .map_err(fail)?;
    writer
        .write_var_u8("radiating_dof", &chars(&names, width))
        .map_err(fail)?;
    writer
        .write_var_u8("complex", &chars(&["re".into(), "im".into()], 2))
        .map_err(fail)?;
    writer.write_var_f64("rho", &[database.rho]).map_err(fail)?;
    writer.write_var_f64("g", &[database.g]).map_err(fail)?;
    writer
        .write_var_f64("forward_speed", &[0.0])
        .map_err(fail)?;
    writer
        .write_var_f64("water_depth", &[database.depth.metres()])
        .map_err(fail)?;
    writer.write_var_f64("added_mass", &added).map_err(fail)?;
    writer
        .write_var_f64("radiation_damping", &damping)
        .map_err(fail)?;
    writer
        .write_var_f64("hydrostatic_stiffness", &stiffness)
        .map_err(fail)?;
    if has_waves {
        let radians: Vec<f64> = database.headings.iter().map(|h| h.to_radians()).collect();
        writer
            .write_var_f64("wave_direction", &radians)
            .map_err(fail)?;
        let mut force = Vec::with_capacity(2 * count * headings * n);
        for part in 0..2 {
            for k in 0..count {
                for h in 0..headings {
                    for j in 0..n {
                        // Capytaine's exp(-i omega t): the conjugate; NaN at omega = inf.
                        force.push(match database.excitation.get(k) {
                            Some(x) if part == 0 => x[(j, h)].re,
                            Some(x) => -x[(j, h)].im,
                            None => f64::NAN,
                        });
                    }
                }
            }
        }
        writer
            .write_var_f64("excitation_force", &force)
            .map_err(fail)?;
    }
    writer.close().map_err(fail)
}
