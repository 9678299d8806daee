"""Elastic semicircular hull: its Craig-Bampton DOFs driven by a beam model, coupled to the
full 9-DOF semicircle FMU (sway heave roll cb1..cb6). Shows the hydro-elastic effect.

Run (from the repository root, with the .venv of tests/python/requirements.txt):

    .venv/bin/python examples/cosim/elastic_hull.py            # full run, writes target/reports/figures/cosim-elastic.svg (--update-docs: docs/figures/)
    .venv/bin/python examples/cosim/elastic_hull.py --quick    # short run, no figure (what the test runs)

The FMU examples/cosim/fmus/Semicircle9.fmu is packed on first use with
`cargo run --release -p fmu-pack -- pack semicircle -o ...` (all nine DOFs, default fit).

Structure (per metre of hull, SI; Schilder et al.'s setup of section 2 (docs/DESIGN.md), with numbers chosen here):

* the submerged semicircle R = 1 m is a thin-walled, homogeneous, prismatic steel shell
  (thickness t = 10 mm, E = 210 GPa, nu = 0.3, 7850 kg/m3): an inextensible thin circular beam
  (seed eqs. 4-5) of bending stiffness D = E t^3 / (12 (1 - nu^2)) = 19.2 kN m and mass
  mu = 78.5 kg/m2 per unit arc length;
* the rest of the section (deck, topsides) is lumped as two point masses at the waterline edges,
  m_e = (rho pi R^2 / 2 - mu pi R) / 2 = 682 kg/m each, so the section floats at H/R = 0;
* the Craig-Bampton modes are the static modes of eq. 4 (unit u, w, psi at one end, the others
  zero), derived here from the 6x6 boundary system. Bending energy
  U = D / (2 R^3) integral (w''' + w')^2 dtheta (eq. 4 is its Euler-Lagrange equation), kinetic
  energy T = mu R / 2 integral (u'^2 + w'^2) dtheta + the edge masses: this gives the 6x6 mass
  and stiffness over cb1..cb6 (exact static condensation; rigid motions have zero energy);
* floating frame (seed section 2): coordinates p = (sway, heave, roll, eta1, eta2, eta3), the
  rigid motion of the frame plus the three elastic (dry) modes of the Craig-Bampton model, which
  are mass-orthogonal to the rigid motions (mean-axis frame). The hull's nine FMU coordinates are
  q = T p: sway, heave, roll from the frame, cb1..cb6 = the elastic modes' end values;
* restoring of the frame: a sway mooring spring as in rigid_sway.py, hydrostatic heave
  rho g 2R, roll m g GM (GM = -y_G, the centre of a circular section being its metacentre).
  Hydrostatic and gravity stiffness of the elastic shapes is left out (the FMU gives radiation
  forces only); a rough estimate, rho g integral(xi_y xi_n) ds, is 7 % of the breathing mode's
  bending stiffness, about a 3 % shift of its frequency. It is the same in both solutions, so
  the coupling error is unaffected.

Compared: dry and wet modes (eigenvalues of Schilder et al., eq. 19 with the structure, wet ones tracked
from the dry ones while the water density grows from 0), the frequency response of the
breathing mode, and the free response from an initial breathing deformation eta1 = 5 cm
(co-simulation under fmpy and libcosimpy against the monolithic eq. 19 solution).
"""
from __future__ import annotations

import argparse
import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import hydrocosim as hc  # noqa: E402

YOUNG = 210e9  # Pa
POISSON = 0.3
STEEL = 7850.0  # kg/m3
THICKNESS = 0.010  # m
INITIAL_ETA1 = 0.05  # m, initial breathing deformation (edges move 0.79 * eta1 each)
SWAY_PERIOD = 4.0  # s, nominal mooring period with m + A_inf, as in rigid_sway.py
PACK_ARGS = ["semicircle"]
FIGURE = "cosim-elastic.svg"
MODE_NAMES = ("roll", "sway", "heave", "elastic 1", "elastic 2", "elastic 3")


# --------------------------------------------------------------------------- beam


def _w_basis(theta: float) -> np.ndarray:
    """Rows w, w', w'', w''' of the six solutions of eq. 4 (columns C1..C6 of eq. 6)."""
    c, s = np.cos(theta), np.sin(theta)
    t = theta
    return np.array(
        [
            [1, t, c, s, t * c, t * s],
            [0, 1, -s, c, c - t * s, s + t * c],
            [0, 0, -c, -s, -2 * s - t * c, 2 * c - t * s],
            [0, 0, s, -c, -3 * c + t * s, -3 * s - t * c],
        ]
    )


