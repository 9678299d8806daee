"""A section in finite water depth against a 3D panel method in finite depth (Capytaine 3.0).

examples/finite_depth/capytaine_cylinder.py runs both codes: `fmu-pack sweep semicircle
--water-depth H` per metre against a long half-immersed cylinder (R = 1 m, L = 40 m, L/D = 20,
1088 panels) whose whole-body heave and sway added mass and damping are divided by L, both in
units of rho pi R^2 (the damping as b / (rho pi R^2 omega), the table's -Im A~), at h/R = inf,
10, 4 and 2 and kR = 0.3, 0.513, 0.877, 1.5. Capytaine's finite-depth kernel is Delhommeau's
with Nemoh's Fortran Prony fit (its default fit samples random points and is off its own energy
balance by x1.4 .. x1.8 at kR = 1.5); deep water uses its default solver.

Each Capytaine point is checked against its own far field: its damping over the damping its
exciting forces over all headings radiate (E, 1 if consistent). On this mesh deep water gives
1.018 .. 1.050 (the mesh: 2448 panels give 1.015 .. 1.025), so a finite-depth point is
compared where its E is within 5 % of deep water's at the same kR. Two points fail: heave at
kR = 1.5, h/R = 4 and 2 (E 8.6 % and 12.2 % above deep water's). Near there, at h/R = 2,
Capytaine's heave damping jumps with kR while ours is smooth; where it passes its check its
ratio to deep water scatters about ours (1.24 .. 1.30 at kR 1.3 .. 1.59 against ours 1.255 ..
1.258; docs/FINITE_DEPTH.md).

The strip and the 3D body differ in deep water by the ends' 3D relief (at most 0.032, heave
added mass at kR = 0.3). Subtracting each code's own deep-water value removes it: the depth
effects (value at depth h minus deep water, up to 0.155 at h/R = 2) agree within 0.0082
(measured, heave damping at h/R = 2, kR = 0.513). Capytaine: about 40 s of CPU.
"""
import math
import subprocess

import numpy as np
import pytest

import conftest

DEPTHS = (math.inf, 10.0, 4.0, 2.0)  # h/R with R = 1 m
# Deep water, strip against 3D per metre: measured at most 0.032 (heave added mass, kR = 0.3;
# the ends' 3D relief: 0.024 at L/D = 40).
DEEP_LIMIT = 0.035
# Depth effects of the two codes (each its value at h minus its deep-water value): measured
# within 0.0082 (heave damping, h/R = 2, kR = 0.513), where the effects reach 0.155.
DEPTH_EFFECT_LIMIT = 0.01
# Capytaine's energy check in deep water on this mesh: measured 1.018 .. 1.050.
DEEP_ENERGY_RANGE = (1.0, 1.06)
# Ours: the 2D energy identity with c_g, measured within 5.4e-5 at every point.
OUR_ENERGY_LIMIT = 1e-4


def load_script():
    return conftest.load_script("examples/finite_depth/capytaine_cylinder.py")


@pytest.fixture(scope="module")
def cylinder():
    return load_script()


@pytest.fixture(scope="module")
def ours(fmu_pack_binary, tmp_path_factory, cylinder):
    """{h/R: {(dof, kR): (a, b, E)}} of `fmu-pack sweep semicircle`, rho pi R^2 units."""
    folder = tmp_path_factory.mktemp("finite-depth")
    out = {}
    for depth in DEPTHS:
        values, depth_line = cylinder.ours(fmu_pack_binary, depth, folder=folder)
        assert depth_line == ("inf" if math.isinf(depth) else f"{depth:g}")
        out[depth] = values
    return out


@pytest.fixture(scope="module")
def theirs(ours, cylinder):
    """{h/R: {(dof, kR): (a, b, E)}}: Capytaine's whole body per metre, E its energy check."""
    kr_values = sorted({kr for (_, kr) in ours[math.inf]})
    return cylinder.capytaine(DEPTHS, kr_values)


def deep_difference(ours, theirs):
    return max(abs(o - t) for key, triple in ours[math.inf].items()
               for o, t in zip(triple[:2], theirs[math.inf][key][:2]))


def test_deep_water_differs_by_the_ends_only(ours, theirs):
    # 2D strip against the 3D body per metre in deep water: the ends' 3D effects only.
    assert deep_difference(ours, theirs) < DEEP_LIMIT


def test_both_codes_pass_their_energy_checks(ours, theirs, cylinder):
    for table in ours.values():
        for key, (_, _, energy) in table.items():
            assert abs(energy - 1) < OUR_ENERGY_LIMIT, (key, energy)
    low, high = DEEP_ENERGY_RANGE
    for key, (_, _, energy) in theirs[math.inf].items():
        assert low < energy < high, (key, energy)
    # In finite depth Capytaine fails its check at two of the 24 points (heave, kR = 1.5,
    # h/R = 4 and 2); those are left out below.
    failed = [(depth, key) for depth in DEPTHS[1:] for key in theirs[depth]
              if not cylinder.trusted(theirs, depth, key)]
    assert len(failed) <= 2, failed


