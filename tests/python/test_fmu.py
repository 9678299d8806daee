"""hydrofmu FMUs under real masters: fmpy (high and low level) and libcosimpy."""
import ctypes
import math
import pathlib
import re
import subprocess
import sys
import threading

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.validation import validate_fmu

# Schilder et al.'s network (after eq. 19), at rho = g = 1.
M0, M1, M2, C1 = 0.1153, 0.5434, 0.1877, 0.9962

FMI2_FUNCTIONS = """
fmi2GetTypesPlatform fmi2GetVersion fmi2SetDebugLogging fmi2Instantiate fmi2FreeInstance
fmi2SetupExperiment fmi2EnterInitializationMode fmi2ExitInitializationMode fmi2Terminate
fmi2Reset fmi2GetReal fmi2GetInteger fmi2GetBoolean fmi2GetString fmi2SetReal fmi2SetInteger
fmi2SetBoolean fmi2SetString fmi2GetFMUstate fmi2SetFMUstate fmi2FreeFMUstate
fmi2SerializedFMUstateSize fmi2SerializeFMUstate fmi2DeSerializeFMUstate
fmi2GetDirectionalDerivative fmi2SetRealInputDerivatives fmi2GetRealOutputDerivatives
fmi2DoStep fmi2CancelStep fmi2GetStatus fmi2GetRealStatus fmi2GetIntegerStatus
fmi2GetBooleanStatus fmi2GetStringStatus
""".split()


class Slave:
    """An initialized FMU2Slave with variables by name."""

    def __init__(self, path, name="hull", rho=1.0, g=1.0, unzipped=None, start=True):
        self.md = read_model_description(str(path))
        self.unzipped = unzipped or extract(str(path))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.unzipped,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate(loggingOn=False)
        if start:
            self.start(rho, g)

    def start(self, rho=1.0, g=1.0):
        self.set(rho=rho, g=g)
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def set(self, **values):
        names = [k.replace("__", ".") for k in values]
        self.fmu.setReal([self.vr[n] for n in names], list(values.values()))

    def get(self, *names):
        return self.fmu.getReal([self.vr[n] for n in names])

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


def test_archives_validate_and_export_all_34_functions(fmus):
    for name, path in fmus.items():
        assert validate_fmu(str(path)) == [], name
        md = read_model_description(str(path))
        unzipped = pathlib.Path(extract(str(path)))
        library = ctypes.CDLL(
            str(unzipped / "binaries" / "linux64" / f"{md.coSimulation.modelIdentifier}.so")
        )
        for function in FMI2_FUNCTIONS:
            assert hasattr(library, function), function
    assert len(FMI2_FUNCTIONS) == 34
    guids = {read_model_description(str(p)).guid for p in fmus.values()}
    assert len(guids) == len(fmus)


def test_fmu_pack_inspect_reports_the_archive(fmus, fmu_pack_binary):
    out = subprocess.run(
        [str(fmu_pack_binary), "inspect", str(fmus["TwoDof"])],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    assert "matches the resources" in out
    assert "sway" in out and "heave" in out
    assert re.search(r"^\s*network states\s+8$", out, re.M), out


def test_simulate_fmu_result_is_independent_of_the_step_within_the_hold_error(fmus):
    # A smooth input velocity; fmpy holds the input over each step (zero-order hold), so
    # the force differs between step sizes by at most ~ c1 |dv/dt| h.
    t = np.linspace(0.0, 10.0, 1001)
    signal = np.array(
        list(zip(t, 0.5 * np.sin(1.3 * t))),
        dtype=[("time", np.float64), ("velocity.sway", np.float64)],
    )
    results = {}
    for h in (0.01, 0.001):
        r = simulate_fmu(
            str(fmus["Seed"]),
            start_values={"rho": 1.0, "g": 1.0},
            input=signal,
            step_size=h,
            output_interval=0.1,
            stop_time=10.0,
            output=["force.sway", "energy"],
        )
        results[h] = r
    coarse, fine = results[0.01], results[0.001]
    assert np.allclose(coarse["time"], fine["time"])
    hold_error = C1 * 0.5 * 1.3 * 0.01  # c1 * max|dv/dt| * h
    difference = np.max(np.abs(coarse["force.sway"] - fine["force.sway"]))
    assert difference < hold_error, difference
    assert np.max(np.abs(fine["force.sway"])) > 0.1


def test_variable_steps_give_the_same_result_for_a_held_input(fmus):
    # Input piecewise constant on a 0.1 s grid; steps split it randomly: the exact
    # discretization makes every split agree to rounding.
    rng = np.random.default_rng(7)

    def run(split):
        s = Slave(fmus["TwoDof"], rho=1025.0, g=9.81)
        t = 0.0
        out = []
        for k in range(50):
            s.set(velocity__sway=math.sin(0.3 * k), velocity__heave=math.cos(0.2 * k))
            cuts = np.sort(rng.uniform(0.0, 0.1, size=split)) if split else np.array([])
            points = [0.0, *cuts, 0.1]
            for a, b in zip(points[:-1], points[1:]):
                if b > a:
                    s.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=b - a)
                    t += b - a
            t = round(t, 12)
            out.append(s.get("force.sway", "force.heave", "energy"))
        s.free()
        return np.array(out)

    reference = run(0)
    for split in (1, 3):
        other = run(split)
        assert np.max(np.abs(other - reference)) < 1e-9 * np.max(np.abs(reference))


