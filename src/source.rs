//! What a source argument names: a built-in section, a hull file, a ship file or an imported
//! 3D database.
//!
//! Every tool that takes a hull-or-body argument (`fmu-pack sweep|fit|pack`) decides with
//! [`Source::from_argument`], in this order:
//!
//! 1. a file whose top-level element is `<ship>`: a ship file ([`crate::ship`]);
//! 2. a name ending in `.1` or `.nc`: a WAMIT or Capytaine NetCDF-3 database
//!    ([`crate::database::import`]; the importer reports a missing or unreadable file);
//! 3. `semicircle` or `circle`: a built-in section ([`crate::hull`]);
//! 4. any other existing file: a hull file, unless it is XML whose top-level element is
//!    neither `<hull>` nor `<ship>` (a file with an XML syntax error counts as a hull file,
//!    so the hull reader names the line).
//!
//! Anything else is refused with a [`SourceError`] that names every kind.

use std::fmt;
use std::path::{Path, PathBuf};

/// The kind of a source argument, with its path when it names a file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    /// The built-in half-immersed semicircle.
    Semicircle,
    /// The built-in fully submerged circle.
    Circle,
    /// A hull file (`docs/HULL_FORMAT.md`).
    HullFile(PathBuf),
    /// A ship file (`docs/SHIPS.md`), swept by strip theory.
    ShipFile(PathBuf),
    /// A WAMIT database, named by its `NAME.1` file.
    Wamit(PathBuf),
    /// A Capytaine NetCDF-3 dataset `NAME.nc`.
    Capytaine(PathBuf),
}

/// Why a source argument names no source.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SourceError {
    /// Not a built-in name and no such file.
    NotFound(String),
    /// An existing XML file whose top-level element is neither `<hull>` nor `<ship>`.
    UnknownFile {
        /// The argument.
        argument: String,
        /// Its top-level element.
        root: String,
    },
}

impl fmt::Display for SourceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SourceError::NotFound(argument) => write!(
                f,
                "hull '{argument}' is neither 'semicircle', 'circle' nor an existing hull file"
            ),
            SourceError::UnknownFile { argument, root } => write!(
                f,
                "'{argument}' (top-level element <{root}>) is neither a built-in section \
                 ('semicircle', 'circle'), a hull file (<hull>), a ship file (<ship>), a WAMIT \
                 NAME.1 nor a Capytaine NAME.nc"
            ),
        }
    }
}

impl std::error::Error for SourceError {}

/// The top-level element of the XML file at `path`, or `None` when it cannot be read or
/// parsed.
fn xml_root(path: &Path) -> Option<String> {
    let limit = crate::xml::MAX_INPUT_BYTES as u64;
    crate::input::read_bounded_text(path, limit, "MAX_INPUT_BYTES")
        .ok()
        .and_then(|text| crate::xml::parse(&text).ok())
        .map(|root| root.name.clone())
}

impl Source {
    /// Decides what `argument` names (order in the [module documentation](self)).
    pub fn from_argument(argument: &str) -> Result<Source, SourceError> {
        let path = Path::new(argument);
        let root = xml_root(path);
        if root.as_deref() == Some("ship") {
            return Ok(Source::ShipFile(path.to_path_buf()));
        }
        if crate::database::import::is_database_path(path) {
            let netcdf = path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("nc"));
            return Ok(if netcdf {
                Source::Capytaine(path.to_path_buf())
            } else {
                Source::Wamit(path.to_path_buf())
            });
        }
        match argument {
            "semicircle" => return Ok(Source::Semicircle),
            "circle" => return Ok(Source::Circle),
            _ => {}
        }
        if !path.exists() {
            return Err(SourceError::NotFound(path.display().to_string()));
        }
        match root {
            Some(root) if root != "hull" => Err(SourceError::UnknownFile {
                argument: argument.to_string(),
                root,
            }),
            _ => Ok(Source::HullFile(path.to_path_buf())),
        }
    }

    /// True for a 2D section (built-in or hull file), false for a whole body (ship or
    /// database).
    pub fn is_section(&self) -> bool {
        matches!(
            self,
            Source::Semicircle | Source::Circle | Source::HullFile(_)
        )
    }

    /// True for an imported database (WAMIT or Capytaine).
    pub fn is_import(&self) -> bool {
        matches!(self, Source::Wamit(_) | Source::Capytaine(_))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file of `text` in a fresh temporary folder, named `name`.
    fn file(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("hydrofmu-source-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    fn kind(path: &Path) -> Result<Source, SourceError> {
        Source::from_argument(path.to_str().unwrap())
    }

    #[test]
    fn built_in_sections_are_named() {
        assert_eq!(Source::from_argument("semicircle"), Ok(Source::Semicircle));
        assert_eq!(Source::from_argument("circle"), Ok(Source::Circle));
        assert!(Source::Circle.is_section() && !Source::Circle.is_import());
    }

    #[test]
    fn a_hull_file_is_a_section() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hulls/midship.xml");
        let source = kind(&path).unwrap();
        assert_eq!(source, Source::HullFile(path));
        assert!(source.is_section());
        // An XML syntax error still goes to the hull reader, which names the line.
        let broken = file("broken.xml", "<hull name=\"x\"");
        assert_eq!(kind(&broken), Ok(Source::HullFile(broken.clone())));
    }

    #[test]
    fn a_ship_file_is_known_by_its_top_level_element() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ships/box_barge.xml");
        let source = kind(&path).unwrap();
        assert_eq!(source, Source::ShipFile(path));
        assert!(!source.is_section() && !source.is_import());
    }

    #[test]
    fn databases_are_known_by_their_extension() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/wamit/sphere.1");
        let source = kind(&path).unwrap();
        assert_eq!(source, Source::Wamit(path));
        assert!(source.is_import() && !source.is_section());
        // By name: the importer reports a missing file.
        assert_eq!(
            Source::from_argument("missing/body.NC"),
            Ok(Source::Capytaine(PathBuf::from("missing/body.NC")))
        );
    }

    #[test]
    fn anything_else_is_refused_with_every_kind_named() {
        let error = Source::from_argument("no/such/hull.xml").unwrap_err();
        assert_eq!(
            error.to_string(),
            "hull 'no/such/hull.xml' is neither 'semicircle', 'circle' nor an existing hull file"
        );
        let other = file("scene.xml", "<scene band=\"0.1:2\"/>");
        let error = kind(&other).unwrap_err();
        assert!(matches!(&error, SourceError::UnknownFile { root, .. } if root == "scene"));
        let text = error.to_string();
        for word in [
            "<scene>",
            "'semicircle'",
            "<hull>",
            "<ship>",
            "NAME.1",
            "NAME.nc",
        ] {
            assert!(text.contains(word), "{text} names {word}");
        }
    }
}
