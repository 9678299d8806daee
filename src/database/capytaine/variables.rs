//! The variables of an open NetCDF-3 file: numbers, coordinates, scalars and character
//! coordinates, each found by name with its dimensions' names, errors naming the file.

use super::super::DatabaseError;
use netcdf3::{DataType, FileReader};

/// Longest DOF name, in bytes.
const MAX_DOF_NAME_BYTES: usize = 64;

/// The open file and its name (for messages).
pub(super) struct Nc<'a> {
    pub(super) reader: FileReader,
    pub(super) file: &'a str,
}

/// A numeric variable: its dimensions (name, size) and values, row-major.
pub(super) struct Array {
    pub(super) name: String,
    pub(super) dims: Vec<(String, usize)>,
    pub(super) data: Vec<f64>,
}

impl Array {
    /// The strides of `axes` (name, expected size): `None` for an axis the variable does not
    /// have (its size must then be 1). Every dimension of the variable must be one of `axes`
    /// or have size 1.
    pub(super) fn strides(&self, axes: &[(&str, usize)]) -> Result<Vec<Option<usize>>, String> {
        let mut strides = vec![None; axes.len()];
        let mut stride = 1;
        for (dim, size) in self.dims.iter().rev() {
            match axes.iter().position(|(a, _)| a == dim) {
                Some(k) => {
                    if *size != axes[k].1 {
                        return Err(format!(
                            "variable {}: dimension {dim} has size {size} where {} belongs",
                            self.name, axes[k].1
                        ));
                    }
                    if strides[k].is_some() {
                        return Err(format!(
                            "variable {}: dimension {dim} appears twice",
                            self.name
                        ));
                    }
                    strides[k] = Some(stride);
                }
                None if *size == 1 => {}
                None => {
                    let names: Vec<&str> = axes.iter().map(|(a, _)| *a).collect();
                    return Err(format!(
                        "variable {}: dimension {dim} (size {size}) is none of {}; only \
                         dimensions of size 1 may be added",
                        self.name,
                        names.join(", ")
                    ));
                }
            }
            stride *= size;
        }
        for ((axis, size), s) in axes.iter().zip(&strides) {
            if s.is_none() && *size != 1 {
                return Err(format!(
                    "variable {} has no dimension {axis} (of size {size})",
                    self.name
                ));
            }
        }
        Ok(strides)
    }

    /// The value at `index` (one per axis of [`Array::strides`]).
    pub(super) fn at(&self, strides: &[Option<usize>], index: &[usize]) -> f64 {
        let offset: usize = strides
            .iter()
            .zip(index)
            .map(|(s, i)| s.map_or(0, |s| s * i))
            .sum();
        self.data[offset]
    }
}

impl Nc<'_> {
    pub(super) fn error(&self, message: String) -> DatabaseError {
        DatabaseError::file(self.file, message)
    }

    pub(super) fn has(&self, var: &str) -> bool {
        self.reader.data_set().has_var(var)
    }

    pub(super) fn missing(&self, var: &str, what: &str) -> DatabaseError {
        self.error(format!(
            "no variable {var} ({what}): not a dataset of cpt.assemble_dataset?"
        ))
    }

    pub(super) fn dims(&self, var: &str) -> Vec<(String, usize)> {
        self.reader
            .data_set()
            .get_var(var)
            .map(|v| {
                v.get_dims()
                    .iter()
                    .map(|d| (d.name().to_string(), d.size()))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// The size of dimension `dim`, or an error naming it.
    pub(super) fn dim(&self, dim: &str) -> Result<usize, DatabaseError> {
        self.reader
            .data_set()
            .dim_size(dim)
            .ok_or_else(|| self.error(format!("no dimension {dim}")))
    }

    pub(super) fn floats(&mut self, var: &str, what: &str) -> Result<Array, DatabaseError> {
        if !self.has(var) {
            return Err(self.missing(var, what));
        }
        let dims = self.dims(var);
        let read = |e: netcdf3::ReadError| DatabaseError::file(self.file, format!("{var}: {e}"));
        let data = match self.reader.data_set().var_data_type(var) {
            Some(DataType::F64) => self.reader.read_var_f64(var).map_err(read)?,
            Some(DataType::F32) => self
                .reader
                .read_var_f32(var)
                .map_err(read)?
                .into_iter()
                .map(f64::from)
                .collect(),
            Some(DataType::I32) => self
                .reader
                .read_var_i32(var)
                .map_err(read)?
                .into_iter()
                .map(f64::from)
                .collect(),
            other => {
                return Err(self.error(format!(
                    "variable {var} ({what}) holds {other:?} values where numbers belong"
                )))
            }
        };
        Ok(Array {
            name: var.to_string(),
            dims,
            data,
        })
    }

    /// A 1-D coordinate `var` along its own dimension (the caller checks the values).
    pub(super) fn coordinate(&mut self, var: &str, what: &str) -> Result<Vec<f64>, DatabaseError> {
        let array = self.floats(var, what)?;
        let n = self.dim(var)?;
        let strides = array
            .strides(&[(var, n)])
            .map_err(|m| self.error(format!("{m} (the coordinate of {what})")))?;
        Ok((0..n).map(|k| array.at(&strides, &[k])).collect())
    }

    /// A scalar (0-D or of size 1).
    pub(super) fn scalar(&mut self, var: &str, what: &str) -> Result<f64, DatabaseError> {
        let array = self.floats(var, what)?;
        array
            .strides(&[])
            .map_err(|m| self.error(format!("{m} ({what}: one value expected)")))?;
        Ok(array.data[0])
    }

    /// The strings of a character coordinate `var` (dimensions `var` and a string length).
    pub(super) fn strings(&mut self, var: &str, what: &str) -> Result<Vec<String>, DatabaseError> {
        if !self.has(var) {
            return Err(self.missing(var, what));
        }
        let dims = self.dims(var);
        let n = self.dim(var)?;
        let width = match dims.as_slice() {
            [(d, _), (_, w)] if d == var => *w,
            _ => {
                let list: Vec<&str> = dims.iter().map(|(d, _)| d.as_str()).collect();
                return Err(self.error(format!(
                    "variable {var} ({what}) has dimensions ({}) where ({var}, a string length) \
                     belong",
                    list.join(", ")
                )));
            }
        };
        let bytes = match self.reader.data_set().var_data_type(var) {
            Some(DataType::U8) => self.reader.read_var_u8(var),
            Some(DataType::I8) => self
                .reader
                .read_var_i8(var)
                .map(|v| v.into_iter().map(|b| b as u8).collect()),
            other => {
                return Err(self.error(format!(
                    "variable {var} ({what}) holds {other:?} values where characters belong"
                )))
            }
        }
        .map_err(|e| self.error(format!("{var}: {e}")))?;
        (0..n)
            .map(|k| {
                let raw = &bytes[k * width..(k + 1) * width];
                let end = raw.iter().position(|&b| b == 0).unwrap_or(width);
                let text = std::str::from_utf8(&raw[..end])
                    .map_err(|_| self.error(format!("{var}[{k}] ({what}) is not UTF-8 text")))?;
                if text.is_empty() || text.len() > MAX_DOF_NAME_BYTES {
                    return Err(self.error(format!(
                        "{var}[{k}] ({what}): a name of {} bytes (1..{MAX_DOF_NAME_BYTES} \
                         expected)",
                        text.len()
                    )));
                }
                Ok(text.to_string())
            })
            .collect()
    }
}