def test_figure_7_unit_impulse_by_explicit_coupling(fmus):
    # A 1 kg body with a unit impulse, coupled explicitly to Schilder et al.'s network; the body's
    # mass includes m0 = added_mass_inf. All bodies end at the common velocity
    # 1 / (m + m0 + m1 + m2) (momentum conservation).
    s = Slave(fmus["Seed"])
    (m0,) = s.get("added_mass_inf[1,1]")
    assert m0 == pytest.approx(M0, rel=1e-12)
    mass = 1.0 + m0
    v = 1.0 / mass
    h = 0.01
    t = 0.0
    history = []
    for _ in range(6000):
        s.set(velocity__sway=v)
        (force,) = s.get("force.sway")
        s.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        t += h
        v += h * force / mass
        history.append(v)
    s.free()
    expected = 1.0 / (1.0 + M0 + M1 + M2)
    assert abs(history[-1] - expected) < 0.01 * expected
    # the primary body slows down first (figure 7)
    assert min(history[:300]) < 0.9 / mass


def test_reset_gives_a_bitwise_identical_second_run(fmus):
    s = Slave(fmus["Seed"])

    def run():
        out = []
        for k in range(200):
            s.set(velocity__sway=math.sin(0.05 * k))
            s.fmu.doStep(currentCommunicationPoint=0.01 * k, communicationStepSize=0.01)
            out.append(s.get("force.sway", "power", "energy"))
        return np.array(out)

    first = run()
    s.fmu.reset()
    s.start()
    second = run()
    s.free()
    assert first.tobytes() == second.tobytes()


CONTINUE = r"""
import sys, numpy as np
sys.path.insert(0, {here!r})
from test_fmu import Slave
s = Slave({path!r})
state = s.fmu.deSerializeFMUstate(open({state!r}, "rb").read())
s.fmu.setFMUstate(state)
out = []
for k in range(100):
    s.set(velocity__sway=0.3)
    s.fmu.doStep(currentCommunicationPoint=round(2.0 + 0.01 * k, 12), communicationStepSize=0.01)
    out.append(s.get("force.sway", "energy"))
s.fmu.freeFMUstate(state)
s.free()
np.save({result!r}, np.array(out))
"""


def test_state_serialized_in_one_process_continues_identically_in_another(fmus, tmp_path):
    s = Slave(fmus["Seed"])
    for k in range(200):
        s.set(velocity__sway=math.sin(0.05 * k))
        s.fmu.doStep(currentCommunicationPoint=round(0.01 * k, 12), communicationStepSize=0.01)
    state = s.fmu.getFMUstate()
    (tmp_path / "state.bin").write_bytes(s.fmu.serializeFMUstate(state))
    s.fmu.freeFMUstate(state)
    out = []
    for k in range(100):
        s.set(velocity__sway=0.3)
        s.fmu.doStep(currentCommunicationPoint=round(2.0 + 0.01 * k, 12), communicationStepSize=0.01)
        out.append(s.get("force.sway", "energy"))
    s.free()
    script = CONTINUE.format(
        here=str(pathlib.Path(__file__).parent),
        path=str(fmus["Seed"]),
        state=str(tmp_path / "state.bin"),
        result=str(tmp_path / "other.npy"),
    )
    subprocess.run([sys.executable, "-c", script], check=True)
    other = np.load(tmp_path / "other.npy")
    assert np.array(out).tobytes() == other.tobytes()


