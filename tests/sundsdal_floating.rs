//! The floating 2D ship section of Sundsdal, Greco, Hanssen and Lugni (2025) in regular beam
//! waves, free in sway, heave and roll on sway springs: our motion per unit wave amplitude
//! (RAO) and mean sway drift force against the flume's measurements
//! (`tests/data/sundsdal/scenario_B.csv`, processed from the public raw data, CC0).
//!
//! Units: sway and heave per wave amplitude `a`; roll per wave slope `k a` (`k = omega^2 / g`);
//! drift coefficient = mean sway force / (rho g a^2 L / 2), at the flume's own density.

use hydrofmu::hull::Hull;
use hydrofmu::motion::Floating;
use hydrofmu::units::WaterDepth;
use hydrofmu::{hydrostatics, sweep};

const RHO: f64 = 1025.0;
const G: f64 = 9.81;
/// Half beam: the sweep's `kR` is the experiment's `xi_B = omega^2 B / (2 g)`.
const HALF_BEAM: f64 = 0.2;
/// The flume's water depth (m): ours is solved in it at every frequency.
const FLUME_DEPTH: f64 = 1.0;
/// The runs settle from this `xi_B` on (the README: below, the window holds 1-5 periods and
/// the slow sway, natural period 7.5 s, has not settled); waves below this steepness `k a` are
/// compared: the README's 0.1, lowered to leave out the H2 runs at xi_B 1.0 (k a 0.0996),
/// whose four repetitions scatter by half-ranges of 0.15-0.2 in motion.
const SETTLED: f64 = 0.65;
const STEEP: f64 = 0.09;

struct Row {
    xi: f64,
    steepness: f64,
    sway: f64,
    heave: f64,
    roll: f64,
    drift: f64,
}

fn measurements() -> Vec<Row> {
    let text = include_str!("data/sundsdal/scenario_B.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let columns = [
        "xi_B",
        "Ka",
        "sway_over_a",
        "heave_over_a",
        "roll_over_ka",
        "drift_force_sway",
    ]
    .map(column);
    lines
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            let v = columns.map(|c| fields[c].parse::<f64>().unwrap());
            Row {
                xi: v[0],
                steepness: v[1],
                sway: v[2],
                heave: v[3],
                roll: v[4],
                drift: v[5].abs(),
            }
        })
        .collect()
}

/// Ours at each measured `xi_B`: (sway / a, heave / a, roll / (k a), drift coefficient).
fn ours(xis: &[f64], depth: WaterDepth) -> Vec<[f64; 4]> {
    let text = include_str!("../examples/hulls/sundsdal_floating.xml");
    let hull = Hull::from_xml_str(text, "sundsdal_floating.xml").unwrap();
    let properties = hull.mass().unwrap().properties(&hull, RHO).unwrap();
    let statics = hydrostatics::stiffness(&hull).unwrap();
    let floating = Floating::new(&hull, &statics, &properties, RHO, G).unwrap();
    let params = sweep::SweepParams {
        kr: xis.to_vec(),
        depth,
        ..sweep::SweepParams::default()
    };
    let result = sweep::run(&hull, &params, &|_, _| {}).unwrap();
    let raos = floating.sweep_raos(&result).unwrap();
    xis.iter()
        .zip(&raos)
        .zip(&result.excitation)
        .map(|((xi, rao), forces)| {
            let k = xi / HALF_BEAM;
            let motion: Vec<_> = rao.column(0).iter().copied().collect();
            let drift = forces.drift.as_ref().unwrap();
            // D / (rho g) per a^2 -> F / (rho g a^2 L / 2).
            let mean = 2.0 * drift.horizontal_far_field_moving(0, &motion);
            [
                motion[0].norm(),
                motion[1].norm(),
                motion[2].norm() / k,
                mean.abs(),
            ]
        })
        .collect()
}

#[test]
fn floating_motion_and_mean_sway_force_agree_with_the_flume() {
    let rows = measurements();
    let mut xis: Vec<f64> = rows.iter().map(|r| r.xi).collect();
    xis.dedup();
    let values = ours(&xis, WaterDepth::Finite(FLUME_DEPTH));
    let mut compared = 0;
    for row in &rows {
        let i = xis.iter().position(|x| *x == row.xi).unwrap();
        let [sway, heave, roll, drift] = values[i];
        if (row.xi - 0.525).abs() < 1e-9 {
            // The flume's largest roll (h/lambda 0.42), our roll resonance at xi_B 0.50:
            // potential flow without viscous roll damping gives 1.51 times the flume's roll
            // (measured; 1.47 in deep water; docs/VISCOUS.md adds the damping).
            let ratio = roll / row.roll;
            assert!((1.3..=1.7).contains(&ratio), "roll peak ratio {ratio}");
        }
        if row.xi < SETTLED || row.steepness >= STEEP {
            continue;
        }
        compared += 1;
        // Measured: heave within 2.5 % (deep water: 2.2 %; kh >= 5 here).
        assert!(
            (heave / row.heave - 1.0).abs() <= 0.03,
            "xi {}: heave {heave} {}",
            row.xi,
            row.heave
        );
        // Measured: sway 1.09 and 1.25, roll 1.07 times the flume's (no viscous roll damping
        // in ours).
        let sway_ratio = sway / row.sway;
        assert!(
            (1.0..=1.35).contains(&sway_ratio),
            "xi {}: sway ratio {sway_ratio}",
            row.xi
        );
        let roll_ratio = roll / row.roll;
        assert!(
            (1.0..=1.15).contains(&roll_ratio),
            "xi {}: roll ratio {roll_ratio}",
            row.xi
        );
        // Measured: within 0.029 of the flume's drift coefficient (0.68 and 0.71), as in
        // deep water.
        assert!(
            (drift - row.drift).abs() <= 0.04,
            "xi {}: drift {drift} {}",
            row.xi,
            row.drift
        );
    }
    assert_eq!(compared, 2);
}
