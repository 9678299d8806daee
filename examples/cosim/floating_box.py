"""A free-floating rigid box barge in regular waves: its 6 rigid DOFs coupled under fmpy to the
FMU of Capytaine's WAMIT database (`fmu-pack pack box.1`), the steady RAOs against the
frequency-domain RAOs from Capytaine's own coefficients and from the FMU's network.

Run (from the repository root, with the .venv of tests/python/requirements.txt):

    .venv/bin/python examples/cosim/floating_box.py            # 2 headings x 9 frequencies, writes target/reports/figures/cosim-floating-box.svg (--update-docs: docs/figures/)
    .venv/bin/python examples/cosim/floating_box.py --quick    # head seas, 3 frequencies, no figure (the test)

The database: examples/databases/capytaine_box_barge.py (Capytaine 3.0, coarse mesh, about 15 s;
box 40 m x 10 m x 3 m, 6 DOFs about the origin on the free surface, omega 0.2 .. 2.5 rad/s step
0.1, headings 0/90/180 deg) writes box.1/.3/.hst and box.json into examples/cosim/fmus/box_barge/
on first use (`--database DIR` takes another folder that holds them); the FMU
examples/cosim/fmus/BoxBarge.fmu is packed on first use with `fmu-pack pack DIR/box.1 --tol
0.004` (PACK_TOLERANCE, the whole band). The RAO at a lightly damped resonance is set by the
damping there and amplifies the fit's error: with the default 1 % tolerance (55 states, 0.95 %)
the network's head-sea pitch RAO is 1.4e-2 of its largest off Capytaine's; 0.4 % asks each
invariant block for more poles (66 states, 0.70 %, the coarse mesh's noise floor 0.76 %) and
brings it to 7.7e-3.

The body (coordinates p = the FMU's surge .. yaw, T = I; moments about the origin):

* M = the rigid body's mass matrix from box.json (`inertia_matrix`): the displaced mass
  m = rho L B T = 1.23e6 kg as a homogeneous solid box L x B x T centred at the origin, so the
  centre of gravity is at the origin as the database assumes: I_44 = m (B^2 + T^2) / 12,
  I_55 = m (L^2 + T^2) / 12, I_66 = m (L^2 + B^2) / 12, no coupling terms (a choice; the RAO
  comparison holds for any M, both sides use the same);
* K = the FMU's `stiffness_hydrostatic` (Capytaine's buoyancy restoring; the centre of gravity
  on the free surface, so no -m g z_G term; surge, sway and yaw have none);
* no structural damping: the water's radiation damping only.

Frequency domain (convention exp(+i omega t)), per unit wave amplitude:

    [C - omega^2 (M + A~(omega))] xi = X(omega, heading),   A~ = a - i b / omega

with Capytaine's a, b and X = conj(X_capytaine) from box.json ("Capytaine"; its A~ as Capytaine
gives it, not symmetrized), or A~ = the FMU's network H(i omega) and the same X ("network":
what the time domain solves; the FMU's exciting force is the file's to 1e-5). "network -
Capytaine" is then the fit's error, "co-simulation - network" the coupling's and the harmonic
fit's.

Time domain (hydrocosim.cosimulate under fmpy, scheme "ramp", h = 0.05 s, 52 steps per period at
2.4 rad/s): regular waves of amplitude 0.5 m, the period exactly the .3 file's (no interpolation in
the FMU), wave.ramp 30 s, from rest. The RAO is the least-squares fit of the last 120 s to
x0 + x1 t + Re[c e^(i omega t)] + the body's lightly damped free modes (see below), divided by the
amplitude.

Roll resonance. The box rolls freely at 0.95 rad/s with a radiation damping ratio of about 5e-4
(Capytaine's b_44 at the coarse mesh; a sharp-edged barge's real roll damping is viscous, which
potential flow leaves out): its free roll, which any start excites, decays as e^(-t / 2000 s).
A steady state in the plain sense would take hours, and at the resonance itself the RAO is set by
a damping that the fit (1 % of |A~|) does not resolve. So (1) no beam-sea frequency is taken in
0.8 .. 1.1 rad/s, and (2) the fit takes out the free modes that have not died out by the window:
the eigenvalues lambda of the coupled body + network (Schilder et al., eq. 19) with Im lambda > 0 and
exp(Re lambda t_window) > 1e-6, as terms Re[d e^(lambda t)] beside the wave's harmonic (a linear
system's response is exactly the steady harmonic plus its modes). Only the roll mode (0.948 rad/s,
damping ratio 1.6e-3 in the network) qualifies; in head seas the symmetric body does not roll and
its term fits nothing. Without it the beam-sea roll RAO is off by 1.3e-3 of the largest, with it
by 4.7e-5.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import hydrocosim as hc  # noqa: E402

# The fit tolerance of the example's FMU (module docs: the RAO at resonance needs 0.4 %).
PACK_TOLERANCE = "0.004"
DATABASE_SCRIPT = hc.ROOT / "examples" / "databases" / "capytaine_box_barge.py"
DATABASE_DIR = hc.FMU_DIR / "box_barge"
FMU_NAME = "BoxBarge"
DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")
AMPLITUDE = 0.5  # m, wave amplitude (wave.height = 1 m)
RAMP = 30.0  # s, wave.ramp
WINDOW = 120.0  # s, the last part of a run that the fit sees
SETTLE = 100.0  # s, from the end of the ramp to the window
STEP = 0.05  # s, communication step
SLOW = 1e-6  # a free mode is fitted when exp(Re lambda t_window) exceeds this
# The co-simulated points: heading (deg) -> wave frequencies (rad/s, database frequencies).
HEAD = 180.0
BEAM = 90.0
POINTS = {
    HEAD: (0.4, 0.7, 0.9, 1.0, 1.1, 1.2, 1.4, 1.7, 2.2),
    BEAM: (0.4, 0.6, 0.7, 1.2, 1.3, 1.5, 1.8, 2.1, 2.4),  # none in 0.8 .. 1.1: roll resonance
}
QUICK_POINTS = {HEAD: (0.6, 1.1, 1.6)}
# The DOFs each heading's RAOs are reported for.
REPORTED = {HEAD: ("heave", "pitch"), BEAM: ("sway", "heave", "roll")}
FIGURE = "cosim-floating-box.svg"


# --------------------------------------------------------------------------- database


def ensure_database(folder=None) -> pathlib.Path:
    """The folder holding box.1/.3/.hst and box.json; runs the Capytaine script when missing."""
    folder = pathlib.Path(folder) if folder else DATABASE_DIR
    if not all((folder / f"box{ext}").is_file() for ext in (".1", ".3", ".hst", ".json")):
        print(f"running {DATABASE_SCRIPT.relative_to(hc.ROOT)} {folder}", file=sys.stderr)
        subprocess.run([sys.executable, str(DATABASE_SCRIPT), str(folder)], check=True, capture_output=True)
    return folder


def capytaine(folder: pathlib.Path) -> dict:
    """box.json in our convention: omega (n,), A~ (n, 6, 6), X (heading -> (n, 6)), C, M."""
    data = json.loads((folder / "box.json").read_text())
    omega = np.array(data["omega"])
    a, b = np.array(data["added_mass"]), np.array(data["radiation_damping"])
    xc = np.array(data["excitation_force_re"]) + 1j * np.array(data["excitation_force_im"])
    if "inertia_matrix" in data:
        mass = np.array(data["inertia_matrix"])
    else:  # a box.json of before the key: the same homogeneous box, computed here
        m, lb, bb, tb = data["mass"], data["length"], data["beam"], data["draft"]
        mass = np.diag([m, m, m, m * (bb**2 + tb**2) / 12, m * (lb**2 + tb**2) / 12, m * (lb**2 + bb**2) / 12])
    return {
        "omega": omega,
        "added": a - 1j * b / omega[:, None, None],
        "damping": b,
        "excitation": {h: np.conj(xc[:, k]) for k, h in enumerate(data["headings_deg"])},
        "stiffness": np.array(data["hydrostatic_stiffness"]),
        "mass": mass,
        "rho": data["rho"],
        "g": data["g"],
    }


def file_periods(folder: pathlib.Path) -> np.ndarray:
    """The periods of box.3 as the file prints them (the FMU's own table rows)."""
    return np.array(sorted({float(line.split()[0]) for line in (folder / "box.3").read_text().splitlines()}))


# --------------------------------------------------------------------------- models


def rao(st: hc.Structure, omega: float, added_mass: np.ndarray, excitation: np.ndarray) -> np.ndarray:
    dynamic = st.stiffness - omega**2 * (st.mass + added_mass) + 1j * omega * st.damping
    return np.linalg.solve(dynamic, excitation)


def slow_modes(st: hc.Structure, network: hc.Network, t_window: float) -> np.ndarray:
    """Eigenvalues (Im > 0) of the coupled body + network still above SLOW of their start at
    t_window."""
    lam = np.linalg.eigvals(hc.coupled_system(st, network))
    keep = (lam.imag > 1e-3) & (np.exp(lam.real * t_window) > SLOW)
    return np.sort_complex(lam[keep])


def steady_fit(t: np.ndarray, x: np.ndarray, omega: float, modes=()) -> np.ndarray:
    """Complex amplitudes c (per column of x) of the least-squares fit
    x(t) = x0 + x1 t + Re[c e^(i omega t)] + sum_k Re[d_k e^(lambda_k t)]; without modes it is
    hydrocosim.harmonic_fit."""
    if not len(modes):
        return hc.harmonic_fit(t, x, omega)
    tau = t - t[0]
    columns = [np.ones_like(t), t - t.mean(), np.cos(omega * t), np.sin(omega * t)]
    for lam in modes:
        e = np.exp(lam * tau)
        columns += [e.real, e.imag]
    coefficients, *_ = np.linalg.lstsq(np.column_stack(columns), x, rcond=None)
    return coefficients[2] - 1j * coefficients[3]


def steady_amplitudes(p: np.ndarray, h: float, omega: float, modes):
    """(RAO over the window, the two half-window RAOs' difference), per unit amplitude."""
    t = np.arange(len(p)) * h
    duration = t[-1]
    window = t > duration - WINDOW - 1e-9
    middle = t > duration - WINDOW / 2 - 1e-9
    whole = steady_fit(t[window], p[window], omega, modes) / AMPLITUDE
    first = steady_fit(t[window & ~middle], p[window & ~middle], omega, modes) / AMPLITUDE
    second = steady_fit(t[middle], p[middle], omega, modes) / AMPLITUDE
    return whole, np.abs(first - second)


# --------------------------------------------------------------------------- run


def run(quick: bool = False, database=None, fmu=None, plot: bool = True, step: float = STEP) -> dict:
    started = time.perf_counter()
    folder = ensure_database(database)
    data = capytaine(folder)
    fmu = hc.ensure_fmu(FMU_NAME, [str(folder / "box.1"), "--tol", PACK_TOLERANCE], fmu)
    probe = hc.FmpyHull(fmu, rho=data["rho"], g=data["g"])
    added_mass_inf, damping_direct = probe.matrix("added_mass_inf"), probe.matrix("damping_direct")
    hydrostatic = probe.matrix("stiffness_hydrostatic")
    dofs = probe.dofs
    probe.close()
    network = hc.Network.from_fmu(fmu).scaled(data["rho"], data["g"])
    assert tuple(dofs) == tuple(network.dofs) == DOFS, dofs
    st = hc.Structure(data["mass"], np.zeros((6, 6)), hydrostatic, np.eye(6))

    omegas = data["omega"]
    periods = file_periods(folder)
    steps = int(round((RAMP + SETTLE + WINDOW) / step))
    duration = steps * step
    modes = slow_modes(st, network, duration - WINDOW)
    # The body's natural modes (the network's eigenvalues in the band): frequency, damping ratio.
    lam = np.linalg.eigvals(hc.coupled_system(st, network))
    lam = lam[(lam.imag > 0.2) & (lam.imag < 2.6)]
    natural = sorted((float(abs(v)), float(-v.real / abs(v))) for v in lam)

    curves, points = {}, []
    cosim_seconds = 0.0
    for heading, markers in (QUICK_POINTS if quick else POINTS).items():
        x_table = data["excitation"][heading]
        curves[heading] = {
            "capytaine": np.array([rao(st, w, a, x) for w, a, x in zip(omegas, data["added"], x_table)]),
            "network": np.array([rao(st, w, network.complex_added_mass(w), x) for w, x in zip(omegas, x_table)]),
        }
        for marker in markers:
            k = int(np.argmin(np.abs(omegas - marker)))
            period = periods[np.argmin(np.abs(2 * np.pi / periods - omegas[k]))]
            omega = 2 * np.pi / period
            waves = {"heading": heading, "kind": 1, "height": 2 * AMPLITUDE, "period": period, "ramp": RAMP}
            hull = hc.FmpyHull(fmu, rho=data["rho"], g=data["g"], waves=waves)
            t0 = time.perf_counter()
            try:
                p = hc.cosimulate(hull, st, added_mass_inf, damping_direct, np.zeros(6), step, steps, "ramp")
            finally:
                hull.close()
            cosim_seconds += time.perf_counter() - t0
            measured, halves = steady_amplitudes(p, step, omega, modes)
            plain, _ = steady_amplitudes(p, step, omega, ())
            points.append({
                "heading": heading, "omega": omega, "period": period, "cosim": measured, "halves": halves,
                "cosim_harmonic_only": plain, "capytaine": curves[heading]["capytaine"][k],
                "network": curves[heading]["network"][k], "steps": steps,
            })

    def worst(key_a, key_b):
        out = {}
        for heading in curves:
            scale = np.max(np.abs(curves[heading]["capytaine"]), axis=0)
            mine = [q for q in points if q["heading"] == heading]
            errors = np.max([np.abs(q[key_a] - q[key_b]) / scale for q in mine], axis=0)
            out[f"{heading:g}"] = {d: float(errors[DOFS.index(d)]) for d in REPORTED[heading]}
        return out

    result = {
        "quick": quick,
        "step": step,
        "amplitude": AMPLITUDE,
        "ramp": RAMP,
        "duration": duration,
        "window": WINDOW,
        "mass_matrix": data["mass"],
        "stiffness_hydrostatic": hydrostatic,
        "stiffness_capytaine": data["stiffness"],
        "added_mass_inf": added_mass_inf,
        "natural_modes": natural,
        "fitted_free_modes": [[v.real, v.imag] for v in modes],
        "curves": {"omega": omegas, **{f"{h:g}": c for h, c in curves.items()}},
        "largest_rao": {f"{h:g}": {d: float(np.max(np.abs(c["capytaine"][:, DOFS.index(d)]))) for d in REPORTED[h]}
                        for h, c in curves.items()},
        "points": points,
        "cosim_minus_network": worst("cosim", "network"),
        "cosim_minus_capytaine": worst("cosim", "capytaine"),
        "network_minus_capytaine": worst("network", "capytaine"),
        "harmonic_only_minus_network": worst("cosim_harmonic_only", "network"),
        "transient_left": {
            f"{h:g}": {d: float(np.max([q["halves"][DOFS.index(d)] for q in points if q["heading"] == h])
                             / np.max(np.abs(c["capytaine"][:, DOFS.index(d)]))) for d in REPORTED[h]}
            for h, c in curves.items()
        },
        "seconds": {"cosimulation": cosim_seconds},
    }
    if plot and not quick:
        result["figure"] = str(figure(result))
    result["seconds"]["total"] = time.perf_counter() - started
    return result


# --------------------------------------------------------------------------- output


def figure(result: dict) -> pathlib.Path:
    plt = hc.pyplot()
    panels = [(h, d) for h in (HEAD, BEAM) for d in REPORTED[h]]
    fig, axes = plt.subplots(2, 3, figsize=(10, 6.2))
    omega = result["curves"]["omega"]
    units = {"surge": "m/m", "sway": "m/m", "heave": "m/m", "roll": "rad/m", "pitch": "rad/m", "yaw": "rad/m"}
    names = {HEAD: "head seas (180 deg)", BEAM: "beam seas (90 deg)"}
    slots = {(HEAD, "heave"): 0, (HEAD, "pitch"): 1, (BEAM, "sway"): 3, (BEAM, "heave"): 4, (BEAM, "roll"): 5}
    for heading, dof in panels:
        ax = axes.flat[slots[(heading, dof)]]
        j = DOFS.index(dof)
        c = result["curves"][f"{heading:g}"]
        ax.plot(omega, np.abs(c["capytaine"][:, j]), "-", color="C0", lw=1.2, label="Capytaine's coefficients")
        ax.plot(omega, np.abs(c["network"][:, j]), ":", color="k", lw=0.9, label="FMU network H(i omega)")
        mine = [q for q in result["points"] if q["heading"] == heading]
        ax.plot([q["omega"] for q in mine], [abs(q["cosim"][j]) for q in mine], "o", mfc="none", color="C3",
                ms=6, label="co-simulation (fmpy)")
        ax.set_title(f"{dof} RAO ({units[dof]}), {names[heading]}", fontsize=9)
        ax.set_xlim(0, 2.6)
        ax.set_xlabel("omega (rad/s)")
        ax.grid(True, lw=0.3, alpha=0.5)
        if heading == BEAM:
            ax.axvspan(0.75, 1.15, color="0.9", lw=0)
        if dof == "roll":
            ax.set_yscale("log")
            ax.text(0.95, 0.02, "roll resonance:\nno co-simulation point", ha="center", fontsize=6.5,
                    transform=ax.get_xaxis_transform())
        ax.legend(loc="upper right", fontsize=6.5)
    ax = axes.flat[2]
    ax.axis("off")
    natural = ", ".join(f"{w:.3f} rad/s (damping ratio {z:.1e})" for w, z in result["natural_modes"] if z < 0.05)
    ax.text(0, 0.95, "Box barge 40 m x 10 m x 3 m, free floating,\nCapytaine 3.0 coarse mesh, FMU of box.1.\n"
            f"h = {result['step']} s, a = {result['amplitude']} m, wave.ramp {result['ramp']:g} s,\n"
            f"{result['duration']:g} s runs, fit over the last {result['window']:g} s.\n\n"
            f"Lightly damped mode of body + network (roll):\n{natural};\nits free oscillation is fitted "
            "beside the wave's\nharmonic (module docs). Grey: no beam-sea\npoint at the roll resonance.",
            va="top", fontsize=7.5, wrap=True)
    fig.suptitle("Floating box barge in regular waves: co-simulated RAOs against the frequency domain", fontsize=9)
    fig.tight_layout()
    path = hc.save_svg(fig, FIGURE)
    plt.close(fig)
    return path


def _fmt(errors: dict) -> str:
    return "; ".join(f"{h} deg: " + ", ".join(f"{k} {v:.1e}" for k, v in e.items()) for h, e in errors.items())


def report(result: dict) -> str:
    m = np.diag(result["mass_matrix"])
    c = np.diag(result["stiffness_hydrostatic"])
    lines = [
        "mass matrix diag: " + " ".join(f"{v:.4e}" for v in m),
        "stiffness_hydrostatic diag: " + " ".join(f"{v:.4e}" for v in c),
        "natural modes of body + network (rad/s, damping ratio): "
        + ", ".join(f"{w:.3f} ({z:.1e})" for w, z in result["natural_modes"]),
        "free modes fitted beside the wave's harmonic (lambda): "
        + (", ".join(f"{a:.2e}{b:+.4f}i" for a, b in result["fitted_free_modes"]) or "none"),
        f"regular waves a = {result['amplitude']} m, h = {result['step']} s, ramp {result['ramp']:g} s, "
        f"{result['duration']:g} s, window {result['window']:g} s; largest RAO (Capytaine): " + _fmt(result["largest_rao"]),
    ]
    for heading in sorted({q["heading"] for q in result["points"]}, reverse=True):
        dofs = REPORTED[heading]
        lines.append(f"  heading {heading:g}:  omega   " + "  ".join(f"|{d}| cosim (Capytaine, network)" for d in dofs))
        for q in [q for q in result["points"] if q["heading"] == heading]:
            cells = "  ".join(
                f"{abs(q['cosim'][DOFS.index(d)]):.4e} ({abs(q['capytaine'][DOFS.index(d)]):.4e}, "
                f"{abs(q['network'][DOFS.index(d)]):.4e})" for d in dofs)
            lines.append(f"    {q['omega']:.4f}  {cells}")
    lines.append("  largest difference, relative to each DOF's largest RAO over the band:")
    lines.append("    co-simulation - network:   " + _fmt(result["cosim_minus_network"]))
    lines.append("    network - Capytaine (fit): " + _fmt(result["network_minus_capytaine"]))
    lines.append("    co-simulation - Capytaine: " + _fmt(result["cosim_minus_capytaine"]))
    lines.append("    transient left (halves):   " + _fmt(result["transient_left"]))
    lines.append("    harmonic fit alone - network: " + _fmt(result["harmonic_only_minus_network"]))
    sec = result["seconds"]
    lines.append(f"seconds: co-simulation {sec['cosimulation']:.1f}, total {sec['total']:.1f}")
    if "figure" in result:
        lines.append(f"figure: {result['figure']}")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="head seas, 3 wave frequencies, no figure")
    parser.add_argument("--database", help="folder with box.1/.3/.hst/.json (default: examples/cosim/fmus/box_barge, made if missing)")
    parser.add_argument("--fmu", help=f"the box FMU (default: examples/cosim/fmus/{FMU_NAME}.fmu, packed if missing)")
    parser.add_argument("--step", type=float, default=STEP, help="communication step (s)")
    parser.add_argument("--json", help="also write the results to this JSON file")
    hc.add_update_docs(parser)
    args = parser.parse_args(argv)
    hc.apply_update_docs(args)
    result = run(args.quick, args.database, args.fmu, step=args.step)
    print(report(result))
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(hc.jsonable(result), indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
