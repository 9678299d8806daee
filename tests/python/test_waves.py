"""Waves through the FMU: regular waves from both headings against an independent
frequency-domain table, calm water unchanged, the hydrostatic stiffness, and the errors.

The FMU is packed by the full pipeline for the semicircle's rigid DOFs. The exciting force
per unit wave amplitude comes from a separate `fmu-pack sweep --excitation` at exactly the
wave's kR, so the FMU's interpolation in its own table is part of what is tested.
"""
import csv
import io
import math
import subprocess

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

RHO, G, RADIUS = 1025.0, 9.81, 1.0
DOFS = ["sway", "heave", "roll"]
LENGTH_EXPONENT = {"sway": 0, "heave": 0, "roll": 1}


@pytest.fixture(scope="module")
def rigid_fmu(fmu_pack_binary, tmp_path_factory):
    path = tmp_path_factory.mktemp("waves") / "SemicircleRigid.fmu"
    subprocess.run(
        [str(fmu_pack_binary), "pack", "semicircle", "--dofs", ",".join(DOFS), "-o", str(path)],
        check=True,
        capture_output=True,
    )
    return path


def excitation_at(fmu_pack_binary, kr):
    """X_j per unit wave amplitude in SI at `kr`: {(dof, heading): complex}."""
    text = subprocess.run(
        [str(fmu_pack_binary), "sweep", "semicircle", "--dofs", ",".join(DOFS),
         "--kr", f"{kr}:{kr}:1", "-o", "/dev/null", "--excitation", "-"],
        check=True, capture_output=True, text=True,
    ).stdout
    rows = [r for r in csv.reader(io.StringIO(text)) if r and not r[0].startswith(("#", "kR"))]
    table = {}
    for k, j, heading, re, im in rows:
        if k == "0":
            continue
        dof = DOFS[int(j) - 1]
        scale = RHO * G * RADIUS ** (1 + LENGTH_EXPONENT[dof])
        table[(dof, float(heading))] = complex(float(re), float(im)) * scale
    return table


def start(path, **wave):
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="waves")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.setReal([vr["rho"], vr["g"]], [RHO, G])
    for name, value in wave.items():
        if name in ("kind", "seed", "components"):
            fmu.setInteger([vr[f"wave.{name}"]], [int(value)])
        else:
            fmu.setReal([vr[f"wave.{name}"]], [float(value)])
    fmu.exitInitializationMode()
    return fmu, vr


@pytest.mark.parametrize("heading", [0.0, 180.0])
def test_a_regular_wave_gives_the_tables_force_in_amplitude_and_phase(rigid_fmu, fmu_pack_binary, heading):
    kr, amplitude = 0.5, 0.75
    omega = math.sqrt(kr * G / RADIUS)
    period = 2 * math.pi / omega
    table = excitation_at(fmu_pack_binary, kr)
    fmu, vr = start(rigid_fmu, kind=1, height=2 * amplitude, period=period, heading=heading)
    names = [f"force_excitation.{d}" for d in DOFS] + [f"force_radiation.{d}" for d in DOFS]
    names += [f"force.{d}" for d in DOFS] + ["wave.elevation"]
    h, t = period / 100, 0.0
    scale = amplitude * abs(table[("heave", heading)])
    for _ in range(250):
        fmu.doStep(t, h)
        t += h
        values = fmu.getReal([vr[n] for n in names])
        excitation, radiation, total, eta = values[:3], values[3:6], values[6:9], values[9]
        assert eta == pytest.approx(amplitude * math.cos(omega * t), abs=1e-12)
        for d, x, r, f in zip(DOFS, excitation, radiation, total):
            expected = (amplitude * table[(d, heading)] * complex(math.cos(omega * t), math.sin(omega * t))).real
            # The FMU interpolates its 201-point table (about 1e-7 of the force) in SI units
            # (roll: N m/m with R = 1 m): 1e-5 of the heave force amplitude.
            assert x == pytest.approx(expected, abs=1e-5 * scale), d
            assert r == 0.0  # the hull is at rest
            assert f == x + r
    fmu.terminate()
    fmu.freeInstance()


def test_calm_water_is_the_default_and_the_hydrostatics_are_exposed(rigid_fmu):
    fmu, vr = start(rigid_fmu)
    (kind,) = fmu.getInteger([vr["wave.kind"]])
    assert kind == 0
    fmu.setReal([vr["velocity.heave"]], [0.2])
    fmu.doStep(0.0, 0.1)
    excitation = fmu.getReal([vr[f"force_excitation.{d}"] for d in DOFS] + [vr["wave.elevation"]])
    assert excitation == [0.0] * 4
    force = fmu.getReal([vr["force.heave"], vr["force_radiation.heave"]])
    assert force[0] == force[1] != 0.0
    # rho g B for heave (B = 2R); sway and the buoyancy part of roll about the origin vanish.
    stiffness = fmu.getReal([vr[f"stiffness_hydrostatic[{i},{j}]"] for i in (1, 2, 3) for j in (1, 2, 3)])
    assert stiffness[4] == pytest.approx(RHO * G * 2 * RADIUS, rel=1e-12)
    assert all(abs(c) < 1e-9 * stiffness[4] for k, c in enumerate(stiffness) if k != 4)
    fmu.terminate()
    fmu.freeInstance()


def test_bad_wave_parameters_are_refused_with_their_name(rigid_fmu, capfd):
    from fmpy.fmi1 import FMICallException

    md = read_model_description(str(rigid_fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipped = extract(str(rigid_fmu))
    for name, call in (
        ("wave.kind", lambda f: f.setInteger([vr["wave.kind"]], [7])),
        ("wave.height", lambda f: f.setReal([vr["wave.height"]], [-1.0])),
        ("wave.heading", lambda f: f.setReal([vr["wave.heading"]], [90.0])),
        ("wave.period", lambda f: f.setReal([vr["wave.period"]], [float("nan")])),
        ("wave.kind", lambda f: f.setReal([vr["wave.kind"]], [1.0])),
    ):
        fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bad")
        fmu.instantiate(loggingOn=True)
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        capfd.readouterr()
        with pytest.raises(FMICallException):
            call(fmu)
        assert name in capfd.readouterr().out, name
        fmu.freeInstance()
