//! The restoring table an FMU carries when it has no hull file to compute it from (a ship):
//!
//! ```text
//! # modes: sway heave roll ...          (required)
//! # other '#' lines: ignored
//! i,j,value                             value = C_ij / (rho g), SI; every entry once
//! ```
//!
//! Read by a strict, bounded parser: at most [`crate::hull::MAX_DOFS`] modes, checked
//! before the matrix is allocated.

use crate::input::FileError;
use nalgebra::DMatrix;

/// A parsed restoring table.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Mode names, in order.
    pub modes: Vec<String>,
    /// `C / (rho g)`.
    pub stiffness_per_rho_g: DMatrix<f64>,
}

impl Table {
    /// Writes the table.
    pub fn to_csv(&self, name: &str, what: &str) -> String {
        let mut out = format!(
            "# hull: {name}\n# modes: {}\n# values: C_ij / (rho g), SI, {what}\n",
            self.modes.join(" ")
        );
        self.write_rows(&mut out);
        out
    }

    /// Appends the column line `i,j,value` and one row per entry, `C_ij / (rho g)` (a zero
    /// entry as 0, not -0): the part every restoring table shares after its `#` lines.
    pub fn write_rows(&self, out: &mut String) {
        out.push_str("i,j,value\n");
        let c = &self.stiffness_per_rho_g;
        for i in 0..c.nrows() {
            for j in 0..c.ncols() {
                out.push_str(&format!("{},{},{:e}\n", i + 1, j + 1, c[(i, j)] + 0.0));
            }
        }
    }

    /// Parses the table; `source` starts every error message.
    ///
    /// # Errors
    /// A missing `# modes:` line or column header, more than [`crate::hull::MAX_DOFS`]
    /// modes, a malformed or non-finite row, an index out of range, a repeated or missing
    /// entry: a [`FileError`] naming `source` and the line.
    pub fn from_csv_str(text: &str, source: &str) -> Result<Table, FileError> {
        let mut modes: Option<Vec<String>> = None;
        let mut matrix: Option<DMatrix<f64>> = None;
        let mut seen: Vec<bool> = Vec::new();
        for (k, line) in text.lines().enumerate() {
            let at = |m: String| FileError::at(source, k + 1, m);
            let line = line.trim();
            if line.is_empty() {
                continue;
            }
            if let Some(comment) = line.strip_prefix('#') {
                if let Some(names) = comment.trim().strip_prefix("modes:") {
                    if modes.is_some() {
                        return Err(at("a second '# modes:' line".into()));
                    }
                    let names: Vec<String> = names.split_whitespace().map(str::to_string).collect();
                    if names.is_empty() || names.len() > crate::hull::MAX_DOFS {
                        return Err(at(format!(
                            "{} modes; give 1 to {}",
                            names.len(),
                            crate::hull::MAX_DOFS
                        )));
                    }
                    modes = Some(names);
                }
                continue;
            }
            let Some(names) = &modes else {
                return Err(at("data before the '# modes:' line".into()));
            };
            let n = names.len();
            let Some(m) = matrix.as_mut() else {
                if line != "i,j,value" {
                    return Err(at(format!("expected the header 'i,j,value', got '{line}'")));
                }
                matrix = Some(DMatrix::zeros(n, n));
                seen = vec![false; n * n];
                continue;
            };
            let fields: Vec<&str> = line.split(',').collect();
            if fields.len() != 3 {
                return Err(at(format!("{} fields; expected i,j,value", fields.len())));
            }
            let index = |f: &str, what: &str| match f.trim().parse::<usize>() {
                Ok(v) if (1..=n).contains(&v) => Ok(v - 1),
                _ => Err(at(format!(
                    "field {what} = '{f}' is not an index from 1 to {n}"
                ))),
            };
            let (i, j) = (index(fields[0], "i")?, index(fields[1], "j")?);
            let value = crate::xml::parse_number(fields[2].trim())
                .map_err(|e| at(format!("field value: {e}")))?;
            if seen[i * n + j] {
                return Err(at(format!("entry {},{} is given twice", i + 1, j + 1)));
            }
            seen[i * n + j] = true;
            m[(i, j)] = value;
        }
        let (Some(modes), Some(matrix)) = (modes, matrix) else {
            return Err(FileError::file(
                source,
                "no '# modes:' line or no 'i,j,value' header".to_string(),
            ));
        };
        if let Some(k) = seen.iter().position(|s| !s) {
            let n = modes.len();
            return Err(FileError::file(
                source,
                format!("entry {},{} is missing", k / n + 1, k % n + 1),
            ));
        }
        Ok(Table {
            modes,
            stiffness_per_rho_g: matrix,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_round_trips_and_bad_tables_name_the_line() {
        let table = Table {
            modes: vec!["heave".into(), "pitch".into()],
            stiffness_per_rho_g: DMatrix::from_row_slice(2, 2, &[1000.0, -5.0, -5.0, 8.0e5]),
        };
        let text = table.to_csv("barge", "whole body");
        assert_eq!(Table::from_csv_str(&text, "c.csv").unwrap(), table);
        let missing: String = text.lines().take(7).map(|l| format!("{l}\n")).collect();
        let e = Table::from_csv_str(&missing, "c.csv").unwrap_err();
        assert_eq!((e.line, e.message.as_str()), (None, "entry 2,2 is missing"));
        let twice = format!("{text}1,1,3\n");
        assert!(Table::from_csv_str(&twice, "c.csv")
            .unwrap_err()
            .to_string()
            .starts_with("c.csv:9: entry 1,1 is given twice"));
        let nan = text.replace("1,1,1e3", "1,1,NaN");
        assert!(Table::from_csv_str(&nan, "c.csv")
            .unwrap_err()
            .message
            .contains("field value"));
        let huge = format!("# modes: {}\n", "a ".repeat(300));
        assert!(Table::from_csv_str(&huge, "c.csv")
            .unwrap_err()
            .message
            .contains("300 modes"));
    }
}
