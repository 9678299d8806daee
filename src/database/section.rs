//! A 2D section's sweep as a whole-body [`Database`] of a 1 m slice: every value per unit
//! length (N/m per m/s^2, ...), for the WAMIT and Capytaine exports of `fmu-pack sweep`.
//!
//! Axes (no sign changes, a right-handed frame): WAMIT's and Capytaine's X runs along the
//! section's longitudinal axis, towards the viewer of the section drawn with our x to the
//! right and y up; Y = our x, Z = our y, origin on the free surface at our origin. Rigid
//! `sway` (+x) is mode 2, `heave` (+y) mode 3, `roll` (counter-clockwise, x towards y) mode 4,
//! a rotation about +X through the roll DOF's reference point (the body origin of the files'
//! rotations; the built-ins' is our origin). Every other DOF is a generalized mode 7, 8, ...
//! in the hull's order, with its own name.
//!
//! Waves: our heading `h` (0: towards +x, 180: towards -x) is the 3D direction
//! `beta = 90 - h` (90 and -90 degrees, beam seas), phase referred to the crest at x = 0.
//!
//! One currency: the [`Database`] carries what a ship's or an import's does (DOF names and
//! units, added mass, `A_inf`, exciting force and its Froude-Krylov part, the long-wave limit,
//! restoring, failures, warnings, notes), every value per unit length, as its
//! [`Database::source`] says. The section's nondimensional tables (docs/DESIGN.md: `kR = omega^2 R /
//! g`, `A~ / (rho pi R^2)`, `X_j / (rho g a R^(1 + e_j))`) are exports of it
//! ([`SectionDatabase::write_table`], [`SectionDatabase::write_excitation_table`]), written from
//! the nondimensional sweep it keeps: the SI values are symmetrized and scaled, and dividing
//! them again would not give the same bytes.

use super::Database;
use crate::bem::HEADINGS;
use crate::hull::{DofKind, Hull, RigidKind};
use crate::hydrostatics::HydrostaticsError;
use crate::identify::FrequencyResponse;
use crate::sweep::{ExcitationPart, SweepResult};
use nalgebra::DMatrix;
use num_complex::Complex64;
use std::fmt;

/// Why a section cannot be exported as a whole-body [`Database`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SectionError {
    /// The sweep is of other DOFs than the hull's.
    OtherDofs {
        /// The sweep's DOFs.
        sweep: Vec<String>,
        /// The hull's DOFs.
        hull: Vec<String>,
    },
    /// An elastic DOF named after a WAMIT rigid mode (`surge` .. `yaw`).
    RigidName(String),
    /// Two DOFs that would be one WAMIT rigid mode.
    SameMode(String),
    /// The restoring could not be computed.
    Restoring(HydrostaticsError),
    /// A table that is not finite in SI (named).
    NonFinite(&'static str),
}

impl fmt::Display for SectionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SectionError::OtherDofs { sweep, hull } => write!(
                f,
                "the sweep's DOFs ({}) are not the hull's ({})",
                sweep.join(" "),
                hull.join(" ")
            ),
            SectionError::RigidName(own) => write!(
                f,
                "DOF '{own}' is not a rigid motion but has the name of a WAMIT rigid \
                 mode; rename it in the hull file to export the section"
            ),
            SectionError::SameMode(name) => write!(
                f,
                "two DOFs of the section are both WAMIT's '{name}'; keep one with --dofs"
            ),
            SectionError::Restoring(e) => write!(f, "{e}"),
            SectionError::NonFinite(what) => write!(f, "{what} of the section is not finite in SI"),
        }
    }
}

impl std::error::Error for SectionError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SectionError::Restoring(e) => Some(e),
            _ => None,
        }
    }
}

impl From<SectionError> for String {
    fn from(error: SectionError) -> String {
        error.to_string()
    }
}

/// The 3D wave direction (degrees) of our section heading `heading`: `90 - heading`.
pub fn wave_direction(heading: f64) -> f64 {
    90.0 - heading
}

/// A section's per-unit-length database, with its frame.
#[derive(Clone, Debug)]
pub struct SectionDatabase {
    /// The coefficients of a 1 m slice, SI; `reference_length` 1 m; rigid DOFs named `sway`,
    /// `heave`, `roll`; headings `beta` ascending (-90, 90).
    pub database: Database,
    /// The roll DOF's reference point (our x, y), m, when the section has one.
    pub roll_centre: Option<[f64; 2]>,
    /// The nondimensional sweep the database was made from (its `R`, [`SweepResult::kr`],
    /// `A~ / (rho pi R^2)`, ...), for the nondimensional tables.
    pub sweep: SweepResult,
}

