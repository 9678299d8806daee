//! The built-in hulls: exact arcs with analytic fields.
//!
//! [`Hull::semicircle`]: radius R, centre at the origin, theta = pi s, hull point
//! P = R(-cos theta, -sin theta): theta = 0 at the left waterline (-R, 0), pi/2 at the keel,
//! pi at the right waterline (R, 0). [`Hull::circle`]: radius R, centre (0, -H) with H/R > 1,
//! theta = 2 pi s, P = (0, -H) + R(-cos theta, -sin theta), starting at the leftmost point.
//! In both, t = (sin theta, -cos theta) and n = (cos theta, sin theta).

use super::{
    check_coordinates, check_length, craig_bampton_coefficients, Contour, Dof, Field, Hull,
    HullError, RigidKind,
};

fn rigid(name: &str, kind: RigidKind) -> Dof {
    Dof {
        name: name.to_string(),
        field: Field::Rigid {
            kind,
            reference: [0.0, 0.0],
        },
    }
}

impl Hull {
    /// The built-in semicircle of radius `radius` (H/R = 0), centre at the origin, with DOFs
    /// `sway heave roll cb1 cb2 cb3 cb4 cb5 cb6` (roll about the origin).
    pub fn semicircle(radius: f64) -> Result<Hull, HullError> {
        let source = "built-in semicircle";
        if !(radius.is_finite() && radius > 0.0) {
            return Err(HullError::new(
                source,
                None,
                format!("radius must be positive and finite, got {radius}"),
            ));
        }
        check_length("radius", radius).map_err(|m| HullError::new(source, None, m))?;
        let coefficients = craig_bampton_coefficients(radius);
        let mut dofs = vec![
            rigid("sway", RigidKind::Sway),
            rigid("heave", RigidKind::Heave),
            rigid("roll", RigidKind::Roll),
        ];
        for (k, c) in coefficients.iter().enumerate() {
            dofs.push(Dof {
                name: format!("cb{}", k + 1),
                field: Field::CraigBampton {
                    mode: k + 1,
                    coefficients: *c,
                },
            });
        }
        Ok(Hull {
            name: "semicircle".to_string(),
            half_beam: radius,
            contour: Contour::Arc {
                radius,
                depth: 0.0,
                depth_ratio: 0.0,
            },
            dofs,
            notes: Vec::new(),
            mass: None,
            bilge_keels: None,
            water_depth: None,
        })
    }

    /// The Lewis form of a ship section of waterline breadth `breadth`, draft `draft` and area
    /// coefficient `area_coefficient` (submerged area over `B T`), with DOFs `sway heave roll`
    /// (roll about the origin, on the free surface at the centreline) and half-beam `B/2`.
    /// `B/(2T) = 1` with `pi/4` is the semicircle.
    ///
    /// # Errors
    /// Data out of range, or a form that loops or rises above the waterline (docs/SHIPS.md).
    pub fn lewis(breadth: f64, draft: f64, area_coefficient: f64) -> Result<Hull, HullError> {
        let source = "built-in Lewis form";
        let error = |m: String| HullError::new(source, None, m);
        let form = super::lewis::LewisForm::new(breadth, draft, area_coefficient)
            .map_err(|e| error(e.to_string()))?;
        check_length("breadth", breadth).map_err(error)?;
        check_length("draft", draft).map_err(error)?;
        super::check_half_beam_ratio(breadth / 2.0, breadth.max(draft)).map_err(error)?;
        Ok(Hull {
            name: "lewis".to_string(),
            half_beam: breadth / 2.0,
            contour: Contour::Lewis(form),
            dofs: vec![
                rigid("sway", RigidKind::Sway),
                rigid("heave", RigidKind::Heave),
                rigid("roll", RigidKind::Roll),
            ],
            notes: Vec::new(),
            mass: None,
            bilge_keels: None,
            water_depth: None,
        })
    }

    /// The built-in circle of radius `radius` with centre at (0, -H), H = `depth_over_radius`
    /// times the radius, closed, with DOFs `sway heave roll` (roll about the origin).
    /// H/R = 0 gives [`Hull::semicircle`]; 0 < H/R <= 1 (the circle pierces or touches the free
    /// surface) and H/R < 0 are errors.
    pub fn circle(radius: f64, depth_over_radius: f64) -> Result<Hull, HullError> {
        let source = "built-in circle";
        if !(radius.is_finite() && radius > 0.0) {
            return Err(HullError::new(
                source,
                None,
                format!("radius must be positive and finite, got {radius}"),
            ));
        }
        check_length("radius", radius).map_err(|m| HullError::new(source, None, m))?;
        if depth_over_radius == 0.0 {
            return Hull::semicircle(radius);
        }
        check_circle_depth(depth_over_radius).map_err(|m| HullError::new(source, None, m))?;
        check_coordinates("centre", [0.0, -depth_over_radius * radius])
            .map_err(|m| HullError::new(source, None, m))?;
        Ok(Hull {
            name: "circle".to_string(),
            half_beam: radius,
            contour: Contour::Arc {
                radius,
                depth: depth_over_radius * radius,
                depth_ratio: depth_over_radius,
            },
            dofs: vec![
                rigid("sway", RigidKind::Sway),
                rigid("heave", RigidKind::Heave),
                rigid("roll", RigidKind::Roll),
            ],
            notes: Vec::new(),
            mass: None,
            bilge_keels: None,
            water_depth: None,
        })
    }
}