def _end_values(theta: float, radius: float) -> np.ndarray:
    """Rows u = w', w, psi = (w'' + w) / R at theta (Schilder et al., eq. 5)."""
    f = _w_basis(theta)
    return np.array([f[1], f[0], (f[2] + f[0]) / radius])


def craig_bampton_coefficients(radius: float) -> np.ndarray:
    """Row k-1: C1..C6 of mode cbk (unit k-th of u(0), w(0), psi(0), u(pi), w(pi), psi(pi))."""
    boundary = np.vstack([_end_values(0.0, radius), _end_values(np.pi, radius)])
    return np.linalg.solve(boundary, np.eye(6)).T


def rigid_in_craig_bampton(radius: float) -> np.ndarray:
    """Columns: sway, heave, roll (about the origin) as cb1..cb6 end values (hull.rs docs)."""
    r = radius
    return np.array([[1, 0, 0, -1, 0, 0], [0, -1, 0, 0, 1, 0], [0, r, 1, 0, r, 1]], dtype=float).T


def beam_matrices(radius: float, nodes: int = 40):
    """Unit-mu mass and unit-D stiffness over cb1..cb6 (Gauss-Legendre in theta, exact for
    these trigonometric-polynomial fields to rounding at 40 nodes)."""
    x, weight = np.polynomial.legendre.leggauss(nodes)
    theta, weight = (x + 1) * np.pi / 2, weight * np.pi / 2
    coefficients = craig_bampton_coefficients(radius)
    basis = np.array([_w_basis(t) for t in theta])  # (nodes, 4, 6)
    w = basis[:, 0, :] @ coefficients.T
    u = basis[:, 1, :] @ coefficients.T
    curvature = (basis[:, 3, :] + basis[:, 1, :]) @ coefficients.T  # R^2 x change of curvature
    mass = radius * (np.einsum("q,qi,qj->ij", weight, w, w) + np.einsum("q,qi,qj->ij", weight, u, u))
    stiffness = np.einsum("q,qi,qj->ij", weight, curvature, curvature) / radius**3
    return mass, stiffness


def shell_properties(thickness: float = THICKNESS):
    bending = YOUNG * thickness**3 / (12 * (1 - POISSON**2))
    mu = STEEL * thickness
    edge_mass = (hc.RHO * np.pi * hc.RADIUS**2 / 2 - mu * np.pi * hc.RADIUS) / 2
    return bending, mu, edge_mass


def structure(added_mass_inf_sway: float, thickness: float = THICKNESS, hydrostatic_heave: bool = True):
    """The floating-frame model: (Structure over p, dry elastic frequencies, elastic shapes).

    `hydrostatic_heave`: add the heave restoring rho g 2R here (False when the caller adds the
    FMU's `stiffness_hydrostatic`, which holds it)."""
    r = hc.RADIUS
    bending, mu, edge_mass = shell_properties(thickness)
    unit_mass, unit_stiffness = beam_matrices(r)
    mass_cb = mu * unit_mass + edge_mass * np.diag([1.0, 1.0, 0.0, 1.0, 1.0, 0.0])
    stiffness_cb = bending * unit_stiffness
    lam, vec = np.linalg.eig(np.linalg.solve(mass_cb, stiffness_cb))
    order = np.argsort(lam.real)
    lam, vec = lam.real[order], vec.real[:, order]
    shapes = vec[:, 3:]  # the three elastic modes; the three zero ones are the rigid motions
    scale = np.array([np.max(np.abs(shapes[:, j] * [1, 1, r, 1, 1, r])) for j in range(3)])
    sign = np.array([np.sign(shapes[np.argmax(np.abs(shapes[:, j])), j]) for j in range(3)])
    shapes = shapes / (scale * sign)  # largest end value (u, w or R psi) = +1 m
    fields = np.hstack([rigid_in_craig_bampton(r), shapes])  # p -> cb end values (total)
    mass = fields.T @ mass_cb @ fields
    stiffness = fields.T @ stiffness_cb @ fields
    total = hc.RHO * np.pi * r**2 / 2
    stiffness[0, 0] += (total + added_mass_inf_sway) * (2 * np.pi / SWAY_PERIOD) ** 2
    if hydrostatic_heave:
        stiffness[1, 1] += hc.RHO * hc.G * 2 * r
    y_g = -(mu * np.pi * r) * (2 * r / np.pi) / total  # edge masses at y = 0, arc centroid -2R/pi
    stiffness[2, 2] += total * hc.G * (-y_g)
    to_hull = np.zeros((9, 6))
    to_hull[:3, :3] = np.eye(3)
    to_hull[3:, 3:] = shapes
    return hc.Structure(mass, np.zeros((6, 6)), stiffness, to_hull), np.sqrt(lam[3:]), shapes