/// The exported names of a section's DOFs, what renaming them noted, and the roll centre.
#[derive(Clone, Debug, PartialEq)]
pub struct WamitNames {
    /// The DOF names in the hull's order: `sway`, `heave`, `roll` for the rigid motions.
    pub names: Vec<String>,
    /// A line for each rigid DOF the hull names otherwise.
    pub notes: Vec<String>,
    /// The roll DOF's reference point (our x, y), m.
    pub roll_centre: Option<[f64; 2]>,
}

/// The exported names of `hull`'s DOFs (checked before a sweep).
///
/// # Errors
/// Two DOFs that would be one WAMIT rigid mode, or an elastic DOF named after a rigid mode
/// (`surge` .. `yaw`).
pub fn wamit_names(hull: &Hull) -> Result<WamitNames, SectionError> {
    let mut names = Vec::with_capacity(hull.dof_count());
    let mut notes = Vec::new();
    let mut roll_centre = None;
    for (j, own) in hull.dof_names().iter().enumerate() {
        let name = match hull.dof_kind(j) {
            Some(DofKind::Rigid { kind, reference }) => {
                if kind == RigidKind::Roll {
                    roll_centre = Some(reference);
                }
                // WAMIT's names of modes 2, 3, 4 are ours.
                let name = kind.as_str();
                if name != *own {
                    notes.push(format!(
                        "DOF '{own}' (rigid {name}) is exported as '{name}'"
                    ));
                }
                name.to_string()
            }
            _ if super::wamit::RIGID_MODES.contains(own) => {
                return Err(SectionError::RigidName(own.to_string()))
            }
            _ => own.to_string(),
        };
        if names.contains(&name) {
            return Err(SectionError::SameMode(name));
        }
        names.push(name);
    }
    Ok(WamitNames {
        names,
        notes,
        roll_centre,
    })
}

impl SectionDatabase {
    /// The section sweep `sweep` of `hull` in SI for `rho` and `g` (the added mass as
    /// [`FrequencyResponse::from_sweep`] scales it, made symmetric), the restoring of
    /// [`crate::hydrostatics::stiffness`], the exciting force of [`SweepResult::excitation`]
    /// (direct solve) when computed, in the sweep's water depth ([`SweepResult::depth`]).
    ///
    /// # Errors
    /// A sweep of other DOFs than the hull's, two DOFs that would be one WAMIT rigid mode,
    /// an elastic DOF named after a rigid mode (`surge` .. `yaw`), or a restoring that is not
    /// finite.
    pub fn from_sweep(
        hull: &Hull,
        sweep: &SweepResult,
        rho: f64,
        g: f64,
    ) -> Result<SectionDatabase, SectionError> {
        if hull.dof_names() != sweep.dof_names {
            return Err(SectionError::OtherDofs {
                sweep: sweep.dof_names.clone(),
                hull: hull.dof_names().iter().map(|d| d.to_string()).collect(),
            });
        }
        let WamitNames {
            names,
            notes,
            roll_centre,
        } = wamit_names(hull)?;
        let n = names.len();
        let response = FrequencyResponse::from_sweep(sweep, rho, g);
        let radius = sweep.reference_half_beam;
        let force_scale: Vec<f64> = sweep
            .length_exponents
            .iter()
            .map(|&e| rho * g * radius.powi(1 + i32::from(e)))
            .collect();
        // Columns in ascending beta.
        let mut columns: Vec<(f64, usize)> = HEADINGS
            .iter()
            .enumerate()
            .map(|(h, heading)| (wave_direction(*heading), h))
            .collect();
        columns.sort_by(|a, b| a.0.total_cmp(&b.0));
        let si = |x: &DMatrix<Complex64>| {
            DMatrix::from_fn(n, columns.len(), |j, c| {
                x[(j, columns[c].1)] * force_scale[j]
            })
        };
        let restoring = crate::hydrostatics::stiffness(hull).map_err(SectionError::Restoring)?;
        let mut units = hull.dof_units();
        for (unit, name) in units.iter_mut().zip(&names) {
            unit.name.clone_from(name);
        }
        let mut database = Database {
            name: hull.name().to_string(),
            source: SOURCE.to_string(),
            dof_names: names,
            dof_units: units,
            rho,
            g,
            omega: response.omega,
            added_mass: response.added_mass,
            added_mass_inf: response.added_mass_inf,
            headings: columns.iter().map(|c| c.0).collect(),
            excitation: sweep.excitation.iter().map(|w| si(&w.direct)).collect(),
            froude_krylov: sweep
                .excitation
                .iter()
                .map(|w| si(&w.froude_krylov))
                .collect(),
            excitation_long_wave: Some(
                sweep
                    .excitation_long_wave
                    .iter()
                    .zip(&force_scale)
                    .map(|(x, s)| x * s)
                    .collect(),
            ),
            stiffness_hydrostatic: restoring.stiffness(rho, g),
            reference_length: 1.0,
            failures: sweep
                .failures
                .iter()
                .map(|(kr, why)| (crate::units::omega_from_kr(*kr, radius, g), why.clone()))
                .collect(),
            warnings: sweep.warnings.clone(),
            notes,
            noise: DMatrix::zeros(0, 0),
            body_panels: vec![sweep.panel_counts.0],
            drift: Vec::new(),
            drift_headings: Vec::new(),
            depth: sweep.depth,
        };
        // The fixed section's mean drift, when every frequency has it (headings 0 and 180).
        let drifts: Option<Vec<DMatrix<f64>>> = sweep
            .excitation
            .iter()
            .map(|w| {
                let d = w.drift.as_ref()?.mean_drift();
                (d.ncols() == columns.len()).then(|| {
                    DMatrix::from_fn(n, columns.len(), |j, c| d[(j, columns[c].1)] * rho * g)
                })
            })
            .collect();
        if let Some(drift) = drifts.filter(|d| !d.is_empty()) {
            database.drift = drift;
            database.drift_headings = database.headings.clone();
        }
        let gaps = super::import::symmetrize(&mut database);
        database.noise = super::import::largest_gap(&gaps, database.dof_names.len());
        if let Some(what) = database.first_non_finite() {
            return Err(SectionError::NonFinite(what));
        }
        Ok(SectionDatabase {
            database,
            roll_centre,
            sweep: sweep.clone(),
        })
    }

