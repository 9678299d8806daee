"""Viscous damping and current through the FMU under fmpy (`fmu-pack pack --viscous`,
docs/CURRENT.md): a current alone gives the drag formula's force exactly; a heave decay of a
mass-spring master coupled to the FMU's force gives back, from its peaks, the linear and
quadratic damping the FMU was packed with; in waves and a current the force is the sum of its
parts at every step.
"""
import math
import subprocess

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from conftest import NETWORKS

RHO, G = 1025.0, 9.81
B_LINEAR = {"sway": 300.0, "heave": 800.0}
B_QUADRATIC = {"sway": 1500.0, "heave": 2000.0}


def pack(fmu_pack_binary, path, extra, damping=True):
    args = [str(fmu_pack_binary), "pack", "semicircle", "--dofs", "sway,heave", "-o", str(path)]
    if damping:
        args += [
            "--viscous",
            "--damping-linear", ",".join(f"{d}={b}" for d, b in B_LINEAR.items()),
            "--damping-quadratic", ",".join(f"{d}={b}" for d, b in B_QUADRATIC.items()),
        ]
    subprocess.run(args + extra, check=True, capture_output=True)
    return path


@pytest.fixture(scope="module")
def calm_fmu(fmu_pack_binary, tmp_path_factory):
    network = ["--network", str(NETWORKS / "two-dof-sway-heave.xml")]
    out = tmp_path_factory.mktemp("viscous")
    return (pack(fmu_pack_binary, out / "Viscous.fmu", network),
            pack(fmu_pack_binary, out / "Plain.fmu", network, damping=False))


@pytest.fixture(scope="module")
def wave_fmu(fmu_pack_binary, tmp_path_factory):
    sweep = ["--panels", "16", "--kr", "0.05:5:12"]
    return pack(fmu_pack_binary, tmp_path_factory.mktemp("viscous") / "Waves.fmu", sweep)


def start(path, parameters=None, integers=None):
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="viscous")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    values = {"rho": RHO, "g": G, **(parameters or {})}
    fmu.setReal([vr[k] for k in values], list(values.values()))
    if integers:
        fmu.setInteger([vr[k] for k in integers], list(integers.values()))
    fmu.exitInitializationMode()
    return fmu, vr, md


def test_the_description_declares_the_variables_and_their_start_values(calm_fmu):
    viscous, plain = calm_fmu
    md = read_model_description(str(viscous))
    by_name = {v.name: v for v in md.modelVariables}
    assert float(by_name["damping_linear[2,2]"].start) == B_LINEAR["heave"]
    assert float(by_name["damping_quadratic[1]"].start) == B_QUADRATIC["sway"]
    assert by_name["current.speed"].causality == "input"
    assert by_name["force_viscous.heave"].causality == "output"
    names = {v.name for v in read_model_description(str(plain)).modelVariables}
    assert not any(n.startswith(("current.", "force_viscous", "damping_linear")) for n in names)


@pytest.mark.parametrize("heading", [0.0, 60.0, 180.0])
def test_a_current_alone_gives_the_drag_formula(calm_fmu, heading):
    fmu, vr, _ = start(calm_fmu[0])
    speed = 0.8
    fmu.setReal([vr["current.speed"], vr["current.heading"]], [speed, heading])
    names = ["force.sway", "force.heave", "force_viscous.sway", "force_viscous.heave",
             "force_radiation.sway"]
    relative = -speed * math.cos(math.radians(heading))
    expected = -B_LINEAR["sway"] * relative - B_QUADRATIC["sway"] * abs(relative) * relative
    forces = []
    for n in range(50):
        fmu.doStep(currentCommunicationPoint=n * 0.1, communicationStepSize=0.1)
        values = dict(zip(names, fmu.getReal([vr[k] for k in names])))
        # The hull at rest: no radiation, the heave sees no current.
        assert values["force_radiation.sway"] == 0.0
        assert values["force_viscous.heave"] == 0.0
        assert values["force_viscous.sway"] == pytest.approx(expected, rel=1e-14)
        assert values["force.sway"] == values["force_viscous.sway"]
        forces.append(values["force.sway"])
    assert np.mean(forces) == pytest.approx(expected, rel=1e-14)
    fmu.terminate()
    fmu.freeInstance()


def decay(path, mass, stiffness, amplitude, h, steps):
    """A heave decay: the master integrates (mass + A_inf) x'' + k x = force.heave
    (semi-implicit Euler), the FMU gets the heave velocity. Returns the heave history."""
    fmu, vr, _ = start(path)
    a_inf = fmu.getReal([vr["added_mass_inf[2,2]"]])[0]
    m = mass + a_inf
    x, v = amplitude, 0.0
    history = [x]
    force_ref = [vr["force.heave"]]
    for n in range(steps):
        fmu.setReal([vr["velocity.heave"]], [v])
        fmu.doStep(currentCommunicationPoint=n * h, communicationStepSize=h)
        force = fmu.getReal(force_ref)[0]
        v += h * (-stiffness * x + force) / m
        x += h * v
        history.append(x)
    fmu.terminate()
    fmu.freeInstance()
    return np.array(history), m


