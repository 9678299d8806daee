//! Cross-flow drag of a section in sway and heave.
//!
//! The section with its mirror image in the free surface is a rectangle of breadth B and
//! height 2T with rounded corners of radius R. Its drag coefficient: the sharp-cornered 2D
//! rectangle's value as a function of its length along the flow over its height across it
//! (Hoerner, *Fluid-Dynamic Drag*, 1965, ch. 3, fig. 21; Delany and Sorensen, NACA TN 3038,
//! 1953, at subcritical Reynolds numbers), times a rounding factor falling linearly from 1 at
//! `R/D = 0` to 0.5 at `R/D >= 0.25` (`D`: the height across the flow; DNV-RP-C205 (2010)
//! table E-1 for rounded squares gives about this reduction). An estimate: a user-given
//! coefficient is preferred. Force per unit length, opposing `v`: sway
//! `-0.5 rho C_D T |v| v`, heave `-0.5 rho C_D B |v| v`, `v` the velocity relative to the current.

/// Sharp-cornered rectangles: (length along the flow / height across it, C_D).
const SHARP_RECTANGLE: [(f64, f64); 6] = [
    (0.0, 2.0),
    (0.5, 2.5),
    (1.0, 2.05),
    (2.0, 1.6),
    (4.0, 1.2),
    (6.0, 0.9),
];

/// The direction of the cross flow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CrossFlow {
    /// Horizontal flow (sway, a ship's yaw).
    Sway,
    /// Vertical flow (heave).
    Heave,
}

fn sharp_rectangle(aspect: f64) -> f64 {
    let last = SHARP_RECTANGLE[SHARP_RECTANGLE.len() - 1];
    if aspect >= last.0 {
        return last.1;
    }
    SHARP_RECTANGLE
        .windows(2)
        .find(|pair| aspect <= pair[1].0)
        .map(|pair| {
            let ((x0, y0), (x1, y1)) = (pair[0], pair[1]);
            y0 + (y1 - y0) * (aspect - x0) / (x1 - x0)
        })
        .unwrap_or(last.1)
}

/// The estimated drag coefficient of a section of breadth B, draft T, bilge radius R.
pub fn cross_flow_drag_coefficient(
    breadth: f64,
    draft: f64,
    bilge_radius: f64,
    flow: CrossFlow,
) -> f64 {
    let (along, across) = match flow {
        CrossFlow::Sway => (breadth, 2.0 * draft),
        CrossFlow::Heave => (2.0 * draft, breadth),
    };
    let rounding = 1.0 - 2.0 * (bilge_radius / across).min(0.25);
    sharp_rectangle(along / across) * rounding
}

/// Drag force per unit length `-0.5 rho C_D D |v| v` (N/m), `D` = T in sway and B in heave.
pub fn cross_flow_force(
    rho: f64,
    drag_coefficient: f64,
    breadth: f64,
    draft: f64,
    flow: CrossFlow,
    velocity: f64,
) -> f64 {
    let projected = match flow {
        CrossFlow::Sway => draft,
        CrossFlow::Heave => breadth,
    };
    -0.5 * rho * drag_coefficient * projected * velocity.abs() * velocity
}
