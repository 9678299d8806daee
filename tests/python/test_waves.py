"""Waves through the FMU: regular waves from both headings against an independent
frequency-domain table (fmpy and libcosim), JONSWAP statistics against the spectrum, seed
reproducibility, FMU state save/restore in a sea, calm water unchanged, the hydrostatic
stiffness, and the errors.

The FMU is packed by the full pipeline for the semicircle's rigid DOFs. The exciting force
per unit wave amplitude comes from a separate `fmu-pack sweep --excitation` at exactly the
wave's kR, so the FMU's interpolation in its own table is part of what is tested.
"""
import csv
import io
import math
import subprocess
import zipfile

import numpy as np
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
        # Order-1 output derivatives: the harmonic's, d/dt Re[a X e^(i omega t)].
        rates = fmu.getRealOutputDerivatives([vr["wave.elevation"], vr["force_excitation.heave"]], [1, 1])
        assert rates[0] == pytest.approx(-amplitude * omega * math.sin(omega * t), abs=1e-12)
        expected = (1j * omega * amplitude * table[("heave", heading)] * complex(math.cos(omega * t), math.sin(omega * t))).real
        assert rates[1] == pytest.approx(expected, abs=1e-5 * omega * scale)
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


# --------------------------------------------------------------------------- irregular seas


def jonswap(omega, hs, tp, gamma):
    """DNV-RP-C205 JONSWAP spectral density (docs/WAVES.md), m^2 s."""
    wp = 2 * math.pi / tp
    sigma = np.where(omega <= wp, 0.07, 0.09)
    shape = np.exp(-((omega - wp) ** 2) / (2 * sigma**2 * wp**2))
    return (
        (1 - 0.287 * math.log(gamma)) * 5 / 16 * hs**2 * wp**4 * omega**-5
        * np.exp(-1.25 * (omega / wp) ** -4) * gamma**shape
    )


def archive_excitation(path):
    """The FMU's own table (resources/excitation.csv) in SI: kR grid and {(dof, heading): X(kR)}."""
    with zipfile.ZipFile(path) as archive:
        text = archive.read("resources/excitation.csv").decode()
    rows = [r for r in csv.reader(io.StringIO(text)) if r and not r[0].startswith(("#", "kR"))]
    values = {}
    for k, j, heading, re, im in rows:
        if float(k) > 0:
            dof = DOFS[int(j) - 1]
            scale = RHO * G * RADIUS ** (1 + LENGTH_EXPONENT[dof])
            values.setdefault((dof, float(heading)), []).append((float(k), complex(float(re), float(im)) * scale))
    grid = np.array([k for k, _ in sorted(values[("heave", 0.0)])])
    return grid, {key: np.array([x for _, x in sorted(v)]) for key, v in values.items()}


def record(fmu, vr, names, h, steps, velocity=None):
    """Outputs `names` after each of `steps` steps of h (times n h from 0); `velocity(t)` sets
    velocity.<dof> inputs before each step when given."""
    out = np.empty((steps, len(names)))
    refs = [vr[n] for n in names]
    for n in range(steps):
        if velocity is not None:
            fmu.setReal([vr[f"velocity.{d}"] for d in DOFS], velocity(n * h))
        fmu.doStep(n * h, h)
        out[n] = fmu.getReal(refs)
    return out


def test_a_jonswap_sea_has_the_spectrums_variance_in_elevation_and_force(rigid_fmu):
    """Time averages of a long record against the spectrum: elevation variance m0 and force
    variance int |X_j|^2 S dw over the sea's range [0.5, 6] wp.

    Tolerance 1.5 %: a record of length T of a Gaussian sea has a variance that scatters about
    m0 by (2 pi int S^2 dw / T)^(1/2) / m0 = 1.1 % rms here (T = 1.05e5 s). The FMU's sea has
    deterministic amplitudes (docs/WAVES.md), so it scatters less: its sum a_n^2 / 2 is within
    0.07 % rms of m0 at 400 components, and the rest is the cross terms of neighbouring
    components whose beat period exceeds the record. Measured over seeds 11..15: -0.62 % to
    +0.10 % for the elevation, -0.66 % to +0.12 % for the forces."""
    hs, tp, gamma, components = 2.0, 8.0, 3.3, 400
    fmu, vr = start(rigid_fmu, kind=2, height=hs, period=tp, gamma=gamma, seed=11, components=components)
    names = ["wave.elevation", "force_excitation.sway", "force_excitation.heave"]
    h, steps = 0.7, 150000
    values = record(fmu, vr, names, h, steps)
    fmu.terminate()
    fmu.freeInstance()

    wp = 2 * math.pi / tp
    omega = np.linspace(0.5 * wp, 6 * wp, 200001)
    spectrum = jonswap(omega, hs, tp, gamma)
    m0 = np.trapezoid(spectrum, omega)
    grid, table = archive_excitation(rigid_fmu)
    kr = omega**2 * RADIUS / G
    measured = np.mean(values**2, axis=0)
    assert abs(np.mean(values[:, 0])) < 0.01 * math.sqrt(m0)
    assert measured[0] == pytest.approx(m0, rel=0.015)
    for column, dof in ((1, "sway"), (2, "heave")):
        x = table[(dof, 0.0)]
        x2 = np.interp(np.log(kr), np.log(grid), np.abs(x) ** 2)
        expected = np.trapezoid(x2 * spectrum, omega)
        assert measured[column] == pytest.approx(expected, rel=0.015), dof


