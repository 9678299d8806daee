"""A harmonic velocity gives, after transients, the force the panel method predicts.

The FMUs are packed by the full pipeline (sweep, fit) for the semicircle: sway in the default
band, and heave in the wide band kR 0.01 .. 5 (where its added mass diverges logarithmically). Its force
excludes -A_inf q'', so for v = Re(V e^{i w t}) the steady force is
F = Re(-i w (A~(w) - A_inf) V e^{i w t}), with A~ from `fmu-pack sweep` at the same kR.
"""
import csv
import io
import math
import subprocess

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

RHO, G, RADIUS = 1025.0, 9.81, 1.0
TOLERANCE = 0.01  # the default fit tolerance: 1 % of the largest |A~| in the band


@pytest.fixture(scope="module")
def sway_fmu(fmu_pack_binary, tmp_path_factory):
    path = tmp_path_factory.mktemp("harmonic") / "SwayOnly.fmu"
    subprocess.run(
        [str(fmu_pack_binary), "pack", "semicircle", "--dofs", "sway", "-o", str(path)],
        check=True,
        capture_output=True,
    )
    return path


@pytest.fixture(scope="module")
def wide_heave_fmu(fmu_pack_binary, tmp_path_factory):
    path = tmp_path_factory.mktemp("harmonic") / "HeaveWide.fmu"
    subprocess.run(
        [str(fmu_pack_binary), "pack", "semicircle", "--dofs", "heave", "--band", "0.01:5",
         "-o", str(path)],
        check=True,
        capture_output=True,
    )
    return path


def panel_sweep(fmu_pack_binary, kr_grid, dof="sway"):
    """A~ at the kR of `kr_grid` ("MIN:MAX:COUNT") and A_inf of one semicircle DOF, SI (R = 1 m)."""
    text = subprocess.run(
        [str(fmu_pack_binary), "sweep", "semicircle", "--dofs", dof, "--kr", kr_grid, "-o", "-"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    rows = [r for r in csv.reader(io.StringIO(text)) if r and not r[0].startswith(("#", "kR"))]
    scale = RHO * math.pi * RADIUS**2
    added_mass = [scale * complex(float(r[3]), float(r[4])) for r in rows if r[0] not in ("0", "inf")]
    added_mass_inf = next(float(r[3]) for r in rows if r[0] == "inf")
    return added_mass, scale * added_mass_inf


def panel_method(fmu_pack_binary, kr, dof="sway"):
    """A~(kR) and A_inf of one semicircle DOF in SI units (R = 1 m)."""
    added_mass, added_mass_inf = panel_sweep(fmu_pack_binary, f"{kr}:{kr}:1", dof)
    return added_mass[0], added_mass_inf


def steady_force_phasor(path, omega, amplitude, steps_per_period=400, periods=40, dof="sway"):
    """Drives velocity.<dof> = amplitude sin(omega t); returns the complex force amplitude
    F^ with F = Re(F^ e^{i omega t}), fitted over the last 10 periods."""
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=extract(str(path)),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="harmonic",
    )
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    h = 2 * math.pi / omega / steps_per_period
    times, forces = [], []
    velocity = lambda t: amplitude * math.sin(omega * t)
    for k in range(steps_per_period * periods):
        t = k * h
        # The held input is the mid-step value: second order in h.
        fmu.setReal([vr[f"velocity.{dof}"]], [velocity(t + h / 2)])
        fmu.doStep(t, h)
        # Outputs reflect the current input: read the force with the end-of-step velocity.
        fmu.setReal([vr[f"velocity.{dof}"]], [velocity(t + h)])
        if k >= steps_per_period * (periods - 10):
            times.append(t + h)
            forces.append(fmu.getReal([vr[f"force.{dof}"]])[0])
    fmu.terminate()
    fmu.freeInstance()
    t = np.array(times)
    basis = np.column_stack([np.cos(omega * t), np.sin(omega * t)])
    (c, s), *_ = np.linalg.lstsq(basis, np.array(forces), rcond=None)
    # c cos + s sin = Re((c - i s) e^{i w t})
    return complex(c, -s)


@pytest.mark.parametrize("kr", [0.3, 1.0, 2.5])
def test_harmonic_force_matches_the_panel_method(sway_fmu, fmu_pack_binary, kr):
    omega = math.sqrt(kr * G / RADIUS)
    amplitude = 0.5
    added_mass, added_mass_inf = panel_method(fmu_pack_binary, kr)
    velocity_phasor = -1j * amplitude  # amplitude sin(w t) = Re(-i amplitude e^{i w t})
    expected = -1j * omega * (added_mass - added_mass_inf) * velocity_phasor
    measured = steady_force_phasor(sway_fmu, omega, amplitude)
    # Allowed: the fit tolerance (1 % of the largest |A~| in the band, which for sway is at
    # most A(0) = rho pi R^2 / 2) times omega |V|, plus 0.2 % for the time discretization.
    largest = 0.55 * RHO * math.pi * RADIUS**2
    allowed = TOLERANCE * largest * omega * amplitude + 2e-3 * abs(expected)
    assert abs(measured - expected) <= allowed, (kr, measured, expected, allowed)


@pytest.mark.parametrize("kr", [0.012, 0.05])
def test_wide_band_heave_holds_at_the_bottom_of_the_band(wide_heave_fmu, fmu_pack_binary, kr):
    """Heave over kR 0.01 .. 5: its added mass grows like -ln kR at the bottom of the band,
    the hardest place for a fit. The FMU's force at kR 0.012 and 0.05 within the fit
    tolerance (1 % of the largest |A~| of heave in the band, from a sweep of the band) times
    omega |V|, plus 0.2 % for the time discretization."""
    omega = math.sqrt(kr * G / RADIUS)
    amplitude = 0.5
    added_mass, added_mass_inf = panel_method(fmu_pack_binary, kr, "heave")
    band, _ = panel_sweep(fmu_pack_binary, "0.01:5:60", "heave")
    largest = max(abs(a) for a in band)
    velocity_phasor = -1j * amplitude
    expected = -1j * omega * (added_mass - added_mass_inf) * velocity_phasor
    # 80 periods: the slowest poles (near the bottom of the band) have died out before the
    # last 10 are fitted.
    measured = steady_force_phasor(wide_heave_fmu, omega, amplitude, periods=80, dof="heave")
    allowed = TOLERANCE * largest * omega * amplitude + 2e-3 * abs(expected)
    assert abs(measured - expected) <= allowed, (kr, measured, expected, allowed)
