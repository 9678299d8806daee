"""A section in finite depth against Capytaine 3.0 on a long half-immersed cylinder.

Ours: `fmu-pack sweep semicircle --water-depth H`, per metre. Capytaine: a horizontal circular
cylinder, R = 1 m, half immersed, L = 40 m (L/D = 20), 1088 panels (16 around the wetted half,
60 along, the end caps 4 rings deep), no lid; its whole-body heave and sway added mass and
damping divided by L. Both in units of rho pi R^2, the damping as b / (rho pi R^2 omega) (the
table's -Im A~). Finite depth uses Capytaine's Delhommeau kernel with Nemoh's Fortran Prony fit
(the default "python" fit samples random points and fails the energy check below: heave
damping at kR = 1.5 off by x1.37 .. x1.85); deep water its default solver.

Energy check of each Capytaine point: its radiation damping over the damping implied by its
own exciting force over all headings,
    E = b_jj / (k / (8 pi rho g c_g) int_0^2pi |X_j(beta)|^2 dbeta),
c_g = (omega / 2k)(1 + 2kh / sinh 2kh), the integral from 0 .. 90 degrees (the body's two
symmetry planes). 1 for a consistent solution; on this mesh deep water gives 1.018 .. 1.050,
so a finite-depth point is trusted where E is within ENERGY_TOLERANCE of the deep-water E at
the same kR. Ours: the 2D identity with headings 0 and 180 (docs/FINITE_DEPTH.md, Equations).

Run from the repository root with the .venv of tests/python/requirements.txt and the release
fmu-pack built (about 1 min on 2 cores; the finer meshes take a few minutes):

    .venv/bin/python examples/finite_depth/capytaine_cylinder.py
    .venv/bin/python examples/finite_depth/capytaine_cylinder.py --depths 2 --kr 1.3:1.7:9
    .venv/bin/python examples/finite_depth/capytaine_cylinder.py --kernel python
    .venv/bin/python examples/finite_depth/capytaine_cylinder.py --rings 6 --around 48 --slices 90
    .venv/bin/python examples/finite_depth/capytaine_cylinder.py --length 80 --slices 120

--kernel legacy: Delhommeau's legacy finite-depth method with the Fortran fit; fingreen:
FinGreen3D (HAMS). docs/FINITE_DEPTH.md, "Against Capytaine 3.0", has the measured numbers.

tests/python/test_finite_depth_capytaine.py runs the same comparison and asserts it.
"""
import argparse
import math
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from linear_waves import group_velocity, wavenumber  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
RHO, G, R = 1025.0, 9.81, 1.0
LENGTH = 40.0
RESOLUTION = (4, 32, 60)  # rings on the end caps, panels around the full circle, slices
KR_GRID = "0.3:1.5:4"  # log-spaced: 0.3, 0.513, 0.877, 1.5
DEPTHS = (math.inf, 10.0, 4.0, 2.0)  # h/R with R = 1 m
DOFS = ("sway", "heave")
# Energy-check headings every HEADING_STEP degrees over a quarter circle: the same E to 4 digits
# as every 1 or 0.25 degrees (kR = 0.3 and 1.5, deep and h/R = 2); every 10 degrees misses the
# narrow beam-seas lobe at kR = 1.5 (kL = 60; E 0.59).
HEADING_STEP = 5.0
ENERGY_TOLERANCE = 0.05


def fmu_pack_default():
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    if not target.is_absolute():
        target = ROOT / target
    return target / "release" / "fmu-pack"


def read_table(path, modes_line="# modes:"):
    lines = pathlib.Path(path).read_text().splitlines()
    modes = next(line for line in lines if line.startswith(modes_line)).split()[2:]
    rows = [line.split(",") for line in lines if line and not line.startswith("#")
            and not line[0].isalpha()]
    return modes, rows