@pytest.mark.parametrize("depth", [10.0, 4.0, 2.0])
def test_the_depth_effects_agree(ours, theirs, cylinder, depth):
    compared, largest = 0, 0.0
    for key, triple in ours[depth].items():
        if not cylinder.trusted(theirs, depth, key):
            continue
        compared += 1
        for what, o, t, o_deep, t_deep in zip(("a", "b"), triple, theirs[depth][key],
                                              ours[math.inf][key], theirs[math.inf][key]):
            ours_moved, theirs_moved = o - o_deep, t - t_deep
            assert abs(ours_moved - theirs_moved) <= DEPTH_EFFECT_LIMIT, (
                depth, key, what, ours_moved, theirs_moved)
            largest = max(largest, abs(theirs_moved))
    assert compared >= 7, compared
    if depth == 2.0:
        # The bottom moves the coefficients far more than the codes differ (measured 0.155,
        # Capytaine's heave damping at kR = 0.3).
        assert largest > 0.12, largest


def test_the_depth_changes_the_coefficients_where_kh_is_small(ours):
    # h/R = 2, kR = 0.3 (kh = 0.86): far from deep water in both DOFs.
    shallow, deep = ours[2.0], ours[math.inf]
    for dof in ("heave", "sway"):
        moved = max(abs(s - d) for s, d in zip(shallow[(dof, 0.3)][:2], deep[(dof, 0.3)][:2]))
        assert moved > 0.08, (dof, shallow[(dof, 0.3)], deep[(dof, 0.3)])


def test_where_kh_is_large_the_bottom_acts_through_the_near_field_only(ours):
    # kh > 5 (h/R = 10 from kR = 0.513, h/R = 4 at kR = 1.5): within 0.3 (R/h)^2 of deep water
    # (measured: at most 0.27 (R/h)^2, heave at h/R = 10, kR = 0.513; sway within 0.05 (R/h)^2).
    checked = 0
    for depth in (10.0, 4.0, 2.0):
        for (dof, kr), triple in ours[depth].items():
            if kr * depth > 5.0:
                checked += 1
                for value, deep in zip(triple[:2], ours[math.inf][(dof, kr)][:2]):
                    assert abs(value - deep) <= 0.3 / depth**2, (depth, dof, kr, value, deep)
    assert checked == 8
    # Heave at kR = 1.5 approaches deep water like (R/h)^2: from h/R = 4 to 10 the difference
    # falls by 7.4 (measured; (10/4)^2 = 6.25).
    deep = ours[math.inf][("heave", 1.5)][:2]
    far, near = (max(abs(v - d) for v, d in zip(ours[h][("heave", 1.5)][:2], deep))
                 for h in (10.0, 4.0))
    assert 5.0 < near / far < 10.0, (near, far)


def test_the_tables_say_their_depth(ours):
    assert all(len(ours[depth]) == 8 for depth in DEPTHS)
    assert np.isfinite([v for table in ours.values() for triple in table.values()
                        for v in triple]).all()


# The FMU of a section in finite depth: its fixed parameter `depth`.

@pytest.fixture(scope="module")
def finite_depth_fmu(fmu_pack_binary, tmp_path_factory):
    out = tmp_path_factory.mktemp("finite-depth-fmu")
    path = out / "shallow.fmu"
    r = subprocess.run([str(fmu_pack_binary), "pack", "semicircle", "--dofs", "heave",
                        "--water-depth", "3", "--kr", "0.05:5:40", "-o", str(path)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return path, r.stdout


def test_the_fmu_declares_its_depth_and_inspect_and_pack_say_it(fmu_pack_binary,
                                                               finite_depth_fmu):
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu

    path, summary = finite_depth_fmu
    assert "water depth      3 m" in summary, summary
    assert validate_fmu(str(path)) == []
    variables = read_model_description(str(path)).modelVariables
    depth = variables[-1]
    assert (depth.name, depth.valueReference, depth.causality) == ("depth", 98, "parameter")
    assert float(depth.start) == 3.0
    r = subprocess.run([str(fmu_pack_binary), "inspect", str(path)], capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    assert "water depth       3 m" in r.stdout, r.stdout


def test_a_master_may_set_depth_only_to_its_packed_value(finite_depth_fmu):
    from fmpy import extract, read_model_description
    from fmpy.fmi1 import FMICallException
    from fmpy.fmi2 import FMU2Slave

    path, _ = finite_depth_fmu
    md = read_model_description(str(path))
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="h")
    slave.instantiate(loggingOn=False)
    slave.setReal([98], [3.0])
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    assert slave.getReal([98]) == [3.0]
    # Refused (fmi2Error: the message names depth, 5 m and the packed 3 m).
    with pytest.raises(FMICallException):
        slave.setReal([98], [5.0])
    slave.freeInstance()
