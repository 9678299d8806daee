"""Strip theory (fmu-pack sweep) against Capytaine 3.0 (3D panel method) on the box barge.

The ship is examples/ships/box_barge.xml: a box 100 m x 10 m x 5 m (L/B = 10), 41 stations of
the exact rectangular section, DOFs heave, pitch and the vertical bending mode vb1 (the first
free-free mode of a uniform beam, w = 1 m at the ends). Capytaine meshes the same box and moves
it in the same DOFs:

- heave (0, 0, 1) and pitch about the origin on the free surface, Capytaine's rigid rotation
  about +y, (z, 0, -x): its vertical part is our w = -x theta (bow down positive); its
  horizontal part z theta moves the flat ends, which strip theory leaves out (see pitch_w);
- vb1 (0, 0, w(x)) with w interpolated linearly between the ship file's station values, the
  same function the strip integration uses;
- pitch_w (0, 0, -x): pitch's vertical part alone, the motion strip theory integrates,
  computed only to tell the ends' surge share of the 3D pitch coefficients.

Irregular frequencies: the box's first one is at omega = 1.84 rad/s (Capytaine's estimate),
just above the compared band (0.2 .. 1.8 rad/s) and close enough to spoil it (without a lid the
coarse mesh's heave damping at 1.77 rad/s drops by 24 %), so Capytaine gets a lid on the
waterplane (z = 0, generate_lid) and our sections their own interior lid (docs/VALIDATION.md).

Conventions: ours exp(+i omega t), A~ = a - i b / omega; Capytaine exp(-i omega t) with real
added mass and damping. Our exciting force is the complex conjugate of Capytaine's. Headings
agree (0 = waves towards +x, 180 head seas, 90 towards +y).

Run (from the repository root, with the .venv of tests/python/requirements.txt and the release
fmu-pack built):

    .venv/bin/python examples/ships/compare_capytaine.py             # table, target/reports/figures/ship-capytaine.svg (docs/figures/ with --update-docs)
    .venv/bin/python examples/ships/compare_capytaine.py --no-plot   # table only

tests/python/test_ship_capytaine.py runs a reduced version (a few frequencies, the coarse mesh)
through compare().
"""
import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
SHIP = ROOT / "examples" / "ships" / "box_barge.xml"
FIGURE = ROOT / "target" / "reports" / "figures" / "ship-capytaine.svg"  # --update-docs: docs/figures/
RHO, G = 1025.0, 9.81
L, B, T = 100.0, 10.0, 5.0
DOFS = ["heave", "pitch", "vb1"]
CAPYTAINE_DOFS = {"heave": "Heave", "pitch": "Pitch", "vb1": "vb1"}

# Capytaine meshes (panels along x, y, z of the box; both symmetry planes are used).
# FINE, the figure's: 1.25 m x 1.25 m x 0.625 m panels, 2048 on the hull and 336 on the lid.
# Against a finer mesh (120 x 12 x 10: 4080 + 1040 panels) at 0.5, 1.08, 1.47 and 1.72 rad/s
# its added masses are within 0.4 %, its damping within 1.6 % and its exciting forces within
# 1.5 %; at 2 rad/s its damping moved by 10-18 %, so the comparison stops at 1.8 rad/s.
# COARSE, the test's: 2.5 m x 2.5 m x 1.25 m panels, 512 on the hull and 88 on the lid, 5 s
# for 8 frequencies; the coarsest of the three meshes tried (600, 1100 and 2384 panels with
# the lid), its differences from FINE well below the strip-3D differences the test asserts:
# at the test's frequencies (0.25 .. 1.5 rad/s) within 2.1 % of FINE in every
# added mass and damping, 2.7 % in the heave and vb1 exciting forces and 4.7 % in pitch's;
# above 1.7 rad/s its damping is off by 5 % to several times (panels longer than an eighth of
# the wavelength).
COARSE = (40, 4, 4)
FINE = (80, 8, 8)

# Our section panels. The ship default (64 panels, 3 extrapolation levels, made for smooth
# sections) puts the box's two bottom corners on a 16-panel level and overshoots: heave added
# mass +2.0..3.2 % and damping +3.7..9.1 % over 0.2 .. 2 rad/s against 256 panels, which agree with
# 512 panels (3 levels) within 0.06 % and with 1024 plain panels within 0.5 %.
PANELS = 256


def fmu_pack_default():
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    if not target.is_absolute():
        target = ROOT / target
    return target / "release" / "fmu-pack"


