//! Generates the viscous roll damping report `VISCOUS.md` and its figures:
//!
//! ```sh
//! cargo run --release -p fmu-pack --example viscous                  # into target/reports/
//! cargo run --release -p fmu-pack --example viscous -- --update-docs # docs/VISCOUS.md
//! cargo run --release -p fmu-pack --example viscous -- --quick       # the tables, checked
//! ```
//!
//! `--quick` computes the same tables without the figures and fails if one of their numbers
//! differs from `docs/VISCOUS.md` by more than two units of its last printed digit.
//!
//! Ikeda's components (`hydrofmu::viscous`) of the floating Sundsdal section and of the barge
//! and midship sections against frequency and amplitude, in Ikeda's nondimensional form
//! `B_hat = B_eq / (rho A B^2) sqrt(B / (2 g))` (`A` the submerged area, `B` the waterline
//! breadth, `B_eq` the equivalent linear damping per unit length); the eddy estimate against
//! Ikeda's measured cylinder (`tests/data/ikeda/`); and the floating Sundsdal section's roll at
//! its resonance in the frequency domain, with the equivalent linear damping solved for the
//! amplitude it produces.

use fmu_pack::plot::{self, Figure, Scale, Style};
use hydrofmu::hull::{DofKind, Hull, RigidKind};
use hydrofmu::sweep::{self, SweepParams, SweepResult};
use hydrofmu::viscous::{
    eddy_making, roll_damping, BilgeKeels, Damping, RollDamping, RollDampingParams,
};
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::time::Instant;

#[path = "report/csv.rs"]
mod csv;
#[path = "report/mod.rs"]
mod report;
#[path = "report/section_motion.rs"]
mod section_motion;

use report::{Output, Tolerance};

const COMMAND: &str = "cargo run --release -p fmu-pack --example viscous";
const RHO: f64 = 1025.0;
const G: f64 = 9.81;

/// One section: its name, its hull file and the inputs Ikeda's method takes from it.
struct Section {
    name: &'static str,
    hull: Hull,
    params: RollDampingParams,
    submerged_area: f64,
}

impl Section {
    /// The section of the hull file `text`, with its waterline breadth, draft and bilge radius
    /// (the file's comment); the area coefficient from its submerged area, the roll axis from
    /// its roll DOF.
    fn new(name: &'static str, text: &str, draft: f64, bilge_radius: f64) -> Section {
        let hull = Hull::from_xml_str(text, name).expect("hull file");
        let statics = hydrofmu::hydrostatics::stiffness(&hull).expect("hydrostatics");
        let breadth = statics.waterline_breadth;
        let sigma = statics.submerged_area / (breadth * draft);
        let mut params = RollDampingParams::new(breadth, draft, sigma, bilge_radius);
        params.roll_axis_height = (0..hull.dof_count())
            .find_map(|j| match hull.dof_kind(j) {
                Some(DofKind::Rigid {
                    kind: RigidKind::Roll,
                    reference,
                }) => Some(-reference[1]),
                _ => None,
            })
            .expect("a roll DOF");
        Section {
            name,
            hull,
            params,
            submerged_area: statics.submerged_area,
        }
    }

    fn with_keels(&self, name: &'static str, keels: BilgeKeels) -> Section {
        let mut params = self.params;
        params.bilge_keels = Some(keels);
        Section {
            name,
            hull: self.hull.clone(),
            params,
            submerged_area: self.submerged_area,
        }
    }

    /// `omega` (rad/s) of the nondimensional frequency `omega_hat = omega sqrt(B / (2 g))`.
    fn omega(&self, omega_hat: f64) -> f64 {
        omega_hat * (2.0 * G / self.params.breadth).sqrt()
    }

    /// Ikeda's nondimensional form of an equivalent linear damping (N m s per m).
    fn hat(&self, equivalent: f64) -> f64 {
        let b = self.params.breadth;
        equivalent / (self.params.rho * self.submerged_area * b * b) * (b / (2.0 * G)).sqrt()
    }

