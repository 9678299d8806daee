//! The data rows of one WAMIT file: each row's fields with its line number, and the field
//! readers that name file, line and field in their errors.

use super::{
    parse_number, DatabaseError, Frequency, FrequencyColumn, Source, MAX_FILE_BYTES,
    MAX_HEADER_LINES, MAX_MODE_INDEX, MAX_ROWS,
};

/// The data rows of one file: fields of each row with its line number.
pub(super) struct Rows<'a> {
    pub(super) source: Source<'a>,
    pub(super) rows: Vec<(usize, Vec<&'a str>)>,
    pub(super) header: Vec<&'a str>,
}

impl<'a> Rows<'a> {
    pub(super) fn read(source: Source<'a>) -> Result<Rows<'a>, DatabaseError> {
        if source.text.len() as u64 > MAX_FILE_BYTES {
            return Err(DatabaseError::file(
                source.name,
                format!("larger than {MAX_FILE_BYTES} bytes"),
            ));
        }
        let mut rows = Vec::new();
        let mut header = Vec::new();
        let mut header_lines = 0;
        for (index, line) in source.text.lines().enumerate() {
            let fields: Vec<&str> = line.split_whitespace().collect();
            let Some(first) = fields.first() else {
                continue;
            };
            if rows.is_empty() && parse_number(first).is_none() {
                header_lines += 1;
                header.push(line);
                if header_lines > MAX_HEADER_LINES {
                    return Err(DatabaseError::at(
                        source.name,
                        index + 1,
                        format!("more than {MAX_HEADER_LINES} lines before the first number row"),
                    ));
                }
                continue;
            }
            if rows.len() == MAX_ROWS {
                return Err(DatabaseError::at(
                    source.name,
                    index + 1,
                    format!("more than {MAX_ROWS} rows"),
                ));
            }
            rows.push((index + 1, fields));
        }
        if rows.is_empty() {
            return Err(DatabaseError::file(source.name, "no data rows".to_string()));
        }
        Ok(Rows {
            source,
            rows,
            header,
        })
    }

    pub(super) fn error(&self, line: usize, message: String) -> DatabaseError {
        DatabaseError::at(self.source.name, line, message)
    }

    pub(super) fn number(
        &self,
        line: usize,
        fields: &[&str],
        column: usize,
        what: &str,
    ) -> Result<f64, DatabaseError> {
        let token = fields[column];
        match parse_number(token) {
            Some(x) if x.is_finite() => Ok(x),
            _ => Err(self.error(
                line,
                format!(
                    "field {what} (column {}): '{token}' is not a finite number",
                    column + 1
                ),
            )),
        }
    }

    pub(super) fn mode(
        &self,
        line: usize,
        fields: &[&str],
        column: usize,
        what: &str,
    ) -> Result<usize, DatabaseError> {
        let token = fields[column];
        match token.parse::<usize>() {
            Ok(i) if (1..=MAX_MODE_INDEX).contains(&i) => Ok(i),
            _ => Err(self.error(
                line,
                format!(
                    "field {what} (column {}): '{token}' is not a mode index 1..{MAX_MODE_INDEX}",
                    column + 1
                ),
            )),
        }
    }

    pub(super) fn columns(
        &self,
        line: usize,
        fields: &[&str],
        allowed: &[usize],
        layout: &str,
    ) -> Result<(), DatabaseError> {
        if allowed.contains(&fields.len()) {
            Ok(())
        } else {
            Err(self.error(
                line,
                format!(
                    "{} fields where the row needs {layout} (a truncated or mixed file?)",
                    fields.len()
                ),
            ))
        }
    }

    pub(super) fn frequency(
        &self,
        line: usize,
        value: f64,
        column: FrequencyColumn,
    ) -> Result<Frequency, DatabaseError> {
        let out = match column {
            FrequencyColumn::Period => {
                if value == -1.0 {
                    Some(Frequency::Zero)
                } else if value == 0.0 {
                    Some(Frequency::Infinite)
                } else if value > 0.0 {
                    Some(Frequency::Finite(2.0 * std::f64::consts::PI / value))
                } else {
                    None
                }
            }
            FrequencyColumn::RadPerSecond | FrequencyColumn::Hertz => {
                let scale = if column == FrequencyColumn::Hertz {
                    2.0 * std::f64::consts::PI
                } else {
                    1.0
                };
                if value == 0.0 {
                    Some(Frequency::Zero)
                } else if value == -1.0 {
                    Some(Frequency::Infinite)
                } else if value > 0.0 {
                    Some(Frequency::Finite(value * scale))
                } else {
                    None
                }
            }
        };
        match out {
            Some(Frequency::Finite(w)) if !(w.is_finite() && w > 0.0) => None,
            other => other,
        }
        .ok_or_else(|| {
            self.error(
                line,
                format!(
                    "field PER (column 1): {value} is no frequency in a {} column (the limits are \
                     written as -1 and 0)",
                    match column {
                        FrequencyColumn::Period => "period",
                        FrequencyColumn::RadPerSecond => "rad/s",
                        FrequencyColumn::Hertz => "Hz",
                    }
                ),
            )
        })
    }
}