def test_two_instances_in_two_threads_match_sequential_runs(fmus):
    unzipped = extract(str(fmus["TwoDof"]))

    def run(name, results):
        s = Slave(fmus["TwoDof"], name=name, unzipped=unzipped, rho=1025.0, g=9.81)
        out = []
        for k in range(2000):
            s.set(velocity__sway=math.sin(0.01 * k), velocity__heave=0.5)
            s.fmu.doStep(currentCommunicationPoint=0.01 * k, communicationStepSize=0.01)
            out.append(s.get("force.sway", "force.heave"))
        s.free()
        results[name] = np.array(out)

    sequential = {}
    run("alone", sequential)
    parallel = {}
    threads = [threading.Thread(target=run, args=(n, parallel)) for n in ("a", "b")]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    for name in ("a", "b"):
        assert parallel[name].tobytes() == sequential["alone"].tobytes()


def _rss_kib():
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    raise RuntimeError("no VmRSS")


def test_500_load_simulate_unload_cycles_keep_memory_stable(fmus):
    unzipped = extract(str(fmus["Seed"]))

    def cycle():
        s = Slave(fmus["Seed"], unzipped=unzipped)
        for k in range(20):
            s.set(velocity__sway=1.0)
            s.fmu.doStep(currentCommunicationPoint=0.01 * k, communicationStepSize=0.01)
        state = s.fmu.getFMUstate()
        s.fmu.serializeFMUstate(state)
        s.fmu.freeFMUstate(state)
        s.free()

    for _ in range(50):
        cycle()
    baseline = _rss_kib()
    for _ in range(450):
        cycle()
    growth = _rss_kib() - baseline
    # A leak of one instance (~ kilobytes) per cycle would show as > 2 MiB here.
    assert growth < 2048, f"RSS grew by {growth} KiB over 450 cycles"


def _expect_error(call):
    with pytest.raises(FMICallException) as info:
        call()
    assert "status 3" in str(info.value)


