//! PDStrip offset files: the section geometry of Söding's strip-theory program PDStrip, read
//! into the ship's stations.
//!
//! ```text
//! nse sym tg                     number of sections, symmetry (T/F), reference draft
//! x nof ngap [gap ...]           per section: position, number of offset points, gaps
//! y_1 .. y_nof z_1 .. z_nof      the offsets: all y, then all z (free format, any lines)
//! ```
//!
//! The offsets' axes are x forward, y to port, z up from any base line (PDStrip's input
//! system; it turns them into its own x forward, y starboard, z down). The still waterline is
//! at `z = waterline` in those axes (PDStrip's main input gives it; a common choice is the
//! reference draft `tg` with the base line at the keel, the default here). A symmetric section
//! (`sym` true) gives one half, from the centreline (`y_1 = 0`) to the waterline; the other
//! half is its mirror image. An unsymmetric one runs from waterline to waterline. A section
//! whose offsets enclose no area below the waterline (a pointed end) becomes a station without
//! a section. Gaps (sections of several hulls) are refused.

use crate::hull::Hull;

/// Most offset points of one section (PDStrip allows 100; the contour limit is larger).
const MAX_OFFSETS: usize = 1000;

/// One station read from the file.
#[derive(Debug)]
pub(super) struct OffsetStation {
    pub(crate) x: f64,
    /// The section, or `None` where it encloses no area below the waterline.
    pub(crate) hull: Option<Hull>,
}

/// Free-format tokens with their lines.
struct Tokens<'a> {
    items: Vec<(&'a str, usize)>,
    next: usize,
    source: &'a str,
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str, source: &'a str) -> Self {
        let items = text
            .lines()
            .enumerate()
            .flat_map(|(k, line)| {
                line.split(|c: char| c.is_whitespace() || c == ',')
                    .filter(|t| !t.is_empty())
                    .map(move |t| (t, k + 1))
            })
            .collect();
        Tokens {
            items,
            next: 0,
            source,
        }
    }

    fn line(&self) -> usize {
        self.items
            .get(self.next)
            .or(self.items.last())
            .map_or(1, |t| t.1)
    }

    fn take(&mut self, what: &str) -> Result<(&'a str, usize), String> {
        let token = self.items.get(self.next).copied().ok_or_else(|| {
            format!(
                "{}:{}: the file ends where {what} should be",
                self.source,
                self.line()
            )
        })?;
        self.next += 1;
        Ok(token)
    }

    fn number(&mut self, what: &str) -> Result<f64, String> {
        let (token, line) = self.take(what)?;
        // Fortran writes exponents as D as well as E.
        let text = token.replace(['d', 'D'], "e");
        match crate::xml::parse_number(&text) {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!(
                "{}:{line}: {what} = '{token}' is not a finite number",
                self.source
            )),
        }
    }

    fn count(&mut self, what: &str, max: usize) -> Result<usize, String> {
        let (token, line) = self.take(what)?;
        match token.parse::<usize>() {
            Ok(v) if v <= max => Ok(v),
            _ => Err(format!(
                "{}:{line}: {what} = '{token}' must be a whole number from 0 to {max}",
                self.source
            )),
        }
    }

    fn logical(&mut self, what: &str) -> Result<bool, String> {
        let (token, line) = self.take(what)?;
        match token.trim_matches('.').to_ascii_lowercase().as_str() {
            "t" | "true" => Ok(true),
            "f" | "false" => Ok(false),
            _ => Err(format!(
                "{}:{line}: {what} = '{token}' must be T or F",
                self.source
            )),
        }
    }
}

/// Reads the stations of a PDStrip offset file; `waterline` is the still waterline's z in the
/// file's axes (`None`: the reference draft `tg`).
pub(super) fn read(
    text: &str,
    source: &str,
    waterline: Option<f64>,
) -> Result<Vec<OffsetStation>, String> {
    let mut tokens = Tokens::new(text, source);
    let sections = tokens.count("the number of sections", super::MAX_STATIONS)?;
    let symmetric = tokens.logical("the symmetry flag")?;
    let draft = tokens.number("the reference draft")?;
    let waterline = waterline.unwrap_or(draft);
    let mut out = Vec::with_capacity(sections);
    for k in 0..sections {
        let line = tokens.line();
        let x = tokens.number(&format!("section {}'s x", k + 1))?;
        let count = tokens.count(
            &format!("section {}'s number of offsets", k + 1),
            MAX_OFFSETS,
        )?;
        let gaps = tokens.count(&format!("section {}'s number of gaps", k + 1), MAX_OFFSETS)?;
        if gaps > 0 {
            return Err(format!(
                "{source}:{line}: section {} at x = {x} m has {gaps} gaps (several hulls in one \
                 section); not supported",
                k + 1
            ));
        }
        let mut y = Vec::with_capacity(count);
        for i in 0..count {
            y.push(tokens.number(&format!("section {}'s y{}", k + 1, i + 1))?);
        }
        let mut z = Vec::with_capacity(count);
        for i in 0..count {
            z.push(tokens.number(&format!("section {}'s z{}", k + 1, i + 1))? - waterline);
        }
        let hull = section(&y, &z, symmetric, x)
            .map_err(|m| format!("{source}:{line}: section {} at x = {x} m: {m}", k + 1))?;
        out.push(OffsetStation { x, hull });
    }
    if tokens.next < tokens.items.len() {
        let (token, line) = tokens.items[tokens.next];
        return Err(format!(
            "{source}:{line}: '{token}' after the last of the {sections} sections"
        ));
    }
    Ok(out)
}

