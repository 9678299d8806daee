//! A ship's cross-flow drag strip by strip (`resources/crossflow.csv`, docs/CURRENT.md).
//!
//! The cross-flow principle (Faltinsen, "Sea loads on ships and offshore structures", 1990,
//! ch. 7): each strip at station `x` feels the 2D drag of the flow across it. With the ship's
//! conventions (docs/SHIPS.md: yaw `r` moves the strip by `x r` to port, pitch `q` by `-x q`
//! up) and the current `U`, `psi` (`U sin(psi)` across the ship):
//!
//! ```text
//! v_y(x) = v_sway + x r - U sin(psi)        dF_y = -rho s c_y |v_y| v_y,   c_y = 0.5 C_D,y T w
//! v_z(x) = v_heave - x q                    dF_z = -rho s c_z |v_z| v_z,   c_z = 0.5 C_D,z B w
//! F_sway = sum dF_y    M_yaw = sum x dF_y    F_heave = sum dF_z    M_pitch = -sum x dF_z
//! ```
//!
//! `w` is the station's trapezoid weight (m), `T` and `B` the section's draft and breadth, `C_D`
//! the section-shape estimate ([`crate::viscous::cross_flow_drag_coefficient`]), `rho` the
//! FMU's `rho` and `s` the fixed parameter `crossflow.drag_scale` (default 1, 0 switches the
//! strips off). A DOF the network does not have moves nothing and gets no force. The
//! Jacobian, with `g = -2 rho s c |v_n|`, is `sum g [1, x; x, x^2]` for sway-yaw and
//! `sum g [1, -x; -x, x^2]` for heave-pitch.
//!
//! File: `#` comment lines, the header `x,weight,draft,breadth,cd_sway,cd_heave`, then one
//! line per strip: finite numbers, all but `x` not negative, at most [`MAX_STRIPS`] strips.

use nalgebra::{DMatrix, DVector};
use std::f64::consts::PI;

/// The most strips `crossflow.csv` may hold.
pub const MAX_STRIPS: usize = 10_000;

/// The header line of `crossflow.csv`.
const HEADER: &str = "x,weight,draft,breadth,cd_sway,cd_heave";

/// The file in messages.
const SOURCE: &str = "resources/crossflow.csv";

/// One strip of a ship: its station and its section's drag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strip {
    /// Station x (m, forward).
    pub x: f64,
    /// Trapezoid weight (m).
    pub weight: f64,
    /// Section draft T (m).
    pub draft: f64,
    /// Section waterline breadth B (m).
    pub breadth: f64,
    /// Drag coefficient of the flow across the ship (sway).
    pub cd_sway: f64,
    /// Drag coefficient of the vertical flow (heave).
    pub cd_heave: f64,
}

impl Strip {
    /// `c_y = 0.5 C_D,y T w` (m^2).
    pub fn lateral(&self) -> f64 {
        0.5 * self.cd_sway * self.draft * self.weight
    }

    /// `c_z = 0.5 C_D,z B w` (m^2).
    pub fn vertical(&self) -> f64 {
        0.5 * self.cd_heave * self.breadth * self.weight
    }
}

/// The strips in the FMU, with the network's DOFs they act on.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossflow {
    strips: Vec<Strip>,
    /// `(x, c_y, c_z)` per strip.
    terms: Vec<(f64, f64, f64)>,
    /// `crossflow.drag_scale`.
    scale: f64,
    sway: Option<usize>,
    yaw: Option<usize>,
    heave: Option<usize>,
    pitch: Option<usize>,
}

impl Crossflow {
    /// The strips acting on the network's DOFs `names` (sway, yaw, heave, pitch where present).
    pub fn new(strips: Vec<Strip>, names: &[String]) -> Crossflow {
        let at = |dof: &str| names.iter().position(|n| n == dof);
        Crossflow {
            terms: strips
                .iter()
                .map(|s| (s.x, s.lateral(), s.vertical()))
                .collect(),
            strips,
            scale: 1.0,
            sway: at("sway"),
            yaw: at("yaw"),
            heave: at("heave"),
            pitch: at("pitch"),
        }
    }