    /// The reference half-beam `R` of the nondimensional tables, m.
    pub fn reference_half_beam(&self) -> f64 {
        self.sweep.reference_half_beam
    }

    /// The nondimensional added-mass table of docs/DESIGN.md (`kR,i,j,re,im`, values
    /// `A~ / (rho pi R^2)`), the bytes [`SweepResult::write_csv`] writes.
    ///
    /// # Errors
    /// The writer's.
    pub fn write_table(&self, out: &mut dyn std::io::Write) -> std::io::Result<()> {
        self.sweep.write_csv(out)
    }

    /// The nondimensional excitation table of docs/DESIGN.md (`kR,j,heading,re,im`, values
    /// `X_j / (rho g a R^(1 + e_j))`) of the total force or its Froude-Krylov part, the bytes
    /// [`SweepResult::write_excitation_csv`] writes.
    ///
    /// # Errors
    /// The writer's.
    pub fn write_excitation_table(
        &self,
        out: &mut dyn std::io::Write,
        part: ExcitationPart,
    ) -> std::io::Result<()> {
        self.sweep.write_excitation_csv(out, part)
    }

    /// The frame in words, for the files' headers.
    pub fn frame(&self) -> String {
        let centre = self.roll_centre.map_or(String::new(), |[x, y]| {
            format!("; roll about X through (Y, Z) = ({x}, {y}) m")
        });
        format!(
            "axes: X along the section, Y = section x, Z = section y (up){centre}; beam seas: \
             beta = 90 - section heading (deg)"
        )
    }

    /// The WAMIT files ([`super::wamit::write`]) with the per-unit-length frame in their
    /// header line.
    pub fn wamit(&self) -> super::wamit::WamitFiles {
        let mut database = self.database.clone();
        database.source = format!("{}; {}", database.source, self.frame());
        super::wamit::write(&database)
    }

    /// The Capytaine dataset ([`super::capytaine::write_with`]) with global attributes
    /// `per_unit_length`, `reference_length` (1, m), `axes`, and `rotation_center` (X, Y, Z,
    /// m) when the section rolls.
    ///
    /// # Errors
    /// [`super::capytaine::WriteError`]: the file cannot be written (its text names the file).
    pub fn write_netcdf(&self, path: &std::path::Path) -> Result<(), super::capytaine::WriteError> {
        use super::capytaine::Attribute;
        let mut attributes = vec![
            (
                "per_unit_length",
                Attribute::Text(PER_UNIT_LENGTH.to_string()),
            ),
            ("reference_length", Attribute::Numbers(vec![1.0])),
            ("axes", Attribute::Text(self.frame())),
        ];
        if let Some([x, y]) = self.roll_centre {
            attributes.push(("rotation_center", Attribute::Numbers(vec![0.0, x, y])));
        }
        super::capytaine::write_with(&self.database, path, &attributes)
    }
}