def station_mode(ship=SHIP, name="vb1"):
    """(x, w) of a mode at the stations of a ship file."""
    root = ET.parse(ship).getroot()
    mode = next(m for m in root.iter("mode") if m.get("name") == name)
    at = [(float(a.get("x")), float(a.get("w", "0"))) for a in mode.iter("at")]
    return np.array([a[0] for a in at]), np.array([a[1] for a in at])


def read_rows(path):
    rows = []
    for line in pathlib.Path(path).read_text().splitlines():
        if line and not line.startswith(("#", "omega", "i,")):
            rows.append(line.split(","))
    return rows


def strip(fmu_pack, omega, headings, panels=None):
    """Our strip theory: (omegas, A~ [n_omega, 3, 3], X {heading: [n_omega, 3]}, wall seconds).

    omega = (MIN, MAX, COUNT), log-spaced as fmu-pack's --omega."""
    with tempfile.TemporaryDirectory() as folder:
        table, excitation = pathlib.Path(folder, "a.csv"), pathlib.Path(folder, "x.csv")
        command = [str(fmu_pack), "sweep", str(SHIP), "-o", str(table),
                   "--excitation", str(excitation),
                   "--omega", f"{omega[0]!r}:{omega[1]!r}:{omega[2]}",
                   "--headings", ",".join(f"{h:g}" for h in headings)]
        if panels:
            # The sections' discretization of docs/SHIPS.md's comparison: 3 levels (the
            # default for sections with corners is 2).
            command += ["--panels", str(panels), "--levels", "3"]
        start = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True, text=True)
        seconds = time.perf_counter() - start
        rows, xrows = read_rows(table), read_rows(excitation)
    omegas = sorted({float(r[0]) for r in rows if r[0] != "inf"})
    index = {w: k for k, w in enumerate(omegas)}
    added = np.zeros((len(omegas), 3, 3), complex)
    for r in rows:
        if r[0] != "inf":
            added[index[float(r[0])], int(r[1]) - 1, int(r[2]) - 1] = complex(float(r[3]), float(r[4]))
    force = {h: np.zeros((len(omegas), 3), complex) for h in headings}
    for r in xrows:
        force[float(r[2])][index[float(r[0])], int(r[1]) - 1] = complex(float(r[3]), float(r[4]))
    return np.array(omegas), added, force, seconds


def capytaine(omegas, headings, resolution=COARSE):
    """Capytaine on the same box: (A~ [n_omega, 4, 4] for heave, pitch, vb1, pitch_w in our
    convention a - i b / omega, X {heading: [n_omega, 3]} in our convention, wall seconds,
    panels (hull, lid))."""
    import capytaine as cpt

    start = time.perf_counter()
    mesh = cpt.mesh_parallelepiped(size=(L, B, T), center=(0, 0, -T / 2), resolution=resolution,
                                   missing_sides={"top"}, reflection_symmetry=True, name="box")
    lid = mesh.generate_lid(z=0.0)
    centres = mesh.faces_centers
    xs, ws = station_mode()
    zero = np.zeros(len(centres))
    dofs = cpt.rigid_body_dofs(only=["Heave", "Pitch"], rotation_center=(0, 0, 0))
    dofs["vb1"] = np.column_stack([zero, zero, np.interp(centres[:, 0], xs, ws)])
    dofs["pitch_w"] = np.column_stack([zero, zero, -centres[:, 0]])
    body = cpt.FloatingBody(mesh=mesh, lid_mesh=lid, dofs=dofs, name="box")
    problems = [cpt.RadiationProblem(body=body, radiating_dof=d, omega=w, rho=RHO, g=G)
                for w in omegas for d in body.dofs]
    problems += [cpt.DiffractionProblem(body=body, wave_direction=np.radians(h), omega=w,
                                        rho=RHO, g=G)
                 for w in omegas for h in headings]
    results = cpt.BEMSolver().solve_all(problems, progress_bar=False)
    data = cpt.assemble_dataset(results, hydrostatics=False)
    seconds = time.perf_counter() - start
    names = [CAPYTAINE_DOFS[d] for d in DOFS] + ["pitch_w"]
    added = np.zeros((len(omegas), 4, 4), complex)
    for i, ni in enumerate(names):
        for j, nj in enumerate(names):
            a = data.added_mass.sel(influenced_dof=ni, radiating_dof=nj).values
            b = data.radiation_damping.sel(influenced_dof=ni, radiating_dof=nj).values
            added[:, i, j] = a - 1j * b / np.asarray(omegas)
    force = {}
    for h in headings:
        x = data.excitation_force.sel(wave_direction=np.radians(h), method="nearest")
        force[h] = np.conj(np.column_stack([x.sel(influenced_dof=n).values for n in names[:3]]))
    return added, force, seconds, (mesh.nb_faces, lid.nb_faces)