    /// The strips.
    pub fn strips(&self) -> &[Strip] {
        &self.strips
    }

    /// `crossflow.drag_scale`.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// Sets `crossflow.drag_scale`, if it is finite and not negative.
    pub fn set_scale(&mut self, value: f64) -> Result<(), String> {
        check_scale(value)?;
        self.scale = value;
        Ok(())
    }

    /// The velocities across the strip at `x`: `(v_y + current, v_z)` with `lateral_current`
    /// the current across the ship, `U sin(psi)`.
    fn flow(&self, velocity: &[f64], lateral_current: f64, x: f64) -> (f64, f64) {
        let v = |dof: Option<usize>| dof.map_or(0.0, |i| velocity[i]);
        (
            v(self.sway) + x * v(self.yaw) - lateral_current,
            v(self.heave) - x * v(self.pitch),
        )
    }

    /// Adds the strips' forces at `velocity` to `force`.
    pub fn add_force(&self, velocity: &[f64], rho: f64, lateral_current: f64, force: &mut [f64]) {
        let k = rho * self.scale;
        let (mut sway, mut yaw, mut heave, mut pitch) = (0.0, 0.0, 0.0, 0.0);
        for &(x, lateral, vertical) in &self.terms {
            let (vy, vz) = self.flow(velocity, lateral_current, x);
            let fy = -k * lateral * vy.abs() * vy;
            let fz = -k * vertical * vz.abs() * vz;
            sway += fy;
            yaw += x * fy;
            heave += fz;
            pitch -= x * fz;
        }
        for (dof, value) in [
            (self.sway, sway),
            (self.yaw, yaw),
            (self.heave, heave),
            (self.pitch, pitch),
        ] {
            if let Some(i) = dof {
                force[i] += value;
            }
        }
    }

    /// Adds the strips' `dF/dv` to `jacobian`, and their `dF/dU` and `dF/dpsi` (per deg) to
    /// `per_speed` and `per_degree`, at `velocity` and the current `(U, psi)` (m/s, deg).
    pub fn add_derivatives(
        &self,
        velocity: &[f64],
        rho: f64,
        (speed, heading): (f64, f64),
        jacobian: &mut DMatrix<f64>,
        per_speed: &mut DVector<f64>,
        per_degree: &mut DVector<f64>,
    ) {
        let (sin, cos) = heading.to_radians().sin_cos();
        let k = -2.0 * rho * self.scale;
        // Sums of g, g x and g x^2 over the strips, lateral and vertical.
        let (mut y0, mut y1, mut y2, mut z0, mut z1, mut z2) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for &(x, lateral, vertical) in &self.terms {
            let (vy, vz) = self.flow(velocity, speed * sin, x);
            let gy = k * lateral * vy.abs();
            let gz = k * vertical * vz.abs();
            y0 += gy;
            y1 += gy * x;
            y2 += gy * x * x;
            z0 += gz;
            z1 += gz * x;
            z2 += gz * x * x;
        }
        let blocks = [
            (self.sway, self.sway, y0),
            (self.sway, self.yaw, y1),
            (self.yaw, self.sway, y1),
            (self.yaw, self.yaw, y2),
            (self.heave, self.heave, z0),
            (self.heave, self.pitch, -z1),
            (self.pitch, self.heave, -z1),
            (self.pitch, self.pitch, z2),
        ];
        for (row, column, value) in blocks {
            if let (Some(i), Some(j)) = (row, column) {
                jacobian[(i, j)] += value;
            }
        }
        // dv_y/dU = -sin(psi), dv_y/dpsi = -U cos(psi) (per rad).
        let per_radian = -speed * cos;
        for (dof, sum) in [(self.sway, y0), (self.yaw, y1)] {
            if let Some(i) = dof {
                per_speed[i] -= sum * sin;
                per_degree[i] += sum * per_radian * PI / 180.0;
            }
        }
    }
}

