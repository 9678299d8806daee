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

Finite depth (--water-depth H, metres): both codes in water of depth H (fmu-pack sweep
--water-depth H, Capytaine's water_depth=H with the Fortran Prony fit of its finite-depth
kernel), then both again in deep water for the depth effect, each code's value at depth H over
its own deep-water value. kL then uses the depth's wavenumber, omega^2 = g k tanh(k h). Each
Capytaine frequency is checked against its own far field (energy_check); points off by more
than 5 % are marked. docs/FINITE_DEPTH.md, "Ships in finite depth", has the measured numbers.

Run (from the repository root, with the .venv of tests/python/requirements.txt and the release
fmu-pack built):

    .venv/bin/python examples/ships/compare_capytaine.py             # table, target/reports/figures/ship-capytaine.svg (docs/figures/ with --update-docs)
    .venv/bin/python examples/ships/compare_capytaine.py --no-plot   # table only
    .venv/bin/python examples/ships/compare_capytaine.py --water-depth 10   # and deep water; ship-capytaine-depth-10m.svg

tests/python/test_ship_capytaine.py runs a reduced version (a few frequencies, the coarse mesh)
through compare(), tests/python/test_ship_capytaine_depth.py the same at h = 10 m.
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

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from linear_waves import group_velocity, wavenumber  # noqa: E402

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
# Headings of energy_check's integral over a quarter circle (every 5 degrees; every 2.5 gives
# the same ratio to 4 digits at 1.555 and 1.8 rad/s in deep water).
ENERGY_HEADINGS = tuple(float(h) for h in np.linspace(0.0, 90.0, 19))
# Capytaine's deep-water box passes energy_check within 3 % (0.2 .. 1.8 rad/s, fine mesh);
# beyond 5 % a finite-depth point is not trusted.
ENERGY_TOLERANCE = 0.05

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


def strip(fmu_pack, omega, headings, panels=None, water_depth=None):
    """Our strip theory: (omegas, A~ [n_omega, 3, 3], X {heading: [n_omega, 3]}, wall seconds).

    omega = (MIN, MAX, COUNT), log-spaced as fmu-pack's --omega; water_depth in m, None for
    deep water."""
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
        if water_depth is not None:
            command += ["--water-depth", f"{water_depth!r}"]
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


def energy_check(data, omegas, water_depth):
    """Capytaine's heave damping over the damping its heave exciting force radiates,
    b33 / (k / (8 pi rho g c_g) int_0^2pi |X3(beta)|^2 dbeta), c_g = (omega / 2k)(1 + 2kh /
    sinh 2kh), per omega: 1 for a consistent solution (the box's two symmetry planes give the
    integral from ENERGY_HEADINGS)."""
    betas = np.radians(ENERGY_HEADINGS)
    ratios = []
    for w in omegas:
        d = data.sel(omega=w)
        b = float(d.radiation_damping.sel(influenced_dof="Heave", radiating_dof="Heave"))
        x = d.excitation_force.sel(influenced_dof="Heave")
        directions = np.asarray(x.wave_direction.values, float)
        x = x.isel(wave_direction=[int(np.argmin(np.abs(directions - beta))) for beta in betas])
        k = float(wavenumber(w, water_depth))
        cg = float(group_velocity(w, water_depth))
        radiated = k / (8 * np.pi * RHO * G * cg) * 4 * np.trapezoid(np.abs(x.values) ** 2, betas)
        ratios.append(b / radiated)
    return np.array(ratios)


def capytaine(omegas, headings, resolution=COARSE, water_depth=None, check_energy=False):
    """Capytaine on the same box: (A~ [n_omega, 4, 4] for heave, pitch, vb1, pitch_w in our
    convention a - i b / omega, X {heading: [n_omega, 3]} in our convention, wall seconds,
    panels (hull, lid), energy_check's ratios or None). water_depth in m, None for deep water
    (Capytaine's default)."""
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
    depth = {} if water_depth is None else {"water_depth": water_depth}
    problems = [cpt.RadiationProblem(body=body, radiating_dof=d, omega=w, rho=RHO, g=G, **depth)
                for w in omegas for d in body.dofs]
    problems += [cpt.DiffractionProblem(body=body, wave_direction=np.radians(h), omega=w,
                                        rho=RHO, g=G, **depth)
                 for w in omegas for h in headings]
    if check_energy:
        problems += [cpt.DiffractionProblem(body=body, wave_direction=np.radians(h), omega=w,
                                            rho=RHO, g=G, **depth)
                     for w in omegas for h in ENERGY_HEADINGS if h not in headings]
    if water_depth is None:
        solver = cpt.BEMSolver()
    else:
        # The Prony fit of the finite-depth kernel: Capytaine 3.0's default ("python") fits at
        # randomized points (h = 10 m, coarse mesh: b33 at 1.5 rad/s moves by 2 % with the
        # other frequencies solved alongside) and fails energy_check from 1.5 rad/s on (fine
        # mesh: 1.17 at 1.555 rad/s, 2.04 at 1.8). Nemoh's Fortran fit is deterministic and
        # passes within 3 % up to kh = 1.9; above, it jumps with kh (0.944, 0.983 and 1.016
        # within 0.001 rad/s of 1.555 rad/s), so report() marks the points it fails.
        solver = cpt.BEMSolver(green_function=cpt.Delhommeau(
            finite_depth_prony_decomposition_method="fortran"))
    results = solver.solve_all(problems, progress_bar=False)
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
    energy = energy_check(data, omegas, water_depth) if check_energy else None
    return added, force, seconds, (mesh.nb_faces, lid.nb_faces), energy