/// Checks H/R of a circle: 0 (semicircle) or above 1 (submerged).
pub(super) fn check_circle_depth(h_over_r: f64) -> Result<(), String> {
    if !h_over_r.is_finite() || h_over_r < 0.0 {
        Err(format!(
            "depth/radius must be 0 (semicircle) or greater than 1 (submerged circle), \
             got {h_over_r}"
        ))
    } else if h_over_r > 0.0 && h_over_r <= 1.0 {
        Err(format!(
            "depth/radius = {h_over_r}: a circle with 0 < H/R <= 1 pierces or touches the free \
             surface; use H/R = 0 (semicircle) or H/R > 1 (submerged circle)"
        ))
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hull::validate::{cross, sub};
    use crate::hull::Point;
    use std::f64::consts::PI;

    fn close(a: Point, b: Point, tol: f64) -> bool {
        (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol
    }

    #[test]
    fn semicircle_geometry() {
        let r = 3.0;
        let h = Hull::semicircle(r).unwrap();
        assert_eq!(h.name(), "semicircle");
        assert!(!h.is_closed());
        assert_eq!(h.reference_half_beam(), r);
        assert_eq!(
            h.dof_names(),
            ["sway", "heave", "roll", "cb1", "cb2", "cb3", "cb4", "cb5", "cb6"]
        );
        assert_eq!(h.breakpoints(), vec![0.0, 1.0]);
        assert!(close(h.point(0.0), [-r, 0.0], 1e-15));
        assert!(close(h.point(0.5), [0.0, -r], 1e-15));
        // Waterline ends exactly on y = 0.
        assert_eq!(h.point(0.0), [-r, 0.0]);
        assert_eq!(h.point(1.0), [r, 0.0]);
        assert!((h.contour_length() - PI * r).abs() < 1e-14);
        for i in 0..100 {
            let s = (f64::from(i) + 0.5) / 100.0;
            let p = h.point(s);
            assert!((p[0].hypot(p[1]) - r).abs() < 1e-14);
            // Normal into the body = towards the centre.
            assert!(close(h.normal(s), [-p[0] / r, -p[1] / r], 1e-15));
            // Arc length: |dP/ds| = pi R; tangent = dP/ds / |dP/ds|.
            let ds = 1e-6;
            let (a, b) = (h.point(s - ds), h.point(s + ds));
            let d = [(b[0] - a[0]) / (2.0 * ds), (b[1] - a[1]) / (2.0 * ds)];
            assert!((d[0].hypot(d[1]) - PI * r).abs() < 1e-6);
            let t = h.tangent(s);
            assert!(close(t, [d[0] / (PI * r), d[1] / (PI * r)], 1e-8));
            // Roll about the origin is purely tangential on the circle.
            assert!(h.normal_displacement(2, s).abs() < 1e-14);
            assert!(close(h.displacement(2, s), [-p[1], p[0]], 1e-15));
        }
        assert!(h.displacement(9, 0.5)[0].is_nan());
        assert!(Hull::semicircle(0.0).is_err());
        assert!(Hull::semicircle(f64::INFINITY).is_err());
    }

    #[test]
    fn circle_geometry_and_depth_checks() {
        let (r, hr) = (2.0, 1.5);
        let c = Hull::circle(r, hr).unwrap();
        assert_eq!(c.name(), "circle");
        assert!(c.is_closed());
        assert_eq!(c.dof_names(), ["sway", "heave", "roll"]);
        assert!(close(c.point(0.0), [-r, -hr * r], 1e-15));
        assert_eq!(c.point(1.0), c.point(0.0));
        // Mirror symmetries, with the two halves evaluated from opposite ends: the circle about
        // y = -H (P(1 - s)), the semicircle about x = 0 (P(1 - s)).
        let semi = Hull::semicircle(r).unwrap();
        for s in [0.1, 0.25, 0.4, 0.5] {
            let (p, q) = (c.point(s), c.point(1.0 - s));
            assert!((p[0] - q[0]).abs() < 1e-15 && (p[1] + q[1] + 2.0 * hr * r).abs() < 1e-14);
            let (p, q) = (semi.point(s), semi.point(1.0 - s));
            assert!((p[0] + q[0]).abs() < 1e-15 && (p[1] - q[1]).abs() < 1e-15);
        }
        let centre = [0.0, -hr * r];
        let mut area = 0.0;
        let n = 400;
        for i in 0..n {
            let s = f64::from(i) / f64::from(n);
            let (p, q) = (c.point(s), c.point(s + 1.0 / f64::from(n)));
            area += cross(p, q) / 2.0;
            let d = sub(p, centre);
            assert!((d[0].hypot(d[1]) - r).abs() < 1e-14);
            assert!(close(c.normal(s), [-d[0] / r, -d[1] / r], 1e-15));
            assert!(p[1] < 0.0);
        }
        // Counter-clockwise: positive area close to pi R^2 (polygon of 400 sides).
        assert!((area - PI * r * r).abs() < 1e-3 * PI * r * r);
        // Roll about the free-surface origin: (-y, x).
        let p = c.point(0.3);
        assert!(close(c.displacement(2, 0.3), [-p[1], p[0]], 1e-15));

        for bad in [0.5, 1.0, -1.0, f64::NAN] {
            let e = Hull::circle(r, bad).unwrap_err();
            assert_eq!(e.source_name(), "built-in circle");
            assert!(e.message().contains("depth/radius"), "{e}");
        }
        assert!(Hull::circle(r, 1.0)
            .unwrap_err()
            .to_string()
            .contains("pierces"));
        let semi = Hull::circle(r, 0.0).unwrap();
        assert_eq!(
            semi.fingerprint(),
            Hull::semicircle(r).unwrap().fingerprint()
        );
    }
}
