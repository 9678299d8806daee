"""Speed of the strip-theory ship sweep (fmu-pack sweep) against Capytaine 3.0 on a Wigley hull.

Both codes solve the same hull, the same frequencies, headings and DOFs in the same run, and the
script reports wall and CPU time of each and their ratios.

The hull: Wigley, L = 20 m, beam 4 m, draft T = 1.25 m, half-breadth
y(x, z) = 2 (1 - (x/10)^2) (1 - (z/1.25)^2) m for -10 <= x <= 10, -1.25 <= z <= 0.

- Ours: a ship file of 41 stations x = -10, -9.5, .., 10 (the pointed ends without a section),
  each other station a hull file section: the open contour from waterline to keel to
  waterline, 33 points a side (z = 0, -T/32, .., -T), the section's 2D frame (x transverse,
  negative on the first side; y vertical, negative down). The symmetric hull has 20 distinct
  sections (the ship sweep solves identical sections once). DOFs: the ship default
  sway heave roll pitch yaw. `fmu-pack sweep` with its defaults but for --omega and --headings,
  which are passed explicitly (the same values as its defaults for the full run).
- Capytaine: the analytic surface in quadrilaterals, NX panels along the length (uniform in x)
  and NZ over the draft (uniform in z) on each side, reflection symmetry about the xz plane
  (ReflectionSymmetricMesh; --symmetry both adds the yz plane, the fore-aft symmetry), a lid
  on the waterplane (z = 0) against irregular frequencies (the hull's first one is near 3 rad/s,
  inside the band): NX x NZ/2 panels on each half of the waterplane, between the centre line and
  the waterline. The lid is built from the same x grid rather than with generate_lid, which on
  this slender hull covers only a quarter to a half of the waterplane (it keeps candidate
  squares lying wholly inside the waterline, and with the symmetric mesh leaves a strip along
  the centre line). Rigid DOFs Sway, Heave, Roll, Pitch, Yaw about the origin (midship, on the
  free surface); radiation and diffraction problems; BEMSolver() defaults, solve_all with its
  default parallelism (one process, OpenMP and BLAS threads).

Frequencies: omega = sqrt(kR g / R), kR log-spaced 0.01 .. 5, R = 2 m (the largest half-beam),
g = 9.81: 100 of them, 0.2215 .. 4.952 rad/s (fmu-pack's default grid for this ship). Headings
0, 45, 90, 135, 180 degrees (0 = waves towards +x, 90 towards +y; Capytaine's wave_direction in
radians is the same angle). rho = 1025 kg/m^3.

Conventions: ours exp(+i omega t), A~ = a - i b / omega; Capytaine exp(-i omega t) with real
added mass a and damping b; our exciting force is the complex conjugate of Capytaine's. Rotation
signs agree (pitch about +y bow down, yaw about +z bow to port, roll about +x).

Mesh search ("coarsest adequate mesh"): the Capytaine meshes of MESHES and the fine REFERENCE at 6
frequencies of the grid (kR indices 0, 20, 40, 59, 79, 99: 0.22 .. 4.95 rad/s) and the 5
headings. A mesh is adequate when its added mass, damping and exciting-force magnitude are all
within 5 % of the reference's: each entry's difference relative to the largest absolute value of
that entry over the compared frequencies (added mass and damping per DOF pair, pairs that vanish
by symmetry left out; the exciting force per DOF, the largest over frequencies and headings).
The coarsest adequate mesh then solves all 100 frequencies x (5 radiation + 5 diffraction)
problems, timed: wall (perf_counter) and CPU of the process (getrusage RUSAGE_SELF user + sys,
which counts every thread). Our sweep runs 3 times (--repeat), interleaved with Capytaine's runs;
median wall and CPU (getrusage RUSAGE_CHILDREN) are reported. fmu-pack is copied to the
temporary folder first, so a rebuild during the run does not change the binary measured.

Run (from the repository root, with the .venv of tests/python/requirements.txt and the release
fmu-pack built):

    .venv/bin/python examples/ships/wigley_speed.py                         # mesh search + timing
    .venv/bin/python examples/ships/wigley_speed.py --capytaine-mesh 40x8   # skip the search
    .venv/bin/python examples/ships/wigley_speed.py --quick                 # smoke run
    .venv/bin/python examples/ships/wigley_speed.py --check-geometry DIR    # compare the ship files
                                                                            # with DIR's wigley_h.xml, sN.xml

The machine's load average is printed at the start and the end: on a shared machine both codes'
wall times move with it (CPU times less so).

Measured (2 cores, docs/SHIPS.md): the coarsest adequate mesh was 40x8 (640 hull + 320 lid
panels; worst: heave damping at 4.95 rad/s, 4.8 % off 100x20). On 2026-11-28 at load 1.1 .. 2.0
its full sweep took Capytaine 33.3 s wall and 64.0 s CPU against our 0.91 s and 1.81 s: 36.7x
in wall time, 35.4x in CPU time. With --symmetry both Capytaine's Green function part shrinks
but its linear solver and matrix-vector products grow: no faster on this mesh (96 s CPU against
84 s with xz alone, in one run under load).
The symmetric solves differ slightly from the unsymmetric one on the same panels (0.2 % for xz,
1.8 % for both on 40x8, falling with the panel size): the twisted quadrilaterals of the curved hull.
"""
import argparse
import logging
import os
import pathlib
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from compare_capytaine import read_rows  # noqa: E402  (the same CSV rows of fmu-pack sweep)
RHO, G = 1025.0, 9.81
L, HALF_BEAM, T = 20.0, 2.0, 1.25
R = HALF_BEAM  # fmu-pack's reference length: the largest section half-beam
STATIONS = 41  # x = -10, -9.5, .., 10
POINTS = 33  # contour points a side, z = 0 .. -T
DOFS = ["sway", "heave", "roll", "pitch", "yaw"]
CAPYTAINE_DOFS = ["Sway", "Heave", "Roll", "Pitch", "Yaw"]
HEADINGS = (0.0, 45.0, 90.0, 135.0, 180.0)
KR = (0.01, 5.0, 100)
CHECK = (0, 20, 40, 59, 79, 99)  # indices of the mesh search's frequencies in the 100-point grid
MESHES = [(20, 4), (30, 6), (40, 8), (60, 12)]
REFERENCE = (100, 20)
TOLERANCE = 0.05


