"""Rigid floating body in sway on a mooring spring, coupled to the semicircle sway FMU.

Run (from the repository root, after `bash tests/run.sh` or with the .venv of
tests/python/requirements.txt):

    .venv/bin/python examples/cosim/rigid_sway.py            # full run, writes target/reports/figures/cosim-rigid-sway.svg (--update-docs: docs/figures/)
    .venv/bin/python examples/cosim/rigid_sway.py --quick    # short run, no figure (what the test runs)

The FMU examples/cosim/fmus/SemicircleSway.fmu is packed on first use with
`cargo run --release -p fmu-pack -- pack semicircle --dofs sway -o ...`.

Model (per metre of hull, SI): semicircle R = 1 m, rho = 1025 kg/m3, g = 9.81 m/s2. The body's
mass is the displaced mass m = rho pi R^2 / 2 = 1610 kg/m; a linear spring k to the sea bed
gives a nominal period of 4 s with the infinite-frequency added mass,
k = (m + A_inf) (2 pi / 4 s)^2. Released at rest from x0 = 0.1 m:

    (m + A_inf) x'' + D x' + k x = F + D x'     co-simulation: F = force.sway from the FMU,
                                                A_inf = added_mass_inf, D = damping_direct
    Schilder et al., eq. 19 with m and k added to x's row   monolithic reference, solved exactly

Masters: fmpy's FMU2Slave and libcosimpy, both driven by the Python loop of
hydrocosim.cosimulate (schemes "zoh" and "ramp"); docs/COSIMULATION.md explains them.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import hydrocosim as hc  # noqa: E402

OFFSET = 0.1  # initial offset x0, m
NOMINAL_PERIOD = 4.0  # s, with m + A_inf
PACK_ARGS = ["semicircle", "--dofs", "sway"]
FIGURE = "cosim-rigid-sway.svg"


def body(network: hc.Network) -> hc.Structure:
    mass = hc.RHO * np.pi * hc.RADIUS**2 / 2
    spring = (mass + network.added_mass_inf[0, 0]) * (2 * np.pi / NOMINAL_PERIOD) ** 2
    return hc.Structure(np.array([[mass]]), np.zeros((1, 1)), np.array([[spring]]), np.eye(1))


def run(quick: bool = False, fmu=None, plot: bool = True) -> dict:
    duration = 20.0 if quick else 60.0
    steps_s = (0.1, 0.05) if quick else (0.1, 0.05, 0.01)
    fmu = hc.ensure_fmu("SemicircleSway", PACK_ARGS, fmu)
    network = hc.Network.from_fmu(fmu).scaled(hc.RHO, hc.G)
    structure = body(network)

    # Matrices as the FMU reports them; the network file must agree (same numbers, SI).
    probe = hc.FmpyHull(fmu)
    added_mass_inf, damping_direct = probe.matrix("added_mass_inf"), probe.matrix("damping_direct")
    probe.close()
    assert np.allclose(added_mass_inf, network.added_mass_inf, rtol=1e-12)
    assert np.allclose(damping_direct, network.damping_direct(), rtol=1e-12)

    mass, spring = structure.mass[0, 0], structure.stiffness[0, 0]
    # The body's mode: of the coupled system's eigenvectors (Im > 0), the one whose hull
    # kinetic energy (m + A_inf) |x'|^2 is the largest share of its energy.
    a = hc.coupled_system(structure, network)
    lam, vec = np.linalg.eig(a)
    n2 = 1 + network.aux_count
    m_aug, _, k_aug = network.augmented_matrices()
    m_aug[0, 0] += mass
    k_aug[0, 0] += spring
    keep = lam.imag > 1e-9
    lam, vec = lam[keep], vec[:, keep]

    def energy_share(v):
        x, xdot, z = v[:n2], v[n2 : 2 * n2], v[2 * n2 :]
        energy = abs(x.conj() @ k_aug @ x) + abs(xdot.conj() @ m_aug @ xdot) + np.vdot(z, z).real
        return abs(xdot[0]) ** 2 * (mass + added_mass_inf[0, 0]) / energy

    share = [energy_share(v) for v in vec.T]
    body_mode = lam[int(np.argmax(share))]
    result = {
        "mass": mass,
        "spring": spring,
        "added_mass_inf": added_mass_inf[0, 0],
        "damping_direct": damping_direct[0, 0],
        "offset": OFFSET,
        "duration": duration,
        "dry_period": 2 * np.pi * np.sqrt(mass / spring),
        "wet_period": 2 * np.pi / body_mode.imag,
        "wet_damping_ratio": -body_mode.real / abs(body_mode),
        "runs": [],
    }

    series = {}
    for h in steps_s:
        steps = int(round(duration / h))
        mono = hc.monolithic(structure, network, [OFFSET], h, steps)[:, 0]
        series[("mono", h)] = mono
        for scheme in hc.SCHEMES:
            hull = hc.FmpyHull(fmu)
            try:
                x = hc.cosimulate(hull, structure, added_mass_inf, damping_direct, [OFFSET], h, steps, scheme)[:, 0]
            finally:
                hull.close()
            lib = hc.LibcosimHull(fmu, h)
            try:
                x_lib = hc.cosimulate(lib, structure, added_mass_inf, damping_direct, [OFFSET], h, steps, scheme)[:, 0]
            finally:
                lib.close()
            series[(scheme, h)] = x
            error = float(np.max(np.abs(x - mono)))
            result["runs"].append(
                {
                    "scheme": scheme,
                    "step": h,
                    "max_error_m": error,
                    "max_error_relative": error / OFFSET,
                    "libcosim_minus_fmpy_m": float(np.max(np.abs(x_lib - x))),
                }
            )

    if plot and not quick:
        result["figure"] = str(figure(series, steps_s, duration))
    return result


def figure(series, steps_s, duration) -> pathlib.Path:
    plt = hc.pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.0, 6.0), sharex=True)
    h = max(steps_s)
    t = np.arange(len(series[("mono", h)])) * h
    top.plot(t, series[("mono", h)], "k-", lw=1.2, label="monolithic (Schilder et al., eq. 19, exact)")
    top.plot(t[::2], series[("zoh", h)][::2], "o", ms=3, mfc="none", color="C3", label=f"co-simulation, zoh, h = {h} s")
    top.plot(t[1::2], series[("ramp", h)][1::2], "x", ms=3, color="C0", label=f"co-simulation, ramp, h = {h} s")
    top.set_ylabel("sway x (m)")
    top.legend(loc="upper right", fontsize=8)
    top.set_title("Semicircle in sway on a spring, released from x0 = 0.1 m (fmpy = libcosimpy)")
    for i, h in enumerate(steps_s):
        for scheme, style in (("zoh", "--"), ("ramp", "-")):
            t, env = hc.envelope(np.abs(series[(scheme, h)] - series[("mono", h)]), h, 1.0)
            bottom.semilogy(t, env, style, color=f"C{i}", lw=1.0, label=f"{scheme}, h = {h} s")
    bottom.set_ylim(1e-8, 1e-1)
    bottom.set_xlim(0, duration)
    bottom.set_xlabel("time (s)")
    bottom.set_ylabel("max |x_cosim - x_mono| per 1 s (m)")
    bottom.legend(ncol=3, fontsize=7, loc="lower right")
    path = hc.save_svg(fig, FIGURE)
    plt.close(fig)
    return path


def report(result: dict) -> str:
    lines = [
        f"body mass {result['mass']:.1f} kg/m, A_inf {result['added_mass_inf']:.1f} kg/m, "
        f"damping_direct {result['damping_direct']:.1f} N s/m2, spring {result['spring']:.1f} N/m2",
        f"period dry {result['dry_period']:.3f} s; wet (eq. 19 eigenvalue) {result['wet_period']:.3f} s, "
        f"damping ratio {result['wet_damping_ratio']:.4f}",
        f"x0 = {result['offset']} m, {result['duration']:.0f} s; max |x_cosim - x_mono| over the run:",
        "  scheme  h (s)   error (m)   rel. to x0   |libcosim - fmpy| (m)",
    ]
    for r in result["runs"]:
        lines.append(
            f"  {r['scheme']:<6} {r['step']:<6}  {r['max_error_m']:.3e}   {100 * r['max_error_relative']:8.4f} %"
            f"   {r['libcosim_minus_fmpy_m']:.1e}"
        )
    if "figure" in result:
        lines.append(f"figure: {result['figure']}")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="20 s, two steps, no figure")
    parser.add_argument(
        "--fmu", help="the sway FMU (default: examples/cosim/fmus/SemicircleSway.fmu, packed if missing)"
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