# --------------------------------------------------------------------------- eq. 19


def tracked_modes(st: hc.Structure, network: hc.Network, steps: int = 200):
    """Dry eigenvalues followed to the wet ones while rho grows from 0 (continuation)."""
    dry, _ = hc.eigen_modes(st.mass, st.damping, st.stiffness)
    current = dry.copy()
    for fraction in np.geomspace(1e-4, 1.0, steps):
        a = hc.coupled_system(st, network.scaled(network.rho * fraction, network.g))
        eig = np.linalg.eigvals(a)
        eig = eig[eig.imag > -1e-12]
        current = np.array([eig[np.argmin(np.abs(eig - lam))] for lam in current])
    return dry, current


def receptance(st: hc.Structure, added_mass, omega: float, coordinate: int) -> float:
    """|p_k / f_k| for a harmonic generalized force on coordinate k, with the hull's complex
    added mass A~(omega) (None: dry)."""
    t = st.to_hull
    mass = st.mass + (t.T @ added_mass @ t if added_mass is not None else 0)
    dynamic = st.stiffness - omega * omega * mass
    return abs(np.linalg.solve(dynamic, np.eye(len(st.mass))[:, coordinate])[coordinate])


def breathing_receptance(st: hc.Structure, network: hc.Network | None, omegas):
    """|eta1 / f1| for a harmonic generalized force on eta1 (dry when network is None)."""
    return np.array([receptance(st, network.complex_added_mass(w) if network else None, w, 3) for w in omegas])


def resonance_peak(omegas: np.ndarray, values: np.ndarray) -> tuple[float, float]:
    """(omega, value) of the largest value, refined by a parabola through log values at the
    three grid points around it (log-spaced grid)."""
    i = int(np.clip(np.argmax(values), 1, len(values) - 2))
    x, y = np.log(omegas[i - 1 : i + 2]), np.log(values[i - 1 : i + 2])
    a, b, c = np.polyfit(x - x[1], y, 2)
    shift = -b / (2 * a) if a < 0 else 0.0
    return float(np.exp(x[1] + shift)), float(np.exp(c - b * b / (4 * a) if a < 0 else y[1]))


def wet_resonances(st: hc.Structure, network: hc.Network, points: int) -> dict:
    """Heave and breathing resonance peaks of the receptance with the panel method's own
    A~(omega) and with the network's: independent of how the network continues off the real
    frequency axis (the eigenvalues of a strongly damped mode do depend on it)."""
    panel = hc.sweep_coefficients(PACK_ARGS, f"0.3:4.5:{points}", network.rho, network.g)
    omegas = np.array([c.omega for c in panel])
    out = {}
    for name, k in (("heave", 1), ("eta1", 3)):
        exact = np.array([receptance(st, c.added_mass, c.omega, k) for c in panel])
        fitted = np.array([receptance(st, network.complex_added_mass(c.omega), c.omega, k) for c in panel])
        (w_exact, r_exact), (w_fit, r_fit) = resonance_peak(omegas, exact), resonance_peak(omegas, fitted)
        out[name] = {"panel_omega": w_exact, "network_omega": w_fit, "panel_peak": r_exact, "network_peak": r_fit}
    return out


def dry_response(st: hc.Structure, p0, h: float, steps: int) -> np.ndarray:
    """The structure without water, released at rest from p0, on the grid n h."""
    a, _ = hc.first_order(st.mass, st.damping, st.stiffness)
    phi = hc.expm(a * h)
    y = np.concatenate([p0, np.zeros_like(p0)])
    out = [y[: len(p0)]]
    for _ in range(steps):
        y = phi @ y
        out.append(y[: len(p0)])
    return np.array(out)


# --------------------------------------------------------------------------- run