def half_breadth(x, z):
    return 2.0 * (1.0 - (x / 10.0) ** 2) * (1.0 - (z / T) ** 2)


def omegas(kr=KR):
    """fmu-pack's default grid: omega = sqrt(kR g / R), kR log-spaced."""
    return np.sqrt(np.logspace(np.log10(kr[0]), np.log10(kr[1]), kr[2]) * G / R)


# ---------------------------------------------------------------------------------------------
# Ours


def fmu_pack_default():
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    if not target.is_absolute():
        target = ROOT / target
    return target / "release" / "fmu-pack"


def write_ship(folder):
    """The strip model: wigley_h.xml and s1.xml .. s39.xml in folder; the ship file's path."""
    folder = pathlib.Path(folder)
    zs = [-T * k / (POINTS - 1) for k in range(POINTS)]
    lines = ['<ship name="wigley">']
    for n in range(STATIONS):
        x = -10.0 + 0.5 * n
        if n in (0, STATIONS - 1):
            lines.append(f'<station x="{x!r}"/>')
            continue
        b = 2.0 * (1.0 - (x / 10.0) ** 2)
        side = [(b * (1.0 - (z / T) ** 2), z) for z in zs]
        points = [(-y, z) for y, z in side] + [(y, z) for y, z in reversed(side[:-1])]
        contour = "".join(f'<point x="{px!r}" y="{py!r}"/>' for px, py in points)
        (folder / f"s{n}.xml").write_text(
            f'<hull name="s{n}" half_beam="{b!r}"><contour closed="false">{contour}</contour>'
            f'<rigid name="sway" kind="sway"/></hull>\n')
        lines.append(f'<station x="{x!r}"><hull file="s{n}.xml"/></station>')
    lines.append("</ship>")
    ship = folder / "wigley_h.xml"
    ship.write_text("\n".join(lines) + "\n")
    return ship