    fn components(&self, omega: f64, phi_a: f64) -> RollDamping {
        roll_damping(&self.params, omega, phi_a).expect("valid section")
    }
}

/// The floating Sundsdal section, the barge and the midship section (without and with keels).
fn sections() -> Vec<Section> {
    let sundsdal = Section::new(
        "Sundsdal",
        include_str!("hulls/sundsdal_floating.xml"),
        0.2,
        0.0512,
    );
    let barge = Section::new("barge", include_str!("hulls/barge.xml"), 5.0, 2.0);
    let midship = Section::new("midship", include_str!("hulls/midship.xml"), 8.0, 3.0);
    let keels = midship.with_keels("midship, keels", MIDSHIP_KEELS);
    vec![sundsdal, barge, midship, keels]
}

/// Bilge keels of the midship section: 0.4 m over 30 % of the length (a typical fit).
const MIDSHIP_KEELS: BilgeKeels = BilgeKeels {
    breadth: 0.4,
    length_fraction: 0.3,
};

/// Equivalent linear dampings of the components: (friction, eddy, keels, total).
fn equivalent(d: &RollDamping, omega: f64, phi_a: f64) -> [f64; 4] {
    [
        d.friction.equivalent_linear(omega, phi_a),
        d.eddy_making.equivalent_linear(omega, phi_a),
        d.bilge_keel.equivalent_linear(omega, phi_a),
        d.total().equivalent_linear(omega, phi_a),
    ]
}

/// One row of the floating model's table (scenario B).
struct FlumeRow {
    xi: f64,
    height: usize,
    amplitude: f64,
    h_over_lambda: f64,
    roll_over_ka: f64,
}

fn flume() -> Vec<FlumeRow> {
    let rows = csv::columns(
        include_str!("../tests/data/sundsdal/scenario_B.csv"),
        [
            "xi_B",
            "height_index",
            "a_mm",
            "h_over_lambda",
            "roll_over_ka",
        ],
    );
    rows.iter()
        .map(|v| FlumeRow {
            xi: v[0],
            height: v[1] as usize,
            amplitude: v[2] / 1000.0,
            h_over_lambda: v[3],
            roll_over_ka: v[4],
        })
        .collect()
}

/// The roll resonance the pytest drives and the tables report: the flume's largest roll.
const RESONANCE_XI: f64 = 0.525;
/// Near our own roll resonance, without a stored flume run: the pytest drives it at the flume's
/// first wave height (a = 12 mm).
const OUR_RESONANCE_XI: f64 = 0.5;
const OUR_RESONANCE_AMPLITUDE: f64 = 0.012;

/// The floating section's roll amplitude (rad) in waves of amplitude `a` (m) at the frequency
/// `index` of `sweep`: without viscous damping, and with the damping `damping_at(phi_a)` at
/// the amplitude it produces (bisection on `phi_a`, the roll decreasing as the damping grows).
fn roll_amplitudes(
    section: &Section,
    sweep: &sweep::SweepResult,
    index: usize,
    a: f64,
    damping_at: &dyn Fn(f64) -> Damping,
) -> (f64, f64) {
    let hull = &section.hull;
    let properties = hull
        .mass()
        .expect("mass")
        .properties(hull, RHO)
        .expect("properties");
    let roll = hull.dof_names().iter().position(|n| *n == "roll");
    let roll = roll.expect("roll");
    let omega = (sweep.kr[index] * G / sweep.reference_half_beam).sqrt();
    let amplitude = |extra: f64| {
        section_motion::motions(hull, &properties, sweep, RHO, G, extra)[index][roll].norm() * a
    };
    let undamped = amplitude(0.0);
    let (mut low, mut high) = (1e-6, undamped);
    for _ in 0..60 {
        let phi = 0.5 * (low + high);
        if amplitude(damping_at(phi).equivalent_linear(omega, phi)) > phi {
            low = phi;
        } else {
            high = phi;
        }
    }
    (undamped, 0.5 * (low + high))
}

