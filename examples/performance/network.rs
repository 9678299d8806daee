//! The time-domain half of the performance report: network order against fit error and
//! step cost, communication step against coupling error and wall time (reference: the
//! monolithic system of Schilder et al.'s eq. 19), the scene-reduced FMU, and the network against a direct
//! convolution.

// The benchmark's baseline (benches/common/convolution.rs), shared with `cargo bench`; its
// unit tests run in tests/convolution.rs. Not every item is used here.
#[allow(dead_code)]
#[path = "../../benches/common/convolution.rs"]
mod convolution;
use convolution::ConvolutionForce;
use fmu_pack::plot::{self, Figure, Scale, Style};
use hydrofmu::discretize::{discretize, expm};
use hydrofmu::fmu::Quantity;
use hydrofmu::hull::Hull;
use hydrofmu::identify::{self, CoupledMethod, FitParams, FitReport, FrequencyResponse};
use hydrofmu::model::{Model, ModelOptions};
use hydrofmu::network::{Network, NetworkForm};
use hydrofmu::sweep::{self, SweepParams};
use nalgebra::{DMatrix, DVector};
use std::fmt::Write as _;
use std::time::Instant;

use super::report::Output;

const RHO: f64 = 1025.0;
const G: f64 = 9.81;
/// The default fit band, kR 0.05 .. 5, in rad/s for R = 1 m.
fn default_band() -> (f64, f64) {
    ((0.05 * G).sqrt(), (5.0 * G).sqrt())
}

fn try_model(network: &Network) -> Result<Model, String> {
    Model::new(network, ModelOptions::default()).map_err(|e| e.to_string())
}

fn model_of(network: &Network) -> Model {
    try_model(network).expect("model")
}

/// [`step_cost`], or the error when the network cannot be stepped (a degenerate fit).
fn try_step_cost(network: &Network) -> Result<f64, String> {
    try_model(network)?
        .step(0.0, 0.01)
        .map_err(|e| e.to_string())?;
    Ok(step_cost(network))
}

/// Median wall time (ns) of one set-velocities + step + get-forces, over 5 batches.
fn step_cost(network: &Network) -> f64 {
    let mut model = model_of(network);
    let n = model.dof_count();
    let h = 0.01;
    let batch = 20_000;
    let mut times = Vec::new();
    let mut sink = 0.0;
    for _ in 0..5 {
        let start = Instant::now();
        for k in 0..batch {
            for i in 0..n {
                let v = ((k % 1000) as f64 * 1e-3 + 0.1 * i as f64).sin();
                model.set_value(Quantity::Velocity(i), v).expect("input");
            }
            model.step(model.time(), h).expect("step");
            sink += model.forces()[0];
        }
        times.push(start.elapsed().as_secs_f64() * 1e9 / batch as f64);
    }
    std::hint::black_box(sink);
    times.sort_by(f64::total_cmp);
    times[2]
}

/// A fit as `fmu-pack` makes it: `form` `None` is the automatic form.
fn fit(
    data: &FrequencyResponse,
    form: Option<NetworkForm>,
    band: (f64, f64),
    order: Option<usize>,
) -> FitReport {
    identify::fit(
        data,
        &FitParams {
            form,
            band,
            order,
            ..FitParams::default()
        },
    )
    .expect("fit")
}

/// kR to rad/s for R = 1 m.
fn omega_of(kr: f64) -> f64 {
    (kr * G).sqrt()
}

/// The sway body of the co-simulation examples: displaced mass, spring to the sea bed.
struct SwayScene {
    body_mass: f64,
    spring: f64,
    offset: f64,
    duration: f64,
}

impl SwayScene {
    fn new(added_mass_inf: f64) -> SwayScene {
        let body_mass = RHO * std::f64::consts::PI / 2.0;
        // Natural period about 4 s with the high-frequency added mass.
        let omega: f64 = 2.0 * std::f64::consts::PI / 4.0;
        SwayScene {
            body_mass,
            spring: (body_mass + added_mass_inf) * omega * omega,
            offset: 0.5,
            duration: 60.0,
        }
    }