/// The section's hull in our 2D frame (x = ship y, y = ship z), or `None` if it encloses no
/// area below the waterline.
fn section(y: &[f64], z: &[f64], symmetric: bool, x: f64) -> Result<Option<Hull>, String> {
    let tolerance = 1e-6 * y.iter().chain(z).fold(1.0f64, |a, v| a.max(v.abs()));
    let mut points: Vec<[f64; 2]> = Vec::with_capacity(2 * y.len());
    if symmetric {
        if y.first().is_some_and(|v| v.abs() > tolerance) {
            return Err(format!(
                "a symmetric section starts on the centreline (y1 = 0), got y1 = {}",
                y[0]
            ));
        }
        // The mirror half (reversed, without the centreline point), then the given half.
        for i in (1..y.len()).rev() {
            points.push([-y[i], z[i]]);
        }
        points.extend(y.iter().zip(z).map(|(a, b)| [*a, *b]));
    } else {
        points.extend(y.iter().zip(z).map(|(a, b)| [*a, *b]));
    }
    // No area below the waterline: a pointed end.
    if points.len() < 3 || points.iter().all(|p| p[1] > -tolerance) {
        return Ok(None);
    }
    let (first, last) = (points[0], points[points.len() - 1]);
    for (what, p) in [("first", first), ("last", last)] {
        if p[1].abs() > tolerance {
            return Err(format!(
                "the {what} offset point is at z = {} m from the waterline; a section runs from \
                 waterline to waterline (check the waterline)",
                p[1]
            ));
        }
    }
    // Points on the waterline at the ends only; repeated points dropped.
    let mut contour: Vec<[f64; 2]> = Vec::with_capacity(points.len());
    for p in points {
        if contour
            .last()
            .is_some_and(|q: &[f64; 2]| (q[0] - p[0]).hypot(q[1] - p[1]) <= tolerance)
        {
            continue;
        }
        contour.push(p);
    }
    let n = contour.len();
    contour[0][1] = 0.0;
    contour[n - 1][1] = 0.0;
    let half_beam = (contour[n - 1][0] - contour[0][0]).abs() / 2.0;
    // One name for every section: identical offsets give identical hulls, solved once.
    let mut xml = format!(
        "<hull name=\"offsets\" half_beam=\"{}\"><contour>",
        if half_beam > 0.0 { half_beam } else { 1.0 }
    );
    for p in &contour {
        xml.push_str(&format!("<point x=\"{:e}\" y=\"{:e}\"/>", p[0], p[1]));
    }
    xml.push_str(
        "</contour><rigid name=\"sway\" kind=\"sway\"/><rigid name=\"heave\" kind=\"heave\"/>\
         <rigid name=\"roll\" kind=\"roll\"/></hull>",
    );
    Hull::from_xml_str(&xml, &format!("the section at x = {x} m"))
        .map(Some)
        .map_err(|e| e.message().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box 10 m wide and 5 m deep, symmetric half: centreline keel, bilge, side.
    const BOX: &str = "3 T 5.0\n-10.0 3 0\n0.0 5.0 5.0 0.0 0.0 5.0\n0.0, 3 0\n\
                       0 5 5\n0 0 5\n10.0D0 3 0\n0.0 5.0 5.0 0.0 0.0 5.0\n";

    #[test]
    fn a_symmetric_box_becomes_the_full_box_on_each_station() {
        let stations = read(BOX, "box.out", None).unwrap();
        assert_eq!(stations.len(), 3);
        assert_eq!(stations[2].x, 10.0);
        let hull = stations[1].hull.as_ref().unwrap();
        let h = crate::hydrostatics::stiffness(hull).unwrap();
        assert!((h.waterline_breadth - 10.0).abs() < 1e-12);
        assert!((h.submerged_area - 50.0).abs() < 1e-9);
        assert!((h.centre_of_buoyancy[1] + 2.5).abs() < 1e-9);
        assert_eq!(hull.reference_half_beam(), 5.0);
    }

    #[test]
    fn a_waterline_above_the_offsets_is_named() {
        let e = read(BOX, "box.out", Some(6.0)).unwrap_err();
        assert!(e.starts_with("box.out:2: section 1 at x = -10 m:"), "{e}");
        assert!(e.contains("waterline"), "{e}");
    }

    #[test]
    fn bad_files_name_the_line_and_the_field() {
        let cases = [
            (
                "2 T 5\n0 3 0\n0 5 5 0 0 5\n",
                "the file ends where section 2's x",
            ),
            ("1 X 5\n", "box.out:1: the symmetry flag = 'X'"),
            ("1 T 5\n0 3 1 2\n0 5 5 0 0 5\n", "gaps"),
            (
                "1 T 5\n0 3 0\n0 5 5 0 NaN 5\n",
                "box.out:3: section 1's z2 = 'NaN'",
            ),
            ("1 T 5\n0 3 0\n1 5 5 0 0 5\n", "starts on the centreline"),
            (
                "1 T 5\n0 3 0\n0 5 5 0 0 5\n7\n",
                "box.out:4: '7' after the last",
            ),
            ("5000 T 5\n", "from 0 to 1000"),
        ];
        for (text, words) in cases {
            let e = read(text, "box.out", None).err().unwrap();
            assert!(e.contains(words), "'{words}' not in: {e}");
        }
    }

    #[test]
    fn a_pointed_end_is_a_station_without_a_section() {
        let text = "2 T 5\n0 2 0\n0 0 5 5\n1 3 0\n0 5 5 0 0 5\n";
        let stations = read(text, "end.out", None).unwrap();
        assert!(stations[0].hull.is_none());
        assert!(stations[1].hull.is_some());
    }
}