def test_the_same_seed_gives_the_same_sea_and_another_seed_another(rigid_fmu):
    names = ["wave.elevation", "force_excitation.sway", "force_excitation.heave"]
    runs = {}
    for key, seed in (("a", 5), ("b", 5), ("c", 6)):
        fmu, vr = start(rigid_fmu, kind=2, height=2.0, period=8.0, seed=seed)
        runs[key] = record(fmu, vr, names, 0.1, 600)
        fmu.terminate()
        fmu.freeInstance()
    assert np.array_equal(runs["a"], runs["b"])  # bit for bit
    spread = np.std(runs["a"], axis=0)
    assert np.all(np.max(np.abs(runs["a"] - runs["c"]), axis=0) > 0.5 * spread)


def test_fmu_state_save_and_restore_in_a_sea(rigid_fmu):
    """A state saved in a JONSWAP sea, while the hull moves, replays the same record: restored
    in the same instance, and deserialized into a fresh instance left in calm water (the wave
    parameters and the start time travel with the state). Tolerance: the phasor recurrence
    against its resynchronization after the restore, 6.7e-13 of the largest force (docs/WAVES.md)."""
    names = ["wave.elevation"] + [f"force_excitation.{d}" for d in DOFS] + [f"force.{d}" for d in DOFS]
    h = 0.05

    def velocity(t):
        return [0.1 * math.sin(0.9 * t), 0.2 * math.cos(1.3 * t), 0.05 * math.sin(2.1 * t)]

    fmu, vr = start(rigid_fmu, kind=2, height=3.0, period=7.0, seed=3, ramp=5.0)
    record(fmu, vr, names, h, 100, velocity)
    state = fmu.getFMUState()
    blob = fmu.serializeFMUState(state)
    refs = [vr[n] for n in names]

    def replay(slave):
        out = np.empty((200, len(names)))
        for n in range(100, 300):
            slave.setReal([vr[f"velocity.{d}"] for d in DOFS], velocity(n * h))
            slave.doStep(n * h, h)
            out[n - 100] = slave.getReal(refs)
        return out

    original = replay(fmu)
    fmu.setFMUState(state)
    again = replay(fmu)
    fmu.freeFMUState(state)
    fmu.terminate()
    fmu.freeInstance()

    fresh, _ = start(rigid_fmu)  # calm water
    restored = fresh.deserializeFMUState(blob)
    fresh.setFMUState(restored)
    elsewhere = replay(fresh)
    fresh.freeFMUState(restored)
    fresh.terminate()
    fresh.freeInstance()

    scale = np.max(np.abs(original), axis=0)
    # A real sea and a moving hull (sway and heave; the water puts no roll moment on a
    # semicircle about its centre: every normal passes through it).
    assert np.all(scale[[0, 1, 2, 4, 5]] > 0.1)
    assert np.all(np.abs(again - original) <= 1e-11 * scale + 1e-300)
    assert np.all(np.abs(elsewhere - original) <= 1e-11 * scale + 1e-300)


@pytest.mark.parametrize("heading", [0.0, 180.0])
def test_libcosim_runs_a_regular_wave_with_the_tables_force(rigid_fmu, fmu_pack_binary, heading):
    """libcosim sets the wave parameters as initial values (Integer kind, Real height, period,
    heading) and steps on its nanosecond clock: the same force as the table, as under fmpy."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.WARNING)
    kr, amplitude = 0.8, 0.4
    omega = math.sqrt(kr * G / RADIUS)
    h_ns = 20_000_000  # 0.02 s
    table = excitation_at(fmu_pack_binary, kr)
    md = read_model_description(str(rigid_fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    execution = CosimExecution.from_step_size(step_size=h_ns)
    slave = execution.add_local_slave(CosimLocalSlave(fmu_path=str(rigid_fmu), instance_name="hull"))
    execution.real_initial_value(slave, vr["rho"], RHO)
    execution.real_initial_value(slave, vr["g"], G)
    execution.integer_initial_value(slave, vr["wave.kind"], 1)
    execution.real_initial_value(slave, vr["wave.height"], 2 * amplitude)
    execution.real_initial_value(slave, vr["wave.period"], 2 * math.pi / omega)
    execution.real_initial_value(slave, vr["wave.heading"], heading)
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    names = ["wave.elevation"] + [f"force_excitation.{d}" for d in DOFS]
    scale = amplitude * abs(table[("heave", heading)])
    for n in range(1, 201):
        assert execution.step()
        t = n * h_ns * 1e-9
        values = observer.last_real_values(slave, [vr[x] for x in names])
        assert values[0] == pytest.approx(amplitude * math.cos(omega * t), abs=1e-12)
        for d, x in zip(DOFS, values[1:]):
            expected = (amplitude * table[(d, heading)] * complex(math.cos(omega * t), math.sin(omega * t))).real
            assert x == pytest.approx(expected, abs=1e-5 * scale), d
    (kind,) = observer.last_integer_values(slave, [vr["wave.kind"]])
    assert kind == 1
    execution.stop()
