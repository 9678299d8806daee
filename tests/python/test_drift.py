"""Mean wave drift through the FMU under fmpy: `fmu-pack pack --drift` packs the section's drift
table, the FMU's `force_drift` in a regular wave equals `a^2 D` of the table that
`fmu-pack sweep --drift` writes independently, `force` includes it, `wave.drift = 0` leaves it
out, and an archive packed without `--drift` declares none of it.

The wave's kR is one of the default grid's (the table's row), so the FMU's interpolation in
kR adds nothing but rounding: the tolerance is 1e-9 of the force.
"""
import csv
import io
import math
import pathlib
import subprocess
import zipfile

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

RHO, G, RADIUS = 1025.0, 9.81, 1.0
DOFS = ["sway", "heave", "roll"]
LENGTH_EXPONENT = {"sway": 0, "heave": 0, "roll": 1}
AMPLITUDE = 0.5


@pytest.fixture(scope="module")
def drift_fmu(fmu_pack_binary, tmp_path_factory):
    path = tmp_path_factory.mktemp("drift") / "SemicircleDrift.fmu"
    subprocess.run(
        [str(fmu_pack_binary), "pack", "semicircle", "--dofs", ",".join(DOFS), "--drift",
         "-o", str(path)],
        check=True, capture_output=True,
    )
    return path


def rows(text):
    return [r for r in csv.reader(io.StringIO(text)) if r and not r[0].startswith(("#", "kR"))]


@pytest.fixture(scope="module")
def swept_drift(fmu_pack_binary):
    """The sweep's own drift table (default grid): {(kR text, dof, heading): D_j in SI}."""
    text = subprocess.run(
        [str(fmu_pack_binary), "sweep", "semicircle", "--dofs", ",".join(DOFS),
         "-o", "/dev/null", "--drift", "-"],
        check=True, capture_output=True, text=True,
    ).stdout
    table = {}
    for kr, j, heading, value in rows(text):
        dof = DOFS[int(j) - 1]
        scale = RHO * G * RADIUS ** LENGTH_EXPONENT[dof]
        table[(kr, dof, float(heading))] = float(value) * scale
    return table


def start(path, kr, heading, drift):
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="drift")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.setReal([vr["rho"], vr["g"]], [RHO, G])
    fmu.setInteger([vr["wave.kind"]], [1])
    period = 2 * math.pi / math.sqrt(kr * G / RADIUS)
    fmu.setReal([vr["wave.height"], vr["wave.period"], vr["wave.heading"]],
                [2 * AMPLITUDE, period, heading])
    fmu.setInteger([vr["wave.drift"]], [drift])
    fmu.exitInitializationMode()
    return fmu, vr


def test_the_archive_carries_the_sweeps_drift_table(drift_fmu, swept_drift):
    with zipfile.ZipFile(drift_fmu) as z:
        packed = rows(z.read("resources/drift.csv").decode())
    assert len(packed) == len(swept_drift) == 201 * 2 * 3
    for kr, j, heading, value in packed:
        dof = DOFS[int(j) - 1]
        expected = swept_drift[(kr, dof, float(heading))]
        scale = RHO * G * RADIUS ** LENGTH_EXPONENT[dof]
        assert float(value) * scale == pytest.approx(expected, rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("heading", [0.0, 180.0])
@pytest.mark.parametrize("drift", [1, 2])
def test_a_regular_wave_gives_a_squared_times_the_tables_drift(drift_fmu, swept_drift, heading, drift):
    # Row 100 of the default grid: kR = 10^-0.5 (a wave 20 R long).
    grid = sorted({k for k, _, _ in swept_drift}, key=float)
    kr_text = grid[100]
    fmu, vr = start(drift_fmu, float(kr_text), heading, drift)
    names = ([f"force_drift.{d}" for d in DOFS] + [f"force.{d}" for d in DOFS]
             + [f"force_radiation.{d}" for d in DOFS] + [f"force_excitation.{d}" for d in DOFS])
    refs = [vr[n] for n in names]
    h = 0.05
    for n in range(40):
        fmu.doStep(currentCommunicationPoint=n * h, communicationStepSize=h)
        values = dict(zip(names, fmu.getReal(refs)))
        for dof in DOFS:
            expected = AMPLITUDE ** 2 * swept_drift[(kr_text, dof, heading)]
            scale = max(abs(expected), 1e-3 * RHO * G * AMPLITUDE ** 2)
            assert abs(values[f"force_drift.{dof}"] - expected) <= 1e-9 * scale, (dof, n)
            total = (values[f"force_radiation.{dof}"] + values[f"force_excitation.{dof}"]
                     + values[f"force_drift.{dof}"])
            assert values[f"force.{dof}"] == pytest.approx(total, rel=1e-12, abs=1e-9)
    # Waves towards +x push the section towards +x (heading 180: towards -x).
    sway = AMPLITUDE ** 2 * swept_drift[(kr_text, "sway", heading)]
    assert (sway > 0) == (heading == 0.0)
    fmu.terminate()
    fmu.freeInstance()


def test_wave_drift_zero_leaves_the_drift_out(drift_fmu, swept_drift):
    grid = sorted({k for k, _, _ in swept_drift}, key=float)
    fmu, vr = start(drift_fmu, float(grid[100]), 0.0, 0)
    names = [f"force_drift.{d}" for d in DOFS] + [f"force.{d}" for d in DOFS] + [
        f"force_radiation.{d}" for d in DOFS] + [f"force_excitation.{d}" for d in DOFS]
    for n in range(10):
        fmu.doStep(currentCommunicationPoint=n * 0.05, communicationStepSize=0.05)
        values = dict(zip(names, fmu.getReal([vr[x] for x in names])))
        for dof in DOFS:
            assert values[f"force_drift.{dof}"] == 0.0
            assert values[f"force.{dof}"] == (values[f"force_radiation.{dof}"]
                                               + values[f"force_excitation.{dof}"])
    fmu.terminate()
    fmu.freeInstance()


def test_an_archive_packed_without_drift_declares_none(fmu_pack_binary, tmp_path):
    path = tmp_path / "Plain.fmu"
    subprocess.run([str(fmu_pack_binary), "pack", "semicircle", "--dofs", "heave",
                    "-o", str(path)], check=True, capture_output=True)
    names = {v.name for v in read_model_description(str(path)).modelVariables}
    assert "wave.drift" not in names and not any(n.startswith("force_drift.") for n in names)
    with zipfile.ZipFile(path) as z:
        assert "resources/drift.csv" not in z.namelist()
    # A network file has no sweep and so no drift table: refused, saying so.
    result = subprocess.run(
        [str(fmu_pack_binary), "pack", "semicircle", "--dofs", "sway,heave", "--drift",
         "--network", "examples/networks/two-dof-sway-heave.xml", "-o", str(tmp_path / "N.fmu")],
        capture_output=True, text=True, cwd=str(pathlib.Path(__file__).resolve().parents[2]),
    )
    assert result.returncode != 0 and "a network packed from a file has no sweep" in result.stderr