def compare(fmu_pack, omega=(0.2, 1.8, 16), headings=(90.0, 180.0), resolution=FINE,
            panels=PANELS, water_depth=None):
    """Both codes at the same omegas in water of depth water_depth (m; None: deep water): a
    dict of the results and the wall times."""
    omegas, ours, our_force, our_seconds = strip(fmu_pack, omega, headings, panels, water_depth)
    # In finite depth Capytaine's heave is checked against its own far field (energy_check).
    theirs, their_force, their_seconds, panels_3d, energy = capytaine(
        omegas, headings, resolution, water_depth, check_energy=water_depth is not None)
    return {"omega": omegas, "ours": ours, "theirs": theirs, "our_force": our_force,
            "their_force": their_force, "our_seconds": our_seconds,
            "their_seconds": their_seconds, "panels": panels_3d, "our_panels": panels,
            "water_depth": water_depth, "their_energy": energy}


def depth_title(water_depth):
    if water_depth is None:
        return ""
    return f", water depth {water_depth:g} m (h/T = {water_depth / T:g})"


def report(r):
    omegas, ours, theirs = r["omega"], r["ours"], r["theirs"]
    kl = wavenumber(omegas, r.get("water_depth")) * L
    if r.get("water_depth") is not None:
        h = r["water_depth"]
        print(f"# water depth {h:g} m, h/T = {h / T:g}; kL with the depth's wavenumber k, "
              f"kh from {kl[0] * h / L:.2f} to {kl[-1] * h / L:.2f}")
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


def depth_effect(r, deep):
    """Finite over deep water, per code: {name: (ours, Capytaine's)} at r's omegas."""
    omegas = r["omega"]
    assert np.allclose(omegas, deep["omega"], rtol=1e-12)
    ratios = {}
    for i, name in enumerate(("33", "55", "77")):
        for part, tag in ((lambda z: z.real, "a"), (lambda z: -z.imag, "b")):
            ratios[tag + name] = tuple(part(r[key][:, i, i]) / part(deep[key][:, i, i])
                                       for key in ("ours", "theirs"))
    for h, j, name in ((90.0, 0, "X3 90"), (180.0, 0, "X3 180"), (180.0, 1, "X5 180"),
                       (180.0, 2, "X7 180")):
        ratios[name] = tuple(np.abs(r[key][h][:, j]) / np.abs(deep[key][h][:, j])
                             for key in ("our_force", "their_force"))
    return ratios


def report_depth_effect(r, deep):
    h = r["water_depth"]
    kh = wavenumber(r["omega"], h) * h
    print(f"# depth effect: the value at h = {h:g} m over the same code's deep-water value, "
          "ours / Capytaine's (|X| for the exciting forces); energy: Capytaine's b33 over the "
          "damping of its far field at this depth (energy_check; 1 if consistent, * off by more "
          f"than {ENERGY_TOLERANCE:.0%}: not trusted)")
    ratios = depth_effect(r, deep)
    print(" ".join(f"{c:>8}" for c in ("omega", "kh", "energy")) + " "
          + " ".join(f"{name:>13}" for name in ratios))
    for k, w in enumerate(r["omega"]):
        energy = r["their_energy"][k]
        cells = [f"{w:8.3f}", f"{kh[k]:8.2f}",
                 f"{energy:7.3f}" + ("*" if abs(energy - 1) > ENERGY_TOLERANCE else " ")]
        cells += [f"{ours[k]:6.3f}/{theirs[k]:6.3f}" for ours, theirs in ratios.values()]
        print(" ".join(cells))
    print(f"# deep water: Capytaine {deep['their_seconds']:.1f} s wall")