    /// Monolithic Schilder et al., eq. 19: body + network augmented M, C, K, plus the spring, released
    /// from the offset with every network spring unstretched. Exact at the sample times.
    fn monolithic(&self, network: &Network, h: f64, steps: usize) -> Vec<f64> {
        let aug = network.augmented_matrices().expect("branches only");
        let size = aug.mass.nrows();
        let mut mass = aug.mass.clone();
        let mut stiffness = aug.stiffness.clone();
        mass[(0, 0)] += self.body_mass;
        stiffness[(0, 0)] += self.spring;
        let inverse = mass.try_inverse().expect("mass matrix");
        let mut a = DMatrix::zeros(2 * size, 2 * size);
        a.view_mut((0, size), (size, size))
            .copy_from(&DMatrix::identity(size, size));
        a.view_mut((size, 0), (size, size))
            .copy_from(&(-&inverse * stiffness));
        a.view_mut((size, size), (size, size))
            .copy_from(&(-&inverse * &aug.damping));
        let phi = expm(&(a * h)).expect("exponential");
        let mut y = DVector::zeros(2 * size);
        y.rows_mut(0, size).fill(self.offset);
        let mut out = Vec::with_capacity(steps + 1);
        for _ in 0..=steps {
            out.push(y[0]);
            y = &phi * y;
        }
        out
    }

