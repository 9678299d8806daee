//! The Lewis form: a ship section from its waterline breadth `B`, draft `T` and area
//! coefficient `sigma = A / (B T)`, by the conformal map of the unit circle
//!
//! ```text
//! x = M [ (1 + a1) sin theta - a3 sin 3 theta ],
//! y = -M [ (1 - a1) cos theta + a3 cos 3 theta ],      theta in [-pi/2, pi/2],
//! ```
//!
//! theta = -pi/2 at the left waterline (-B/2, 0), 0 at the keel (0, -T), pi/2 at the right
//! waterline. With `H = B / (2 T)` (Journee and Massie, "Offshore Hydromechanics", 2001):
//!
//! ```text
//! C1 = (3 + 4 sigma/pi) + (1 - 4 sigma/pi) ((H - 1)/(H + 1))^2,
//! a3 = (3 - C1 + sqrt(9 - 2 C1)) / C1,   a1 = (1 + a3)(H - 1)/(H + 1),   M = (B/2)/(1 + a1 + a3).
//! ```
//!
//! The form exists for `9 - 2 C1 >= 0`, and the mapped curve is a valid contour only where it
//! neither loops nor rises above the waterline between its ends (very full or very fine
//! sections): [`LewisForm::new`] checks the sampled curve itself. The contour's
//! parameter `s` follows arc length through a table of the cumulative length (1024 intervals
//! of Gauss-integrated `|dP/dtheta|`), inverted by linear interpolation in theta: every point
//! lies exactly on the curve; `s` is proportional to arc length to the table's accuracy.

use super::contact::first_contact;
use super::Point;
use std::f64::consts::PI;
use std::fmt;

/// Why [`LewisForm::new`] refuses its data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LewisError {
    /// `breadth` or `draft` not positive and finite.
    NotPositive {
        /// `breadth` or `draft`.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// An area coefficient outside (0, 1].
    AreaCoefficient(f64),
    /// No valid form has these data (it would loop or leave the water).
    NoForm {
        /// B, m.
        breadth: f64,
        /// T, m.
        draft: f64,
        /// sigma.
        area_coefficient: f64,
    },
}

impl fmt::Display for LewisError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LewisError::NotPositive { what, value } => write!(
                f,
                "Lewis form: {what} must be positive and finite, got {value}"
            ),
            LewisError::AreaCoefficient(value) => write!(
                f,
                "Lewis form: area_coefficient must be in (0, 1], got {value}"
            ),
            LewisError::NoForm {
                breadth,
                draft,
                area_coefficient,
            } => write!(
                f,
                "Lewis form: no form has B = {breadth} m, T = {draft} m and area coefficient \
                 {area_coefficient} (the mapped curve would loop or leave the water); use a \
                 hull file with the contour's points"
            ),
        }
    }
}

impl std::error::Error for LewisError {}

impl From<LewisError> for String {
    fn from(error: LewisError) -> String {
        error.to_string()
    }
}

/// Intervals of the arc-length table.
const TABLE_INTERVALS: usize = 1024;

/// A Lewis form: its data and its arc-length table.
#[derive(Clone)]
pub(super) struct LewisForm {
    pub(crate) breadth: f64,
    pub(crate) draft: f64,
    pub(crate) area_coefficient: f64,
    a1: f64,
    a3: f64,
    scale: f64,
    /// Cumulative arc length at theta_k = -pi/2 + pi k / TABLE_INTERVALS, divided by the total.
    s_of_theta: Vec<f64>,
    pub(crate) length: f64,
}