def decrement_fit(history, omega, m):
    """Peaks of |x| (every half cycle); the fit dphi = a phi + b phi^2 per half cycle, turned
    into (B_1, B_2) by a = pi B_1 / (2 m omega), b = 4 B_2 / (3 m)."""
    peaks = []
    for k in range(1, len(history) - 1):
        if abs(history[k]) >= abs(history[k - 1]) and abs(history[k]) > abs(history[k + 1]):
            # Parabola through the three points around the discrete peak.
            y0, y1, y2 = abs(history[k - 1]), abs(history[k]), abs(history[k + 1])
            peaks.append(y1 + 0.125 * (y0 - y2) ** 2 / (2 * y1 - y0 - y2))
    peaks = np.array(peaks)
    dphi = peaks[:-1] - peaks[1:]
    phi = 0.5 * (peaks[:-1] + peaks[1:])
    design = np.vstack([phi, phi ** 2]).T
    (a, b), *_ = np.linalg.lstsq(design, dphi, rcond=None)
    return 2 * m * omega * a / math.pi, 3 * m * b / 4, len(peaks)


def test_a_heave_decay_gives_back_the_packed_damping(calm_fmu):
    viscous, plain = calm_fmu
    # Light damping (a few % of the amplitude per half cycle): the decrement formula's
    # equivalent linearization holds; a large start amplitude separates a and b.
    mass, omega, h, amplitude = 100000.0, 1.0, 0.004, 2.0
    steps = int(150.0 / h)
    results = []
    for path in (plain, viscous):
        fmu, vr, _ = start(path)
        a_inf = fmu.getReal([vr["added_mass_inf[2,2]"]])[0]
        fmu.terminate()
        fmu.freeInstance()
        stiffness = (mass + a_inf) * omega ** 2
        history, m = decay(path, mass, stiffness, amplitude, h, steps)
        results.append(decrement_fit(history, omega, m))
    (linear0, quadratic0, _), (linear1, quadratic1, peaks) = results
    # The radiation damping is the same in both runs: the difference is the viscous part.
    linear, quadratic = linear1 - linear0, quadratic1 - quadratic0
    print(f"decay fit: B_l {linear:.2f} (packed {B_LINEAR['heave']}), B_q {quadratic:.2f} "
          f"(packed {B_QUADRATIC['heave']}), radiation-only fit {linear0:.2f}, "
          f"{quadratic0:.3f}, {peaks} peaks")
    assert abs(quadratic0) < 0.03 * B_QUADRATIC["heave"]
    assert linear == pytest.approx(B_LINEAR["heave"], rel=0.03)
    assert quadratic == pytest.approx(B_QUADRATIC["heave"], rel=0.03)


def test_in_waves_and_a_current_the_force_is_the_sum_of_its_parts(wave_fmu):
    fmu, vr, _ = start(wave_fmu, {"wave.height": 1.0, "wave.period": 4.0}, {"wave.kind": 1})
    fmu.setReal([vr["current.speed"], vr["current.heading"]], [0.5, 30.0])
    parts = ["force_radiation", "force_excitation", "force_viscous"]
    names = [f"{p}.{d}" for d in ("sway", "heave") for p in ["force", *parts]]
    h = 0.05
    viscous_seen = 0.0
    for n in range(200):
        t = n * h
        fmu.setReal([vr["velocity.sway"], vr["velocity.heave"]],
                    [0.3 * math.sin(0.8 * t), 0.2 * math.cos(1.1 * t)])
        fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        values = dict(zip(names, fmu.getReal([vr[k] for k in names])))
        for d in ("sway", "heave"):
            total = (values[f"force_radiation.{d}"] + values[f"force_excitation.{d}"]
                     + values[f"force_viscous.{d}"])
            assert values[f"force.{d}"] == total
        viscous_seen = max(viscous_seen, abs(values["force_viscous.sway"]))
        assert values["force_excitation.heave"] != 0.0 or n == 0
    assert viscous_seen > 100.0
    fmu.terminate()
    fmu.freeInstance()


