//! Reading the report generators' measured tables.

/// The columns `names` of a CSV text with a header line, one array per row (a cell that is
/// not a number reads NaN). Panics naming a missing column: the report's data is its own.
pub fn columns<const N: usize>(text: &str, names: [&str; N]) -> Vec<[f64; N]> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let index = names.map(|name| header.iter().position(|h| *h == name).expect(name));
    lines
        .map(|line| {
            let cells: Vec<f64> = line
                .split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect();
            index.map(|i| cells[i])
        })
        .collect()
}