impl LewisForm {
    /// The form of breadth `B`, draft `T` and area coefficient `sigma`.
    ///
    /// # Errors
    /// Non-positive or non-finite data, `sigma` above 1 or at most 0, a form that does not
    /// exist (`9 - 2 C1 < 0`) or whose curve loops or leaves the water (it must run strictly
    /// below y = 0 between the waterline points, left to right, without crossing itself).
    pub fn new(breadth: f64, draft: f64, area_coefficient: f64) -> Result<Self, LewisError> {
        for (what, value) in [("breadth", breadth), ("draft", draft)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(LewisError::NotPositive { what, value });
            }
        }
        if !(area_coefficient.is_finite() && area_coefficient > 0.0 && area_coefficient <= 1.0) {
            return Err(LewisError::AreaCoefficient(area_coefficient));
        }
        let h = breadth / (2.0 * draft);
        let ratio = ((h - 1.0) / (h + 1.0)).powi(2);
        let c1 = (3.0 + 4.0 * area_coefficient / PI) + (1.0 - 4.0 * area_coefficient / PI) * ratio;
        let discriminant = 9.0 - 2.0 * c1;
        let no_form = || LewisError::NoForm {
            breadth,
            draft,
            area_coefficient,
        };
        if discriminant < 0.0 {
            return Err(no_form());
        }
        let a3 = (3.0 - c1 + discriminant.sqrt()) / c1;
        let a1 = (1.0 + a3) * (h - 1.0) / (h + 1.0);
        let scale = breadth / 2.0 / (1.0 + a1 + a3);
        let mut form = LewisForm {
            breadth,
            draft,
            area_coefficient,
            a1,
            a3,
            scale,
            s_of_theta: Vec::new(),
            length: 0.0,
        };
        // Valid: strictly below the surface between the ends, and not touching itself.
        let samples: Vec<Point> = (0..=TABLE_INTERVALS)
            .map(|k| form.at_angle(theta_at(k)))
            .collect();
        let inside = &samples[1..TABLE_INTERVALS];
        if inside.iter().any(|p| p[1] >= 0.0) || !form.simple(&samples) {
            return Err(no_form());
        }
        // Arc-length table, 4-point Gauss per interval.
        const NODES: [f64; 4] = [
            -0.861_136_311_594_052_6,
            -0.339_981_043_584_856_3,
            0.339_981_043_584_856_3,
            0.861_136_311_594_052_6,
        ];
        const WEIGHTS: [f64; 4] = [
            0.347_854_845_137_453_9,
            0.652_145_154_862_546_1,
            0.652_145_154_862_546_1,
            0.347_854_845_137_453_9,
        ];
        let step = PI / TABLE_INTERVALS as f64;
        let mut cumulative = Vec::with_capacity(TABLE_INTERVALS + 1);
        cumulative.push(0.0);
        let mut total = 0.0;
        for k in 0..TABLE_INTERVALS {
            let middle = theta_at(k) + step / 2.0;
            total += NODES
                .iter()
                .zip(WEIGHTS)
                .map(|(t, w)| {
                    let d = form.derivative(middle + t * step / 2.0);
                    w * d[0].hypot(d[1]) * step / 2.0
                })
                .sum::<f64>();
            cumulative.push(total);
        }
        form.s_of_theta = cumulative.iter().map(|c| c / total).collect();
        form.length = total;
        Ok(form)
    }

    /// Point at map angle `theta`.
    fn at_angle(&self, theta: f64) -> Point {
        let (a1, a3, m) = (self.a1, self.a3, self.scale);
        [
            m * ((1.0 + a1) * theta.sin() - a3 * (3.0 * theta).sin()),
            -m * ((1.0 - a1) * theta.cos() + a3 * (3.0 * theta).cos()),
        ]
    }

    /// dP/dtheta.
    fn derivative(&self, theta: f64) -> Point {
        let (a1, a3, m) = (self.a1, self.a3, self.scale);
        [
            m * ((1.0 + a1) * theta.cos() - 3.0 * a3 * (3.0 * theta).cos()),
            m * ((1.0 - a1) * theta.sin() + 3.0 * a3 * (3.0 * theta).sin()),
        ]
    }

    /// The map angle at contour parameter `s` in [0, 1].
    fn angle(&self, s: f64) -> f64 {
        let s = s.clamp(0.0, 1.0);
        let k = self
            .s_of_theta
            .partition_point(|&v| v <= s)
            .saturating_sub(1)
            .min(TABLE_INTERVALS - 1);
        let (lo, hi) = (self.s_of_theta[k], self.s_of_theta[k + 1]);
        let t = if hi > lo { (s - lo) / (hi - lo) } else { 0.0 };
        theta_at(k) + t * PI / TABLE_INTERVALS as f64
    }

    /// Contour point at `s`; the ends exactly on the waterline.
    pub fn point(&self, s: f64) -> Point {
        if s <= 0.0 {
            return [-self.breadth / 2.0, 0.0];
        }
        if s >= 1.0 {
            return [self.breadth / 2.0, 0.0];
        }
        self.at_angle(self.angle(s))
    }

    /// Unit tangent at `s` (direction of increasing s).
    pub fn tangent(&self, s: f64) -> Point {
        let d = self.derivative(self.angle(s));
        let l = d[0].hypot(d[1]);
        [d[0] / l, d[1] / l]
    }

    /// The sampled polyline does not touch itself and has no vanishing step (a cusp).
    fn simple(&self, samples: &[Point]) -> bool {
        let cusp = samples
            .windows(2)
            .any(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]) <= 1e-9 * self.breadth);
        !cusp && first_contact(samples, samples.len() - 1, false, 1e-9 * self.breadth).is_none()
    }
}

