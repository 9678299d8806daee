//! The NetCDF-3 header walked with every count, name and offset bounded by the file's size,
//! before the `netcdf3` crate (which allocates by those counts) parses it.

use super::{HOW_TO_WRITE, MAX_HEADER_BYTES};

/// Longest name (dimension, attribute, variable) in the header (NetCDF's own limit).
const MAX_NAME_BYTES: usize = 256;
/// Most dimensions of one variable.
const MAX_VARIABLE_DIMS: usize = 32;

/// A cursor over the header, bounded by the file and [`MAX_HEADER_BYTES`].
struct Walk<'a> {
    bytes: &'a [u8],
    limit: usize,
    pos: usize,
}

impl Walk<'_> {
    fn take(&mut self, n: usize, what: &str) -> Result<&[u8], String> {
        match self.pos.checked_add(n) {
            Some(end) if end <= self.limit => {
                let out = &self.bytes[self.pos..end];
                self.pos = end;
                Ok(out)
            }
            _ if self.limit < self.bytes.len() => Err(format!(
                "the NetCDF header is longer than {MAX_HEADER_BYTES} bytes (at {what})"
            )),
            _ => Err(format!(
                "the NetCDF header ends at byte {} in the middle of {what}: a truncated file",
                self.bytes.len()
            )),
        }
    }

    fn u32(&mut self, what: &str) -> Result<u32, String> {
        let b = self.take(4, what)?;
        Ok(u32::from_be_bytes([b[0], b[1], b[2], b[3]]))
    }

    /// A non-negative 32-bit count or size (NetCDF's NON_NEG).
    fn non_negative(&mut self, what: &str) -> Result<usize, String> {
        let value = self.u32(what)?;
        if value > i32::MAX as u32 {
            return Err(format!("{what}: {value} is no non-negative 32-bit number"));
        }
        Ok(value as usize)
    }

    /// A count of entries of at least `entry_bytes` each, bounded by what is left.
    fn count(&mut self, what: &str, entry_bytes: usize) -> Result<usize, String> {
        let n = self.non_negative(what)?;
        if n > (self.limit - self.pos) / entry_bytes {
            return Err(format!(
                "{what}: {n} entries cannot fit in the {} header bytes left",
                self.limit - self.pos
            ));
        }
        Ok(n)
    }

    fn padded(&mut self, n: usize, what: &str) -> Result<&[u8], String> {
        let start = self.pos;
        self.take(n.div_ceil(4).saturating_mul(4), what)?;
        Ok(&self.bytes[start..start + n])
    }

    fn name(&mut self, what: &str) -> Result<String, String> {
        let n = self.non_negative(what)?;
        if n == 0 || n > MAX_NAME_BYTES {
            return Err(format!(
                "{what}: a name of {n} bytes (1..{MAX_NAME_BYTES} expected)"
            ));
        }
        let bytes = self.padded(n, what)?;
        Ok(String::from_utf8_lossy(bytes).into_owned())
    }

    /// NetCDF's nc_type: its size in bytes.
    fn data_type(&mut self, what: &str) -> Result<usize, String> {
        match self.u32(what)? {
            1 | 2 => Ok(1),
            3 => Ok(2),
            4 | 5 => Ok(4),
            6 => Ok(8),
            other => Err(format!("{what}: {other} is no NetCDF-3 data type")),
        }
    }

    /// A list's tag (`expected`, or ABSENT with a zero count) and its count.
    fn list(&mut self, tag: u32, what: &str, entry_bytes: usize) -> Result<usize, String> {
        let found = self.u32(what)?;
        if found == 0 {
            let n = self.u32(what)?;
            return if n == 0 {
                Ok(0)
            } else {
                Err(format!("{what}: absent, yet {n} entries"))
            };
        }
        if found != tag {
            return Err(format!(
                "{what}: tag {found:#x} where {tag:#x} or 0 belongs"
            ));
        }
        self.count(what, entry_bytes)
    }

    fn attributes(&mut self, owner: &str) -> Result<(), String> {
        let what = format!("the attributes of {owner}");
        let n = self.list(0x0C, &what, 12)?;
        for _ in 0..n {
            let name = self.name(&what)?;
            let what = format!("attribute {name} of {owner}");
            let size = self.data_type(&what)?;
            let count = self.non_negative(&what)?;
            let bytes = count
                .checked_mul(size)
                .ok_or_else(|| format!("{what}: {count} values overflow"))?;
            self.padded(bytes, &what)?;
        }
        Ok(())
    }
}