    /// Explicit co-simulation (body first, then the FMU model). With `first_order` the body
    /// sees the force ramp from the output derivative and the FMU the velocity ramp to the
    /// body's new velocity; otherwise both hold their inputs (zero-order hold).
    fn cosimulation(&self, network: &Network, h: f64, steps: usize, first_order: bool) -> Vec<f64> {
        let mut model = model_of(network);
        let total_mass = self.body_mass + network.added_mass_inf[(0, 0)];
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -self.spring / total_mass, 0.0]);
        let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0 / total_mass]);
        let body = discretize(&a, &b, h, true).expect("body");
        let gamma1 = body.gamma1.as_ref().expect("first-order hold");
        let mut y = DVector::from_row_slice(&[self.offset, 0.0]);
        let mut out = Vec::with_capacity(steps + 1);
        for _ in 0..=steps {
            out.push(y[0]);
            model
                .set_value(Quantity::Velocity(0), y[1])
                .expect("velocity");
            let force = model.forces()[0];
            let force_rate = if first_order {
                model
                    .output_derivative(Quantity::Force(0))
                    .expect("derivative")
            } else {
                0.0
            };
            let next =
                &body.phi * &y + body.gamma0.column(0) * force + gamma1.column(0) * force_rate;
            if first_order {
                model
                    .set_input_derivative(Quantity::Velocity(0), (next[1] - y[1]) / h)
                    .expect("ramp");
            }
            model.step(model.time(), h).expect("step");
            y = next;
        }
        out
    }
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Writes the sections; `command` goes into the figure captions.
pub fn sections(out: &Output, doc: &mut String, threads: usize, command: &str) {
    eprintln!("semicircle sweep for the network sections ...");
    let hull = Hull::semicircle(1.0).expect("semicircle");
    let params = SweepParams {
        threads,
        ..SweepParams::default()
    };
    let result = sweep::run(&hull, &params, &|_, _| {}).expect("sweep");
    let all = FrequencyResponse::from_sweep(&result, RHO, G);
    let sway = all.select(&["sway"]).expect("sway");
    let band = default_band();

    // --- Network order against fit error and step cost.
    let automatic_full = fit(&all, None, band, None);
    let _ = writeln!(doc, "## Network order against fit error and step cost\n");
    let _ = writeln!(
        doc,
        "Semicircle, default band kR 0.05 .. 5, fixed orders. Two identifications: the branch \
         chains (series chain for one DOF; for 9 DOFs groups of chains, the order counted per \
         invariant block of the data, two for the mirror-symmetric semicircle) and the rational \
         path (passive vector fitting per invariant block, each block realized as a mechanical \
         substructure; order = poles per block, a pair counted twice; the default, \
         `CoupledMethod::Rational`; the chains are `CoupledMethod::Chains`). The default \
         automatic fit of the 9 DOFs meets 1 % with {} states. Error: the fit's largest \
         `|dA_ij| / sqrt(s_i s_j)` in the band. Fit time: one run, wall clock. Step cost: \
         median wall time of one set-velocities + step + get-forces through the Rust model (no \
         C ABI), 5 batches of 20 000 steps; `cargo bench --bench step` measures the C ABI path \
         of the default 9-DOF network independently.\n",
        automatic_full.states
    );
    let _ = writeln!(
        doc,
        "| DOFs | method | order | states | error | fit time (ms) | step cost (ns) |\n| --- | --- | --- | --- | --- | --- | --- |"
    );
    let mut curves: Vec<(&str, Vec<(f64, f64)>)> = Vec::new();
    let mut degenerate = Vec::new();
    let mut rows = |label: &str,
                    form: NetworkForm,
                    method: CoupledMethod,
                    orders: &[usize],
                    data: &FrequencyResponse| {
        let mut curve = Vec::new();
        for &order in orders {
            eprintln!("{label}, order {order} ...");
            let forced = FitParams {
                form: Some(form),
                band,
                order: Some(order),
                coupled_method: method,
                ..FitParams::default()
            };
            let start = Instant::now();
            let result = identify::fit(data, &forced);
            let fit_time = start.elapsed().as_secs_f64() * 1e3;
            let report = match result {
                Ok(report) => report,
                Err(e) => {
                    let _ = writeln!(doc, "| {label} | {order} | - | refused | - | - |");
                    degenerate.push(format!("{label} order {order}: {e}"));
                    continue;
                }
            };
            if let Some(note) = report
                .notes
                .iter()
                .find(|n| n.starts_with("the rational path failed"))
            {
                let _ = writeln!(
                    doc,
                    "| {label} | {order} | - | no passive fit (the chains would be used) | - | - |"
                );
                degenerate.push(format!("{label} order {order}: {note}"));
                continue;
            }
            let cost = match try_step_cost(&report.network) {
                Ok(cost) => {
                    curve.push((report.states as f64, report.max_relative_error));
                    format!("{cost:.0}")
                }
                Err(e) => {
                    degenerate.push(format!("{label} order {order}: {e}"));
                    "fails".into()
                }
            };
            let _ = writeln!(
                doc,
                "| {label} | {order} | {} | {:.3} % | {fit_time:.1} | {cost} |",
                report.states,
                100.0 * report.max_relative_error
            );
        }
        curve
    };
    let sway_chain = rows(
        "sway | series chain",
        NetworkForm::SeriesChain,
        CoupledMethod::Chains,
        &[1, 2, 3, 4, 5],
        &sway,
    );
    let sway_rational = rows(
        "sway | rational",
        NetworkForm::Coupled,
        CoupledMethod::Rational,
        &[2, 3, 4, 5, 6],
        &sway,
    );
    let full_chains = rows(
        "9 | chains",
        NetworkForm::Coupled,
        CoupledMethod::Chains,
        &[2, 4, 6, 8, 10, 12],
        &all,
    );
    let full_rational = rows(
        "9 | rational",
        NetworkForm::Coupled,
        CoupledMethod::Rational,
        &[2, 3, 4, 5, 6, 7, 8],
        &all,
    );
    curves.push(("sway, series chain", sway_chain));
    curves.push(("sway, rational", sway_rational));
    curves.push(("9 DOFs, chains", full_chains));
    curves.push(("9 DOFs, rational", full_rational));
    if !degenerate.is_empty() {
        let _ = writeln!(
            doc,
            "\nForced orders beyond what the tolerance needs can over-fit: the least-squares \
             optimum then has a stage of negligible mass with extreme stiffness or damping, \
             whose time constants no step resolves, or a pole far outside the band. The fitter \
             refuses such networks; the automatic order (the smallest that meets the tolerance) \
             stops before that. A forced rational order can also end without passive residues \
             (the exact check still fails after the enforcement's 6 rounds); the fit then falls back to the \
             chains. Refused here:\n"
        );
        for d in &degenerate {
            let _ = writeln!(doc, "- {d}");
        }
    }
    let mut figure = Figure::new(
        "network order: fit error against states",
        "states of the network",
        "largest fit error in the band",
    );
    figure.x_scale = Scale::Log;
    figure.y_scale = Scale::Log;
    for (label, curve) in curves {
        figure.add(label, curve, Style::Markers);
    }
    figure.add(
        "1 % default tolerance",
        vec![(1.0, 0.01), (200.0, 0.01)],
        Style::Dashed,
    );
    figure.caption = plot::provenance(command);
    out.write_figure("performance-order", &figure.to_svg());
    let _ = writeln!(doc, "\n![order](figures/performance-order.svg)\n");

    // --- The identification against the peers (issue table, re-measured).
    peers(doc, &all, &sway);

    // --- Communication step against coupling error and wall time.
    let chain = fit(&sway, Some(NetworkForm::SeriesChain), band, None);
    let scene = SwayScene::new(chain.network.added_mass_inf[(0, 0)]);
    let _ = writeln!(
        doc,
        "## Communication step against coupling error and wall time\n"
    );
    let _ = writeln!(
        doc,
        "A rigid semicircle (R = 1 m, mass {:.0} kg/m, the displaced mass) in sway on a spring \
         of {:.0} N/m^2 to the sea bed (natural period 4 s with A_inf), released from {} m \
         and simulated for {} s, coupled explicitly to the sway network (series chain, {} \
         auxiliary masses, default tolerance). The master adds `added_mass_inf` to the body's \
         mass and integrates the body exactly over each step with the force held (zero-order \
         hold) or ramped by the FMU's output derivative while the FMU ramps the velocity \
         (first-order hold). Error: largest |x - x_ref| over the run, where x_ref is the \
         monolithic seed eq. 19 system (body + network M, C, K + spring), solved exactly. Wall \
         time: median of 5 runs.\n",
        scene.body_mass, scene.spring, scene.offset, scene.duration, chain.aux_dofs
    );
    let _ = writeln!(
        doc,
        "| step h (s) | error, zero-order hold (m) | error, first-order hold (m) | wall time, first-order hold (ms) |\n| --- | --- | --- | --- |"
    );
    let mut zoh_curve = Vec::new();
    let mut foh_curve = Vec::new();
    let mut observed = Vec::new();
    for h in [0.4, 0.2, 0.1, 0.05, 0.025, 0.0125] {
        let steps = (scene.duration / h).round() as usize;
        let reference = scene.monolithic(&chain.network, h, steps);
        let zoh = max_difference(
            &scene.cosimulation(&chain.network, h, steps, false),
            &reference,
        );
        let mut times = Vec::new();
        let mut foh = 0.0;
        for _ in 0..5 {
            let start = Instant::now();
            let run = scene.cosimulation(&chain.network, h, steps, true);
            times.push(start.elapsed().as_secs_f64() * 1e3);
            foh = max_difference(&run, &reference);
        }
        times.sort_by(f64::total_cmp);
        zoh_curve.push((h, zoh));
        foh_curve.push((h, foh));
        observed.push((h, zoh, foh));
        let _ = writeln!(doc, "| {h} | {zoh:.2e} | {foh:.2e} | {:.2} |", times[2]);
    }
    let order = |pick: fn(&(f64, f64, f64)) -> f64| {
        let (first, last) = (observed[1], observed[observed.len() - 1]);
        (pick(&first) / pick(&last)).ln() / (first.0 / last.0).ln()
    };
    let _ = writeln!(
        doc,
        "\nObserved orders between h = {} and {} s: {:.2} (zero-order hold), {:.2} (first-order \
         hold), as the hold orders predict (1 and 2).\n",
        observed[1].0,
        observed[observed.len() - 1].0,
        order(|o| o.1),
        order(|o| o.2)
    );
    let mut figure = Figure::new(
        "sway body on a spring: coupling error against step",
        "communication step h (s)",
        "largest |x - x_monolithic| (m)",
    );
    figure.x_scale = Scale::Log;
    figure.y_scale = Scale::Log;
    figure.add("zero-order hold", zoh_curve, Style::Line);
    figure.add("first-order hold (derivatives)", foh_curve, Style::Line);
    figure.caption = plot::provenance(command);
    out.write_figure("performance-coupling", &figure.to_svg());
    let _ = writeln!(doc, "![coupling](figures/performance-coupling.svg)\n");

    // --- Scene-driven: sway only in a narrow band against the full 9-DOF default.
    let narrow_band = ((0.3 * G).sqrt(), (2.0 * G).sqrt());
    let narrow = fit(&sway, None, narrow_band, None);
    let full = automatic_full;
    let (narrow_cost, full_cost) = (step_cost(&narrow.network), step_cost(&full.network));
    let _ = writeln!(doc, "## Modelling only what the scene needs\n");
    let _ = writeln!(
        doc,
        "`fmu-pack pack semicircle --dofs sway --band 0.3:2` against the default \
         `fmu-pack pack semicircle` (all 9 DOFs, kR 0.05 .. 5), both at the 1 % default \
         tolerance:\n"
    );
    let _ = writeln!(
        doc,
        "| FMU | DOFs | states | error in its band | step cost (ns) |\n| --- | --- | --- | --- | --- |\n\
         | sway, kR 0.3 .. 2 | 1 | {} | {:.2} % | {narrow_cost:.0} |\n\
         | full default | 9 | {} | {:.2} % | {full_cost:.0} |\n",
        narrow.states,
        100.0 * narrow.max_relative_error,
        full.states,
        100.0 * full.max_relative_error
    );
    let _ = writeln!(
        doc,
        "The sway scene's FMU has {:.1} % of the full state size and steps {:.0} times faster.\n",
        100.0 * narrow.states as f64 / full.states as f64,
        full_cost / narrow_cost
    );

    // --- Network against direct convolution.
    let ss = full.network.state_space().expect("state space");
    let h = 0.01;
    let history = 6000;
    let n = ss.input_count();
    let steps = 6000;
    // Velocity of DOF i at time t: smooth, ramped in over 5 s.
    let signal = |t: f64, i: usize| {
        let ramp = (t / 5.0).min(1.0);
        ramp * (0.8 + 0.3 * i as f64) * (1.3 * t + i as f64).sin()
    };
    let input = |k: usize, i: usize| signal(k as f64 * h, i);
    // Reference: the network with first-order hold at h / 8 (O(h^2) from the smooth input).
    let network_forces = |sub: usize, first_order: bool| -> Vec<f64> {
        let mut model = model_of(&full.network);
        let mut out = Vec::with_capacity(steps + 1);
        let hs = h / sub as f64;
        for k in 0..=steps * sub {
            let value = |k: usize, i: usize| signal(k as f64 * hs, i);
            for i in 0..n {
                model
                    .set_value(Quantity::Velocity(i), value(k, i))
                    .expect("v");
                if first_order {
                    let rate = (value(k + 1, i) - value(k, i)) / hs;
                    model
                        .set_input_derivative(Quantity::Velocity(i), rate)
                        .expect("dv");
                }
            }
            if k % sub == 0 {
                out.extend(model.forces().iter().copied());
            }
            model.step(model.time(), hs).expect("step");
        }
        out
    };
    let reference = network_forces(8, true);
    let network_run = network_forces(1, true);
    let mut convolution = ConvolutionForce::new(&ss, h, history).expect("kernel");
    let mut force = DVector::zeros(n);
    let mut convolution_run = Vec::with_capacity((steps + 1) * n);
    for k in 0..=steps {
        let v = DVector::from_fn(n, |i, _| input(k, i));
        convolution.push(&v, &mut force).expect("convolution");
        convolution_run.extend(force.iter().copied());
    }
    let scale = reference.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let network_error = max_difference(&network_run, &reference) / scale;
    let convolution_error = max_difference(&convolution_run, &reference) / scale;
    let mut times = Vec::new();
    for _ in 0..5 {
        let start = Instant::now();
        for k in 0..500 {
            let v = DVector::from_fn(n, |i, _| input(k, i));
            convolution.push(&v, &mut force).expect("convolution");
        }
        times.push(start.elapsed().as_secs_f64() * 1e9 / 500.0);
    }
    times.sort_by(f64::total_cmp);
    let convolution_cost = times[2];
    let _ = writeln!(doc, "## Network against direct convolution\n");
    let _ = writeln!(
        doc,
        "The default 9-DOF network's radiation force, `F = D v + integral K(t - tau) v(tau) \
         dtau`, computed two ways for 9 smooth velocity signals over {} s at h = {h} s: by the \
         network (exact stepping, first-order hold) and by direct convolution with the same \
         retardation function `K(t) = C exp(A t) B` over a {history}-step history (trapezoidal \
         rule, `benches/common/convolution.rs`). Error: largest force difference from the network at \
         h/8, relative to the largest force.\n",
        steps as f64 * h
    );
    let _ = writeln!(
        doc,
        "| method | error | cost per step (ns) |\n| --- | --- | --- |\n\
         | network, {} states | {network_error:.1e} | {full_cost:.0} |\n\
         | convolution, {history}-step history | {convolution_error:.1e} | {convolution_cost:.0} |\n",
        full.states
    );
    let _ = writeln!(
        doc,
        "At equal step, the network is as accurate or more, and {:.0} times cheaper per step \
         (measured in this run; `cargo bench --bench step` and `cargo bench -p fmu-pack --bench \
         convolution` measure both independently).\n",
        convolution_cost / full_cost
    );
}