def compare(fmu_pack, omega=(0.2, 1.8, 16), headings=(90.0, 180.0), resolution=FINE,
            panels=PANELS):
    """Both codes at the same omegas: a dict of the results and the wall times."""
    omegas, ours, our_force, our_seconds = strip(fmu_pack, omega, headings, panels)
    theirs, their_force, their_seconds, panels_3d = capytaine(omegas, headings, resolution)
    return {"omega": omegas, "ours": ours, "theirs": theirs, "our_force": our_force,
            "their_force": their_force, "our_seconds": our_seconds,
            "their_seconds": their_seconds, "panels": panels_3d, "our_panels": panels}


def report(r):
    omegas, ours, theirs = r["omega"], r["ours"], r["theirs"]
    kl = omegas**2 / G * L
    print(f"# strip theory: fmu-pack sweep, 41 stations x 1 section of {r['our_panels']} panels, "
          f"{r['our_seconds']:.2f} s wall")
    print(f"# Capytaine {capytaine_version()}: {r['panels'][0]} hull + {r['panels'][1]} lid panels, "
          f"{r['their_seconds']:.1f} s wall")
    print("# relative differences (ours - Capytaine) / |Capytaine| in %; a = added mass, "
          "b = damping; c37 = a(heave,vb1) / sqrt(a33 a_vb1)")
    header = ("omega", "kL", "a33", "b33", "a55", "b55", "a77", "b77", "c37 ours", "c37 3D",
              "a55w", "b55w")
    print(" ".join(f"{h:>8}" for h in header))
    for k, w in enumerate(omegas):
        cells = [f"{w:8.3f}", f"{kl[k]:8.2f}"]
        for i in range(3):
            a, b = ours[k, i, i].real, -ours[k, i, i].imag * w
            ac, bc = theirs[k, i, i].real, -theirs[k, i, i].imag * w
            cells += [f"{100 * (a - ac) / abs(ac):8.1f}", f"{100 * (b - bc) / abs(bc):8.1f}"]
        for added in (ours, theirs):
            c = added[k, 0, 2].real / np.sqrt(added[k, 0, 0].real * added[k, 2, 2].real)
            cells.append(f"{c:8.3f}")
        a, b = ours[k, 1, 1].real, -ours[k, 1, 1].imag * w
        ac, bc = theirs[k, 3, 3].real, -theirs[k, 3, 3].imag * w
        cells += [f"{100 * (a - ac) / abs(ac):8.1f}", f"{100 * (b - bc) / abs(bc):8.1f}"]
        print(" ".join(cells))
    print("# exciting force: |X| ratio ours / Capytaine and phase difference (degrees)")
    print(" ".join(f"{h:>8}" for h in ("omega", "kL", "180 X3", "deg", "180 X5", "deg",
                                        "180 X7", "deg", "90 X3", "deg", "90 X7", "deg")))
    for k, w in enumerate(omegas):
        cells = [f"{w:8.3f}", f"{kl[k]:8.2f}"]
        for h, j in ((180.0, 0), (180.0, 1), (180.0, 2), (90.0, 0), (90.0, 2)):
            if h not in r["our_force"]:
                cells += ["-", "-"]
                continue
            x, xc = r["our_force"][h][k, j], r["their_force"][h][k, j]
            cells += [f"{abs(x) / abs(xc):8.3f}", f"{np.degrees(np.angle(x / xc)):8.1f}"]
        print(" ".join(cells))


def capytaine_version():
    import capytaine as cpt
    return cpt.__version__