def test_every_bad_call_gets_fmi2error_and_the_process_survives(fmus):
    s = Slave(fmus["Seed"], start=False)
    f = s.fmu
    vr = s.vr
    # wrong phase: refused, phase kept
    _expect_error(lambda: f.doStep(0.0, 0.1))
    _expect_error(lambda: f.getReal([vr["force.sway"]]))
    _expect_error(lambda: f.terminate())
    s.start()
    bad = [
        lambda: f.doStep(0.0, 0.0),
        lambda: f.doStep(0.0, -0.1),
        lambda: f.doStep(0.0, float("nan")),
        lambda: f.doStep(5.0, 0.1),
        lambda: f.setReal([vr["velocity.sway"]], [float("nan")]),
        lambda: f.setReal([vr["velocity.sway"]], [float("inf")]),
        lambda: f.setReal([vr["force.sway"]], [1.0]),
        lambda: f.setReal([vr["rho"]], [2.0]),
        lambda: f.setReal([99999], [1.0]),
        lambda: f.getReal([99999]),
        lambda: f.getInteger([vr["velocity.sway"]]),
        lambda: f.setString([vr["velocity.sway"]], ["x"]),
        lambda: f.setBoolean([vr["velocity.sway"]], [True]),
        lambda: f.setRealInputDerivatives([vr["velocity.sway"]], [2], [1.0]),
        lambda: f.getRealOutputDerivatives([vr["force.sway"]], [2]),
        lambda: f.getDirectionalDerivative([vr["velocity.sway"]], [vr["force.sway"]], [1.0]),
        lambda: f.deSerializeFMUstate(b"\x00" * 40),
        lambda: f.deSerializeFMUstate(b"HYDROFMU" + b"\x01" * 100),
        lambda: f.setDebugLogging(True, ["noSuchCategory"]),
        lambda: f.fmi2CancelStep(f.component),
    ]
    f.setReal([vr["velocity.sway"]], [1.0])
    f.doStep(0.0, 0.1)
    good = f.getFMUstate()
    reference = s.get("force.sway", "energy")
    for call in bad:
        _expect_error(call)
        # Error phase: outputs still readable and unchanged; the saved state recovers.
        assert s.get("force.sway", "energy") == reference
        f.setFMUstate(good)
    f.freeFMUstate(good)
    # A corrupted serialized state (one flipped byte) is refused.
    state = f.getFMUstate()
    data = bytearray(f.serializeFMUstate(state))
    data[len(data) // 2] ^= 0xFF
    _expect_error(lambda: f.deSerializeFMUstate(bytes(data)))
    f.reset()
    s.start()
    f.doStep(0.0, 0.1)
    f.freeFMUstate(state)
    s.free()
    # Instantiation with a wrong GUID or resource location fails cleanly.
    md = read_model_description(str(fmus["Seed"]))
    other = FMU2Slave(
        guid="{00000000-0000-0000-0000-000000000000}",
        unzipDirectory=s.unzipped,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="wrong",
    )
    with pytest.raises(Exception, match="instantiate"):
        other.instantiate()
    other.freeLibrary()


def test_derivatives_through_fmpy(fmus):
    s = Slave(fmus["SeedKeep"])
    vr = s.vr
    d = s.fmu.getDirectionalDerivative(
        [vr["force.sway"]], [vr["velocity.sway"], vr["acceleration.sway"]], [1.0, 0.0]
    )
    assert d[0] == pytest.approx(-C1, rel=1e-12)
    d = s.fmu.getDirectionalDerivative([vr["force.sway"]], [vr["acceleration.sway"]], [1.0])
    assert d[0] == pytest.approx(-M0, rel=1e-12)
    # First-order hold: a ramp via derivatives over one step equals ten small steps.
    s.set(velocity__sway=0.2)
    s.fmu.setRealInputDerivatives([vr["velocity.sway"]], [1], [0.5])
    s.fmu.doStep(0.0, 1.0)
    one = s.get("force.sway", "velocity.sway")
    (slope,) = s.fmu.getRealOutputDerivatives([vr["force.sway"]], [1])
    s.free()
    t = Slave(fmus["SeedKeep"])
    t.set(velocity__sway=0.2)
    t.fmu.setRealInputDerivatives([vr["velocity.sway"]], [1], [0.5])
    for k in range(10):
        t.fmu.doStep(0.1 * k, 0.1)
    ten = t.get("force.sway", "velocity.sway")
    t.free()
    assert one[1] == pytest.approx(0.7, abs=1e-15)
    assert abs(one[0] - ten[0]) < 1e-10
    assert math.isfinite(slope)


def test_libcosim_runs_two_different_fmus_in_one_system(fmus):
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.WARNING)
    execution = CosimExecution.from_step_size(step_size=int(1e7))  # 10 ms
    seed = execution.add_local_slave(CosimLocalSlave(fmu_path=str(fmus["Seed"]), instance_name="seed"))
    two = execution.add_local_slave(CosimLocalSlave(fmu_path=str(fmus["TwoDof"]), instance_name="two"))
    vr_seed = {v.name: v.valueReference for v in read_model_description(str(fmus["Seed"])).modelVariables}
    vr_two = {v.name: v.valueReference for v in read_model_description(str(fmus["TwoDof"])).modelVariables}
    for index, vr in ((seed, vr_seed), (two, vr_two)):
        assert execution.real_initial_value(index, vr["rho"], 1.0)
        assert execution.real_initial_value(index, vr["g"], 1.0)
        assert execution.real_initial_value(index, vr["velocity.sway"], 1.0)
    # data flows between the two FMUs: two's heave velocity follows seed's power
    assert execution.connect_real_variables(seed, vr_seed["power"], two, vr_two["velocity.heave"]) == 0
    observer = CosimObserver.create_last_value()
    assert execution.add_observer(observer)
    assert execution.simulate_until(target_time=int(1e9))  # 1 s
    (force_seed,) = observer.last_real_values(seed, [vr_seed["force.sway"]])
    force_two = observer.last_real_values(two, [vr_two["force.sway"], vr_two["force.heave"]])
    (heave,) = observer.last_real_values(two, [vr_two["velocity.heave"]])
    # Same sway branch in both networks, same held input: same sway force.
    reference = Slave(fmus["Seed"])
    reference.set(velocity__sway=1.0)
    for k in range(100):
        reference.fmu.doStep(0.01 * k, 0.01)
    (expected,) = reference.get("force.sway")
    reference.free()
    assert force_seed == pytest.approx(expected, rel=1e-9)
    assert force_two[0] != force_seed  # the 2-DOF network has a coupled third branch
    assert heave > 0.0 and force_two[1] < 0.0