def ours(fmu_pack, depth, kr_grid=KR_GRID, folder=None):
    """{(dof, kR): (a, b, E)} of `fmu-pack sweep semicircle` per metre (rho pi R^2 units), E
    our 2D energy identity (1 if consistent), and the table's depth line."""
    with tempfile.TemporaryDirectory(dir=folder) as tmp:
        table, forces = pathlib.Path(tmp, "a.csv"), pathlib.Path(tmp, "x.csv")
        command = [str(fmu_pack), "sweep", "semicircle", "--kr", kr_grid, "-o", str(table),
                   "--excitation", str(forces)]
        if math.isfinite(depth):
            command += ["--water-depth", str(depth * R)]
        r = subprocess.run(command, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        depth_line = next(line for line in table.read_text().splitlines()
                          if line.startswith("# depth:"))
        modes, rows = read_table(table)
        _, force_rows = read_table(forces)
    values, squared = {}, {}
    for kr, i, j, re, im in rows:
        if kr in ("0", "inf") or i != j or modes[int(i) - 1] not in DOFS:
            continue
        values[(modes[int(i) - 1], float(kr))] = (float(re), -float(im))
    for kr, j, _heading, re, im in force_rows:
        if kr in ("0", "inf") or modes[int(j) - 1] not in DOFS:
            continue
        key = (modes[int(j) - 1], float(kr))
        squared[key] = squared.get(key, 0.0) + float(re) ** 2 + float(im) ** 2
    out = {}
    for (dof, kr), (a, b) in values.items():
        omega = math.sqrt(kr * G / R)
        k = wavenumber(omega, depth)
        depth_factor = 1.0 if math.isinf(depth) else 1 + 2 * k * depth / math.sinh(2 * k * depth)
        # -Im A~ / (rho pi R^2) implied by |x(0)|^2 + |x(180)|^2 (docs/FINITE_DEPTH.md)
        implied = (k / kr) * squared[(dof, kr)] / (2 * depth_factor) / math.pi
        out[(dof, kr)] = (a, b, b / implied)
    return out, depth_line.split(":")[1].strip()


def solver_for(depth, kernel="fortran"):
    import capytaine as cpt

    if math.isinf(depth) or kernel == "python":
        return cpt.BEMSolver()
    if kernel == "fortran":
        return cpt.BEMSolver(green_function=cpt.Delhommeau(
            finite_depth_prony_decomposition_method="fortran"))
    if kernel == "legacy":
        return cpt.BEMSolver(green_function=cpt.Delhommeau(
            finite_depth_method="legacy", finite_depth_prony_decomposition_method="fortran"))
    if kernel == "fingreen":
        return cpt.BEMSolver(green_function=cpt.FinGreen3D())
    raise ValueError(kernel)


def capytaine(depths, kr_values, length=LENGTH, resolution=RESOLUTION, kernel="fortran",
              heading_step=HEADING_STEP):
    """{h/R: {(dof, kR): (a, b, E)}}: Capytaine's whole body per metre, rho pi R^2 units, E its
    energy check."""
    import logging

    import capytaine as cpt
    from capytaine.bem.airy_waves import froude_krylov_force

    logging.getLogger("capytaine").setLevel(logging.ERROR)
    mesh = cpt.mesh_horizontal_cylinder(length=length, radius=R, center=(0, 0, 0),
                                        resolution=resolution).immersed_part()
    body = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)))
    body = body.with_only_dofs(["Sway", "Heave"])
    scale = RHO * math.pi * R * R
    betas = np.radians(np.arange(0.0, 90.0 + heading_step / 2, heading_step))
    out = {}
    for depth in depths:
        solver = solver_for(depth, kernel)
        out[depth] = {}
        for kr in kr_values:
            omega = math.sqrt(kr * G / R)
            k = wavenumber(omega, depth)
            waves = [cpt.DiffractionProblem(body=body, omega=omega, rho=RHO, g=G,
                                            water_depth=depth * R, wave_direction=beta)
                     for beta in betas]
            diffracted = solver.solve_all(waves, progress_bar=False)
            for dof, name in (("heave", "Heave"), ("sway", "Sway")):
                problem = cpt.RadiationProblem(body=body, omega=omega, rho=RHO, g=G,
                                               water_depth=depth * R, radiating_dof=name)
                result = solver.solve(problem)
                damping = result.radiation_damping[name]
                force = np.array([d.forces[name] + froude_krylov_force(w)[name]
                                  for d, w in zip(diffracted, waves)])
                radiated = (k / (8 * math.pi * RHO * G * group_velocity(omega, depth))
                            * 4 * np.trapezoid(np.abs(force) ** 2, betas))
                out[depth][(dof, kr)] = (result.added_mass[name] / length / scale,
                                         damping / length / (scale * omega),
                                         damping / radiated)
    return out


