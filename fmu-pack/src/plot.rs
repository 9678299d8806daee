//! Small self-contained SVG line plots for the reports (validation, fit, performance).
//!
//! Not on any simulation path. A [`Figure`] holds axes with linear or logarithmic scales,
//! line and marker series, and a legend; [`Figure::to_svg`] renders it as a standalone SVG
//! document. Markers are drawn first and lines over them, so a fitted curve stays visible
//! over dense data. Tick labels are short: linear ticks at 1, 2 or 5 times a power of ten,
//! printed with the step's decimals, or as `2e6` / `5e-4` outside 1e-3 .. 1e4; log axes tick
//! every decade, with 2 and 5 between when the axis spans two decades or less, and every
//! other decade beyond eight. Axis labels carry their units (`omega (rad/s)`, `A~ (kg)`).

use hydrofmu::xml::escape;
use std::fmt::Write as _;

/// Scale of an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Linear.
    Linear,
    /// Base-10 logarithmic (values <= 0 are dropped).
    Log,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A solid polyline.
    Line,
    /// A dashed polyline.
    Dashed,
    /// Circles at the points.
    Markers,
}

/// One data series.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points `(x, y)`.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
    /// Colour index into the palette.
    pub colour: usize,
}

/// A plot with one pair of axes.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Title above the axes.
    pub title: String,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// Scale of the x axis.
    pub x_scale: Scale,
    /// Scale of the y axis.
    pub y_scale: Scale,
    /// The series: markers first, then lines and dashed lines, each kind in order.
    pub series: Vec<Series>,
    /// A footnote under the plot (command, machine, date).
    pub caption: String,
}

const PALETTE: [&str; 8] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];
const WIDTH: f64 = 720.0;
const HEIGHT: f64 = 400.0;
const LEFT: f64 = 70.0;
const RIGHT: f64 = 250.0;
const TOP: f64 = 36.0;
const BOTTOM: f64 = 64.0;

