//! Where a report generator writes, and the drift check of its quick mode.
//!
//! Command line of every generator: `[--quick] [--out DIR] [--update-docs]`.
//!
//! - default: the page and its figures go to `target/reports/` (`PAGE.md`, `figures/*.svg`);
//!   tracked files are left alone;
//! - `--out DIR`: the same into `DIR`;
//! - `--update-docs`: into `docs/` (the tracked page and figures), full runs only;
//! - `--quick`: a subset that runs in seconds to a minute; each number of its tables is
//!   compared with the same number in the tracked page (`docs/PAGE.md`), and a number that
//!   drifted beyond the stated tolerance fails the run (exit code 1).
//!
//! Tables are matched by their section heading (`## ...`) and header; a row by its key
//! columns (a quick table may hold fewer rows than the tracked one).

use std::path::{Path, PathBuf};

/// Where a report goes and how much of it is computed.
pub struct Output {
    /// Folder of the page; figures in its `figures/`.
    pub dir: PathBuf,
    /// The quick subset, checked against the tracked page.
    pub quick: bool,
}

impl Output {
    /// From the process arguments (module docs); exits with code 2 on a malformed line.
    pub fn from_args() -> Output {
        let mut args = std::env::args().skip(1);
        let (mut dir, mut quick, mut updates_docs) = (None, false, false);
        while let Some(arg) = args.next() {
            match arg.as_str() {
                "--quick" => quick = true,
                "--update-docs" => updates_docs = true,
                "--out" => dir = args.next().map(PathBuf::from),
                // Options a generator reads itself.
                other if other.starts_with("--") => {}
                other => usage(&format!("unexpected argument {other:?}")),
            }
        }
        if updates_docs && (quick || dir.is_some()) {
            usage("--update-docs writes the full report into docs/: no --quick, no --out");
        }
        let dir = match (updates_docs, dir) {
            (true, _) => PathBuf::from("docs"),
            (false, Some(dir)) => dir,
            (false, None) => PathBuf::from("target/reports"),
        };
        std::fs::create_dir_all(dir.join("figures"))
            .unwrap_or_else(|e| fail(&format!("cannot create {}: {e}", dir.display())));
        Output { dir, quick }
    }

    /// Writes the figure `name` (`figures/NAME.svg`).
    pub fn write_figure(&self, name: &str, svg: &str) {
        let path = self.dir.join("figures").join(format!("{name}.svg"));
        std::fs::write(&path, svg)
            .unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", path.display())));
    }

    /// Writes the page `PAGE.md` and returns its path.
    pub fn write_page(&self, page: &str, text: &str) -> PathBuf {
        let path = self.dir.join(format!("{page}.md"));
        std::fs::write(&path, text)
            .unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", path.display())));
        path
    }
}

fn usage(why: &str) -> ! {
    eprintln!("error: {why}\nusage: [--quick] [--out DIR] [--update-docs]");
    std::process::exit(2);
}

/// Prints `why` and exits with code 1.
pub fn fail(why: &str) -> ! {
    eprintln!("error: {why}");
    std::process::exit(1);
}

/// How close a regenerated number must stay to the tracked one:
/// `|new - old| <= relative |old| + absolute + units * (one unit of old's last printed digit)`.
#[derive(Clone, Copy)]
pub struct Tolerance {
    pub relative: f64,
    pub absolute: f64,
    pub units: f64,
}

