"""A 3D database imported from Capytaine's WAMIT files: the FMU of `fmu-pack pack box.1` under
fmpy gives Capytaine's radiation and exciting forces, and Capytaine's files hold what its
dataset holds.

Setup. examples/databases/capytaine_box_barge.py (coarse mesh, about 15 s) writes box.1, box.3,
box.hst (Capytaine 3.0's `export_to_wamit`), box.nc and box.json (Capytaine's coefficients in
double precision) for a box barge 40 m x 10 m x 3 m, deep water, rho = 1025 kg/m^3,
g = 9.81 m/s^2, 6 rigid DOFs about the origin on the free surface (centre of gravity there too),
omega = 0, 0.2 .. 2.5 (step 0.1), inf rad/s, headings 0, 90, 180 deg. `fmu-pack pack box.1`
packs the FMU with its defaults (the fit tolerance 1 %). Every expected value below is
Capytaine's own (box.json), converted to our convention: exp(+i omega t),
A~ = a - i b / omega, X = conj(X_capytaine).

Tolerances, in physical units:
- the files against the dataset: the files print 7 significant digits (%12.6e), so every
  number is within 5e-7 of itself relative (6e-7 allowed); phases (%.3f degrees) within
  0.0005 degrees;
- radiation force of harmonic motion V sin(omega t) at omega = 1 rad/s (inside the band; kL = 4):
  the fit's tolerance, 1 % of the entry scale sqrt(s_i s_j) (s_i the largest |A~_ii| over the
  database's frequencies) times omega |V|, plus 0.5 % of the expected force for the input held
  over 200 steps per period, as tests/python/test_ships.py. For heave (s = 3.4e6 kg) at 0.2 m/s
  that is 6.7 kN + 0.5 %; for surge-pitch (sqrt(s_1 s_5) = 7.5e6 kg m) 3 % of the entry. The
  expected force uses the symmetric part of Capytaine's A~ (the FMU fits reciprocity's
  symmetric matrix): Capytaine's surge-pitch and pitch-surge entries are 5.5 % apart on the
  coarse mesh (3.2 % on the fine one), about the size of the tolerance itself;
- exciting force in regular waves (period exactly the file's PER, so no interpolation): the
  files' rounding, 1e-5 of |X_j| (Re and Im have 7 digits, but the phase column only 0.0005
  degrees, 8.7e-6 rad; for head-sea heave at 1 rad/s, |X| = 0.83 MN/m, that is 8 N per metre of
  wave amplitude) plus 1e-9 of the heading's largest |X| for the entries that vanish by symmetry,
  in amplitude and phase against wave.elevation's phase;
- added_mass_inf and stiffness_hydrostatic: 1e-5 of sqrt(|M_ii M_jj|) (added mass, against the
  symmetric part of Capytaine's A(inf), whose surge-pitch entries are 10 % apart on the coarse
  mesh) or of |C_ij| plus 1e-9 of the largest |C| (stiffness), the files' 6-7 digits.

The files carry neither rho nor g; the database is made with the FMU's defaults (1025, 9.81).
"""
import json
import math
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from conftest import ROOT

SCRIPT = ROOT / "examples" / "databases" / "capytaine_box_barge.py"
DOFS = ["surge", "sway", "heave", "roll", "pitch", "yaw"]
OMEGA = 1.0  # rad/s, a database frequency in the middle of the band
HEADINGS = (0.0, 90.0, 180.0)


# ---------------------------------------------------------------------------------------------
# The database and its files


