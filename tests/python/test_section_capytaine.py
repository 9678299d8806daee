"""A section's NetCDF export (`fmu-pack sweep semicircle --netcdf`) as Capytaine reads it:
xarray.open_dataset + capytaine.io.xarray.merge_complex_values give the sweep's coefficients
per metre in SI (rho = 1025 kg/m^3, g = 9.81 m/s^2, R = 1 m), in Capytaine's exp(-i omega t)
and its DOF names, the waves beam seas (wave_direction = 90 deg - our heading). Capytaine's
own Froude-Krylov force on a long half-immersed cylinder, per metre, agrees with ours under
that mapping (its phase and heading conventions).
"""
import math
import subprocess

import numpy as np
import pytest
import xarray as xr

RHO, G, R = 1025.0, 9.81, 1.0
SCALE = RHO * math.pi * R * R  # the table's added-mass unit, kg/m


def rows(path):
    """Data rows of a `fmu-pack sweep` table: [(first column, i, j or heading, re, im)]."""
    out = []
    for line in path.read_text().splitlines():
        if line.startswith("#") or line[0].isalpha():
            continue
        first, i, j, re, im = line.split(",")
        out.append((float(first), int(i), float(j), float(re), float(im)))
    return out


@pytest.fixture(scope="module")
def section(fmu_pack_binary, tmp_path_factory):
    out = tmp_path_factory.mktemp("section")
    files = {name: out / name for name in ("t.csv", "x.csv", "fk.csv", "h.csv", "s.nc")}
    r = subprocess.run(
        [str(fmu_pack_binary), "sweep", "semicircle", "--kr", "0.25:4:5",
         "-o", files["t.csv"], "--excitation", files["x.csv"],
         "--froude-krylov", files["fk.csv"], "--hydrostatics", files["h.csv"],
         "--netcdf", files["s.nc"]],
        capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return files


@pytest.fixture(scope="module")
def dataset(section):
    import capytaine as cpt
    return cpt.io.xarray.merge_complex_values(xr.open_dataset(section["s.nc"]))


def test_the_dataset_says_per_unit_length_and_names_capytaines_dofs(dataset):
    assert "per unit length" in dataset.attrs["per_unit_length"]
    assert float(dataset.attrs["reference_length"]) == 1.0
    assert list(np.ravel(dataset.attrs["rotation_center"])) == [0.0, 0.0, 0.0]
    assert list(dataset.influenced_dof.values) == [
        "Sway", "Heave", "Roll", "cb1", "cb2", "cb3", "cb4", "cb5", "cb6"]
    assert float(dataset.rho) == RHO and float(dataset.g) == G
    assert np.allclose(np.degrees(dataset.wave_direction.values), [-90.0, 90.0])


def test_added_mass_and_damping_are_the_sweep_per_metre(section, dataset):
    # Diagonals to the table's 17 digits (1e-12); off-diagonals to the symmetric part (the
    # export makes A~ symmetric), 1e-3 of sqrt(|A_ii A_jj|) (the reciprocity residual, 6e-4).
    table = rows(section["t.csv"])
    kr = sorted({k for k, *_ in table if k > 0})
    n = 9
    nd = np.zeros((len(kr), n, n), complex)
    for k, i, j, re, im in table:
        if k > 0:
            nd[kr.index(k), i - 1, int(j) - 1] = complex(re, im)
    omega = np.sqrt(np.array(kr) * G / R)
    finite = dataset.sel(omega=omega, method="nearest")
    assert np.allclose(finite.omega.values, omega, rtol=1e-15)
    a = finite.added_mass.transpose("omega", "influenced_dof", "radiating_dof").values
    b = finite.radiation_damping.transpose("omega", "influenced_dof", "radiating_dof").values
    expected_a = SCALE * nd.real
    expected_b = -SCALE * nd.imag * omega[:, None, None]
    diag = np.einsum("kii->ki", expected_a)
    entry = np.sqrt(np.abs(diag)[:, :, None] * np.abs(diag)[:, None, :])
    for got, want in ((a, expected_a), (b, expected_b)):
        assert np.all(np.abs(got - np.swapaxes(got, 1, 2)) == 0)
        d = np.abs(np.einsum("kii->ki", got) - np.einsum("kii->ki", want))
        assert np.all(d <= 1e-12 * np.abs(np.einsum("kii->ki", want)) + 1e-9)
    assert np.all(np.abs(a - expected_a) <= 1e-3 * entry + 1e-9)
    # Heave: A_inf = rho pi R^2 / 2 per metre (exact limit, to 1e-3 of it).
    inf = dataset.added_mass.sel(omega=np.inf, influenced_dof="Heave", radiating_dof="Heave")
    assert abs(float(inf) - SCALE / 2) < 1e-3 * SCALE
    # Damping: no negative diagonal (radiated energy).
    assert np.all(np.einsum("kii->ki", b)[:, :2] > 0)


def test_exciting_force_is_the_sweep_conjugated_in_beam_seas(section, dataset):
    # Capytaine's exp(-i omega t): conj(ours); wave_direction 90 deg is our heading 0,
    # -90 deg our heading 180. The table's 17 digits: 1e-12 of the largest |X_j|.
    x = dataset.excitation_force
    largest = 0.0
    pairs = []
    for k, j, heading, re, im in rows(section["x.csv"]):
        if k == 0:
            continue
        ours = complex(re, im) * RHO * G * R ** (1 + (1 if j in (3, 6, 9) else 0))
        got = complex(x.sel(omega=math.sqrt(k * G / R), method="nearest")
                      .sel(wave_direction=math.radians(90.0 - heading), method="nearest")
                      .isel(influenced_dof=j - 1).values)
        pairs.append((got, ours.conjugate()))
        largest = max(largest, abs(ours))
    assert len(pairs) == 5 * 2 * 9
    for got, want in pairs:
        assert abs(got - want) <= 1e-12 * largest


def test_capytaines_froude_krylov_force_per_metre_is_ours_in_its_frame(section):
    # A 20 m half-immersed cylinder along X (Capytaine's mesh, no solve): in beam seas the
    # wave is uniform along it and the end caps push only in X, so its sway and heave
    # Froude-Krylov force over 20 m is the section's. Within 1e-3 of the larger of the two
    # (measured with 200 panels around the wetted half: 9e-6, 4e-5, 3.6e-4 at kR = 0.25, 1,
    # 4; with 30: 3.9e-4, 1.8e-3, 1.6e-2, the mesh's second-order error).
    import capytaine as cpt

    length = 20.0
    mesh = cpt.mesh_horizontal_cylinder(length=length, radius=R, center=(0, 0, 0),
                                        resolution=(2, 400, 4)).immersed_part()
    body = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)))
    ours = {(k, j, h): complex(re, im) for k, j, h, re, im in rows(section["fk.csv"])}
    for kr in (0.25, 1.0, 4.0):
        omega = math.sqrt(kr * G / R)
        for heading in (0.0, 180.0):
            problem = cpt.DiffractionProblem(body=body, omega=omega, rho=RHO, g=G,
                                             wave_direction=math.radians(90.0 - heading))
            force = cpt.bem.airy_waves.froude_krylov_force(problem)
            key = min((k for k in ours if k[1] == 2 and k[2] == heading),
                      key=lambda q: abs(q[0] - kr))[0]
            scale = max(abs(ours[(key, j, heading)]) for j in (1, 2))
            for j, name in ((1, "Sway"), (2, "Heave")):
                theirs = complex(force[name]).conjugate() / (length * RHO * G * R)
                assert abs(theirs - ours[(key, j, heading)]) < 1e-3 * scale, (kr, heading, name)


def test_restoring_is_the_sections_per_metre(section, dataset):
    c = np.zeros((9, 9))
    for line in section["h.csv"].read_text().splitlines():
        if line[0].isdigit():
            i, j, v = line.split(",")
            c[int(i) - 1, int(j) - 1] = float(v) * RHO * G
    got = dataset.hydrostatic_stiffness.transpose("influenced_dof", "radiating_dof").values
    assert np.allclose(got, c, rtol=1e-15, atol=1e-12 * np.abs(c).max())
    assert abs(got[1, 1] - RHO * G * 2 * R) < 1e-9 * RHO * G