fn save(out: &Output, figure: &mut Figure, name: &str) -> String {
    figure.caption = plot::provenance(COMMAND);
    out.write_figure(name, &figure.to_svg());
    format!("![{}](figures/{name}.svg)\n", figure.title)
}

const INTRODUCTION: &str = "`hydrofmu::viscous` estimates a section's roll damping from its \
geometry by Ikeda's components at zero speed, and its cross-flow drag in sway and heave. The \
moment per unit length is `M = -B_l phi_dot - B_q |phi_dot| phi_dot`. `OG` is Ikeda's distance \
from the waterline down to the roll axis: positive below the water, negative above \
(`RollDampingParams::roll_axis_height` holds it with this sign; `OG = T` is the keel).\n\n\
| component | form | source |\n\
|---|---|---|\n\
| skin friction | linear at the frequency and amplitude | Kato (1958), ITTC 7.5-02-07-04.5 |\n\
| eddy making | quadratic, `B_q = rho T^4 max(C_R, 0) / 2` | Ikeda (1978), Lewis-form mapping |\n\
| bilge keels, normal force | linear `60 rho l^2 b^2 omega / pi^2` + quadratic `2.4 rho l^3 b f` | Ikeda (1978), ITTC |\n\
| bilge keels, hull pressure | equivalent linear at the amplitude | Ikeda (1978), ITTC |\n\n\
Equivalent linear damping: `B_eq = B_l + 8/(3 pi) omega phi_a B_q` (harmonic), \
`B_eq = B_l + sqrt(8/pi) sigma_phidot B_q` (Gaussian sea state). Kinematic viscosity default \
`1.19e-6 m^2/s` (sea water, 15 C).\n\n\
Validity: warnings outside `2.5 <= B/T <= 4.5`, `sigma >= 0.5`, `-1.5 <= OG/T <= 0.2`; errors \
(naming the field) for non-finite or negative inputs, a bilge radius above the half beam or the \
draft, `OG >= sigma T`, `sigma > 1`, or no Lewis form.\n\n\
Cross-flow drag: the double body's sharp-rectangle coefficient (Hoerner 1965; Delany and \
Sorensen 1953) times a rounding factor from 1 at `R/D = 0` to 0.5 at `R/D >= 0.25`; an estimate, \
a user-given coefficient is preferred.\n";

/// The co-simulation of `tests/python/test_sundsdal_roll.py` (pytest, not this generator).
const COSIMULATION: &str = include_str!("report/viscous_cosimulation.md");

/// How the estimates reach the FMU and the RAOs (hand-kept: options and their tests).
const ESTIMATES: &str = include_str!("report/viscous_estimates.md");