def trusted(theirs, depth, key):
    """Capytaine's point passes its energy check: E within ENERGY_TOLERANCE of deep water's."""
    return abs(theirs[depth][key][2] / theirs[math.inf][key][2] - 1) <= ENERGY_TOLERANCE


def report(mine, theirs):
    print("# a, b: added mass and damping / (rho pi R^2 [omega]) per metre; E: energy check "
          "(* not trusted); effect: value - the same code's deep-water value")
    print(f"{'h/R':>4} {'dof':>5} {'kR':>6} {'kh':>6} {'E ours':>7} {'E cpt':>7} | "
          f"{'a ours':>7} {'a cpt':>7} {'effect':>15} | {'b ours':>7} {'b cpt':>7} "
          f"{'effect':>15} | {'b/b_deep':>13}")
    for dof in DOFS:
        for depth in theirs:
            for key in sorted(k for k in theirs[depth] if k[0] == dof):
                kr = key[1]
                o, t = mine[depth][key], theirs[depth][key]
                od, td = mine[math.inf][key], theirs[math.inf][key]
                kh = wavenumber(math.sqrt(kr * G / R), depth) * depth
                mark = " " if trusted(theirs, depth, key) else "*"
                print(f"{depth:4g} {dof:>5} {kr:6.3f} {kh:6.2f} {o[2]:7.4f} {t[2]:6.3f}{mark} | "
                      f"{o[0]:7.4f} {t[0]:7.4f} {o[0] - od[0]:+7.4f}/{t[0] - td[0]:+7.4f} | "
                      f"{o[1]:7.4f} {t[1]:7.4f} {o[1] - od[1]:+7.4f}/{t[1] - td[1]:+7.4f} | "
                      f"{o[1] / od[1]:6.3f}/{t[1] / td[1]:6.3f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fmu-pack", type=pathlib.Path, default=fmu_pack_default())
    parser.add_argument("--kr", default=KR_GRID, help="MIN:MAX:COUNT, log-spaced")
    parser.add_argument("--depths", default="inf,10,4,2", help="h/R, comma-separated")
    parser.add_argument("--kernel", choices=("fortran", "python", "legacy", "fingreen"),
                        default="fortran", help="Capytaine's finite-depth kernel")
    parser.add_argument("--length", type=float, default=LENGTH, help="cylinder length / R")
    parser.add_argument("--slices", type=int, default=RESOLUTION[2])
    parser.add_argument("--around", type=int, default=RESOLUTION[1],
                        help="panels around the full circle")
    parser.add_argument("--rings", type=int, default=RESOLUTION[0])
    args = parser.parse_args()
    depths = sorted({math.inf, *(float(d) for d in args.depths.split(","))}, reverse=True)
    mine = {depth: ours(args.fmu_pack, depth, args.kr)[0] for depth in depths}
    kr_values = sorted({kr for (_, kr) in mine[math.inf]})
    theirs = capytaine(depths, kr_values, args.length, (args.rings, args.around, args.slices),
                       args.kernel)
    print(f"# Capytaine: L = {args.length:g} R, resolution ({args.rings}, {args.around}, "
          f"{args.slices}), finite-depth kernel {args.kernel}")
    report(mine, theirs)


if __name__ == "__main__":
    sys.exit(main())