def run(quick: bool = False, fmu=None, plot: bool = True) -> dict:
    duration = 4.0 if quick else 12.0
    steps_s = (0.02, 0.01) if quick else (0.02, 0.01, 0.005)
    fmu = hc.ensure_fmu("Semicircle9", PACK_ARGS, fmu)
    network = hc.Network.from_fmu(fmu).scaled(hc.RHO, hc.G)
    probe = hc.FmpyHull(fmu)
    added_mass_inf, damping_direct = probe.matrix("added_mass_inf"), probe.matrix("damping_direct")
    dofs = probe.dofs
    probe.close()
    assert dofs == network.dofs == ["sway", "heave", "roll", "cb1", "cb2", "cb3", "cb4", "cb5", "cb6"], dofs
    assert np.allclose(added_mass_inf, network.added_mass_inf, rtol=1e-12, atol=1e-9)
    assert np.allclose(damping_direct, network.damping_direct(), rtol=1e-12, atol=1e-9)

    st, dry_elastic, shapes = structure(added_mass_inf[0, 0])
    bending, mu, edge_mass = shell_properties()
    dry, wet = tracked_modes(st, network, 60 if quick else 200)
    result = {
        "thickness": THICKNESS,
        "bending_stiffness": bending,
        "shell_mass": mu,
        "edge_mass": edge_mass,
        "elastic_shapes": shapes.T.tolist(),
        "modes": [
            {
                "name": name,
                "dry_omega": abs(d),
                "wet_omega": abs(w),
                "wet_damped_omega": w.imag,
                "wet_damping_ratio": -w.real / abs(w),
                "wet_kR": abs(w) ** 2 * hc.RADIUS / hc.G,
            }
            for name, d, w in zip(MODE_NAMES, dry, wet)
        ],
        "resonances": wet_resonances(st, network, 120 if quick else 400),
        "initial_eta1": INITIAL_ETA1,
        "duration": duration,
        "runs": [],
    }

    p0 = np.zeros(6)
    p0[3] = INITIAL_ETA1
    series = {}
    for h in steps_s:
        steps = int(round(duration / h))
        mono = hc.monolithic(st, network, p0, h, steps)
        series[("mono", h)] = mono
        for scheme in hc.SCHEMES:
            hull = hc.FmpyHull(fmu)
            try:
                p = hc.cosimulate(hull, st, added_mass_inf, damping_direct, p0, h, steps, scheme)
            finally:
                hull.close()
            series[(scheme, h)] = p
            run_result = {
                "scheme": scheme,
                "step": h,
                "max_error_eta1_m": float(np.max(np.abs(p[:, 3] - mono[:, 3]))),
                "max_error_eta1_relative": float(np.max(np.abs(p[:, 3] - mono[:, 3])) / INITIAL_ETA1),
                "max_error_heave_m": float(np.max(np.abs(p[:, 1] - mono[:, 1]))),
                "max_error_any_m": float(np.max(np.abs(p - mono))),
            }
            if scheme == "ramp" and h == steps_s[-2]:
                lib = hc.LibcosimHull(fmu, h)
                try:
                    p_lib = hc.cosimulate(lib, st, added_mass_inf, damping_direct, p0, h, steps, scheme)
                finally:
                    lib.close()
                run_result["libcosim_minus_fmpy_m"] = float(np.max(np.abs(p_lib - p)))
            result["runs"].append(run_result)
    h = steps_s[-1]
    series["dry"] = dry_response(st, p0, h, int(round(duration / h)))
    wet_series = series[("mono", h)]
    names = ("sway", "heave", "roll", "eta1", "eta2", "eta3")
    result["max_abs_wet_m"] = dict(zip(names, np.max(np.abs(wet_series), axis=0).tolist()))
    last_period = int(round(2 * np.pi / result["modes"][3]["wet_damped_omega"] / h))
    result["eta1_last_period_wet_m"] = float(np.max(np.abs(wet_series[-last_period:, 3])))
    if plot and not quick:
        result["figure"] = str(figure(series, steps_s, duration, st, network, dry, wet))
    return result