fn main() {
    let started = Instant::now();
    let out = Output::from_args();
    let mut doc = String::new();
    let _ = writeln!(doc, "# Viscous roll damping and cross-flow drag\n");
    let _ = writeln!(
        doc,
        "Generated by {}; the last section, measured by `tests/python/test_sundsdal_roll.py`, \
         is kept in `examples/report/viscous_cosimulation.md`, the sections on the estimates in \
         the FMU and the RAOs in `examples/report/viscous_estimates.md`. Do not edit by hand.\n",
        plot::provenance(COMMAND)
    );
    doc.push_str(INTRODUCTION);
    doc.push('\n');
    doc.push_str(ESTIMATES);

    // 1. The sections' inputs.
    let sections = sections();
    let _ = writeln!(doc, "\n## The sections\n");
    let _ = writeln!(
        doc,
        "Inputs from the hull files (`examples/hulls/`): waterline breadth B and area coefficient \
         `sigma = A / (B T)` from the hydrostatics, draft T and bilge radius R from the files' \
         comments, the roll axis (OG below the waterline) from the roll DOF. The midship section \
         with keels adds bilge keels of {} m over {:.0} % of the length (an assumed, typical \
         fit). rho = {RHO} kg/m^3, nu = 1.19e-6 m^2/s. Warnings: where the section lies outside \
         the range in which Ikeda's formulas were checked.\n",
        MIDSHIP_KEELS.breadth,
        100.0 * MIDSHIP_KEELS.length_fraction
    );
    let _ = writeln!(
        doc,
        "| section | B (m) | T (m) | sigma | R (m) | OG (m) | B/T | OG/T | warnings |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    for s in &sections {
        let p = &s.params;
        let warnings = p.validate().expect("valid section");
        let listed: Vec<String> = warnings.iter().map(|w| w.field.to_string()).collect();
        let _ = writeln!(
            doc,
            "| {} | {} | {} | {:.4} | {} | {} | {:.2} | {:.3} | {} |",
            s.name,
            p.breadth,
            p.draft,
            p.area_coefficient,
            p.bilge_radius,
            p.roll_axis_height,
            p.breadth / p.draft,
            p.roll_axis_height / p.draft,
            if listed.is_empty() {
                "none".to_string()
            } else {
                listed.join(", ")
            }
        );
    }

    // 2. The components at a few frequencies and amplitudes.
    let _ = writeln!(doc, "\n## Components\n");
    let _ = writeln!(
        doc,
        "Equivalent linear damping of each component, `B_hat = B_eq / (rho A B^2) sqrt(B / (2 g))` \
         at `omega_hat = omega sqrt(B / (2 g))` (= sqrt(xi_B)) and roll amplitude phi_a (rad). \
         Friction is 6-10 % of the barge's total at full scale and 15-29 % of the Sundsdal \
         section's at the flume's scale (B = 0.4 m: a lower Reynolds number); eddy making grows \
         with `omega phi_a` and dominates the naked sections; keels, where present, take the \
         largest share.\n"
    );
    let _ = writeln!(
        doc,
        "| section | omega_hat | phi_a | friction | eddy | keels | total | eddy share |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    for s in &sections {
        for (omega_hat, phi_a) in [(0.5, 0.1), (0.8, 0.1), (0.8, 0.2)] {
            let omega = s.omega(omega_hat);
            let e = equivalent(&s.components(omega, phi_a), omega, phi_a);
            let _ = writeln!(
                doc,
                "| {} | {omega_hat} | {phi_a} | {:.5} | {:.5} | {:.5} | {:.5} | {:.1} % |",
                s.name,
                s.hat(e[0]),
                s.hat(e[1]),
                s.hat(e[2]),
                s.hat(e[3]),
                100.0 * e[1] / e[3]
            );
        }
    }
    if !out.quick {
        doc.push('\n');
        doc.push_str(&component_figures(&out, &sections));
    }

    // 3. Ikeda's measured cylinder.
    let _ = writeln!(doc, "\n## Against Ikeda's measurement\n");
    let _ = writeln!(
        doc,
        "Eddy making of a 2D cylinder, `B_E*_hat = (3 pi / 8) B_E / (rho Disp B^2) sqrt(B / (2 g))` \
         with `B_E = 8/(3 pi) omega phi_a B_q L` (`tests/ikeda.rs` asserts 8 %; data in \
         `tests/data/ikeda/`, rho 1000 kg/m^3).\n"
    );
    let _ = writeln!(
        doc,
        "| cylinder | B (m) | T (m) | sigma | OG/T | phi_a | omega_hat | measured B_E*_hat | ours | error |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    for row in ikeda_rows() {
        let ours = ikeda_estimate(&row);
        let _ = writeln!(
            doc,
            "| rectangle | {} | {} | {} | {} | {} | {} | {} | {:.4} | {:+.1} % |",
            row[0],
            row[1],
            row[2],
            row[4],
            row[7],
            row[8],
            row[9],
            ours,
            100.0 * (ours / row[9] - 1.0)
        );
    }
    let _ = writeln!(
        doc,
        "\nOnly this one cylinder is included: the digitized Ikeda (1978) table (Alexandersson, \
         Mendeley, doi 10.17632/p3r9nmtvyj.1) is not part of the public repository \
         `martinlarsalbert/rolldecay-estimators`."
    );

    // 4. The floating Sundsdal section at its roll resonance, frequency domain.
    doc.push_str(&resonance_section(&out, &sections[0]));
    doc.push_str(COSIMULATION);

    let path = out.write_page("VISCOUS", &doc);
    eprintln!(
        "wrote {} in {:.1} s",
        path.display(),
        started.elapsed().as_secs_f64()
    );
    if out.quick {
        report::check_against_docs(
            "VISCOUS",
            &doc,
            &["section", "omega_hat", "phi_a", "cylinder", "xi_B", "wave"],
            &|_| true,
            Tolerance {
                relative: 0.0,
                absolute: 0.0,
                units: 2.0,
            },
        );
    }
}