impl Figure {
    /// An empty figure.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: Vec::new(),
            caption: String::new(),
        }
    }

    /// Adds a series; the colour follows the series count unless set later.
    pub fn add(&mut self, label: &str, points: Vec<(f64, f64)>, style: Style) -> &mut Self {
        let colour = self.series.len();
        self.series.push(Series {
            label: label.into(),
            points,
            style,
            colour,
        });
        self
    }

    fn transformed(&self) -> Vec<Vec<(f64, f64)>> {
        let t = |v: f64, scale: Scale| match scale {
            Scale::Linear => Some(v),
            Scale::Log => (v > 0.0).then(|| v.log10()),
        };
        self.series
            .iter()
            .map(|s| {
                s.points
                    .iter()
                    .filter_map(|&(x, y)| Some((t(x, self.x_scale)?, t(y, self.y_scale)?)))
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
                    .collect()
            })
            .collect()
    }

    /// Renders the figure as an SVG document.
    pub fn to_svg(&self) -> String {
        let data = self.transformed();
        let all = data.iter().flatten();
        let (mut x0, mut x1, mut y0, mut y1) = all.fold(
            (
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ),
            |(a, b, c, d), &(x, y)| (a.min(x), b.max(x), c.min(y), d.max(y)),
        );
        if !x0.is_finite() {
            (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
        }
        if x1 - x0 < 1e-12 {
            x0 -= 0.5;
            x1 += 0.5;
        }
        if y1 - y0 < 1e-12 * (1.0 + y0.abs()) {
            y0 -= 0.5 * (1.0 + y0.abs());
            y1 += 0.5 * (1.0 + y1.abs());
        }
        let x_ticks = ticks(x0, x1, self.x_scale);
        let y_ticks = ticks(y0, y1, self.y_scale);
        if self.x_scale == Scale::Linear {
            x0 = x0.min(x_ticks[0]);
            x1 = x1.max(*x_ticks.last().unwrap_or(&x1));
        }
        let pad = 0.04 * (y1 - y0);
        let (y0, y1) = (y0 - pad, y1 + pad);
        let plot_w = WIDTH - LEFT - RIGHT;
        let plot_h = HEIGHT - TOP - BOTTOM;
        let sx = |x: f64| LEFT + (x - x0) / (x1 - x0) * plot_w;
        let sy = |y: f64| TOP + (1.0 - (y - y0) / (y1 - y0)) * plot_h;

        let mut svg = String::new();
        let _ = writeln!(
            svg,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" viewBox="0 0 {WIDTH} {HEIGHT}" font-family="sans-serif" font-size="11">"#
        );
        let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
        let _ = writeln!(
            svg,
            r#"<text x="{}" y="20" text-anchor="middle" font-size="13">{}</text>"#,
            LEFT + plot_w / 2.0,
            escape(&self.title)
        );
        for &t in &x_ticks {
            if t < x0 - 1e-9 || t > x1 + 1e-9 {
                continue;
            }
            let x = sx(t);
            let _ = writeln!(
                svg,
                r##"<line x1="{x:.1}" y1="{TOP}" x2="{x:.1}" y2="{:.1}" stroke="#e0e0e0"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
                TOP + plot_h,
                TOP + plot_h + 14.0,
                label(t, self.x_scale, &x_ticks)
            );
        }
        for &t in &y_ticks {
            if t < y0 || t > y1 {
                continue;
            }
            let y = sy(t);
            let _ = writeln!(
                svg,
                r##"<line x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#e0e0e0"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
                LEFT + plot_w,
                LEFT - 4.0,
                y + 4.0,
                label(t, self.y_scale, &y_ticks)
            );
        }
        let _ = writeln!(
            svg,
            r#"<rect x="{LEFT}" y="{TOP}" width="{plot_w}" height="{plot_h}" fill="none" stroke="black"/>"#
        );
        let _ = writeln!(
            svg,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            LEFT + plot_w / 2.0,
            TOP + plot_h + 32.0,
            escape(&self.x_label)
        );
        let _ = writeln!(
            svg,
            r#"<text transform="translate(16 {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
            TOP + plot_h / 2.0,
            escape(&self.y_label)
        );
        let markers_first =
            |(series, _): &(&Series, &Vec<(f64, f64)>)| series.style != Style::Markers;
        let mut drawn: Vec<(&Series, &Vec<(f64, f64)>)> = self.series.iter().zip(&data).collect();
        drawn.sort_by_key(markers_first);
        for (series, points) in drawn {
            let colour = PALETTE[series.colour % PALETTE.len()];
            match series.style {
                Style::Line | Style::Dashed => {
                    let path: Vec<String> = points
                        .iter()
                        .map(|&(x, y)| format!("{:.1},{:.1}", sx(x), sy(y)))
                        .collect();
                    let dash = if series.style == Style::Dashed {
                        r#" stroke-dasharray="6 4""#
                    } else {
                        ""
                    };
                    let _ = writeln!(
                        svg,
                        r#"<polyline fill="none" stroke="{colour}" stroke-width="1.6"{dash} points="{}"/>"#,
                        path.join(" ")
                    );
                }
                Style::Markers => {
                    for &(x, y) in points {
                        let _ = writeln!(
                            svg,
                            r#"<circle cx="{:.1}" cy="{:.1}" r="2.6" fill="none" stroke="{colour}"/>"#,
                            sx(x),
                            sy(y)
                        );
                    }
                }
            }
        }
        for (k, series) in self.series.iter().enumerate() {
            let colour = PALETTE[series.colour % PALETTE.len()];
            let y = TOP + 10.0 + 16.0 * k as f64;
            let x = LEFT + plot_w + 10.0;
            let mark = match series.style {
                Style::Markers => format!(
                    r#"<circle cx="{:.1}" cy="{:.1}" r="2.6" fill="none" stroke="{colour}"/>"#,
                    x + 10.0,
                    y - 4.0
                ),
                style => format!(
                    r#"<line x1="{x:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{colour}" stroke-width="1.6"{}/>"#,
                    y - 4.0,
                    x + 20.0,
                    y - 4.0,
                    if style == Style::Dashed {
                        r#" stroke-dasharray="6 4""#
                    } else {
                        ""
                    }
                ),
            };
            let _ = writeln!(
                svg,
                r#"{mark}<text x="{:.1}" y="{y:.1}">{}</text>"#,
                x + 24.0,
                escape(&series.label)
            );
        }
        if !self.caption.is_empty() {
            let _ = writeln!(
                svg,
                r##"<text x="4" y="{:.1}" font-size="9" fill="#555">{}</text>"##,
                HEIGHT - 6.0,
                escape(&self.caption)
            );
        }
        svg.push_str("</svg>\n");
        svg
    }
}

/// Tick positions in transformed coordinates.
fn ticks(lo: f64, hi: f64, scale: Scale) -> Vec<f64> {
    if scale == Scale::Log {
        let (a, b) = (lo.floor() as i32, hi.ceil() as i32);
        let decades = b - a;
        let every = if decades > 8 { 2 } else { 1 };
        let mut out: Vec<f64> = (a..=b)
            .filter(|d| (d - a) % every == 0)
            .map(f64::from)
            .collect();
        if decades <= 2 {
            out = (a..=b)
                .flat_map(|d| [1.0f64, 2.0, 5.0].map(|m| f64::from(d) + m.log10()))
                .filter(|&t| t <= f64::from(b))
                .collect();
        }
        return out;
    }
    let span = hi - lo;
    let raw = span / 6.0;
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * magnitude)
        .find(|s| span / s <= 7.0)
        .unwrap_or(10.0 * magnitude);
    let first = (lo / step).floor() * step;
    (0..=((hi - first) / step).ceil() as usize)
        .map(|k| first + k as f64 * step)
        .collect()
}

