"""Floating semicircle in regular beam seas: a rigid section and the elastic hull of
elastic_hull.py, driven by the FMU's exciting, radiation and hydrostatic forces, co-simulated
under fmpy and libcosimpy against the frequency-domain response (RAO) of the same panel method.

Run (from the repository root, with the .venv of tests/python/requirements.txt):

    .venv/bin/python examples/cosim/beam_seas.py            # 9 wave periods, writes target/reports/figures/cosim-beam-seas.svg (--update-docs: docs/figures/)
    .venv/bin/python examples/cosim/beam_seas.py --quick    # 2 wave periods, no figure (what the test runs)

FMUs, packed on first use into examples/cosim/fmus/: SemicircleRigid.fmu
(`fmu-pack pack semicircle --dofs sway,heave,roll`) and Semicircle9.fmu (`fmu-pack pack
semicircle`, all nine DOFs). Both carry the excitation table of their sweep (docs/WAVES.md).

Sea: regular waves of height 0.1 m (amplitude a = 0.05 m) from heading 0 (travelling towards
+x), wave.ramp 20 s; 41 wave numbers kR = 0.04 .. 4 (periods 10 s .. 1 s), co-simulated at
every fifth (9 periods), each with 64 communication steps per wave period.

Rigid section (per metre, SI; numbers chosen here): semicircle R = 1 m floating at its
diameter, mass m = rho pi R^2 / 2, centre of gravity on the centre line at y_G = -0.2 R,
radius of gyration 0.35 R about it. Coordinates sway x, heave y, roll theta about the origin
(the waterline centre, the FMU's roll axis):

    M_s = [[m, 0, -m y_G], [0, m, 0], [-m y_G, 0, m (k_G^2 + y_G^2)]]
    K   = mooring spring in sway (nominal period 4 s with m + A_inf, as rigid_sway.py)
          + the weight's restoring -m g y_G in roll + the FMU's stiffness_hydrostatic
    C_s = linear roll damping, 5 % of critical (the viscous damping potential flow lacks: the
          water does no work on a semicircle rolling about its centre)

Elastic hull: elastic_hull.structure (10 mm steel shell, edge masses, floating frame; coordinates
sway, heave, roll, eta1..eta3) with its heave restoring replaced by T^T C T, C the FMU's 9 x 9
stiffness_hydrostatic (the elastic shapes' pressure stiffness included; the pre-loaded shell's
initial stress, which a structural model would add (docs/HYDROSTATICS.md), is left out of both
solutions alike), and the same 5 % roll damping.

Time domain (hydrocosim.cosimulate, scheme "ramp"; force.<dof> = radiation + excitation):

    (M_s + T^T A_inf T) p'' + (C_s + T^T D T) p' + K p = T^T (F + D v)

Frequency domain, per unit wave amplitude, convention exp(+i omega t):

    [K - omega^2 (M_s + T^T A~(omega) T) + i omega C_s] P = T^T X(omega)

with A~ and X from `fmu-pack sweep --excitation` at each kR (the "table" RAO), or A~ the FMU's
network H(i omega) (the "network" RAO: what the time-domain model solves; it differs from the
table RAO by the fit error only). The co-simulation's RAO is the least-squares harmonic of
p(t) / a over the last 40 s of 100 s (a constant and a linear drift taken out); the same fit on
the two halves of that window measures what is left of the transient.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import elastic_hull  # noqa: E402
import hydrocosim as hc  # noqa: E402

AMPLITUDE = 0.05  # m, wave amplitude a (height 0.1 m)
HEADING = 0.0  # deg
RAMP = 20.0  # s
DURATION = 200.0  # s
WINDOW = 60.0  # s, the last part of the run that the harmonic fit sees
STEPS_PER_PERIOD = 64
KR_GRID = (0.04, 4.0, 41)  # the table sweep; the co-simulated periods are every fifth point
MARKERS = tuple(range(0, 41, 5))
QUICK_MARKERS = (15, 30)  # kR 0.23 (T 4.2 s) and 1.3 (T 1.8 s)
Y_G = -0.2  # R, centre of gravity of the rigid section
K_G = 0.35  # R, its radius of gyration about G
ROLL_DAMPING_RATIO = 0.05
SWAY_PERIOD = 4.0  # s, nominal mooring period with m + A_inf
FIGURE = "cosim-beam-seas.svg"
HULLS = {
    # name: (FMU name, fmu-pack arguments of the hull, coordinate names)
    "rigid": ("SemicircleRigid", ["semicircle", "--dofs", "sway,heave,roll"], ("sway", "heave", "roll")),
    "elastic": ("Semicircle9", ["semicircle"], ("sway", "heave", "roll", "eta1", "eta2", "eta3")),
}


def roll_damping(mass: np.ndarray, stiffness: np.ndarray, roll: int = 2) -> float:
    """5 % of the critical damping of roll alone: 2 zeta sqrt(K_rr M_rr)."""
    return 2 * ROLL_DAMPING_RATIO * np.sqrt(stiffness[roll, roll] * mass[roll, roll])


def rigid_structure(added_mass_inf: np.ndarray, hydrostatic: np.ndarray) -> hc.Structure:
    """The rigid section of the module docs (coordinates = the FMU's sway, heave, roll)."""
    r = hc.RADIUS
    m = hc.RHO * np.pi * r**2 / 2
    y_g, k_g = Y_G * r, K_G * r
    mass = np.array([[m, 0, -m * y_g], [0, m, 0], [-m * y_g, 0, m * (k_g**2 + y_g**2)]])
    stiffness = hydrostatic.copy()
    stiffness[0, 0] += (m + added_mass_inf[0, 0]) * (2 * np.pi / SWAY_PERIOD) ** 2
    stiffness[2, 2] += -m * hc.G * y_g
    damping = np.zeros((3, 3))
    damping[2, 2] = roll_damping(mass + added_mass_inf, stiffness)
    return hc.Structure(mass, damping, stiffness, np.eye(3))


def elastic_structure(added_mass_inf: np.ndarray, hydrostatic: np.ndarray) -> hc.Structure:
    """elastic_hull.structure with the FMU's hydrostatics (module docs)."""
    st, _, _ = elastic_hull.structure(added_mass_inf[0, 0], hydrostatic_heave=False)
    t = st.to_hull
    stiffness = st.stiffness + t.T @ hydrostatic @ t
    damping = st.damping.copy()
    damping[2, 2] += roll_damping(st.mass + t.T @ added_mass_inf @ t, stiffness)
    return hc.Structure(st.mass, damping, stiffness, t)


def rao(st: hc.Structure, omega: float, added_mass: np.ndarray, excitation: np.ndarray) -> np.ndarray:
    """P per unit wave amplitude: [K - w^2 (M_s + T^T A~ T) + i w C_s] P = T^T X."""
    t = st.to_hull
    dynamic = st.stiffness - omega**2 * (st.mass + t.T @ added_mass @ t) + 1j * omega * st.damping
    return np.linalg.solve(dynamic, t.T @ excitation)


def step_size(period: float) -> float:
    """period / 64, rounded to whole nanoseconds (libcosim's time unit)."""
    return round(period / STEPS_PER_PERIOD * 1e9) * 1e-9


def steady_amplitudes(p: np.ndarray, h: float, omega: float):
    """(RAO over the window, the two half-window RAOs' largest difference), per unit amplitude."""
    t = np.arange(len(p)) * h
    window = t > DURATION - WINDOW - 1e-9
    middle = t > DURATION - WINDOW / 2 - 1e-9
    whole = hc.harmonic_fit(t[window], p[window], omega) / AMPLITUDE
    first = hc.harmonic_fit(t[window & ~middle], p[window & ~middle], omega) / AMPLITUDE
    second = hc.harmonic_fit(t[middle], p[middle], omega) / AMPLITUDE
    return whole, np.abs(first - second)


def run_hull(name: str, fmu, quick: bool) -> dict:
    fmu_name, hull_args, coordinates = HULLS[name]
    fmu = hc.ensure_fmu(fmu_name, hull_args, fmu)
    network = hc.Network.from_fmu(fmu).scaled(hc.RHO, hc.G)
    probe = hc.FmpyHull(fmu)
    added_mass_inf, damping_direct = probe.matrix("added_mass_inf"), probe.matrix("damping_direct")
    hydrostatic = probe.matrix("stiffness_hydrostatic")
    probe.close()
    st = rigid_structure(added_mass_inf, hydrostatic) if name == "rigid" else elastic_structure(
        added_mass_inf, hydrostatic
    )
    lo, hi, n = KR_GRID
    table = hc.sweep_coefficients(hull_args, f"{lo}:{hi}:{n}")
    assert table[0].dofs == network.dofs, (table[0].dofs, network.dofs)
    curves = {"kr": [], "omega": [], "table": [], "network": []}
    for c in table:
        x = c.excitation[HEADING]
        curves["kr"].append(c.kr)
        curves["omega"].append(c.omega)
        curves["table"].append(rao(st, c.omega, c.added_mass, x))
        curves["network"].append(rao(st, c.omega, network.complex_added_mass(c.omega), x))
    result = {
        "coordinates": list(coordinates),
        "stiffness_hydrostatic": hydrostatic.tolist(),
        "roll_damping": float(st.damping[2, 2]),
        "curves": {k: np.array(v) for k, v in curves.items()},
        "points": [],
    }
    for index in QUICK_MARKERS if quick else MARKERS:
        c = table[index]
        period = 2 * np.pi / c.omega
        h = step_size(period)
        steps = int(round(DURATION / h))
        waves = {"kind": 1, "height": 2 * AMPLITUDE, "period": period, "heading": HEADING, "ramp": RAMP}
        p0 = np.zeros(len(coordinates))
        point = {"kr": c.kr, "omega": c.omega, "period": period, "step": h}
        for master in ("fmpy", "libcosim"):
            hull = hc.FmpyHull(fmu, waves=waves) if master == "fmpy" else hc.LibcosimHull(fmu, h, waves=waves)
            try:
                p = hc.cosimulate(hull, st, added_mass_inf, damping_direct, p0, h, steps, "ramp")
            finally:
                hull.close()
            point[master], point[f"{master}_halves"] = steady_amplitudes(p, h, c.omega)
        point["table"] = curves["table"][index]
        point["network"] = curves["network"][index]
        result["points"].append(point)
    scale = np.max(np.abs(result["curves"]["table"]), axis=0)  # each coordinate's largest RAO
    pts = result["points"]
    result["largest_rao"] = dict(zip(coordinates, scale.tolist()))

    def worst(values):
        return dict(zip(coordinates, np.max(np.array(values) / scale, axis=0).tolist()))

    result["cosim_minus_network"] = worst([np.abs(q["fmpy"] - q["network"]) for q in pts])
    result["network_minus_table"] = worst([np.abs(q["network"] - q["table"]) for q in pts])
    result["cosim_minus_table"] = worst([np.abs(q["fmpy"] - q["table"]) for q in pts])
    result["network_minus_table_all_kr"] = worst(
        np.abs(result["curves"]["network"] - result["curves"]["table"])
    )
    result["transient_left"] = worst([q["fmpy_halves"] for q in pts])
    result["libcosim_minus_fmpy"] = float(max(np.max(np.abs(q["libcosim"] - q["fmpy"])) for q in pts))
    return result


def run(quick: bool = False, fmus: dict | None = None, plot: bool = True) -> dict:
    fmus = fmus or {}
    result = {
        "amplitude": AMPLITUDE,
        "heading": HEADING,
        "ramp": RAMP,
        "duration": DURATION,
        "window": WINDOW,
        "hulls": {name: run_hull(name, fmus.get(name), quick) for name in HULLS},
    }
    if plot and not quick:
        result["figure"] = str(figure(result))
    return result


def figure(result: dict) -> pathlib.Path:
    plt = hc.pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(8.0, 7.0))
    titles = {"rigid": "Rigid section", "elastic": "Elastic hull"}
    shown = {"rigid": ("sway", "heave", "roll"), "elastic": ("sway", "heave", "roll", "eta1")}
    units = {"sway": "m/m", "heave": "m/m", "roll": "rad/m", "eta1": "m/m"}
    for row, (name, hull) in enumerate(result["hulls"].items()):
        amplitude_ax, phase_ax = axes[row]
        omega = hull["curves"]["omega"]
        for k, coordinate in enumerate(shown[name]):
            j = hull["coordinates"].index(coordinate)
            colour = f"C{k}"
            label = f"{coordinate} ({units[coordinate]})"
            table = hull["curves"]["table"][:, j]
            net = hull["curves"]["network"][:, j]
            amplitude_ax.semilogy(omega, np.abs(table), "-", color=colour, lw=1.2, label=label)
            amplitude_ax.semilogy(omega, np.abs(net), ":", color="k", lw=0.8)
            phase = np.degrees(np.angle(table))
            phase[1:][np.abs(np.diff(phase)) > 180] = np.nan  # no vertical line at a wrap
            phase_ax.plot(omega, phase, "-", color=colour, lw=1.2)
            pts = hull["points"]
            w = [q["omega"] for q in pts]
            fm = np.array([q["fmpy"][j] for q in pts])
            lc = np.array([q["libcosim"][j] for q in pts])
            amplitude_ax.semilogy(w, np.abs(fm), "o", mfc="none", color=colour, ms=6)
            amplitude_ax.semilogy(w, np.abs(lc), "x", color=colour, ms=4)
            phase_ax.plot(w, np.degrees(np.angle(fm)), "o", mfc="none", color=colour, ms=6)
            phase_ax.plot(w, np.degrees(np.angle(lc)), "x", color=colour, ms=4)
        amplitude_ax.set_title(f"{titles[name]}: amplitude per unit wave amplitude", fontsize=9)
        amplitude_ax.set_ylabel("|RAO|")
        amplitude_ax.legend(loc="lower left", fontsize=7)
        phase_ax.set_title("phase against the wave elevation at x = 0", fontsize=9)
        phase_ax.set_ylabel("phase (deg)")
        phase_ax.set_ylim(-185, 185)
        phase_ax.set_yticks([-180, -90, 0, 90, 180])
        for ax in (amplitude_ax, phase_ax):
            ax.set_xlabel("omega (rad/s)")
            ax.grid(True, lw=0.3, alpha=0.5)
    fig.suptitle(
        "Beam seas, heading 0: lines RAO from the panel method's tables, dotted from the FMU's network,\n"
        "o fmpy and x libcosimpy co-simulation (steady harmonic, 64 steps per period)",
        fontsize=9,
    )
    fig.tight_layout()
    path = hc.save_svg(fig, FIGURE)
    plt.close(fig)
    return path