/// What the files say of their values.
const PER_UNIT_LENGTH: &str = "every value per unit length of the 2D section (a 1 m slice): \
    added mass kg/m, damping kg/(m s), exciting force N/m per m of wave amplitude, restoring \
    N/m^2 (rotations and generalized modes: one more m per DOF)";

/// The database's source.
const SOURCE: &str = "2D section, panel method, per unit length (a 1 m slice)";

#[cfg(test)]
mod tests {
    use super::*;

    fn hull(dofs: &str) -> Hull {
        let text = format!(
            r#"<hull name="box" half_beam="1" units="m">
  <contour closed="false">
    <point x="-1" y="0"/><point x="-1" y="-1"/><point x="1" y="-1"/><point x="1" y="0"/>
  </contour>
  {dofs}
</hull>"#
        );
        Hull::from_xml_str(&text, "box.xml").unwrap()
    }

    const MODE: &str = r#"<u x="0" y="0"/><u x="0" y="1"/><u x="0" y="1"/><u x="0" y="0"/>"#;

    #[test]
    fn rigid_dofs_take_wamit_names_and_clashes_are_refused() {
        let named = wamit_names(&hull(
            r#"<rigid name="drift" kind="sway"/><rigid name="r" kind="roll" x="0" y="-0.5"/>"#,
        ))
        .unwrap();
        assert_eq!(named.names, ["sway", "roll"]);
        assert_eq!(named.roll_centre, Some([0.0, -0.5]));
        assert_eq!(
            named.notes,
            [
                "DOF 'drift' (rigid sway) is exported as 'sway'",
                "DOF 'r' (rigid roll) is exported as 'roll'"
            ]
        );
        let elastic = format!(r#"<mode name="pitch">{MODE}</mode>"#);
        let e = wamit_names(&hull(&elastic)).unwrap_err();
        assert_eq!(e, SectionError::RigidName("pitch".to_string()));
        assert!(
            e.to_string().contains("DOF 'pitch' is not a rigid motion"),
            "{e}"
        );
        let twice = r#"<rigid name="a" kind="heave"/><rigid name="b" kind="heave"/>"#;
        let e = wamit_names(&hull(twice)).unwrap_err();
        assert!(e.to_string().contains("both WAMIT's 'heave'"), "{e}");
    }

    /// The section database of `hull` on a small grid, and its sweep's own tables.
    fn exported(hull: &Hull) -> (SectionDatabase, [Vec<u8>; 3]) {
        exported_in(hull, crate::units::WaterDepth::Infinite)
    }

    /// [`exported`] in water depth `depth`.
    fn exported_in(
        hull: &Hull,
        depth: crate::units::WaterDepth,
    ) -> (SectionDatabase, [Vec<u8>; 3]) {
        use crate::panels::PanelParams;
        use crate::sweep::{run, SweepParams};
        let params = SweepParams {
            kr: vec![0.3, 1.2],
            panels: PanelParams {
                body_panels: 24,
                ..PanelParams::default()
            },
            depth,
            ..SweepParams::default()
        };
        let sweep = run(hull, &params, &|_, _| {}).unwrap();
        let mut today: [Vec<u8>; 3] = Default::default();
        sweep.write_csv(&mut today[0]).unwrap();
        sweep
            .write_excitation_csv(&mut today[1], ExcitationPart::Total)
            .unwrap();
        sweep
            .write_excitation_csv(&mut today[2], ExcitationPart::FroudeKrylov)
            .unwrap();
        (
            SectionDatabase::from_sweep(hull, &sweep, 1025.0, 9.81).unwrap(),
            today,
        )
    }

    fn assert_tables_as_today(hull: &Hull) {
        let (section, today) = exported(hull);
        let mut ours: [Vec<u8>; 3] = Default::default();
        section.write_table(&mut ours[0]).unwrap();
        section
            .write_excitation_table(&mut ours[1], ExcitationPart::Total)
            .unwrap();
        section
            .write_excitation_table(&mut ours[2], ExcitationPart::FroudeKrylov)
            .unwrap();
        for (k, (ours, today)) in ours.iter().zip(&today).enumerate() {
            assert!(ours == today, "{}: table {k} differs", hull.name());
        }
        // The export is of this database: its DOFs, R and rows.
        let text = String::from_utf8(ours[0].clone()).unwrap();
        let n = section.database.dof_names.len();
        let rows = text.lines().filter(|l| l.starts_with("inf,")).count();
        assert_eq!(rows, n * n);
        assert!(text.contains(&format!("# R: {} m\n", section.reference_half_beam())));
        assert_eq!(section.database.omega.len(), 2);
        assert!(section
            .database
            .stiffness_hydrostatic
            .iter()
            .any(|c| *c != 0.0));
        assert_eq!(section.database.excitation.len(), 2);
    }

    #[test]
    fn a_databases_depth_goes_into_every_table_and_the_dataset() {
        use crate::units::WaterDepth;
        let (mut section, _) = exported(&Hull::semicircle(2.0).unwrap());
        let header = |database: &Database| {
            let mut tables: [Vec<u8>; 3] = Default::default();
            database.write_excitation_table(&mut tables[0]).unwrap();
            database.write_csv(&mut tables[1]).unwrap();
            database.write_excitation_csv(&mut tables[2]).unwrap();
            tables.map(|t| String::from_utf8(t).unwrap())
        };
        let deep = header(&section.database);
        assert!(deep[0].contains("\n# depth: inf\n"));
        assert!(deep[1].contains("\n# depth: inf\n") && deep[2].contains("\n# depth: inf\n"));
        // h = 6 m: the FMU's table says h/R with its R (the section's 1 m slice: R = 1 m in
        // SI, the table's R the database's reference length), the SI tables metres.
        section.database.depth = WaterDepth::Finite(6.0);
        let finite = header(&section.database);
        let table = crate::waves::ExcitationTable::from_csv_str(&finite[0], "x.csv").unwrap();
        assert_eq!(table.depth(), WaterDepth::Finite(6.0));
        assert!(finite[1].contains("\n# depth: 6 m\n"));
        // The Capytaine dataset's water_depth, read back.
        let path = std::env::temp_dir().join(format!("hydrofmu-depth-{}.nc", std::process::id()));
        section.write_netcdf(&path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        let params = crate::database::wamit::WamitParams::default();
        let back = crate::database::capytaine::read("s", bytes, "s.nc", &params).unwrap();
        assert_eq!(back.database.depth, WaterDepth::Finite(6.0));
        assert!(back
            .database
            .notes
            .iter()
            .any(|n| n.contains("water depth 6 m")));
    }

    #[test]
    fn the_database_of_a_finite_depth_sweep_has_the_sweeps_depth() {
        use crate::units::WaterDepth;
        let hull = Hull::semicircle(2.0).unwrap();
        let (deep, _) = exported(&hull);
        assert_eq!(deep.database.depth, WaterDepth::Infinite);
        // h = 3 m, h/R = 1.5: the bottom raises heave's A_inf well above deep water's.
        let (finite, today) = exported_in(&hull, WaterDepth::Finite(3.0));
        assert_eq!(finite.database.depth, WaterDepth::Finite(3.0));
        let sweep_table = String::from_utf8(today[0].clone()).unwrap();
        assert!(sweep_table.contains("\n# depth: 1.5\n"), "{sweep_table}");
        let mut table = Vec::new();
        finite.database.write_csv(&mut table).unwrap();
        let table = String::from_utf8(table).unwrap();
        assert!(table.contains("\n# depth: 3 m\n"), "{table}");
        let heave = |s: &SectionDatabase| s.database.added_mass_inf[(1, 1)];
        assert!(heave(&finite) > 1.1 * heave(&deep), "{}", heave(&finite));
    }

    #[test]
    fn a_semicircle_exports_todays_tables() {
        assert_tables_as_today(&Hull::semicircle(2.0).unwrap());
    }

    #[test]
    fn a_submerged_circle_exports_todays_tables() {
        assert_tables_as_today(&Hull::circle(1.0, 2.0).unwrap());
    }

    #[test]
    fn the_midship_section_exports_todays_tables() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hulls/midship.xml");
        let hull = Hull::from_file(&path)
            .unwrap()
            .select_dofs(&["sway", "heave", "roll"])
            .unwrap();
        assert_tables_as_today(&hull);
    }
}