impl std::fmt::Debug for LewisForm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LewisForm")
            .field("breadth", &self.breadth)
            .field("draft", &self.draft)
            .field("area_coefficient", &self.area_coefficient)
            .field("a1", &self.a1)
            .field("a3", &self.a3)
            .finish_non_exhaustive()
    }
}

fn theta_at(k: usize) -> f64 {
    -PI / 2.0 + PI * k as f64 / TABLE_INTERVALS as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Shoelace area of the closed polygon (contour plus waterline).
    fn area(form: &LewisForm, n: usize) -> f64 {
        let points: Vec<Point> = (0..=n).map(|k| form.point(k as f64 / n as f64)).collect();
        let mut twice = 0.0;
        for k in 0..points.len() {
            let (a, b) = (points[k], points[(k + 1) % points.len()]);
            twice += a[0] * b[1] - b[0] * a[1];
        }
        twice.abs() / 2.0
    }

    #[test]
    fn the_form_has_the_breadth_draft_and_area_it_was_made_for() {
        for &(b, t, sigma) in &[
            (10.0, 5.0, 0.9),
            (20.0, 4.0, 0.95),
            (6.0, 4.0, 0.7),
            (10.0, 5.0, PI / 4.0),
        ] {
            let form = LewisForm::new(b, t, sigma).unwrap();
            let keel = form.point(0.5);
            assert!((keel[0]).abs() < 1e-9 * b, "{keel:?}");
            assert!((keel[1] + t).abs() < 1e-9 * t, "{keel:?}");
            assert_eq!(form.point(0.0), [-b / 2.0, 0.0]);
            assert_eq!(form.point(1.0), [b / 2.0, 0.0]);
            let ends = [form.at_angle(-PI / 2.0), form.at_angle(PI / 2.0)];
            assert!((ends[0][0] + b / 2.0).abs() < 1e-12 * b && ends[0][1].abs() < 1e-12 * b);
            assert!((ends[1][0] - b / 2.0).abs() < 1e-12 * b && ends[1][1].abs() < 1e-12 * b);
            // Area within the polygon's error, (pi/4096)^2 of the area.
            let a = area(&form, 4096);
            assert!(
                (a / (b * t) - sigma).abs() < 1e-5,
                "{a} vs {}",
                sigma * b * t
            );
        }
    }

    #[test]
    fn b_over_2t_of_1_and_sigma_pi_over_4_is_the_semicircle() {
        let form = LewisForm::new(10.0, 5.0, PI / 4.0).unwrap();
        assert!(form.a1.abs() < 1e-12 && form.a3.abs() < 1e-12);
        for k in 0..=16 {
            let p = form.point(k as f64 / 16.0);
            assert!((p[0].hypot(p[1]) - 5.0).abs() < 1e-12, "{p:?}");
            // s follows arc length: theta = pi s on the semicircle.
            let theta = -PI / 2.0 + PI * k as f64 / 16.0;
            assert!((p[0] - 5.0 * theta.sin()).abs() < 1e-9, "{k}: {p:?}");
        }
        assert!((form.length - 5.0 * PI).abs() < 1e-10);
    }

    #[test]
    fn impossible_forms_are_refused_with_the_data() {
        for &(b, t, sigma) in &[
            (10.0, 1.0, 0.5),
            (10.0, 1.0, 0.2),
            (10.0, 5.0, 1.2),
            (f64::NAN, 1.0, 0.9),
        ] {
            let e = LewisForm::new(b, t, sigma).unwrap_err().to_string();
            assert!(e.starts_with("Lewis form:"), "{e}");
        }
    }
}