def plot_depth(r, deep, path):
    """Heave at depth h and in deep water, both codes, and the depth effects of heave, pitch
    and the heave force."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"svg.hashsalt": "hydrofmu", "svg.fonttype": "none", "figure.dpi": 100,
                         "font.size": 9})
    h, omegas = r["water_depth"], r["omega"]
    mass = RHO * L * B * T
    fig, axes = plt.subplots(2, 3, figsize=(11, 6.5), constrained_layout=True)
    curves = ((0, lambda z: z.real, "heave a33 / (rho L B T)"),
              (0, lambda z: -z.imag, "heave b33 / (omega rho L B T)"))
    for col, (i, part, title) in enumerate(curves):
        ax = axes[0, col]
        for data, style, label in ((r, "", f"h = {h:g} m"), (deep, "--", "deep")):
            ax.plot(omegas, part(data["ours"][:, i, i]) / mass, "C0" + (style or "-"),
                    label=f"strip theory, {label}")
            ax.plot(omegas, part(data["theirs"][:, i, i]) / mass, "C3x" if style else "C3o",
                    ms=4, label=f"Capytaine 3D, {label}")
        ax.set_title(title)
    ax = axes[0, 2]
    for heading, color in ((90.0, "C0"), (180.0, "C2")):
        scale = RHO * G * L * B
        ax.plot(omegas, np.abs(r["our_force"][heading][:, 0]) / scale, "-", color=color,
                label=f"strip theory, {heading:g} deg")
        ax.plot(omegas, np.abs(r["their_force"][heading][:, 0]) / scale, "o", color=color, ms=4,
                mfc="none", label=f"Capytaine, {heading:g} deg")
    ax.set_title("heave |X3| / (rho g L B a)")
    ratios = depth_effect(r, deep)
    for ax, names, title in ((axes[1, 0], ("a33", "b33"), "heave"),
                             (axes[1, 1], ("a55", "b55"), "pitch"),
                             (axes[1, 2], ("X3 90", "X3 180"), "|X3|")):
        for name, color in zip(names, ("C0", "C1")):
            ours, theirs = ratios[name]
            ax.plot(omegas, ours, "-", color=color, label=f"{name}, strip theory")
            ax.plot(omegas, theirs, "o", color=color, ms=4, label=f"{name}, Capytaine")
        ax.axhline(1, color="k", lw=0.5)
        ax.set_yscale("log")
        ax.set_title(f"{title}: value at h = {h:g} m / deep water")
    failing = omegas[np.abs(r["their_energy"] - 1) > ENERGY_TOLERANCE]
    for ax in axes.flat:
        if len(failing):
            ax.axvspan(failing.min(), omegas[-1], color="#dddddd", lw=0,
                       label=f"Capytaine's energy check off by > {ENERGY_TOLERANCE:.0%}")
        ax.set_xscale("log")
        ax.set_xticks([0.2, 0.5, 1.0, 2.0], ["0.2", "0.5", "1", "2"])
        ax.set_xticks([], minor=True)
        ax.set_xlabel("omega, rad/s")
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"Box barge {L:g} m x {B:g} m x {T:g} m{depth_title(h)}: strip theory vs "
                 f"Capytaine {capytaine_version()} ({r['panels'][0]} hull + {r['panels'][1]} "
                 "lid panels)")
    kh = wavenumber(omegas[[0, -1]], h) * h
    fig.text(0.01, -0.01, ".venv/bin/python examples/ships/compare_capytaine.py --water-depth "
             f"{h:g}; kh = {kh[0]:.2f} .. {kh[1]:.2f}", fontsize=7, color="#555555")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, format=path.suffix[1:],
                metadata={"Date": None} if path.suffix == ".svg" else None, bbox_inches="tight")
    return path


def figure_name(water_depth):
    return FIGURE.name if water_depth is None else f"ship-capytaine-depth-{water_depth:g}m.svg"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fmu-pack", type=pathlib.Path, default=fmu_pack_default())
    parser.add_argument("--omega", default="0.2:1.8:16", help="MIN:MAX:COUNT, log-spaced")
    parser.add_argument("--coarse", action="store_true", help="the test's coarse Capytaine mesh")
    parser.add_argument("--no-plot", action="store_true")
    parser.add_argument("--update-docs", action="store_true", help="write the figure into the tracked docs/figures")
    parser.add_argument("--water-depth", type=float, default=None, metavar="H",
                        help="water depth in m (default: deep water); runs deep water too, "
                        "for the depth effect")
    args = parser.parse_args()
    lo, hi, n = args.omega.split(":")
    omega = (float(lo), float(hi), int(n))
    resolution = COARSE if args.coarse else FINE
    r = compare(args.fmu_pack, omega, resolution=resolution, water_depth=args.water_depth)
    report(r)
    deep = None
    if args.water_depth is not None:
        deep = compare(args.fmu_pack, omega, resolution=resolution)
        report_depth_effect(r, deep)
    if not args.no_plot:
        name = figure_name(args.water_depth)
        path = ROOT / "docs" / "figures" / name if args.update_docs else FIGURE.with_name(name)
        path.parent.mkdir(parents=True, exist_ok=True)
        path = plot(r, path) if deep is None else plot_depth(r, deep, path)
        print("wrote", path.relative_to(ROOT))


if __name__ == "__main__":
    sys.exit(main())
