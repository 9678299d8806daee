"""A 3D hydrodynamic database of a box barge from Capytaine 3.0, as WAMIT files for the importer.

Writes, into OUTDIR:

- box.1, box.3, box.hst: Capytaine's own `capytaine.io.wamit.export_to_wamit` (the input of
  `fmu-pack sweep|fit|pack OUTDIR/box.1`);
- box.nc: the same dataset as NetCDF-3 (64-bit offset, scipy engine), complex arrays split by
  `cpt.io.xarray.separate_complex_values` along a leading dimension `complex` = ("re", "im");
- box.json: Capytaine's coefficients in full double precision for the tests
  (tests/python/test_database_capytaine.py), in CAPYTAINE's convention (see below).

The barge: a rectangular box L x B x T = 40 m x 10 m x 3 m (length along x, beam along y, draft),
deep water, rho = 1025 kg/m^3, g = 9.81 m/s^2. Ship axes as docs/DESIGN.md: x forward, y to
port, z up, origin on the mean free surface at midship on the centre line. 6 rigid DOFs, in the
order Surge, Sway, Heave, Roll, Pitch, Yaw (Capytaine's names; the FMU's `surge` .. `yaw`),
rotations about the ORIGIN (0, 0, 0) on the free surface: every moment in the files and in the
FMU is about that point. The centre of gravity is put there too, with the mass of the displaced
water, so that the gravity term `-m g z_G` of the roll and pitch restoring vanishes and the .hst
holds the buoyancy part alone (docs/DESIGN.md: the weight's own restoring belongs to the master); GM
is then KB + BM - KG = 1.5 + 2.78 - 3 = 1.28 m (a draft of 4 m would leave GM = 0.08 m).

Frequencies: omega = 0, 0.2, 0.3, ..., 2.5 rad/s and infinity (radiation at omega = 0 and inf
gives the added-mass limits, the .1's PER = -1 and PER = 0 rows; Capytaine has no diffraction
there, so the excitation there is NaN in box.nc and box.json and absent from box.3). Headings
0, 90, 180 deg (Capytaine's wave_direction, 0 = waves travelling towards +x, the same as ours).

Meshes (the hull's x, y, z panel counts; both symmetry planes used; a lid on the waterplane
z = 0, `generate_lid`, removes the irregular frequencies, the first of which is at 2.06 rad/s
without it, inside the band: there the coarse mesh's heave damping drops by half without the lid):
- COARSE (default): 32 x 8 x 3, 1.25 m x 1.25 m x 1 m panels (496 hull + 204 lid panels), 8
  panels per wavelength at 2.5 rad/s (9.9 m); about 15 s on 2 cores;
- FINE (--fine): 64 x 16 x 6, twice finer in each direction (1984 hull + 792 lid panels); about
  70 s. Coarse against fine: heave, pitch and roll added mass within 0.9, 1.2 and 2.5 %, sway and
  yaw 6 %, surge 21 % (a small added mass carried by the ends, 3 panels deep); damping within
  4 % of each DOF's largest (roll 11 %).
The hydrostatic stiffness is integrated with Gauss-Legendre 2 quadrature on the same hull (exact
for the box's waterplane moments): Capytaine's default one-point quadrature gives the roll
restoring 3.4 % low on the coarse mesh (it integrates y^2 over the waterplane by the panel
centres, and C44 is a difference of two large terms).

Conventions. Capytaine: exp(-i omega t), real added mass a and damping b, complex exciting force
X_c per unit wave amplitude. Ours (docs/DESIGN.md): exp(+i omega t), A~ = a - i b / omega, X = conj(X_c).
The files follow WAMIT: .1 holds a / (rho L^k) and b / (omega rho L^k), .3 holds conj(X_c) /
(rho g L^m) (modulus, phase in degrees, re, im), .hst C / (rho g L^k), with L = 1 m (Capytaine's
export takes no length scale), k = 3, 4, 5 and m = 2, 3 for forces and moments.
The files carry neither rho nor g nor L: this database uses the FMU's defaults, 1025 kg/m^3 and
9.81 m/s^2. Beware: in Capytaine's .1 the second column is the RADIATING DOF and the third the
influenced one (the transpose of WAMIT's A_ij, force in i by motion in j); Capytaine's matrices
are symmetric only to the mesh's accuracy (surge-pitch 5.5 % apart at 1 rad/s on the coarse
mesh). tests/python/test_database_capytaine.py checks every number of the files against the
dataset and states the files' layout.

Run (from the repository root, with the .venv of tests/python/requirements.txt):

    .venv/bin/python examples/databases/capytaine_box_barge.py OUTDIR [--fine]

Deterministic: the same command writes the same bytes (the dataset's time stamps are removed).
"""
import argparse
import json
import pathlib
import sys
import time