def test_bad_values_are_refused_naming_them(calm_fmu):
    md = read_model_description(str(calm_fmu[0]))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    cases = [("damping_quadratic[2]", -1.0), ("damping_linear[1,1]", math.nan)]
    for name, value in cases:
        fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(calm_fmu[0])),
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bad")
        fmu.instantiate()
        fmu.enterInitializationMode()
        with pytest.raises(Exception):
            fmu.setReal([vr[name]], [value])
        fmu.freeInstance()
    fmu, vr, _ = start(calm_fmu[0])
    with pytest.raises(Exception):
        fmu.setReal([vr["current.speed"]], [math.inf])
    fmu.freeInstance()


# A ship whose stern is deeper than its bow (drafts 6 m aft to 3 m forward): its lateral area
# lies aft of the origin, so a current across it turns it (docs/CURRENT.md, "A ship's
# cross-flow strips").
WEDGE_SHIP = """<ship name="wedge" units="m" version="1">
{stations}  <rigid dofs="sway yaw"/>
</ship>
""".format(stations="".join(
    f'  <station x="{x}"><lewis breadth="10" draft="{draft}" area_coefficient="0.9"/></station>\n'
    for x, draft in zip(range(-30, 31, 10), [6.0, 5.5, 5.0, 4.5, 4.0, 3.5, 3.0])))


@pytest.fixture(scope="module")
def ship_fmu(fmu_pack_binary, tmp_path_factory):
    folder = tmp_path_factory.mktemp("crossflow")
    ship = folder / "wedge.xml"
    ship.write_text(WEDGE_SHIP)
    path = folder / "Wedge.fmu"
    subprocess.run([str(fmu_pack_binary), "pack", str(ship), "--omega", "0.2:2:8", "--panels", "16",
                    "--allow-tolerance-miss", "--viscous", "-o", str(path)],
                   check=True, capture_output=True)
    return path


def strips_of(path):
    """(x, c_y = 0.5 C_D T w) of every strip in the archive's resources/crossflow.csv."""
    import zipfile
    with zipfile.ZipFile(path) as archive:
        text = archive.read("resources/crossflow.csv").decode()
    rows = [line.split(",") for line in text.splitlines() if line and not line.startswith("#")]
    assert rows[0] == ["x", "weight", "draft", "breadth", "cd_sway", "cd_heave"]
    return [(float(r[0]), 0.5 * float(r[4]) * float(r[2]) * float(r[1])) for r in rows[1:]]


@pytest.mark.parametrize("heading", [90.0, 240.0, 0.0])
def test_a_current_across_a_ship_gives_the_strips_sway_force_and_yaw_moment(ship_fmu, heading):
    strips = strips_of(ship_fmu)
    assert len(strips) == 7
    fmu, vr, md = start(ship_fmu)
    by_name = {v.name: v for v in md.modelVariables}
    # The strips carry the drag: the per-DOF quadratic coefficients are packed 0.
    assert float(by_name["damping_quadratic[1]"].start) == 0.0
    assert float(by_name["damping_quadratic[2]"].start) == 0.0
    assert float(by_name["crossflow.drag_scale"].start) == 1.0
    speed = 1.2
    fmu.setReal([vr["current.speed"], vr["current.heading"]], [speed, heading])
    across = speed * math.sin(math.radians(heading))
    force = RHO * sum(c for _, c in strips) * abs(across) * across
    moment = RHO * sum(x * c for x, c in strips) * abs(across) * across
    names = ["force_viscous.sway", "force_viscous.yaw", "force.sway", "force.yaw"]
    for n in range(5):
        fmu.doStep(currentCommunicationPoint=n * 0.1, communicationStepSize=0.1)
        values = dict(zip(names, fmu.getReal([vr[k] for k in names])))
        if heading == 0.0:
            # A head current: no cross flow, no force, no moment.
            assert values["force_viscous.sway"] == 0.0 and values["force_viscous.yaw"] == 0.0
            continue
        # Sums of seven strips: rounding of 1e-15 relative.
        assert values["force_viscous.sway"] == pytest.approx(force, rel=1e-12)
        assert values["force_viscous.yaw"] == pytest.approx(moment, rel=1e-12)
        # The hull at rest in calm water: the force is the viscous force alone.
        assert values["force.yaw"] == values["force_viscous.yaw"]
    if heading != 0.0:
        # The deeper stern: the drag's centre lies aft, about 3.5 m behind the origin.
        assert moment / force < -1.5
    fmu.terminate()
    fmu.freeInstance()


def test_the_drag_scale_switches_the_strips_off(ship_fmu):
    fmu, vr, _ = start(ship_fmu, parameters={"crossflow.drag_scale": 0.0})
    fmu.setReal([vr["current.speed"], vr["current.heading"]], [1.2, 90.0])
    fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.1)
    assert fmu.getReal([vr["force_viscous.sway"], vr["force_viscous.yaw"]]) == [0.0, 0.0]
    fmu.terminate()
    fmu.freeInstance()