def _fmt(errors: dict) -> str:
    return ", ".join(f"{k} {v:.1e}" for k, v in errors.items())


def report(result: dict) -> str:
    lines = [
        f"regular beam seas: a = {result['amplitude']} m, heading {result['heading']:.0f} deg, ramp "
        f"{result['ramp']:.0f} s, {result['duration']:.0f} s runs, harmonic fit over the last {result['window']:.0f} s"
    ]
    for name, hull in result["hulls"].items():
        lines.append(f"{name}: roll damping {hull['roll_damping']:.1f} N m s/m; largest RAO per coordinate: "
                     + _fmt(hull["largest_rao"]))
        lines.append("   kR      T (s)   h (s)     " + "  ".join(f"|{c}| fmpy (table)" for c in hull["coordinates"][:4]))
        for q in hull["points"]:
            cells = "  ".join(f"{abs(q['fmpy'][j]):.4f} ({abs(q['table'][j]):.4f})" for j in range(min(4, len(q["table"]))))
            lines.append(f"  {q['kr']:.4f}  {q['period']:6.3f}  {q['step']:.5f}   {cells}")
        lines.append("  errors relative to each coordinate's largest RAO:")
        lines.append("    co-simulation - network RAO: " + _fmt(hull["cosim_minus_network"]))
        lines.append("    network - table RAO (fit):   " + _fmt(hull["network_minus_table"]))
        lines.append("      the same at all 41 kR:     " + _fmt(hull["network_minus_table_all_kr"]))
        lines.append("    co-simulation - table RAO:   " + _fmt(hull["cosim_minus_table"]))
        lines.append("    transient left (halves):     " + _fmt(hull["transient_left"]))
        lines.append(f"    |libcosim - fmpy| RAO: {hull['libcosim_minus_fmpy']:.1e}")
    if "figure" in result:
        lines.append(f"figure: {result['figure']}")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 wave periods, no figure")
    parser.add_argument("--fmu-rigid", help="the sway/heave/roll FMU (default: fmus/SemicircleRigid.fmu)")
    parser.add_argument("--fmu-elastic", help="the 9-DOF FMU (default: fmus/Semicircle9.fmu)")
    parser.add_argument("--json", help="also write the results to this JSON file")
    hc.add_update_docs(parser)
    args = parser.parse_args(argv)
    hc.apply_update_docs(args)
    result = run(args.quick, {"rigid": args.fmu_rigid, "elastic": args.fmu_elastic})
    print(report(result))
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(hc.jsonable(result), indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