import numpy as np

L, B, T = 40.0, 10.0, 3.0
RHO, G = 1025.0, 9.81
DOFS = ["Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw"]
OMEGAS = [k / 10 for k in range(2, 26)]  # 0.2 .. 2.5 rad/s, 24 frequencies
HEADINGS = [0.0, 90.0, 180.0]  # degrees
COARSE = (32, 8, 3)
FINE = (64, 16, 6)
NAME = "box"


def body(resolution=COARSE, lid=True):
    """The barge as a Capytaine FloatingBody (hull, lid unless `lid` is False, 6 rigid DOFs
    about the origin, centre of gravity at the origin, displaced mass) with its hydrostatic
    stiffness attached."""
    import capytaine as cpt

    mesh = cpt.mesh_parallelepiped(size=(L, B, T), center=(0, 0, -T / 2), resolution=resolution,
                                   missing_sides={"top"}, reflection_symmetry=True, name=NAME)
    lid_mesh = mesh.generate_lid(z=0.0) if lid else None
    hull = cpt.FloatingBody(mesh=mesh, lid_mesh=lid_mesh,
                            dofs=cpt.rigid_body_dofs(rotation_center=(0.0, 0.0, 0.0)),
                            center_of_mass=(0.0, 0.0, 0.0), name=NAME)
    exact = cpt.FloatingBody(mesh=mesh.with_quadrature("Gauss-Legendre 2"),
                             dofs=cpt.rigid_body_dofs(rotation_center=(0.0, 0.0, 0.0)),
                             center_of_mass=(0.0, 0.0, 0.0), name=NAME)
    # assemble_dataset takes a body's hydrostatic_stiffness attribute when it has one.
    hull.hydrostatic_stiffness = exact.compute_hydrostatic_stiffness(rho=RHO, g=G)
    return hull


def solve(resolution=COARSE, lid=True):
    """The dataset (DOFs in the order of DOFS) and (hull panels, lid panels)."""
    import capytaine as cpt

    hull = body(resolution, lid)
    omegas = [0.0, *OMEGAS, np.inf]
    problems = [cpt.RadiationProblem(body=hull, radiating_dof=d, omega=w, rho=RHO, g=G)
                for w in omegas for d in DOFS]
    problems += [cpt.DiffractionProblem(body=hull, wave_direction=np.radians(h), omega=w,
                                        rho=RHO, g=G)
                 for w in OMEGAS for h in HEADINGS]
    results = cpt.BEMSolver().solve_all(problems, progress_bar=False)
    data = cpt.assemble_dataset(results, hydrostatics=True)
    data = data.sel(influenced_dof=DOFS, radiating_dof=DOFS)
    # Determinism: no wall-clock time stamps in the files.
    data.attrs = {k: v for k, v in data.attrs.items() if "computation" not in k
                  and "creation" not in k}
    return data, (hull.mesh.nb_faces, hull.lid_mesh.nb_faces if lid else 0)