/// A table of a page: its section heading, its header cells and its rows.
struct Table {
    section: String,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

fn cells(line: &str) -> Vec<String> {
    line.trim()
        .trim_matches('|')
        .split('|')
        .map(|c| c.trim().to_string())
        .collect()
}

fn tables(text: &str) -> Vec<Table> {
    let mut section = String::new();
    let mut out: Vec<Table> = Vec::new();
    let mut lines = text.lines().peekable();
    while let Some(line) = lines.next() {
        if line.starts_with('#') {
            section = line.trim_start_matches('#').trim().to_string();
        } else if line.starts_with('|') && lines.peek().is_some_and(|l| l.starts_with("| ---")) {
            lines.next();
            let mut rows = Vec::new();
            while lines.peek().is_some_and(|l| l.starts_with('|')) {
                rows.push(cells(lines.next().unwrap_or_default()));
            }
            out.push(Table {
                section: section.clone(),
                header: cells(line),
                rows,
            });
        }
    }
    out
}

/// A printed number and one unit of its last digit (`1.4e-5` -> 1e-6, `0.49665` -> 1e-5).
fn printed_number(cell: &str) -> Option<(f64, f64)> {
    let cell = cell.trim_end_matches('%').trim();
    let value: f64 = cell.parse().ok()?;
    let (mantissa, exponent) = match cell.find(['e', 'E']) {
        Some(i) => (&cell[..i], cell[i + 1..].parse::<i32>().ok()?),
        None => (cell, 0),
    };
    let decimals = mantissa.find('.').map_or(0, |i| mantissa.len() - i - 1) as i32;
    Some((value, 10f64.powi(exponent - decimals)))
}

/// Compares every number of the columns `compared` (by header) in the tables of `generated`
/// with the row of the same key (the cells of the columns `keys`) in the same section of
/// `tracked`. Returns the count of numbers compared, or every drift found.
pub fn check_drift(
    generated: &str,
    tracked: &str,
    keys: &[&str],
    compared: &dyn Fn(&str) -> bool,
    tolerance: Tolerance,
) -> Result<usize, Vec<String>> {
    let tracked = tables(tracked);
    let (mut count, mut drifts) = (0, Vec::new());
    for table in tables(generated) {
        let is_key: Vec<bool> = table
            .header
            .iter()
            .map(|h| keys.contains(&h.as_str()))
            .collect();
        let columns: Vec<bool> = table
            .header
            .iter()
            .zip(&is_key)
            .map(|(h, k)| !k && compared(h))
            .collect();
        let key = |row: &[String]| -> Vec<String> {
            row.iter()
                .zip(&is_key)
                .filter(|(_, k)| **k)
                .map(|(cell, _)| cell.clone())
                .collect()
        };
        let Some(old) = tracked
            .iter()
            .find(|t| t.section == table.section && t.header == table.header)
        else {
            drifts.push(format!("table in \"{}\" not in the docs", table.section));
            continue;
        };
        for row in &table.rows {
            let Some(old_row) = old.rows.iter().find(|r| key(r) == key(row)) else {
                drifts.push(format!(
                    "\"{}\": row {:?} not in the docs",
                    table.section,
                    key(row)
                ));
                continue;
            };
            for (j, cell) in row.iter().enumerate() {
                if !columns[j] {
                    continue;
                }
                let (Some((new, _)), Some((before, unit))) = (
                    printed_number(cell),
                    old_row.get(j).and_then(|c| printed_number(c)),
                ) else {
                    continue;
                };
                count += 1;
                let allowed =
                    tolerance.relative * before.abs() + tolerance.absolute + tolerance.units * unit;
                if (new - before).abs() > allowed {
                    drifts.push(format!(
                        "\"{}\" {:?}, {}: {cell} now, {} in the docs (allowed {allowed:.1e})",
                        table.section,
                        key(row),
                        table.header[j],
                        old_row[j]
                    ));
                }
            }
        }
    }
    if drifts.is_empty() {
        Ok(count)
    } else {
        Err(drifts)
    }
}

/// The quick mode's ending: checks `generated` against `docs/PAGE.md`, prints the count of
/// numbers compared and the tolerance, and exits with code 1 on drift.
pub fn check_against_docs(
    page: &str,
    generated: &str,
    keys: &[&str],
    compared: &dyn Fn(&str) -> bool,
    tolerance: Tolerance,
) {
    let path = Path::new("docs").join(format!("{page}.md"));
    let tracked = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", path.display())));
    match check_drift(generated, &tracked, keys, compared, tolerance) {
        Ok(0) => fail(&format!("no number of {} was compared", path.display())),
        Ok(count) => eprintln!(
            "{count} numbers agree with {} (tolerance: {} relative + {:.1e} + {} units of the \
             last printed digit)",
            path.display(),
            tolerance.relative,
            tolerance.absolute,
            tolerance.units
        ),
        Err(drifts) => {
            for d in &drifts {
                eprintln!("drift: {d}");
            }
            fail(&format!(
                "{} numbers drifted from {}: rerun with --update-docs if the change is intended",
                drifts.len(),
                path.display()
            ));
        }
    }
}