def figure(series, steps_s, duration, st, network, dry, wet) -> pathlib.Path:
    plt = hc.pyplot()
    fig, (top, middle, bottom) = plt.subplots(3, 1, figsize=(7.0, 8.5))
    h = steps_s[-1]
    t = np.arange(len(series["dry"])) * h
    top.plot(t, series["dry"][:, 3] * 100, color="0.6", lw=1.0, label="dry (no water)")
    top.plot(t, series[("mono", h)][:, 3] * 100, "k-", lw=1.2, label="wet, monolithic (Schilder et al., eq. 19)")
    h_co = steps_s[0]
    tc = np.arange(len(series[("ramp", h_co)])) * h_co
    label = f"wet, co-simulation (ramp, h = {h_co} s)"
    top.plot(tc[::3], series[("ramp", h_co)][::3, 3] * 100, "x", ms=3, color="C0", label=label)
    top.set_ylabel("breathing mode eta1 (cm)")
    top.set_xlim(0, duration)
    top.set_xlabel("time (s)")
    top.legend(loc="upper right", fontsize=7, ncol=3)
    top.set_title("Elastic semicircle (10 mm steel shell, edge masses): free breathing from eta1 = 5 cm")
    middle.plot(t, series[("mono", h)][:, 1] * 1000, "k-", lw=1.2, label="monolithic")
    middle.plot(tc[::3], series[("ramp", h_co)][::3, 1] * 1000, "x", ms=3, color="C0", label="co-simulation")
    middle.set_ylabel("heave (mm)")
    middle.set_title("Heave set off by the breathing hull through the water (zero when dry)", fontsize=9)
    middle.set_xlim(0, duration)
    middle.set_xlabel("time (s)")
    middle.legend(loc="upper right", fontsize=7)
    omegas = np.linspace(0.5, 12.0, 700)
    bottom.semilogy(omegas, breathing_receptance(st, None, omegas), color="0.6", lw=1.0, label="dry")
    wet_curve = breathing_receptance(st, network, omegas)
    bottom.semilogy(omegas, wet_curve, "k-", lw=1.2, label="wet (network H(i omega))")
    for d, w, name in zip(dry, wet, MODE_NAMES):
        if name == "elastic 1":
            bottom.axvline(abs(d), color="0.6", ls=":", lw=0.8)
            bottom.axvline(abs(w), color="k", ls=":", lw=0.8)
    bottom.set_title("Receptance of the breathing mode (dotted: dry and wet eigenfrequencies)", fontsize=9)
    bottom.set_xlabel("omega (rad/s)")
    bottom.set_ylabel("|eta1 / f_eta1| (m/N)")
    bottom.legend(loc="upper right", fontsize=7)
    fig.tight_layout()
    path = hc.save_svg(fig, FIGURE)
    plt.close(fig)
    return path


def report(result: dict) -> str:
    lines = [
        f"shell t = {1000 * result['thickness']:.0f} mm: D = {result['bending_stiffness']:.0f} N m, "
        f"mu = {result['shell_mass']:.1f} kg/m2, edge masses {result['edge_mass']:.1f} kg/m each",
        "mode         dry omega   wet omega   wet zeta   wet kR   wet/dry",
    ]
    for m in result["modes"]:
        lines.append(
            f"{m['name']:<11} {m['dry_omega']:9.3f}   {m['wet_omega']:9.3f}   {m['wet_damping_ratio']:8.4f}"
            f"   {m['wet_kR']:6.2f}   {m['wet_omega'] / m['dry_omega']:.3f}"
        )
    for name, r in result["resonances"].items():
        lines.append(
            f"{name} receptance peak: panel method {r['panel_omega']:.4f} rad/s {r['panel_peak']:.4e} m/N, "
            f"network {r['network_omega']:.4f} rad/s {r['network_peak']:.4e} m/N"
        )
    lines.append(
        f"free breathing from eta1 = {result['initial_eta1']} m over {result['duration']:.0f} s: "
        f"wet |eta1| over the last period {result['eta1_last_period_wet_m']:.2e} m; largest wet |p|: "
        + ", ".join(f"{k} {v:.1e}" for k, v in result["max_abs_wet_m"].items())
    )
    lines.append(
        "  scheme  h (s)   max|d eta1| (m)  rel. to eta1(0)  max|d heave| (m)  max|d p| (m)  |libcosim - fmpy|"
    )
    for r in result["runs"]:
        lib = f"{r['libcosim_minus_fmpy_m']:.1e}" if "libcosim_minus_fmpy_m" in r else "-"
        lines.append(
            f"  {r['scheme']:<6} {r['step']:<6}  {r['max_error_eta1_m']:.3e}"
            f"        {100 * r['max_error_eta1_relative']:8.4f} %       {r['max_error_heave_m']:.3e}"
            f"         {r['max_error_any_m']:.3e}     {lib}"
        )
    if "figure" in result:
        lines.append(f"figure: {result['figure']}")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="4 s, two steps, coarse mode tracking, no figure")
    parser.add_argument(
        "--fmu", help="the 9-DOF FMU (default: examples/cosim/fmus/Semicircle9.fmu, packed if missing)"
    )
    parser.add_argument("--json", help="also write the results to this JSON file")
    hc.add_update_docs(parser)
    args = parser.parse_args(argv)
    hc.apply_update_docs(args)
    result = run(args.quick, args.fmu)
    print(report(result))
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