def plot(r, path=FIGURE):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"svg.hashsalt": "hydrofmu", "svg.fonttype": "none", "figure.dpi": 100,
                         "font.size": 9})
    omegas, ours, theirs = r["omega"], r["ours"], r["theirs"]
    kl = omegas**2 / G * L
    xs, ws = station_mode()
    # Reference masses: rho L B T, its pitch inertia about the waterline centre line, and
    # rho B T integral w^2 dx for the mode.
    mass = RHO * L * B * T
    refs = [mass, mass * L**2 / 12, RHO * B * T * np.trapezoid(ws**2, xs)]
    labels = ["heave", "pitch", "vb1"]
    fig, axes = plt.subplots(4, 3, figsize=(11, 11), constrained_layout=True)
    for i in range(3):
        for col, (part, name) in enumerate(((1, "a / m"), (-1, "b / (omega m)"))):
            ax = axes[i, col]
            ax.plot(kl, (ours[:, i, i].real if part > 0 else -ours[:, i, i].imag) / refs[i],
                    "-", color="C0", label="strip theory (ours)")
            ax.plot(kl, (theirs[:, i, i].real if part > 0 else -theirs[:, i, i].imag) / refs[i],
                    "o", color="C3", ms=4, label="Capytaine 3D")
            if i == 1:
                ax.plot(kl, (theirs[:, 3, 3].real if part > 0 else -theirs[:, 3, 3].imag) / refs[i],
                        "x", color="C2", ms=4, label="Capytaine 3D, pitch_w (no end surge)")
            ax.set_title(f"{labels[i]}-{labels[i]}: {name}")
        for h, marker in ((180.0, "-"), (90.0, "--")):
            if i == 1 and h == 90.0:
                continue  # zero by symmetry
            scale = RHO * G * (L * B if i == 0 else L**2 * B / 12 if i == 1 else np.trapezoid(np.abs(ws), xs) * B)
            ax = axes[i, 2]
            ax.plot(kl, np.abs(r["our_force"][h][:, i]) / scale, marker, color="C0",
                    label=f"ours, {h:g} deg")
            ax.plot(kl, np.abs(r["their_force"][h][:, i]) / scale, "o" if h == 180 else "s",
                    color="C3", ms=4, mfc="none" if h == 90 else None, label=f"Capytaine, {h:g} deg")
            ax.set_title(f"|X| {labels[i]} per unit wave amplitude (normalized)")
    for col, (part, name) in enumerate(((1, "a"), (-1, "b / omega"))):
        ax = axes[3, col]
        norm = np.sqrt(ours[:, 0, 0].real * ours[:, 2, 2].real)
        normc = np.sqrt(theirs[:, 0, 0].real * theirs[:, 2, 2].real)
        ax.plot(kl, (ours[:, 0, 2].real if part > 0 else -ours[:, 0, 2].imag) / norm, "-",
                color="C0", label="strip theory (ours)")
        ax.plot(kl, (theirs[:, 0, 2].real if part > 0 else -theirs[:, 0, 2].imag) / normc, "o",
                color="C3", ms=4, label="Capytaine 3D")
        ax.set_title(f"heave-vb1: {name} / sqrt(a33 a77)")
    ax = axes[3, 2]
    for i, color in ((0, "C0"), (1, "C1"), (2, "C2")):
        a, ac = ours[:, i, i], theirs[:, i, i]
        ax.plot(kl, 100 * (a.real - ac.real) / np.abs(ac.real), "-", color=color,
                label=f"{labels[i]} a")
        ax.plot(kl, 100 * (ac.imag - a.imag) / np.abs(ac.imag), "--", color=color,
                label=f"{labels[i]} b")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_ylim(-50, 150)
    ax.set_title("ours - Capytaine, % of Capytaine (clipped)")
    for ax in axes.flat:
        ax.set_xscale("log")
        ax.set_xlabel("kL = omega^2 L / g")
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"Box barge {L:g} m x {B:g} m x {T:g} m: strip theory (41 stations) vs "
                 f"Capytaine {capytaine_version()} ({r['panels'][0]} hull + {r['panels'][1]} lid panels)")
    fig.text(0.01, -0.01, ".venv/bin/python examples/ships/compare_capytaine.py; m: rho L B T, "
             "rho L^3 B T / 12, rho B T int w^2 dx", fontsize=7, color="#555555")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, format=path.suffix[1:], metadata={"Date": None} if path.suffix == ".svg" else None,
                bbox_inches="tight")
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fmu-pack", type=pathlib.Path, default=fmu_pack_default())
    parser.add_argument("--omega", default="0.2:1.8:16", help="MIN:MAX:COUNT, log-spaced")
    parser.add_argument("--coarse", action="store_true", help="the test's coarse Capytaine mesh")
    parser.add_argument("--no-plot", action="store_true")
    parser.add_argument("--update-docs", action="store_true", help="write the figure into the tracked docs/figures")
    args = parser.parse_args()
    lo, hi, n = args.omega.split(":")
    r = compare(args.fmu_pack, (float(lo), float(hi), int(n)),
                resolution=COARSE if args.coarse else FINE)
    report(r)
    if not args.no_plot:
        path = ROOT / "docs" / "figures" / FIGURE.name if args.update_docs else FIGURE
        path.parent.mkdir(parents=True, exist_ok=True)
        print("wrote", plot(r, path).relative_to(ROOT))


if __name__ == "__main__":
    sys.exit(main())