/// The side-by-side table, re-measured: the chains and the rational path against the
/// peer (pyvectorfit with passivity enforcement; numbers as reported to the project).
fn peers(doc: &mut String, all: &FrequencyResponse, sway: &FrequencyResponse) {
    let narrow = (omega_of(0.05), omega_of(5.0));
    let wide = (omega_of(0.01), omega_of(5.0));
    let run = |data: &FrequencyResponse, band, method, order: Option<usize>| {
        eprintln!("peers table: {method:?}, order {order:?} ...");
        let params = FitParams {
            band,
            order,
            coupled_method: method,
            form: (data.dof_count() > 1 || method == CoupledMethod::Rational)
                .then_some(NetworkForm::Coupled),
            ..FitParams::default()
        };
        match identify::fit(data, &params) {
            Ok(r) => format!(
                "{} states, {:.3} %{}",
                r.states,
                100.0 * r.max_relative_error,
                if r.tolerance_met { "" } else { " (misses 1 %)" }
            ),
            Err(e) => format!("refused ({e})"),
        }
    };
    let _ = writeln!(doc, "## Identification against the peers\n");
    let _ = writeln!(
        doc,
        "The semicircle's data, tolerance 1 % in the error of the previous section. Chains: the \
         identification before the rational path (sway: series chain; 9 DOFs: groups of \
         chains). Rational: `CoupledMethod::Rational`. Automatic: the smallest order within 1 %; fixed orders \
         show what more poles buy. Peer: pyvectorfit with passivity enforcement, as reported to \
         the project (not run here).\n"
    );
    let _ = writeln!(
        doc,
        "| case | chains | rational | peer (as reported) |\n| --- | --- | --- | --- |"
    );
    let rows = [
        (
            "sway, kR 0.05 .. 5, automatic",
            run(sway, narrow, CoupledMethod::Chains, None),
            run(sway, narrow, CoupledMethod::Rational, None),
            "4 states, 0.20 %",
        ),
        (
            "sway, order 5 (rational) / 3 (chain)",
            run(sway, narrow, CoupledMethod::Chains, Some(3)),
            run(sway, narrow, CoupledMethod::Rational, Some(5)),
            "5 states, 0.012 %",
        ),
        (
            "9 DOFs, kR 0.05 .. 5, automatic",
            run(all, narrow, CoupledMethod::Chains, None),
            run(all, narrow, CoupledMethod::Rational, None),
            "25 states, 0.99 %",
        ),
        (
            "9 DOFs, kR 0.05 .. 5, rational order 8",
            "-".to_string(),
            run(all, narrow, CoupledMethod::Rational, Some(8)),
            "40 states, 0.073 %",
        ),
        (
            "9 DOFs, kR 0.01 .. 5, automatic",
            run(all, wide, CoupledMethod::Chains, None),
            run(all, wide, CoupledMethod::Rational, None),
            "35 states, 0.35 %",
        ),
    ];
    for (case, chains, rational, peer) in rows {
        let _ = writeln!(doc, "| {case} | {chains} | {rational} | {peer} |");
    }
    let _ = writeln!(
        doc,
        "\nOn inputs nobody tuned the fit to (ship sections, imported databases, 7 frequencies, \
         a noisy coarse mesh): states, error and fit time in docs/IDENTIFICATION.md \
         (`cargo run --release -p fmu-pack --example identification`).\n"
    );
}