def geometry(ship):
    """{station x: (half_beam, points [n, 2])} of a ship file of hull-file sections."""
    out = {}
    for station in ET.parse(ship).getroot().iter("station"):
        hull = station.find("hull")
        if hull is None:
            out[float(station.get("x"))] = None
            continue
        root = ET.parse(pathlib.Path(ship).parent / hull.get("file")).getroot()
        points = np.array([[float(p.get("x")), float(p.get("y"))] for p in root.iter("point")])
        out[float(station.get("x"))] = (float(root.get("half_beam")), points)
    return out


def check_geometry(ship, folder):
    """The largest coordinate difference between our ship files and folder's wigley_h.xml."""
    ours, theirs = geometry(ship), geometry(pathlib.Path(folder) / "wigley_h.xml")
    assert list(ours) == list(theirs), "stations differ"
    worst = 0.0
    for x in ours:
        if ours[x] is None or theirs[x] is None:
            assert ours[x] is None and theirs[x] is None, f"station {x}: section differs"
            continue
        assert ours[x][1].shape == theirs[x][1].shape, f"station {x}: point count differs"
        worst = max(worst, abs(ours[x][0] - theirs[x][0]), np.abs(ours[x][1] - theirs[x][1]).max())
    return worst


def strip(fmu_pack, ship, omega, headings, folder):
    """One run of our sweep: (omegas, a [n, 5, 5], b [n, 5, 5], X [n, n_headings, 5] in
    Capytaine's convention, wall s of the process, wall s it printed, CPU s)."""
    table, excitation = pathlib.Path(folder, "a.csv"), pathlib.Path(folder, "x.csv")
    command = [str(fmu_pack), "sweep", str(ship), "-o", str(table), "--excitation", str(excitation),
               "--omega", f"{float(omega[0])!r}:{float(omega[-1])!r}:{len(omega)}",
               "--headings", ",".join(f"{h:g}" for h in headings)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    run = subprocess.run(command, check=True, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    printed = re.findall(r"([0-9.]+) s wall", run.stdout + run.stderr)
    summary = [s for s in (run.stdout + run.stderr).splitlines() if " s wall" in s]
    rows, xrows = read_rows(table), read_rows(excitation)
    ws = np.array(sorted({float(r[0]) for r in rows if r[0] != "inf"}))
    index = {w: k for k, w in enumerate(ws)}
    n = len(DOFS)
    added = np.zeros((len(ws), n, n), complex)
    for r in rows:
        if r[0] != "inf":
            added[index[float(r[0])], int(r[1]) - 1, int(r[2]) - 1] = complex(float(r[3]), float(r[4]))
    force = np.zeros((len(ws), len(headings), n), complex)
    hindex = {h: k for k, h in enumerate(headings)}
    for r in xrows:
        force[index[float(r[0])], hindex[float(r[2])], int(r[1]) - 1] = complex(float(r[3]), float(r[4]))
    return {"omega": ws, "a": added.real, "b": -added.imag * ws[:, None, None],
            "X": np.conj(force), "wall": wall, "printed_wall": float(printed[-1]) if printed else None,
            "cpu": cpu, "summary": summary[-1] if summary else ""}


# ---------------------------------------------------------------------------------------------
# Capytaine


def hull_half(nx, nz, x_from=-10.0):
    """The port half (y >= 0) of the hull from x_from to +10, normals into the water."""
    from capytaine.meshes import Mesh

    xs = np.linspace(x_from, 10.0, nx + 1)
    zs = np.linspace(-T, 0.0, nz + 1)
    X, Z = np.meshgrid(xs, zs, indexing="ij")
    vertices = np.column_stack([X.ravel(), half_breadth(X, Z).ravel(), Z.ravel()])
    at = lambda i, j: i * (nz + 1) + j  # noqa: E731
    # (x, z) -> (x, z + dz) -> (x + dx, z + dz) -> (x + dx, z): normal towards +y.
    faces = [[at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)]
             for i in range(nx) for j in range(nz)]
    return Mesh(vertices, np.array(faces), name="wigley half")


def lid_half(nx, ny, x_from=-10.0):
    """The waterplane between the centre line and the port waterline (z = 0), on the hull's x
    grid with ny panels across; triangles at the pointed ends."""
    from capytaine.meshes import Mesh

    xs = np.linspace(x_from, 10.0, nx + 1)
    vertices, at = [], {}
    for i, x in enumerate(xs):
        b = half_breadth(x, 0.0)
        for j in range(ny + 1):
            if b == 0.0 and j > 0:
                at[i, j] = at[i, 0]
                continue
            at[i, j] = len(vertices)
            vertices.append((x, b * j / ny, 0.0))
    faces = []
    for i in range(nx):
        for j in range(ny):
            face = [at[i, j], at[i + 1, j], at[i + 1, j + 1], at[i, j + 1]]
            face = [v for k, v in enumerate(face) if v not in face[:k]]
            faces.append(face)
    return Mesh(np.array(vertices), faces, name="wigley lid half")


def capytaine_body(nx, nz, symmetry="xz"):
    """The FloatingBody: (body, hull panels, lid panels)."""
    import capytaine as cpt
    from capytaine.meshes import ReflectionSymmetricMesh

    ny = max(1, nz // 2)
    if symmetry == "both":
        assert nx % 2 == 0, "--symmetry both needs an even NX"
        hull = ReflectionSymmetricMesh(
            ReflectionSymmetricMesh(hull_half(nx // 2, nz, 0.0), plane="xOz"), plane="yOz",
            name="wigley")
        lid = ReflectionSymmetricMesh(
            ReflectionSymmetricMesh(lid_half(nx // 2, ny, 0.0), plane="xOz"), plane="yOz",
            name="wigley lid")
    elif symmetry == "xz":
        hull = ReflectionSymmetricMesh(hull_half(nx, nz), plane="xOz", name="wigley")
        lid = ReflectionSymmetricMesh(lid_half(nx, ny), plane="xOz", name="wigley lid")
    else:
        hull = ReflectionSymmetricMesh(hull_half(nx, nz), plane="xOz").merged(name="wigley")
        lid = ReflectionSymmetricMesh(lid_half(nx, ny), plane="xOz").merged(name="wigley lid")
    dofs = cpt.rigid_body_dofs(only=CAPYTAINE_DOFS, rotation_center=(0.0, 0.0, 0.0))
    body = cpt.FloatingBody(mesh=hull, lid_mesh=lid, dofs=dofs, name="wigley")
    return body, hull.nb_faces, lid.nb_faces


def capytaine(ws, headings, mesh, symmetry="xz"):
    """Capytaine on the hull: a [n, 5, 5], b [n, 5, 5], X [n, n_headings, 5] (its convention),
    wall s, CPU s (all threads), panels (hull, lid), the solver's timer summary."""
    import capytaine as cpt

    before = resource.getrusage(resource.RUSAGE_SELF)
    start = time.perf_counter()
    body, hull_panels, lid_panels = capytaine_body(*mesh, symmetry=symmetry)
    problems = [cpt.RadiationProblem(body=body, radiating_dof=d, omega=w, rho=RHO, g=G)
                for w in ws for d in CAPYTAINE_DOFS]
    problems += [cpt.DiffractionProblem(body=body, wave_direction=np.radians(h), omega=w,
                                        rho=RHO, g=G)
                 for w in ws for h in headings]
    solver = cpt.BEMSolver()
    results = solver.solve_all(problems, progress_bar=False)
    data = cpt.assemble_dataset(results, hydrostatics=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_SELF)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    n = len(CAPYTAINE_DOFS)
    a, b = np.zeros((len(ws), n, n)), np.zeros((len(ws), n, n))
    x = np.zeros((len(ws), len(headings), n), complex)
    for i, di in enumerate(CAPYTAINE_DOFS):  # a[k, i, j]: i influenced, j radiating, as ours
        for j, dj in enumerate(CAPYTAINE_DOFS):
            a[:, i, j] = data.added_mass.sel(influenced_dof=di, radiating_dof=dj).sel(
                omega=ws, method="nearest").values
            b[:, i, j] = data.radiation_damping.sel(influenced_dof=di, radiating_dof=dj).sel(
                omega=ws, method="nearest").values
        for h, heading in enumerate(headings):
            x[:, h, i] = data.excitation_force.sel(influenced_dof=di).sel(
                omega=ws, wave_direction=np.radians(heading), method="nearest").values
    try:
        timer = solver.timer_summary()
    except Exception:  # the timer needs pandas; only a detail of the report
        timer = None
    return {"a": a, "b": b, "X": x, "wall": wall, "cpu": cpu, "panels": (hull_panels, lid_panels),
            "timer": timer, "problems": len(problems)}


# ---------------------------------------------------------------------------------------------
# Mesh search


# The DOF pairs (sway heave roll pitch yaw = 0 .. 4) that do not vanish by the hull's two
# symmetry planes; the others (heave-pitch, sway-yaw, roll-yaw by the fore-aft symmetry, every
# pair of a symmetric and an antisymmetric motion by the xz plane) are numerical noise in 3D.
PAIRS = [(0, 0), (0, 2), (1, 1), (2, 2), (3, 3), (4, 4)]


def errors(result, reference, compared, ws):
    """Largest relative differences from the reference: (a, b, |X|) each a (value, where)."""
    worst = {}
    for part in ("a", "b"):
        best = (0.0, "")
        for i, j in compared:
            scale = np.abs(reference[part][:, i, j]).max()
            d = np.abs(result[part][:, i, j] - reference[part][:, i, j]) / scale
            if d.max() > best[0]:
                best = (d.max(), f"{part} {DOFS[i]}-{DOFS[j]} at {ws[d.argmax()]:.2f} rad/s")
        worst[part] = best
    best = (0.0, "")
    for j in range(len(CAPYTAINE_DOFS)):
        ref = np.abs(reference["X"][:, :, j])
        d = np.abs(np.abs(result["X"][:, :, j]) - ref) / ref.max()
        if d.max() > best[0]:
            k, h = np.unravel_index(d.argmax(), d.shape)
            best = (d.max(), f"X {DOFS[j]} at {ws[k]:.2f} rad/s, {HEADINGS[h]:g} deg")
    worst["X"] = best
    return worst


def mesh_search(ws, headings, meshes, reference_mesh, symmetry, log):
    log(f"## Capytaine mesh search: {len(ws)} frequencies "
        f"({', '.join(f'{w:.3f}' for w in ws)} rad/s), {len(headings)} headings, "
        f"reference {reference_mesh[0]}x{reference_mesh[1]}")
    reference = capytaine(ws, headings, reference_mesh, symmetry)
    compared = PAIRS
    log("compared: a and b of " + ", ".join(f"{DOFS[i]}-{DOFS[j]}" for i, j in compared)
        + " (the other pairs vanish by symmetry), each relative to its largest over the "
        "frequencies; abs(X) of every DOF, relative to its largest over frequencies and headings")
    log("| mesh NXxNZ | hull + lid panels | a | b | abs(X) | worst | wall s | CPU s | adequate |")
    log("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    chosen = None
    for mesh in meshes:
        r = capytaine(ws, headings, mesh, symmetry)
        e = errors(r, reference, compared, ws)
        ok = all(v[0] <= TOLERANCE for v in e.values())
        worst = max(e.values(), key=lambda v: v[0])
        log(f"| {mesh[0]}x{mesh[1]} | {r['panels'][0]} + {r['panels'][1]} | "
            f"{100 * e['a'][0]:.2f} % | {100 * e['b'][0]:.2f} % | {100 * e['X'][0]:.2f} % | "
            f"{worst[1]} | {r['wall']:.1f} | {r['cpu']:.1f} | {'yes' if ok else 'no'} |")
        if ok and chosen is None:
            chosen = mesh
    log(f"| {reference_mesh[0]}x{reference_mesh[1]} (reference) | {reference['panels'][0]} + "
        f"{reference['panels'][1]} | - | - | - | - | {reference['wall']:.1f} | "
        f"{reference['cpu']:.1f} | - |")
    if chosen is None:
        chosen = reference_mesh
        log("no mesh of the sequence within 5 %: the reference is used")
    return chosen


# ---------------------------------------------------------------------------------------------


def parse_mesh(text):
    nx, nz = text.lower().split("x")
    return int(nx), int(nz)


def thread_cpu():
    """{thread id: CPU seconds (user + sys)} of this process's threads; {} off Linux."""
    try:
        tick = os.sysconf("SC_CLK_TCK")
        out = {}
        for task in pathlib.Path("/proc/self/task").iterdir():
            fields = (task / "stat").read_text().rsplit(")", 1)[1].split()
            out[task.name] = (int(fields[11]) + int(fields[12])) / tick
        return out
    except (OSError, ValueError, IndexError):
        return {}


def load():
    return "{:.2f} {:.2f} {:.2f}".format(*os.getloadavg())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fmu-pack", type=pathlib.Path, default=fmu_pack_default())
    parser.add_argument("--capytaine-mesh", type=parse_mesh, metavar="NXxNZ",
                        help="skip the mesh search and time this mesh")
    parser.add_argument("--meshes", default=",".join(f"{a}x{b}" for a, b in MESHES),
                        help="the mesh search's sequence, coarse to fine (default %(default)s)")
    parser.add_argument("--reference", type=parse_mesh, default=REFERENCE, metavar="NXxNZ",
                        help="the mesh search's reference (default %(default)s)")
    parser.add_argument("--symmetry", choices=("xz", "both", "none"), default="xz",
                        help="Capytaine's mesh symmetry: the xz plane (default), also the yz "
                             "plane, or none")
    parser.add_argument("--repeat", type=int, default=3, help="runs of our sweep (median)")
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: 10 frequencies, meshes 20x4 and 30x6 against 40x8")
    parser.add_argument("--check-geometry", type=pathlib.Path, metavar="DIR",
                        help="compare the generated ship files with DIR/wigley_h.xml, DIR/sN.xml")
    args = parser.parse_args()

    logging.getLogger("capytaine").setLevel(logging.ERROR)  # wavelength and panel warnings
    import capytaine as cpt

    lines = []

    def log(text=""):
        print(text, flush=True)
        lines.append(text)

    kr = (KR[0], KR[1], 10) if args.quick else KR
    ws = omegas(kr)
    check = [round(k * (len(ws) - 1) / (CHECK[-1])) for k in CHECK] if args.quick else list(CHECK)
    check = sorted(set(check))
    meshes = [(20, 4), (30, 6)] if args.quick else [parse_mesh(m) for m in args.meshes.split(",")]
    reference_mesh = (40, 8) if args.quick else args.reference

    log(f"# Wigley hull L = {L:g} m, B = {2 * HALF_BEAM:g} m, T = {T:g} m; "
        f"{len(ws)} frequencies {ws[0]:.4f} .. {ws[-1]:.4f} rad/s, headings "
        f"{', '.join(f'{h:g}' for h in HEADINGS)}; DOFs {' '.join(DOFS)}")
    log(f"# Capytaine {cpt.__version__}, symmetry {args.symmetry}; numpy {np.__version__}; "
        f"{os.cpu_count()} CPUs; OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}")
    log(f"# command: {' '.join([pathlib.Path(sys.executable).name] + sys.argv)}")
    log(f"# load average at start (1, 5, 15 min): {load()}")
    total_start = time.perf_counter()

    with tempfile.TemporaryDirectory() as folder:
        fmu_pack = pathlib.Path(folder, "fmu-pack")
        shutil.copy2(args.fmu_pack, fmu_pack)
        log(f"# fmu-pack: {args.fmu_pack} (modified "
            f"{time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(args.fmu_pack.stat().st_mtime))}), "
            "copied for the run")
        ship = write_ship(folder)
        if args.check_geometry:
            log(f"# geometry against {args.check_geometry}: largest coordinate difference "
                f"{check_geometry(ship, args.check_geometry):.3g} m")
        runs = []

        def ours():
            r = strip(fmu_pack, ship, ws, HEADINGS, folder)
            log(f"our sweep, run {len(runs) + 1}: {r['wall']:.2f} s wall (printed "
                f"{r['printed_wall']} s), {r['cpu']:.2f} s CPU, load {load()}")
            runs.append(r)
            return r

        first = ours()
        log(f"# {first['summary']}")
        assert np.allclose(first["omega"], ws, rtol=1e-9), "our frequencies differ"

        if args.capytaine_mesh:
            mesh = args.capytaine_mesh
            log(f"## Capytaine mesh given: {mesh[0]}x{mesh[1]} (no search)")
        else:
            mesh = mesh_search(ws[check], HEADINGS, meshes, reference_mesh, args.symmetry, log)
        log(f"## chosen Capytaine mesh: {mesh[0]}x{mesh[1]}")

        while len(runs) < max(1, args.repeat) - 1:
            ours()
        log(f"## Capytaine, all {len(ws)} frequencies, load {load()}")
        threads_before = thread_cpu()
        theirs = capytaine(ws, HEADINGS, mesh, args.symmetry)
        threads = sorted((t - threads_before.get(tid, 0.0) for tid, t in thread_cpu().items()),
                         reverse=True)
        log(f"Capytaine: {theirs['wall']:.1f} s wall, {theirs['cpu']:.1f} s CPU "
            f"(CPU / wall {theirs['cpu'] / theirs['wall']:.2f}), {theirs['problems']} problems, "
            f"load {load()}")
        if threads:
            log("CPU s of each of this process's threads during it (/proc; OpenMP and BLAS "
                "workers included): " + ", ".join(f"{t:.1f}" for t in threads if t >= 0.05))
        if theirs["timer"] is not None:
            log("Capytaine's timer (s, summed over problems):")
            for text in theirs["timer"].to_string(float_format="{:.2f}".format).splitlines():
                log("    " + text)
        while len(runs) < max(1, args.repeat):
            ours()

    wall = statistics.median(r["printed_wall"] or r["wall"] for r in runs)
    process_wall = statistics.median(r["wall"] for r in runs)
    cpu = statistics.median(r["cpu"] for r in runs)
    hull_panels, lid_panels = theirs["panels"]
    log()
    log(f"## Speed: {len(ws)} frequencies x {len(HEADINGS)} headings, 5 DOFs")
    log("| code | mesh | wall s | CPU s | CPU / wall |")
    log("| --- | --- | --- | --- | --- |")
    log(f"| hydrofmu fmu-pack sweep (median of {len(runs)}) | 41 stations, 20 distinct sections | "
        f"{wall:.2f} (process {process_wall:.2f}) | {cpu:.2f} | {cpu / process_wall:.2f} |")
    log(f"| Capytaine {cpt.__version__} | {mesh[0]}x{mesh[1]}: {hull_panels} hull + {lid_panels} "
        f"lid panels, symmetry {args.symmetry} | {theirs['wall']:.1f} | {theirs['cpu']:.1f} | "
        f"{theirs['cpu'] / theirs['wall']:.2f} |")
    log(f"| ratio Capytaine / ours | | {theirs['wall'] / wall:.1f} | {theirs['cpu'] / cpu:.1f} | |")
    log(f"our runs (wall printed / process / CPU s): "
        + "; ".join(f"{r['printed_wall']} / {r['wall']:.2f} / {r['cpu']:.2f}" for r in runs))

    # Sanity: the two codes solve the same hull (strip theory against 3D, not a convergence
    # measure): diagonal coefficients and exciting forces, (ours - Capytaine) relative to
    # Capytaine's largest over the frequencies (the exciting force: over frequencies and headings).
    ours_r = runs[-1]
    log()
    log("## Same hull? (ours - Capytaine) / Capytaine's largest over all frequencies, in %, at the "
        "search's frequencies; X: magnitudes at 180 and 90 deg")
    log("| omega | " + " | ".join(f"a {d}" for d in DOFS) + " | " + " | ".join(f"b {d}" for d in DOFS)
        + " | X heave 180 | X pitch 180 | X sway 90 | X roll 90 |")
    log("| --- " * (1 + 2 * len(DOFS) + 4) + "|")
    h180, h90 = HEADINGS.index(180.0), HEADINGS.index(90.0)
    for k in check:
        cells = [f"{ws[k]:.3f}"]
        for part in ("a", "b"):
            for i in range(len(DOFS)):
                scale = np.abs(theirs[part][:, i, i]).max()
                cells.append(f"{100 * (ours_r[part][k, i, i] - theirs[part][k, i, i]) / scale:.0f}")
        for h, j in ((h180, 1), (h180, 3), (h90, 0), (h90, 2)):
            scale = np.abs(theirs["X"][:, :, j]).max()
            cells.append(f"{100 * (abs(ours_r['X'][k, h, j]) - abs(theirs['X'][k, h, j])) / scale:.0f}")
        log("| " + " | ".join(cells) + " |")
    log()
    log(f"# whole script: {time.perf_counter() - total_start:.0f} s; load average at end: {load()}")


if __name__ == "__main__":
    sys.exit(main())