/// Refuses what is no NetCDF-3 file, and any header whose counts, names or data offsets do
/// not fit in the file (before the `netcdf3` crate, which allocates by those counts, sees it).
pub(super) fn check_header(bytes: &[u8]) -> Result<(), String> {
    if bytes.starts_with(b"\x89HDF") {
        return Err(format!(
            "a NetCDF-4 (HDF5) file: only NetCDF-3 is read (pure Rust, no HDF5 library); \
             {HOW_TO_WRITE} (or convert it: `nccopy -k nc6 in.nc out.nc`)"
        ));
    }
    if bytes.starts_with(b"CDF\x05") {
        return Err(format!(
            "a CDF-5 (64-bit data) NetCDF file: only the classic and 64-bit offset formats are \
             read; {HOW_TO_WRITE}"
        ));
    }
    let version = match bytes.get(..4) {
        Some(b"CDF\x01") => 1,
        Some(b"CDF\x02") => 2,
        _ => {
            return Err(format!(
                "not a NetCDF file (it does not start with 'CDF'); {HOW_TO_WRITE}"
            ))
        }
    };
    let mut walk = Walk {
        bytes,
        limit: bytes.len().min(MAX_HEADER_BYTES),
        pos: 4,
    };
    walk.u32("the number of records")?;
    let n_dims = walk.list(0x0A, "the dimensions", 8)?;
    let mut dims = Vec::with_capacity(n_dims);
    for _ in 0..n_dims {
        let name = walk.name("a dimension's name")?;
        let size = walk.non_negative(&format!("the size of dimension {name}"))?;
        if size == 0 {
            return Err(format!(
                "dimension {name} is a record (unlimited) dimension: not read (Capytaine's \
                 datasets have none)"
            ));
        }
        dims.push((name, size));
    }
    walk.attributes("the file")?;
    let n_vars = walk.list(0x0B, "the variables", 28)?;
    for _ in 0..n_vars {
        let name = walk.name("a variable's name")?;
        let what = format!("variable {name}");
        let rank = walk.count(&format!("the dimensions of {what}"), 4)?;
        if rank > MAX_VARIABLE_DIMS {
            return Err(format!(
                "{what} has {rank} dimensions (at most {MAX_VARIABLE_DIMS} read)"
            ));
        }
        let mut len: usize = 1;
        for _ in 0..rank {
            let id = walk.non_negative(&what)?;
            let (dim, size) = dims.get(id).ok_or_else(|| {
                format!("{what}: dimension id {id} where the file has {n_dims} dimensions")
            })?;
            len = len.checked_mul(*size).ok_or_else(|| {
                format!("{what}: its size overflows (dimension {dim} of size {size})")
            })?;
        }
        walk.attributes(&what)?;
        let size = walk.data_type(&what)?;
        walk.u32(&format!("the size of {what}"))?;
        let begin = if version == 1 {
            i64::from(walk.u32(&what)? as i32)
        } else {
            let b = walk.take(8, &what)?;
            i64::from_be_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])
        };
        let end = len
            .checked_mul(size)
            .and_then(|n| usize::try_from(begin).ok()?.checked_add(n));
        if end.is_none_or(|end| end > bytes.len()) {
            return Err(format!(
                "{what}: {len} values of {size} bytes from byte {begin} do not fit in the \
                 file's {} bytes (a truncated file?)",
                bytes.len()
            ));
        }
    }
    Ok(())
}