/// The label of tick `t` (transformed coordinates) among `ticks`.
fn label(t: f64, scale: Scale, ticks: &[f64]) -> String {
    match scale {
        Scale::Log => {
            let v = 10f64.powf(t);
            // One significant digit: ticks sit at 1, 2 or 5 times a power of ten.
            number(v, 10f64.powf(t.floor()))
        }
        Scale::Linear => {
            let step = ticks.windows(2).map(|w| w[1] - w[0]).next().unwrap_or(1.0);
            number(t, step.abs())
        }
    }
}

/// `v` printed to the decimals of `step` (`0.25`, `1500`), or in exponent form (`2e6`,
/// `-1.5e-4`) when its size is outside 1e-3 .. 1e4.
fn number(v: f64, step: f64) -> String {
    let step = if step > 0.0 && step.is_finite() {
        step
    } else {
        1.0
    };
    let v = (v / step).round() * step;
    if v == 0.0 {
        return "0".into();
    }
    let step_exponent = step.log10().floor() as i32;
    if (1e-3..1e4).contains(&v.abs()) {
        let decimals = (-step_exponent).max(0) as usize;
        return format!("{v:.decimals$}");
    }
    let exponent = v.abs().log10().floor() as i32;
    let digits = (exponent - step_exponent).max(0) as usize;
    let text = format!("{v:.digits$e}");
    // 2.0e6 -> 2e6: no trailing zeros in the mantissa.
    match text.split_once('e') {
        Some((mantissa, power)) if mantissa.contains('.') => {
            format!(
                "{}e{power}",
                mantissa.trim_end_matches('0').trim_end_matches('.')
            )
        }
        _ => text,
    }
}

/// Where a report's numbers came from: the command, the machine and the date (UTC), for the
/// captions of figures and the headers of generated documents.
pub fn provenance(command: &str) -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!("`{command}` on {cpu} ({cores} cores), {}", today())
}

/// Today's date (UTC) as `YYYY-MM-DD`.
pub fn today() -> String {
    let days = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() / 86_400) as i64;
    // Civil date from days since 1970-01-01 (H. Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn svg_contains_every_series_and_escapes_text() {
        let mut figure = Figure::new("a < b & c", "kR", "A / (rho pi R^2)");
        figure.x_scale = Scale::Log;
        figure.add(
            "line",
            vec![(0.01, 1.0), (1.0, 2.0), (10.0, 0.5)],
            Style::Line,
        );
        figure.add("points", vec![(0.1, 1.5), (-1.0, 3.0)], Style::Markers);
        let svg = figure.to_svg();
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>\n"));
        assert!(svg.contains("a &lt; b &amp; c"));
        assert_eq!(svg.matches("<polyline").count(), 1);
        // The point at x = -1 cannot be drawn on a log axis and is dropped.
        assert_eq!(svg.matches("<circle").count(), 1 + 1);
    }

    #[test]
    fn today_is_a_plausible_date() {
        let date = today();
        assert_eq!(date.len(), 10);
        let year: i32 = date[..4].parse().unwrap();
        assert!(year >= 2024, "{date}");
    }

    #[test]
    fn lines_are_drawn_over_markers_and_labels_are_short() {
        let mut figure = Figure::new("fit", "omega (rad/s)", "A~ (kg)");
        figure.x_scale = Scale::Log;
        figure.add("network", vec![(0.2, -1e6), (2.5, 3e6)], Style::Line);
        figure.add("data", vec![(0.3, 1e6), (2.0, 2e6)], Style::Markers);
        let svg = figure.to_svg();
        let (circle, line) = (svg.find("<circle").unwrap(), svg.find("<polyline").unwrap());
        assert!(circle < line, "the line is drawn first");
        // 0.2 .. 2.5 rad/s: ticks at 0.2, 0.5, 1 and 2, not just 1.
        for tick in [">0.2<", ">0.5<", ">1<", ">2<"] {
            assert!(svg.contains(tick), "{tick} missing");
        }
        assert!(svg.contains(">2e6<") && svg.contains(">-1e6<"), "{svg}");
        assert!(!svg.contains("000000"), "{svg}");
    }

    #[test]
    fn numbers_keep_the_step_s_decimals() {
        assert_eq!(number(0.30000000000000004, 0.1), "0.3");
        assert_eq!(number(1500.0, 500.0), "1500");
        assert_eq!(number(-1.5e-4, 5e-5), "-1.5e-4");
        assert_eq!(number(2_000_000.0, 1e6), "2e6");
        assert_eq!(number(0.0, 0.2), "0");
    }

    #[test]
    fn linear_ticks_cover_the_range_with_round_steps() {
        let t = ticks(-0.23, 1.07, Scale::Linear);
        assert!(t[0] <= -0.23 && *t.last().unwrap() >= 1.07);
        let step = t[1] - t[0];
        assert!((step - 0.2).abs() < 1e-12, "{t:?}");
    }
}