/// The floating Sundsdal section's roll against the flume (scenario B) at the periods near its
/// roll resonance, and the FMU's coefficients at the resonance.
fn resonance_section(out: &Output, section: &Section) -> String {
    let mut doc = String::new();
    let _ = writeln!(
        doc,
        "\n## Roll near resonance: the Sundsdal section, frequency domain\n"
    );
    let _ = writeln!(
        doc,
        "The floating section of Sundsdal et al. (2025) (`examples/hulls/sundsdal_floating.xml`, \
         docs/DRIFT.md) in the flume's regular beam waves of amplitude a (scenario B, \
         `tests/data/sundsdal/scenario_B.csv`; roll per wave slope `k a`, `k = omega^2 / g`): \
         our RAO (deep water, `hydrofmu::motion::Floating`) without viscous damping, \
         and with Ikeda's damping (the FMU's coefficients below) as the equivalent linear \
         damping at the amplitude it produces (solved by bisection). xi_B < 0.65 is shallow for \
         deep-water theory (`h / lambda` < 0.5).\n"
    );
    let _ = writeln!(
        doc,
        "| xi_B | wave | a (mm) | h/lambda | roll/ka measured | ours, potential flow | ours, with Ikeda | phi_a (rad) | B_eq (N m s/m) |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    let rows = flume();
    let mut kr = vec![OUR_RESONANCE_XI];
    kr.extend(
        rows.iter()
            .map(|r| r.xi)
            .filter(|x| (0.5..=0.6).contains(x)),
    );
    kr.dedup();
    let result = sweep_at(&section.hull, kr.clone());
    let omega_of = |xi: f64| (xi * G / section.hull.reference_half_beam()).sqrt();
    // The FMU's coefficients: Ikeda's at the flume's resonance and the amplitude they give.
    let at = kr
        .iter()
        .position(|x| *x == RESONANCE_XI)
        .expect("resonance");
    let resonance = rows.iter().find(|r| r.xi == RESONANCE_XI).expect("row");
    let omega = omega_of(RESONANCE_XI);
    let ikeda = |phi: f64| section.components(omega, phi).total();
    let (_, phi) = roll_amplitudes(section, &result, at, resonance.amplitude, &ikeda);
    let packed = ikeda(phi);
    for (index, xi) in kr.iter().enumerate() {
        let row = rows.iter().find(|r| r.xi == *xi);
        let amplitude = row.map_or(OUR_RESONANCE_AMPLITUDE, |r| r.amplitude);
        let omega = omega_of(*xi);
        let ka = omega * omega / G * amplitude;
        let (undamped, phi) = roll_amplitudes(section, &result, index, amplitude, &|_| packed);
        let measured = |f: &dyn Fn(&FlumeRow) -> String| row.map_or("not stored".into(), f);
        let _ = writeln!(
            doc,
            "| {xi} | {} | {:.2} | {} | {} | {:.2} | {:.3} | {:.4} | {:.4} |",
            measured(&|r| r.height.to_string()),
            1000.0 * amplitude,
            measured(&|r| format!("{:.3}", r.h_over_lambda)),
            measured(&|r| format!("{:.3}", r.roll_over_ka)),
            undamped / ka,
            phi / ka,
            phi,
            packed.equivalent_linear(omega, phi)
        );
    }
    let (peak, height) = potential_flow_peak(section);
    let _ = writeln!(
        doc,
        "\nOur potential-flow roll peaks at xi_B {peak:.3} ({height:.1} per k a), below the \
         flume's largest measured roll (xi_B {RESONANCE_XI}; the flume has no stored run at \
         0.5). The FMU's coefficients: Ikeda's at xi_B {RESONANCE_XI} (omega {omega:.4} rad/s) \
         and the amplitude they give there, phi_a {:.4} rad (friction linear at these, eddy \
         making quadratic); the column \"with Ikeda\" uses them at every row, as the FMU does:\n",
        phi
    );
    let _ = writeln!(
        doc,
        "| section | B_l (N m s/m) | B_q (N m s^2/m) |\n| --- | --- | --- |\n| Sundsdal | {:.5} | {:.5} |\n",
        packed.linear, packed.quadratic
    );
    let _ = writeln!(
        doc,
        "`fmu-pack pack examples/hulls/sundsdal_floating.xml --viscous --damping-linear \
         roll={:.5} --damping-quadratic roll={:.5}` (`tests/python/test_sundsdal_roll.py`).",
        packed.linear, packed.quadratic
    );
    if !out.quick {
        doc.push('\n');
        doc.push_str(&resonance_figure(out, section, packed, &rows));
    }
    doc
}

/// The default sweep of `hull` at `kr`.
fn sweep_at(hull: &Hull, kr: Vec<f64>) -> SweepResult {
    let params = SweepParams {
        kr,
        ..SweepParams::default()
    };
    sweep::run(hull, &params, &|_, _| {}).expect("sweep")
}

/// Roll per `k a` across the resonance in waves of 12 mm: potential flow, with the FMU's
/// coefficients, and the flume's stored runs.
fn resonance_figure(out: &Output, section: &Section, packed: Damping, rows: &[FlumeRow]) -> String {
    let kr: Vec<f64> = (0..=80).map(|i| 0.4 + 0.005 * i as f64).collect();
    let result = sweep_at(&section.hull, kr);
    let (mut plain, mut viscous) = (Vec::new(), Vec::new());
    for (index, xi) in result.kr.iter().enumerate() {
        let ka = xi / result.reference_half_beam * OUR_RESONANCE_AMPLITUDE;
        let (undamped, phi) =
            roll_amplitudes(section, &result, index, OUR_RESONANCE_AMPLITUDE, &|_| {
                packed
            });
        plain.push((*xi, undamped / ka));
        viscous.push((*xi, phi / ka));
    }
    let mut figure = Figure::new(
        "Sundsdal section, floating: roll near its resonance, a = 12 mm",
        "xi_B = omega^2 B / (2 g)",
        "roll / (k a)",
    );
    figure.add("ours, potential flow", plain, Style::Line);
    figure.add("ours, with Ikeda's damping", viscous, Style::Line);
    figure.add(
        "flume (scenario B)",
        rows.iter()
            .filter(|r| (0.4..=0.8).contains(&r.xi))
            .map(|r| (r.xi, r.roll_over_ka))
            .collect(),
        Style::Markers,
    );
    save(out, &mut figure, "viscous-sundsdal-resonance")
}

/// Where our roll per `k a` peaks without viscous damping, and its height (xi_B 0.45 .. 0.6).
fn potential_flow_peak(section: &Section) -> (f64, f64) {
    let kr: Vec<f64> = (0..=60).map(|i| 0.45 + 0.0025 * i as f64).collect();
    let result = sweep_at(&section.hull, kr);
    let properties = section
        .hull
        .mass()
        .expect("mass")
        .properties(&section.hull, RHO)
        .expect("properties");
    let motions = section_motion::motions(&section.hull, &properties, &result, RHO, G, 0.0);
    let r = result.reference_half_beam;
    result
        .kr
        .iter()
        .zip(&motions)
        .map(|(xi, motion)| (*xi, motion[2].norm() / (xi / r)))
        .fold(
            (0.0, 0.0),
            |best, point| {
                if point.1 > best.1 {
                    point
                } else {
                    best
                }
            },
        )
}

/// Figures: the components of the Sundsdal section against amplitude at its resonance, and
/// the sections' totals against frequency.
fn component_figures(out: &Output, sections: &[Section]) -> String {
    let sundsdal = &sections[0];
    let omega = sundsdal.omega(RESONANCE_XI.sqrt());
    let amplitudes: Vec<f64> = (1..=40).map(|i| 0.01 * i as f64).collect();
    let mut by_amplitude = Figure::new(
        "Sundsdal section: Ikeda's components at xi_B 0.525",
        "roll amplitude phi_a (rad)",
        "B_eq / (rho A B^2) sqrt(B / (2 g))",
    );
    let names = ["friction", "eddy making", "keels", "total"];
    for (k, name) in names.iter().enumerate() {
        if k == 2 {
            continue;
        }
        let points = amplitudes
            .iter()
            .map(|&phi| {
                let e = equivalent(&sundsdal.components(omega, phi), omega, phi);
                (phi, sundsdal.hat(e[k]))
            })
            .collect();
        by_amplitude.add(name, points, Style::Line);
    }
    let mut by_frequency = Figure::new(
        "Ikeda's components against frequency, phi_a = 0.1 rad",
        "omega_hat = omega sqrt(B / (2 g))",
        "B_eq / (rho A B^2) sqrt(B / (2 g))",
    );
    by_frequency.y_scale = Scale::Log;
    let grid: Vec<f64> = (1..=30).map(|i| 0.05 * i as f64).collect();
    for s in sections {
        for (k, name) in names.iter().enumerate() {
            // Totals of every section; the barge's and the keeled midship's main components.
            let shown =
                k == 3 || (s.name == "barge" && k < 2) || (s.name == "midship, keels" && k != 1);
            if !shown {
                continue;
            }
            let points = grid
                .iter()
                .map(|&w| {
                    let omega = s.omega(w);
                    let e = equivalent(&s.components(omega, 0.1), omega, 0.1);
                    (w, s.hat(e[k]))
                })
                .collect();
            let style = if k == 3 { Style::Line } else { Style::Dashed };
            by_frequency.add(&format!("{}, {name}", s.name), points, style);
        }
    }
    let mut text = save(out, &mut by_amplitude, "viscous-sundsdal-amplitude");
    text.push_str(&save(out, &mut by_frequency, "viscous-sections-frequency"));
    text
}

fn ikeda_rows() -> Vec<Vec<f64>> {
    include_str!("../tests/data/ikeda/rectangle.csv")
        .lines()
        .skip(1)
        .map(|line| {
            line.split(',')
                .map(|v| v.parse().expect("number"))
                .collect()
        })
        .collect()
}

/// Our `B_E*_hat` of one row of `tests/data/ikeda/` (as `tests/ikeda.rs`).
fn ikeda_estimate(row: &[f64]) -> f64 {
    let rho = 1000.0;
    let [beam, draft, sigma, radius, og_over_draft, length, displacement, phi_a, omega_hat] =
        [0, 1, 2, 3, 4, 5, 6, 7, 8].map(|i| row[i]);
    let mut params = RollDampingParams::new(beam, draft, sigma, radius);
    params.roll_axis_height = og_over_draft * draft;
    params.rho = rho;
    let quadratic = eddy_making(&params).expect("valid row").quadratic;
    let omega = omega_hat * (2.0 * G / beam).sqrt();
    let linear = 8.0 / (3.0 * PI) * omega * phi_a * quadratic * length;
    let hat = linear / (rho * displacement * beam * beam) * (beam / (2.0 * G)).sqrt();
    3.0 * PI / 8.0 * hat
}