@pytest.fixture(scope="module")
def database(tmp_path_factory):
    """(folder, Capytaine's coefficients in our convention)."""
    out = tmp_path_factory.mktemp("capytaine-box")
    r = subprocess.run([sys.executable, str(SCRIPT), str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    return out, ours(json.loads((out / "box.json").read_text()))


def ours(data):
    """box.json (Capytaine's convention) -> our convention, numpy arrays, SI."""
    omega = np.array(data["omega"])
    a, b = np.array(data["added_mass"]), np.array(data["radiation_damping"])
    xc = np.array(data["excitation_force_re"]) + 1j * np.array(data["excitation_force_im"])
    return {
        "raw": data,
        "rho": data["rho"], "g": data["g"],
        "omega": omega,
        "headings": list(data["headings_deg"]),
        # [omega, influenced i, radiating j]: force in DOF i by motion in DOF j
        "added": a - 1j * b / omega[:, None, None],
        "inf": np.array(data["added_mass_inf"]),
        "zero": np.array(data["added_mass_zero"]),
        "a": a, "b": b,
        # [omega, heading, dof], per unit wave amplitude
        "force": np.conj(xc),
        "stiffness": np.array(data["hydrostatic_stiffness"]),
    }


def read_1(path):
    """WAMIT .1 rows as written: [(PER, I, J, A, B or None)] (nondimensional)."""
    rows = []
    for line in path.read_text().splitlines():
        f = line.split()
        rows.append((float(f[0]), int(f[1]), int(f[2]), float(f[3]),
                     float(f[4]) if len(f) > 4 else None))
    return rows


def read_3(path):
    """WAMIT .3 rows: [(PER, BETA deg, I, |X|, phase deg, re, im)] (nondimensional)."""
    rows = []
    for line in path.read_text().splitlines():
        f = line.split()
        rows.append((float(f[0]), float(f[1]), int(f[2]), *map(float, f[3:7])))
    return rows


def read_hst(path):
    """WAMIT .hst rows: [(I, J, C)] (nondimensional)."""
    return [(int(f[0]), int(f[1]), float(f[2])) for f in
            (line.split() for line in path.read_text().splitlines())]


def close(value, exact, rel=6e-7):
    """Equal to the files' 7 significant digits."""
    return abs(value - exact) <= rel * abs(exact)


def test_the_1_file_is_capytaines_added_mass_and_damping_transposed(database):
    # Facts of Capytaine 3.0's export_to_wamit, as the importer must read them:
    # - ULEN = 1: A / rho and B / (omega rho) (rho L^k with L = 1 m), tab-separated, %12.6e;
    # - the PER = -1 block (omega = 0) first, then PER = 0 (omega = inf), A only, then the
    #   periods in increasing order (omega decreasing), A and B;
    # - 36 rows per period, zero entries written too, the second column varying fastest;
    # - the second column is the RADIATING DOF and the third the INFLUENCED one: the row
    #   "I J" holds the force in DOF J by motion in DOF I, the transpose of WAMIT's A_IJ.
    #   Capytaine's matrices are not symmetric (5.5 % between surge-pitch and pitch-surge at
    #   1 rad/s on the coarse mesh, 10 % at omega = inf), so the order is visible.
    folder, c = database
    rho = c["rho"]
    rows = read_1(folder / "box.1")
    n = len(c["omega"])
    assert len(rows) == 36 * (n + 2)
    periods = [r[0] for r in rows[::36]]
    assert periods[:2] == [-1.0, 0.0]
    assert periods[2:] == sorted(periods[2:])
    for block, per in enumerate(periods):
        got = rows[36 * block:36 * block + 36]
        assert all(r[0] == per for r in got)
        assert [(r[1], r[2]) for r in got] == [(i, j) for j in range(1, 7) for i in range(1, 7)]
        if per == -1.0:
            exact_a, exact_b = c["zero"], None
        elif per == 0.0:
            exact_a, exact_b = c["inf"], None
        else:
            k = int(np.argmin(np.abs(c["omega"] - 2 * np.pi / per)))
            assert close(2 * np.pi / per, c["omega"][k])
            exact_a, exact_b = c["a"][k], c["b"][k] / c["omega"][k]
        for _, i, j, a, b in got:
            # force in j (influenced) by motion in i (radiating)
            assert close(a, exact_a[j - 1, i - 1] / rho), (per, i, j, a, exact_a[j - 1, i - 1] / rho)
            if exact_b is None:
                assert b is None
            else:
                assert close(b, exact_b[j - 1, i - 1] / rho), (per, i, j)
    # The transposition is real: the file's (5, 1) is Capytaine's force in surge by pitch.
    k = int(np.argmin(np.abs(c["omega"] - OMEGA)))
    row = next(r for r in rows if r[0] > 0 and close(2 * np.pi / r[0], OMEGA)
               and (r[1], r[2]) == (5, 1))
    assert close(row[3], c["a"][k, 0, 4] / rho) and not close(row[3], c["a"][k, 4, 0] / rho, 1e-3)


def test_the_3_file_is_the_conjugate_of_capytaines_exciting_force(database):
    # .3: X / (rho g L^m), m = 2 forces, 3 moments, L = 1 m, in our exp(+i omega t) convention
    # (Capytaine conjugates its own); columns PER, BETA (deg, %12.6f), I, |X| (%12.6e),
    # phase (deg, %12.3f), Re, Im (%12.6e), tab-separated; periods increasing, then the
    # headings in the dataset's order, then DOFs 1..6, zero entries written; no rows at
    # omega = 0 or inf.
    folder, c = database
    rg = c["rho"] * c["g"]
    rows = read_3(folder / "box.3")
    n = len(c["omega"])
    assert len(rows) == n * len(c["headings"]) * 6
    assert [r[2] for r in rows] == list(range(1, 7)) * (n * len(c["headings"]))
    assert [r[1] for r in rows[:18:6]] == c["headings"]
    periods = [r[0] for r in rows[::18]]
    assert periods == sorted(periods)
    for per, beta, i, modulus, phase, re, im in rows:
        k = int(np.argmin(np.abs(c["omega"] - 2 * np.pi / per)))
        assert close(2 * np.pi / per, c["omega"][k])
        x = c["force"][k, c["headings"].index(beta), i - 1] / rg
        assert close(re, x.real) and close(im, x.imag) and close(modulus, abs(x)), (per, beta, i)
        if abs(x) > 1e-6 * np.abs(c["force"][k] / rg).max():
            d = (phase - math.degrees(np.angle(x)) + 180) % 360 - 180
            assert abs(d) <= 5e-4 + 1e-9, (per, beta, i, phase)


def test_the_hst_file_is_the_buoyancy_stiffness(database):
    # .hst: C / (rho g L^k), "%5d %5d %12.6e" (spaces), 36 rows, row-major (I the influenced
    # DOF, J fastest), zero entries written. With the centre of gravity on the free surface it
    # is the buoyancy part alone: rho g L B, rho g (L B^3 / 12 - V T / 2), rho g (B L^3 / 12 -
    # V T / 2) (Gauss-Legendre quadrature in the script: exact for the box).
    folder, c = database
    rows = read_hst(folder / "box.hst")
    assert [(i, j) for i, j, _ in rows] == [(i, j) for i in range(1, 7) for j in range(1, 7)]
    for i, j, value in rows:
        assert close(value, c["stiffness"][i - 1, j - 1] / (c["rho"] * c["g"])), (i, j)
    length, beam, draft = c["raw"]["length"], c["raw"]["beam"], c["raw"]["draft"]
    volume = length * beam * draft
    exact = {(3, 3): length * beam, (4, 4): length * beam**3 / 12 - volume * draft / 2,
             (5, 5): beam * length**3 / 12 - volume * draft / 2}
    for (i, j), value in exact.items():
        assert c["stiffness"][i - 1, j - 1] / (c["rho"] * c["g"]) == pytest.approx(value, rel=1e-9)


def test_the_netcdf_file_is_the_same_dataset(database):
    # NetCDF-3 (64-bit offset): complex variables split along a leading dimension `complex`
    # ("re", "im"), DOF names as char arrays.
    folder, c = database
    with xr.open_dataset(folder / "box.nc", engine="scipy") as ds:
        ds = ds.load()
    assert ds.added_mass.dims == ("omega", "influenced_dof", "radiating_dof")
    assert ds.excitation_force.dims == ("complex", "omega", "wave_direction", "influenced_dof")
    assert list(ds.influenced_dof.values) == ["Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw"]
    assert ds.omega.values[0] == 0.0 and np.isinf(ds.omega.values[-1])
    finite = ds.sel(omega=c["omega"])
    np.testing.assert_array_equal(finite.added_mass.values, c["a"])
    np.testing.assert_array_equal(finite.radiation_damping.values, c["b"])
    np.testing.assert_array_equal(ds.added_mass.sel(omega=np.inf).values, c["inf"])
    x = finite.excitation_force.sel(complex="re") - 1j * finite.excitation_force.sel(complex="im")
    np.testing.assert_array_equal(x.transpose("omega", "wave_direction", "influenced_dof").values,
                                  c["force"])
    np.testing.assert_array_equal(ds.hydrostatic_stiffness.values, c["stiffness"])


# ---------------------------------------------------------------------------------------------
# The FMU packed from box.1


@pytest.fixture(scope="module")
def box_fmu(fmu_pack_binary, database):
    folder, _ = database
    path = folder / "box.fmu"
    r = subprocess.run([str(fmu_pack_binary), "pack", str(folder / "box.1"), "-o", str(path)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    return path


def open_fmu(path, name):
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    return md, vr, fmu


def harmonic(times, values, omega):
    """The complex amplitude Y of values ~ Re(Y exp(i omega t)), least squares."""
    t = np.asarray(times)
    (c, s), *_ = np.linalg.lstsq(np.column_stack([np.cos(omega * t), np.sin(omega * t)]),
                                 np.asarray(values), rcond=None)
    return complex(c, -s)


def test_the_fmu_has_the_ship_variables(box_fmu):
    md = read_model_description(str(box_fmu))
    names = {v.name for v in md.modelVariables}
    for d in DOFS:
        for kind in ("velocity", "force", "force_radiation", "force_excitation"):
            assert f"{kind}.{d}" in names, (kind, d)
    for i in range(1, 7):
        for j in range(1, 7):
            assert f"added_mass_inf[{i},{j}]" in names and f"stiffness_hydrostatic[{i},{j}]" in names
    for name in ("wave.kind", "wave.height", "wave.period", "wave.heading", "wave.elevation"):
        assert name in names, name


def test_the_parameters_are_capytaines_infinite_frequency_mass_and_stiffness(box_fmu, database):
    _, c = database
    md, vr, fmu = open_fmu(box_fmu, "parameters")
    fmu.exitInitializationMode()
    mass = np.array(fmu.getReal([vr[f"added_mass_inf[{i},{j}]"] for i in range(1, 7)
                                 for j in range(1, 7)])).reshape(6, 6)
    stiffness = np.array(fmu.getReal([vr[f"stiffness_hydrostatic[{i},{j}]"] for i in range(1, 7)
                                      for j in range(1, 7)])).reshape(6, 6)
    fmu.terminate()
    fmu.freeInstance()
    # The FMU's added_mass_inf is symmetric (a master's mass matrix); Capytaine's A(inf) is
    # not quite (10 % between surge-pitch and pitch-surge on the coarse mesh): its symmetric part.
    inf = (c["inf"] + c["inf"].T) / 2
    scale = np.sqrt(np.outer(np.diag(inf), np.diag(inf)))
    assert np.all(np.abs(mass - inf) <= 1e-5 * scale), (mass, inf)
    cs = c["stiffness"]
    assert np.all(np.abs(stiffness - cs) <= 1e-5 * np.abs(cs) + 1e-9 * np.abs(cs).max()), (
        stiffness, cs)


@pytest.fixture(scope="module")
def harmonic_run(box_fmu):
    """run(dof, amplitude) -> {output name: complex amplitude} of every force output in the
    steady state of velocity.<dof> = amplitude sin(OMEGA t), each run once."""
    done = {}

    def run(dof, amplitude):
        if dof in done:
            return done[dof]
        md, vr, fmu = open_fmu(box_fmu, f"harmonic-{dof}")
        fmu.exitInitializationMode()
        names = [f"{kind}.{d}" for kind in ("force", "force_radiation") for d in DOFS]
        refs = [vr[x] for x in names]
        steps, periods = 200, 30
        h = 2 * math.pi / OMEGA / steps
        times, values = [], []
        for n in range(steps * periods):
            t = n * h
            fmu.setReal([vr[f"velocity.{dof}"]], [amplitude * math.sin(OMEGA * (t + h / 2))])
            fmu.doStep(t, h)
            fmu.setReal([vr[f"velocity.{dof}"]], [amplitude * math.sin(OMEGA * (t + h))])
            if n >= steps * (periods - 10):
                times.append(t + h)
                values.append(fmu.getReal(refs))
        fmu.terminate()
        fmu.freeInstance()
        values = np.array(values)
        done[dof] = {x: harmonic(times, values[:, k], OMEGA) for k, x in enumerate(names)}
        return done[dof]

    return run


@pytest.mark.parametrize("moved, measured, amplitude", [
    ("heave", "heave", 0.2),     # m/s
    ("pitch", "pitch", 0.01),    # rad/s
    ("pitch", "surge", 0.01),    # the surge force of pitching about the waterline
    ("sway", "roll", 0.2),       # the roll moment of swaying
])
def test_harmonic_motion_gives_capytaines_radiation_force(harmonic_run, database, moved,
                                                          measured, amplitude):
    _, c = database
    k, m = DOFS.index(moved), DOFS.index(measured)
    w = int(np.argmin(np.abs(c["omega"] - OMEGA)))
    assert c["omega"][w] == OMEGA
    added = c["added"][w]
    added = (added + added.T) / 2  # reciprocity: the FMU models the symmetric part
    inf = (c["inf"] + c["inf"].T) / 2
    forces = harmonic_run(moved, amplitude)
    measured_force = forces[f"force_radiation.{measured}"]
    # velocity amplitude sin(omega t) = Re(-i amplitude exp(i omega t)); the master adds A_inf.
    expected = -1j * OMEGA * (added[m, k] - inf[m, k]) * (-1j * amplitude)
    scales = np.abs(np.diagonal(c["added"], axis1=1, axis2=2)).max(axis=0)
    allowed = 0.01 * math.sqrt(scales[m] * scales[k]) * OMEGA * amplitude + 5e-3 * abs(expected)
    assert abs(measured_force - expected) <= allowed, (moved, measured, measured_force, expected,
                                                       allowed)
    # In calm water the total force is the radiation force.
    assert abs(forces[f"force.{measured}"] - measured_force) <= 1e-9 * max(abs(measured_force), 1.0)


@pytest.mark.parametrize("heading", HEADINGS)
def test_a_regular_wave_gives_capytaines_exciting_force(box_fmu, database, heading):
    folder, c = database
    w = int(np.argmin(np.abs(c["omega"] - OMEGA)))
    # The period exactly as the files print it, so the FMU takes its own table's row.
    period = next(r[0] for r in read_3(folder / "box.3") if close(2 * np.pi / r[0], OMEGA))
    omega = 2 * math.pi / period
    amplitude = 0.5
    md, vr, fmu = open_fmu(box_fmu, f"waves-{heading:g}")
    fmu.setInteger([vr["wave.kind"]], [1])
    fmu.setReal([vr["wave.height"], vr["wave.period"], vr["wave.heading"]],
                [2 * amplitude, period, heading])
    fmu.exitInitializationMode()
    names = ["wave.elevation"] + [f"force_excitation.{d}" for d in DOFS]
    refs = [vr[x] for x in names]
    steps = 50
    h = period / steps
    times, values = [], []
    for n in range(4 * steps):
        fmu.doStep(n * h, h)
        if n >= steps:
            times.append((n + 1) * h)
            values.append(fmu.getReal(refs))
    fmu.terminate()
    fmu.freeInstance()
    values = np.array(values)
    elevation = harmonic(times, values[:, 0], omega)
    # eta(x = 0, t) = a cos(omega t): amplitude a, phase 0.
    assert abs(elevation - amplitude) <= 1e-9 * amplitude, elevation
    expected = c["force"][w, c["headings"].index(heading)] * amplitude
    largest = np.abs(expected).max()
    for j, d in enumerate(DOFS):
        measured = harmonic(times, values[:, 1 + j], omega)
        # Against the elevation's own phase: X = F / eta per unit amplitude.
        relative = measured / elevation * amplitude
        allowed = 1e-5 * abs(expected[j]) + 1e-9 * largest
        assert abs(relative - expected[j]) <= allowed, (heading, d, relative, expected[j], allowed)
        if abs(expected[j]) > 1e-3 * largest:
            # amplitude (relative) and phase (rad), each within the same bound
            bound = allowed / abs(expected[j])
            assert abs(abs(relative) / abs(expected[j]) - 1) <= bound, (heading, d, relative)
            assert abs(np.angle(relative / expected[j])) <= bound, (heading, d, relative)


# ---------------------------------------------------------------------------------------------
# Real data's troubles: no omega = inf rows, no lid


def fmu_pack(binary, *args):
    r = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    return r


def a_inf_table(path):
    """The omega = inf rows of a `fmu-pack sweep` table: {(i, j): A_inf_ij}."""
    out = {}
    for line in path.read_text().splitlines():
        if line.startswith("inf,"):
            _, i, j, re, _ = line.split(",")
            out[(int(i) - 1, int(j) - 1)] = float(re)
    return out


def test_a_missing_a_inf_is_estimated_within_its_stated_uncertainty_where_it_can_be(
        fmu_pack_binary, database, tmp_path):
    folder, _ = database
    # The same files without the PER = 0 rows.
    rows = (folder / "box.1").read_text().splitlines()
    (tmp_path / "box.1").write_text(
        "\n".join(r for r in rows if float(r.split()[0]) != 0.0) + "\n")
    for ext in ("3", "hst"):
        (tmp_path / f"box.{ext}").write_text((folder / f"box.{ext}").read_text())
    r = fmu_pack(fmu_pack_binary, "sweep", tmp_path / "box.1", "-o", tmp_path / "t.csv")
    note = next(line for line in r.stderr.splitlines() if "Kramers-Kronig" in line)
    stated = {name: float(note.split(f" {name} ")[1].split(" %")[0]) / 100 for name in DOFS}
    estimate = a_inf_table(tmp_path / "t.csv")
    fmu_pack(fmu_pack_binary, "sweep", folder / "box.1", "-o", tmp_path / "given.csv")
    given = a_inf_table(tmp_path / "given.csv")
    error = {name: abs(estimate[(k, k)] - given[(k, k)]) / given[(k, k)]
             for k, name in enumerate(DOFS)}
    # Measured against Capytaine's own omega = inf solve: heave 1.2 %, roll 0.3 %, pitch 0.9 %
    # (stated 1.0, 1.3, 0.6 %: the statement is the right size, not a bound); surge 1.7 %,
    # sway 4.9 %, yaw 21 %, where the grid ends (kL = 25) before their damping has decayed and
    # the statement says so (36 %, 37 %, 71 %).
    for name in ("heave", "roll", "pitch"):
        assert error[name] < 0.02, (name, error, stated)
        assert stated[name] < 0.03, (name, stated)
    for name in ("surge", "sway", "yaw"):
        assert error[name] < stated[name], (name, error, stated)
        assert stated[name] > 0.1, (name, stated)


@pytest.fixture(scope="module")
def without_lid(tmp_path_factory):
    out = tmp_path_factory.mktemp("capytaine-box-no-lid")
    r = subprocess.run([sys.executable, str(SCRIPT), str(out), "--no-lid"], capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    return out


def fit_error(report):
    line = next(x for x in report.splitlines() if x.startswith("largest error"))
    return float(line.split()[2]) / 100


def test_without_a_lid_the_irregular_frequency_is_found_and_kept_out_of_the_fit(
        fmu_pack_binary, database, without_lid):
    # Without a lid the first irregular frequency of the 40 x 10 x 3 m box, 2.06 rad/s, shows
    # at the grid's 2.1 rad/s (pitch damping 53 % of its scale off the lid's value, negative
    # damping); it is the one frequency left out, and none of the lid's data is.
    r = fmu_pack(fmu_pack_binary, "fit", without_lid / "box.1")
    left_out = [x for x in r.stdout.splitlines() if x.startswith("left out:")]
    assert len(left_out) == 1, r.stdout
    assert "omega = 2.1" in left_out[0] and "irregular-frequency spike" in left_out[0]
    clean = fmu_pack(fmu_pack_binary, "fit", database[0] / "box.1")
    assert not [x for x in clean.stdout.splitlines() if x.startswith("left out:")], clean.stdout
    # Kept in (--plain), the spike wrecks the fit (measured 35 %); left out, the rest of the
    # irregular frequency's broad influence (a few % at 2.0 .. 2.5 rad/s on this coarse mesh)
    # makes A~_ij and A~_ji differ by more than the tolerance (sway-roll, 3.25 % of
    # sqrt(s_i s_j)): the report judges the fit against that noise floor and says so. The fit
    # itself now reaches 0.956 % with 59 states (poles refined under the passivity
    # constraints; before 1.4 %); a band below 1.95 rad/s meets 1 % (0.8 %).
    kept = fmu_pack(fmu_pack_binary, "fit", without_lid / "box.1", "--plain")
    assert fit_error(kept.stdout) > 0.10, kept.stdout
    floor = [x for x in r.stdout.splitlines() if x.startswith("note: the data's own noise")]
    assert len(floor) == 1, r.stdout
    verdict = next(x for x in r.stdout.splitlines() if x.startswith("largest error"))
    tolerance = float(verdict.split("(tolerance ")[1].split()[0]) / 100
    assert 0.032 < tolerance < 0.033, verdict
    assert fit_error(r.stdout) <= tolerance and "met)" in verdict, r.stdout
    below = fmu_pack(fmu_pack_binary, "fit", without_lid / "box.1", "--band", "0.2:1.95rad/s")
    assert fit_error(below.stdout) < 0.01, below.stdout


def sweep_rows(path):
    """`fmu-pack sweep` rows: {(omega, i, j or heading): complex}, omega to 5 decimals (the
    WAMIT periods' 7 digits)."""
    out = {}
    for line in path.read_text().splitlines():
        if line.startswith("#") or line[0].isalpha():
            continue
        w, i, j, re, im = line.split(",")
        out[(round(float(w), 5), int(i), float(j))] = complex(float(re), float(im))
    return out


def test_capytaines_netcdf_and_its_wamit_export_import_alike(fmu_pack_binary, database,
                                                              tmp_path):
    # The same dataset read twice: box.nc (NetCDF-3, Capytaine's own convention, conjugated on
    # reading) and box.1/.3/.hst (7 digits). Equal to the files' digits: 2e-6 of the entry
    # scale sqrt(|A_ii A_jj|) (measured 3e-7) and of the DOF's largest exciting force.
    folder, _ = database
    tables = {}
    for name in ("box.nc", "box.1"):
        out, x = tmp_path / f"{name}.csv", tmp_path / f"{name}-x.csv"
        fmu_pack(fmu_pack_binary, "sweep", folder / name, "-o", out, "--excitation", x)
        tables[name] = (sweep_rows(out), sweep_rows(x))
    (nc, nc_x), (wamit, wamit_x) = tables["box.nc"], tables["box.1"]
    assert nc.keys() == wamit.keys() and nc_x.keys() == wamit_x.keys()
    scale = {i: max(abs(v) for (w, a, b), v in nc.items() if a == b == i) for i in range(1, 7)}
    for (w, i, j), v in nc.items():
        assert abs(v - wamit[(w, i, j)]) <= 2e-6 * math.sqrt(scale[i] * scale[j]), (w, i, j)
    largest = {j: max(abs(v) for (w, jj, h), v in nc_x.items() if jj == j) for j in range(1, 7)}
    for (w, j, h), v in nc_x.items():
        assert abs(v - wamit_x[(w, j, h)]) <= 2e-6 * largest[j], (w, j, h)


def test_our_netcdf_export_reads_in_capytaine_as_its_own_dataset(fmu_pack_binary, database,
                                                                  tmp_path):
    # Capytaine -> export_to_wamit -> fmu-pack -> `--netcdf` -> xarray + Capytaine's
    # merge_complex_values: Capytaine's coefficients again, in its own convention and names.
    # Within the WAMIT files' 7 digits (6e-7 of each entry's scale); the added mass as its
    # symmetric part (the import makes A~ symmetric).
    import capytaine as cpt

    folder, ours_data = database
    path = tmp_path / "export.nc"
    fmu_pack(fmu_pack_binary, "sweep", folder / "box.1", "-o", tmp_path / "t.csv",
             "--netcdf", path)
    ds = cpt.io.xarray.merge_complex_values(xr.open_dataset(path))
    raw = ours_data["raw"]
    assert list(ds.influenced_dof.values) == raw["dofs"]
    assert np.allclose(np.degrees(ds.wave_direction.values), raw["headings_deg"])
    assert float(ds.rho) == raw["rho"] and float(ds.g) == raw["g"]
    omega = np.array(raw["omega"])
    finite = ds.sel(omega=omega, method="nearest")
    assert np.allclose(finite.omega.values, omega, rtol=1e-6)

    def symmetric(m):
        return (m + np.swapaxes(m, -1, -2)) / 2

    scale = np.sqrt(np.abs(np.einsum("kii->ki", np.array(raw["added_mass"]))).max(axis=0))
    entry = np.outer(scale, scale)
    a = symmetric(np.array(raw["added_mass"]))
    b = symmetric(np.array(raw["radiation_damping"])) / omega[:, None, None]
    assert np.all(np.abs(finite.added_mass.values - a) <= 6e-7 * entry)
    assert np.all(np.abs(finite.radiation_damping.values / omega[:, None, None] - b)
                  <= 6e-7 * entry)
    inf = symmetric(np.array(raw["added_mass_inf"]))
    assert np.all(np.abs(ds.added_mass.sel(omega=np.inf).values - inf) <= 6e-7 * entry)
    x = np.array(raw["excitation_force_re"]) + 1j * np.array(raw["excitation_force_im"])
    got = finite.excitation_force.transpose("omega", "wave_direction", "influenced_dof").values
    largest = np.abs(x).max(axis=(0, 1))
    assert np.all(np.abs(got - x) <= 1e-6 * largest)
    c = np.array(raw["hydrostatic_stiffness"])
    assert np.all(np.abs(ds.hydrostatic_stiffness.values - c) <= 1e-6 * np.abs(c).max())
