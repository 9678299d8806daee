"""A ship's FMU (strip theory, docs/SHIPS.md) under fmpy: the radiation force of harmonic
motion and the exciting force of an oblique regular wave follow the ship's own tables, the
units are whole-ship SI, and a heading the table lacks is refused when it is set.

The ship is examples/ships/barge.xml (100 m x 10 m x 5 m, Lewis sections, a vertical bending
mode `vb1`), packed and swept with the same default grid, so the table's frequencies are the
FMU's.
"""
import csv
import io
import math
import subprocess

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave

from conftest import ROOT

RHO, G = 1025.0, 9.81
SHIP = ROOT / "examples" / "ships" / "barge.xml"
DOFS = ["sway", "heave", "roll", "pitch", "yaw", "vb1"]


@pytest.fixture(scope="module")
def ship_fmu(fmu_pack_binary, tmp_path_factory):
    path = tmp_path_factory.mktemp("ship") / "Barge.fmu"
    subprocess.run([str(fmu_pack_binary), "pack", str(SHIP), "-o", str(path)], check=True,
                   capture_output=True)
    return path


@pytest.fixture(scope="module")
def tables(fmu_pack_binary, tmp_path_factory):
    """(A~ by omega, A_inf, X by (omega, heading)): the ship's sweep in SI."""
    folder = tmp_path_factory.mktemp("ship-tables")
    excitation = folder / "x.csv"
    text = subprocess.run(
        [str(fmu_pack_binary), "sweep", str(SHIP), "--excitation", str(excitation), "-o", "-"],
        check=True, capture_output=True, text=True).stdout
    rows = [r for r in csv.reader(io.StringIO(text)) if r and not r[0].startswith(("#", "omega"))]
    n = len(DOFS)
    added = {}
    inf = np.zeros((n, n))
    for r in rows:
        i, j = int(r[1]) - 1, int(r[2]) - 1
        if r[0] == "inf":
            inf[i, j] = float(r[3])
        else:
            added.setdefault(float(r[0]), np.zeros((n, n), complex))[i, j] = complex(float(r[3]), float(r[4]))
    forces = {}
    for r in csv.reader(io.StringIO(excitation.read_text())):
        if r and not r[0].startswith(("#", "omega")):
            forces[(float(r[0]), int(r[1]) - 1, float(r[2]))] = complex(float(r[3]), float(r[4]))
    return added, inf, forces


def open_fmu(path, name, logging=False):
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
    fmu.instantiate(loggingOn=logging)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    return md, vr, fmu


def test_the_ship_fmu_speaks_whole_ship_si(ship_fmu):
    md, vr, fmu = open_fmu(ship_fmu, "units")
    unit = {v.name: v.unit for v in md.modelVariables}
    assert unit["force.heave"] == "N" and unit["force.pitch"] == "N.m"
    assert unit["force.vb1"] == "N.m"  # a dimensionless mode amplitude carries one metre
    assert unit["added_mass_inf[2,2]"] == "kg" and unit["added_mass_inf[4,4]"] == "kg.m2"
    assert unit["stiffness_hydrostatic[2,2]"] == "N/m" and unit["power"] == "W"
    fmu.exitInitializationMode()
    # The heave restoring of the 100 m x 10 m waterplane, rho g L B.
    (c,) = fmu.getReal([vr["stiffness_hydrostatic[2,2]"]])
    assert c == pytest.approx(RHO * G * 100.0 * 10.0, rel=1e-9)
    fmu.terminate()
    fmu.freeInstance()