/// Refuses a `crossflow.drag_scale` that is not finite or negative.
pub fn check_scale(value: f64) -> Result<(), String> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(format!(
            "crossflow.drag_scale = {value}: must be finite and not negative"
        ))
    }
}

/// Parses `crossflow.csv` (module docs).
pub fn parse_csv(text: &str) -> Result<Vec<Strip>, String> {
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    match rows.next() {
        Some((_, HEADER)) => {}
        Some((line, other)) => {
            return Err(format!(
                "{SOURCE}:{line}: header '{other}', expected '{HEADER}'"
            ))
        }
        None => return Err(format!("{SOURCE}: no header '{HEADER}'")),
    }
    let mut strips = Vec::new();
    for (line, row) in rows {
        if strips.len() == MAX_STRIPS {
            return Err(format!("{SOURCE}:{line}: more than {MAX_STRIPS} strips"));
        }
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        if fields.len() != 6 {
            return Err(format!(
                "{SOURCE}:{line}: {} fields, expected 6 ({HEADER})",
                fields.len()
            ));
        }
        let mut values = [0.0; 6];
        for (k, (value, field)) in values.iter_mut().zip(&fields).enumerate() {
            let name = HEADER.split(',').nth(k).unwrap_or("value");
            *value = field
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && (k == 0 || *v >= 0.0))
                .ok_or_else(|| {
                    format!(
                        "{SOURCE}:{line}: {name} '{field}': expected a finite number{}",
                        {
                            if k == 0 {
                                ""
                            } else {
                                ", not negative"
                            }
                        }
                    )
                })?;
        }
        let [x, weight, draft, breadth, cd_sway, cd_heave] = values;
        strips.push(Strip {
            x,
            weight,
            draft,
            breadth,
            cd_sway,
            cd_heave,
        });
    }
    if strips.is_empty() {
        return Err(format!("{SOURCE}: no strips"));
    }
    Ok(strips)
}

/// The text of `crossflow.csv` for `strips` (exact: shortest round-trip numbers).
pub fn write_csv(strips: &[Strip]) -> String {
    let mut text = String::from(
        "# hydrofmu cross-flow strips (docs/CURRENT.md): dF = -rho drag_scale c |v_n| v_n per strip\n\
         # sway: c = 0.5 cd_sway draft weight, v_n = v_sway + x r - U sin(psi); yaw gets x dF\n\
         # heave: c = 0.5 cd_heave breadth weight, v_n = v_heave - x q; pitch gets -x dF\n\
         # x station (m), weight its trapezoid weight (m), draft and breadth its section's (m),\n\
         # cd the section-shape estimate (Hoerner 1965; docs/VISCOUS.md)\n",
    );
    text.push_str(HEADER);
    text.push('\n');
    for s in strips {
        text.push_str(&format!(
            "{:?},{:?},{:?},{:?},{:?},{:?}\n",
            s.x, s.weight, s.draft, s.breadth, s.cd_sway, s.cd_heave
        ));
    }
    text
}

/// One line on the strips: their count, the range of their sway `C_D`, the lateral area
/// `sum T w` (m^2) and its moment `sum x T w` (m^3).
pub fn describe(strips: &[Strip]) -> String {
    let (low, high) = strips.iter().fold((f64::INFINITY, 0.0_f64), |(l, h), s| {
        (l.min(s.cd_sway), h.max(s.cd_sway))
    });
    let area: f64 = strips.iter().map(|s| s.draft * s.weight).sum();
    let moment: f64 = strips.iter().map(|s| s.x * s.draft * s.weight).sum();
    format!(
        "{} strips, C_D (sway) {low:.3}..{high:.3}, lateral area {area:.4e} m2 (moment about x = 0 \
         {moment:.4e} m3)",
        strips.len()
    )
}