def coefficients(data, panels, resolution):
    """Capytaine's coefficients as a JSON-ready dict (Capytaine's own convention)."""
    finite = data.sel(omega=OMEGAS)

    def matrix(x):
        return np.asarray(x, float).tolist()

    x = finite.excitation_force.sel(wave_direction=np.radians(HEADINGS), method="nearest")
    x = x.transpose("omega", "wave_direction", "influenced_dof").values
    return {
        "about": "Capytaine 3.0 box barge (examples/databases/capytaine_box_barge.py). "
                 "Capytaine's convention exp(-i omega t): added_mass a and radiation_damping b "
                 "real; excitation_force X_c per unit wave amplitude, [omega][heading][dof] "
                 "(ours, exp(+i omega t): A~ = a - i b / omega, X = conj(X_c)). SI units; "
                 "moments about the rotation centre.",
        "capytaine_version": str(data.attrs.get("capytaine_version", "")),
        "rho": RHO, "g": G, "length": L, "beam": B, "draft": T,
        "rotation_center": [0.0, 0.0, 0.0], "center_of_mass": [0.0, 0.0, 0.0],
        "mass": float(data.disp_mass), "resolution": list(resolution),
        "panels": {"hull": panels[0], "lid": panels[1]},
        "dofs": DOFS,
        "omega": list(OMEGAS),
        "headings_deg": list(HEADINGS),
        "added_mass": matrix(finite.added_mass.values),
        "radiation_damping": matrix(finite.radiation_damping.values),
        "added_mass_zero": matrix(data.added_mass.sel(omega=0.0).values),
        "added_mass_inf": matrix(data.added_mass.sel(omega=np.inf).values),
        "excitation_force_re": matrix(x.real),
        "excitation_force_im": matrix(x.imag),
        "hydrostatic_stiffness": matrix(data.hydrostatic_stiffness.values),
        "inertia_matrix": matrix(rigid_inertia(float(data.disp_mass))),
        "inertia_about": "a homogeneous solid box L x B x T of the displaced mass, centred at "
                         "the origin (centre of gravity there); 6 x 6 about the origin, "
                         "surge .. yaw (examples/cosim/floating_box.py)",
    }


def rigid_inertia(mass):
    """The body's 6 x 6 mass matrix about the origin: the displaced mass as a homogeneous solid
    box of the hull's L x B x T centred at the origin, so that the centre of gravity is at the
    origin as the database assumes (no coupling terms): m, m, m, m (B^2 + T^2) / 12,
    m (L^2 + T^2) / 12, m (L^2 + B^2) / 12. A choice of this example, not Capytaine's: its
    `inertia_matrix` (compute_rigid_body_inertia) integrates the submerged volume, whose centre
    is at z = -T / 2, not at the centre of gravity given."""
    return np.diag([mass, mass, mass, mass * (B**2 + T**2) / 12, mass * (L**2 + T**2) / 12,
                    mass * (L**2 + B**2) / 12])


def write(data, panels, resolution, outdir):
    """box.1, box.3, box.hst, box.nc, box.json in outdir; their paths."""
    import capytaine as cpt
    from capytaine.io.wamit import export_to_wamit

    outdir = pathlib.Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    prefix = outdir / NAME
    paths = [prefix.with_suffix(s) for s in (".1", ".3", ".hst", ".nc", ".json")]
    for p in paths:
        p.unlink(missing_ok=True)
    export_to_wamit(data, str(prefix), exports=("1", "3", "hst"))
    # export_to_wamit logs a failed file as a warning and goes on: check that all are there.
    missing = [p.name for p in paths[:3] if not p.is_file()]
    if missing:
        raise RuntimeError(f"export_to_wamit did not write {missing}")
    separate = cpt.io.xarray.separate_complex_values(data)
    for name in ("influenced_dof", "radiating_dof"):
        separate[name] = separate[name].astype(str)
    separate.to_netcdf(paths[3], engine="scipy", format="NETCDF3_64BIT")
    paths[4].write_text(json.dumps(coefficients(data, panels, resolution), indent=1) + "\n")
    return paths


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("outdir", type=pathlib.Path)
    parser.add_argument("--fine", action="store_true", help="the fine mesh (64 x 16 x 6)")
    parser.add_argument("--no-lid", action="store_true",
                        help="no lid: the irregular frequencies stay in the data (2.06 rad/s)")
    args = parser.parse_args(argv)
    resolution = FINE if args.fine else COARSE
    start = time.perf_counter()
    data, panels = solve(resolution, lid=not args.no_lid)
    paths = write(data, panels, resolution, args.outdir)
    seconds = time.perf_counter() - start
    print(f"box barge {L:g} m x {B:g} m x {T:g} m, {panels[0]} hull + {panels[1]} lid panels, "
          f"{len(OMEGAS)} frequencies + 0 + inf, headings {HEADINGS}: {seconds:.1f} s")
    for p in paths:
        print("wrote", p)


if __name__ == "__main__":
    sys.exit(main())