@pytest.mark.parametrize("dof", ["heave", "pitch", "vb1"])
def test_harmonic_motion_gives_the_tables_radiation_force(ship_fmu, tables, dof):
    added, inf, _ = tables
    omegas = sorted(added)
    omega = omegas[len(omegas) // 2]  # inside the fitted band
    k = DOFS.index(dof)
    amplitude = 0.2
    md, vr, fmu = open_fmu(ship_fmu, "harmonic")
    fmu.exitInitializationMode()
    steps, periods = 200, 30
    h = 2 * math.pi / omega / steps
    times, forces = [], []
    for n in range(steps * periods):
        t = n * h
        fmu.setReal([vr[f"velocity.{dof}"]], [amplitude * math.sin(omega * (t + h / 2))])
        fmu.doStep(t, h)
        fmu.setReal([vr[f"velocity.{dof}"]], [amplitude * math.sin(omega * (t + h))])
        if n >= steps * (periods - 10):
            times.append(t + h)
            forces.append(fmu.getReal([vr[f"force.{dof}"]])[0])
    fmu.terminate()
    fmu.freeInstance()
    t = np.array(times)
    (c, s), *_ = np.linalg.lstsq(np.column_stack([np.cos(omega * t), np.sin(omega * t)]),
                                 np.array(forces), rcond=None)
    measured = complex(c, -s)
    expected = -1j * omega * (added[omega][k, k] - inf[k, k]) * (-1j * amplitude)
    # The fit's tolerance, 1 % of |A~_kk| at most over the band, times omega |V|, plus 0.5 %
    # for the held input over 200 steps per period.
    largest = max(abs(added[w][k, k]) for w in omegas)
    allowed = 0.01 * largest * omega * amplitude + 5e-3 * abs(expected)
    assert abs(measured - expected) <= allowed, (dof, measured, expected, allowed)


@pytest.mark.parametrize("heading", [45.0, 180.0])
def test_an_oblique_wave_gives_the_tables_exciting_force(ship_fmu, tables, heading):
    added, _, forces = tables
    omega = sorted(added)[60]
    amplitude = 0.5
    md, vr, fmu = open_fmu(ship_fmu, "waves")
    fmu.setInteger([vr["wave.kind"]], [1])
    fmu.setReal([vr["wave.height"], vr["wave.period"], vr["wave.heading"]],
                [2 * amplitude, 2 * math.pi / omega, heading])
    fmu.exitInitializationMode()
    h = 0.05
    names = [f"force_excitation.{d}" for d in DOFS]
    for n in range(1, 101):
        fmu.doStep((n - 1) * h, h)
        t = n * h
        values = fmu.getReal([vr[x] for x in names])
        for j, value in enumerate(values):
            x = forces[(omega, j, heading)]
            expected = (amplitude * x * complex(math.cos(omega * t), math.sin(omega * t))).real
            scale = amplitude * max(abs(forces[(omega, i, heading)]) for i in range(len(DOFS)))
            assert value == pytest.approx(expected, abs=1e-6 * scale), (DOFS[j], t)
    fmu.terminate()
    fmu.freeInstance()


def test_a_heading_the_ship_was_not_swept_for_is_refused_when_set(ship_fmu, capfd):
    md, vr, fmu = open_fmu(ship_fmu, "heading", logging=True)
    capfd.readouterr()
    with pytest.raises(FMICallException):
        fmu.setReal([vr["wave.heading"]], [30.0])
    out = capfd.readouterr().out
    fmu.freeInstance()
    assert "wave.heading = 30 deg" in out and "0, 45, 90, 135, 180" in out.replace(".0", ""), out


def test_a_ship_swept_without_heading_0_takes_its_wave_parameters_in_any_order(fmu_pack_binary, tmp_path):
    """The declared start value of wave.heading is 0; a ship swept for 180 and 90 only must
    still accept wave.kind before wave.heading, and its calm-water state must round-trip."""
    path = tmp_path / "HeadSeas.fmu"
    subprocess.run([str(fmu_pack_binary), "pack", str(SHIP), "--headings", "180,90", "--omega",
                    "0.3:3:40", "-o", str(path)], check=True, capture_output=True)
    md, vr, fmu = open_fmu(path, "order")
    state = fmu.getFMUstate()
    fmu.setFMUstate(state)  # calm water, heading 0: a valid state
    fmu.freeFMUstate(state)
    fmu.setInteger([vr["wave.kind"]], [1])
    fmu.setReal([vr["wave.height"], vr["wave.period"]], [1.0, 6.0])
    fmu.setReal([vr["wave.heading"]], [180.0])
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 0.1)
    (force,) = fmu.getReal([vr["force_excitation.heave"]])
    assert math.isfinite(force) and force != 0.0
    fmu.terminate()
    fmu.freeInstance()
    # Building the sea with a heading the table lacks fails at the end of initialization.
    md, vr, fmu = open_fmu(path, "missing")
    fmu.setInteger([vr["wave.kind"]], [1])
    with pytest.raises(Exception):
        fmu.exitInitializationMode()
    fmu.freeInstance()
