"""Campaigns of hull FMUs in irregular seas, case by case, serially or on a Dask cluster.

A case is one fmpy simulation of one hull FMU alone in a JONSWAP sea with the hull held fixed
(every ``velocity.<dof>`` input 0, so ``force.<dof> = force_excitation.<dof>``): wave.kind 2,
wave.height Hs, wave.period Tp, wave.gamma, wave.heading, wave.seed, wave.components and
wave.ramp set in initialization mode (docs/WAVES.md), ``ramp`` seconds of ramp, then
``duration`` seconds recorded every ``step`` seconds.

The archives are packed before the campaign (``fmu-pack pack``), never here. Each worker
process receives an archive's bytes once (``Client.scatter(..., broadcast=True)``), extracts
them once (``fmpy.extract``, cached by SHA-256 of the archive) and instantiates a fresh
``FMU2Slave`` from the extracted directory per case.

Statistics per case and DOF of the recorded force ``x(t)`` (``case_statistics``):

* ``mean``, ``std`` (standard deviation about the sample mean), ``significant`` = 4 std
  (the significant force, the analogue of Hs = 4 sqrt(m0)), ``max``, ``min``;
* ``tz``: the mean zero-upcrossing period of ``x - mean`` (record length / upcrossings);
* ``record_sha256``: a digest of the recorded float64 array (bitwise reproducibility checks).

Frequency-domain expectation (``spectral_statistics``), from the FMU's own excitation table
(``resources/excitation.csv``: ``kR,j,heading,re,im`` with ``re + i im = X_j / (rho g a
R^(1 + e_j))``, ``omega = sqrt(kR g / R)``): ``m_k = integral omega^k S(omega) |X_j(omega,
heading)|^2 d omega`` over the sea's range ``[0.5, 6] wp`` cut to the table's band (as the FMU
builds its sea), ``sigma = sqrt(m0)``, ``Tz = 2 pi sqrt(m0 / m2)``; and ``gaussian_scatter``,
the rms relative scatter of the sample std of a Gaussian sea's record of length T,
``(2 pi integral S_F^2 d omega / T)^(1/2) / (2 m0)`` (S_F = S |X|^2). The FMU's sea has
deterministic amplitudes (docs/WAVES.md), so it scatters less than that; the bound is what the
test uses.
"""
from __future__ import annotations

import csv
import hashlib
import io
import math
import os
import pathlib
import tempfile
import time
import zipfile

import numpy as np

RHO = 1025.0  # kg/m3, set on every FMU
G = 9.81  # m/s2
WAVE_INTEGERS = ("kind", "seed", "components")
STAT_COLUMNS = ("mean", "std", "significant", "max", "min", "tz", "upcrossings", "record_sha256")

# --------------------------------------------------------------------------- cases


def make_cases(hulls, sea_states, headings, seeds=(1,), duration=600.0, ramp=20.0, step=0.1, components=64):
    """The campaign matrix: hulls x sea states (Hs, Tp, gamma) x headings x seeds, as dicts."""
    cases = []
    for hull in hulls:
        for hs, tp, gamma in sea_states:
            for heading in headings:
                for seed in seeds:
                    cases.append(
                        dict(
                            hull=str(hull), hs=float(hs), tp=float(tp), gamma=float(gamma),
                            heading=float(heading), seed=int(seed), components=int(components),
                            duration=float(duration), ramp=float(ramp), step=float(step),
                        )
                    )
    return cases


def archive_payload(path) -> tuple[str, bytes]:
    """(SHA-256 hex digest, bytes) of an FMU archive: what is shipped to the workers."""
    data = pathlib.Path(path).read_bytes()
    return hashlib.sha256(data).hexdigest(), data


# --------------------------------------------------------------------------- worker side

_EXTRACTED: dict = {}  # digest -> (unzip directory, model description); one per process
_EXTRACTIONS = [0]


def extraction_count() -> dict:
    """How many archives this process has extracted, and from which process (for checks)."""
    return {"pid": os.getpid(), "extractions": _EXTRACTIONS[0], "digests": sorted(_EXTRACTED)}


def _extracted(payload):
    from fmpy import extract, read_model_description

    digest, data = payload
    if digest not in _EXTRACTED:
        directory = tempfile.mkdtemp(prefix=f"hydrocampaign-{digest[:12]}-")
        archive = pathlib.Path(directory) / "hull.fmu"
        archive.write_bytes(data)
        unzipped = extract(str(archive), unzipdir=str(pathlib.Path(directory) / "unzipped"))
        _EXTRACTED[digest] = (unzipped, read_model_description(str(archive)))
        _EXTRACTIONS[0] += 1
    return _EXTRACTED[digest]


def simulate(case: dict, payload) -> tuple[list[str], np.ndarray]:
    """Runs one case; returns the DOF names and the recorded force_excitation (samples x DOFs),
    sampled after each step from t = ramp + step to ramp + duration."""
    from fmpy.fmi2 import FMU2Slave

    unzipped, md = _extracted(payload)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    dofs = [v.name[len("velocity."):] for v in md.modelVariables if v.name.startswith("velocity.")]
    slave = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unzipped,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName=f"{case['hull']}",
    )
    slave.instantiate(loggingOn=False)
    try:
        slave.setReal([vr["rho"], vr["g"]], [RHO, G])
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        waves = dict(
            kind=2, height=case["hs"], period=case["tp"], gamma=case["gamma"], heading=case["heading"],
            seed=case["seed"], components=case["components"], ramp=case["ramp"],
        )
        for name, value in waves.items():
            if name in WAVE_INTEGERS:
                slave.setInteger([vr[f"wave.{name}"]], [int(value)])
            else:
                slave.setReal([vr[f"wave.{name}"]], [float(value)])
        slave.exitInitializationMode()
        slave.setReal([vr[f"velocity.{d}"] for d in dofs], [0.0] * len(dofs))  # hull held fixed
        h = case["step"]
        ramp_steps = int(round(case["ramp"] / h))
        steps = int(round(case["duration"] / h))
        refs = [vr[f"force_excitation.{d}"] for d in dofs]
        record = np.empty((steps, len(dofs)))
        for n in range(ramp_steps + steps):
            slave.doStep(currentCommunicationPoint=n * h, communicationStepSize=h)
            if n >= ramp_steps:
                record[n - ramp_steps] = slave.getReal(refs)
        slave.terminate()
    finally:
        slave.freeInstance()
    return dofs, record


def case_statistics(x: np.ndarray, step: float) -> dict:
    """The statistics of one recorded DOF (module docstring)."""
    mean = float(np.mean(x))
    y = x - mean
    std = float(np.sqrt(np.mean(y**2)))
    upcrossings = int(np.count_nonzero((y[:-1] < 0) & (y[1:] >= 0)))
    length = step * len(x)
    return dict(
        mean=mean, std=std, significant=4.0 * std, max=float(np.max(x)), min=float(np.min(x)),
        tz=length / upcrossings if upcrossings else math.nan, upcrossings=upcrossings,
        record_sha256=hashlib.sha256(np.ascontiguousarray(x).tobytes()).hexdigest(),
    )


def run_case(case: dict, payload) -> list[dict]:
    """One case -> one row per DOF: the case's parameters, the statistics, the wall time and
    the process that ran it."""
    start = time.perf_counter()
    dofs, record = simulate(case, payload)
    seconds = time.perf_counter() - start
    return [
        dict(case, dof=dof, **case_statistics(record[:, j], case["step"]), seconds=seconds, pid=os.getpid())
        for j, dof in enumerate(dofs)
    ]


def simulate_libcosim(case: dict, fmu) -> tuple[list[str], np.ndarray]:
    """The same case under OSP's libcosim (libcosimpy): the FMU as a local slave, rho, g and the
    wave parameters as initial values, libcosim's fixed-step algorithm on its nanosecond clock,
    the outputs read by a last-value observer after each step. Returns what `simulate` does."""
    from fmpy import read_model_description
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.WARNING)
    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    dofs = [v.name[len("velocity."):] for v in md.modelVariables if v.name.startswith("velocity.")]
    step_ns = int(round(case["step"] * 1e9))
    execution = CosimExecution.from_step_size(step_size=step_ns)
    slave = execution.add_local_slave(CosimLocalSlave(fmu_path=str(fmu), instance_name=case["hull"]))
    execution.real_initial_value(slave, vr["rho"], RHO)
    execution.real_initial_value(slave, vr["g"], G)
    waves = dict(
        kind=2, height=case["hs"], period=case["tp"], gamma=case["gamma"], heading=case["heading"],
        seed=case["seed"], components=case["components"], ramp=case["ramp"],
    )
    for name, value in waves.items():
        if name in WAVE_INTEGERS:
            execution.integer_initial_value(slave, vr[f"wave.{name}"], int(value))
        else:
            execution.real_initial_value(slave, vr[f"wave.{name}"], float(value))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    refs = [vr[f"force_excitation.{d}"] for d in dofs]
    ramp_steps = int(round(case["ramp"] / case["step"]))
    steps = int(round(case["duration"] / case["step"]))
    record = np.empty((steps, len(dofs)))
    for n in range(ramp_steps + steps):
        assert execution.step()
        if n >= ramp_steps:
            record[n - ramp_steps] = observer.last_real_values(slave, refs)
    execution.stop()
    return dofs, record


# --------------------------------------------------------------------------- running


def run_serial(cases, archives: dict) -> list[dict]:
    """All cases in this process, in order (archives: hull name -> FMU path)."""
    payloads = {name: archive_payload(path) for name, path in archives.items()}
    return [row for case in cases for row in run_case(case, payloads[case["hull"]])]


def run_dask(client, cases, archives: dict, show_progress: bool = False) -> list[dict]:
    """All cases on the cluster of `client`: each archive is scattered once to every worker,
    this module is uploaded to the workers (so a remote cluster needs only fmpy and numpy),
    and `client.map` runs one task per case. Rows come back in case order."""
    module = pathlib.Path(__file__).resolve()
    # load=False: a scheduler in this process (a LocalCluster) would otherwise re-import this
    # module from its scratch copy, and __file__ would point there once the cluster is gone.
    client.upload_file(str(module), load=False)
    payloads = {
        name: client.scatter(archive_payload(path), broadcast=True, hash=False) for name, path in archives.items()
    }
    futures = client.map(run_case, cases, [payloads[c["hull"]] for c in cases], pure=False)
    if show_progress:
        from distributed import progress

        progress(futures)
        print()
    return [row for rows in client.gather(futures) for row in rows]


# --------------------------------------------------------------------------- frequency domain


def jonswap(omega, hs, tp, gamma):
    """DNV-RP-C205 JONSWAP spectral density (docs/WAVES.md), m^2 s."""
    wp = 2 * math.pi / tp
    sigma = np.where(omega <= wp, 0.07, 0.09)
    shape = np.exp(-((omega - wp) ** 2) / (2 * sigma**2 * wp**2))
    return (
        (1 - 0.287 * math.log(gamma)) * 5 / 16 * hs**2 * wp**4 * omega**-5
        * np.exp(-1.25 * (omega / wp) ** -4) * gamma**shape
    )


class ExcitationTable:
    """resources/excitation.csv of an FMU archive (src/waves/table.rs), in SI at rho, g."""

    def __init__(self, fmu, rho=RHO, g=G):
        with zipfile.ZipFile(fmu) as archive:
            text = archive.read("resources/excitation.csv").decode()
        header, rows = {}, []
        for row in csv.reader(io.StringIO(text)):
            if not row:
                continue
            if row[0].startswith("#"):
                key, _, value = ",".join(row)[1:].partition(":")
                header[key.strip()] = value.strip()
            elif row[0] != "kR":
                rows.append(row)
        self.modes = header["modes"].split()
        self.radius = float(header["R"].split()[0])
        exponents = [int(e) for e in header["length exponents"].split()]
        self.g = g
        values: dict = {}
        for k, j, heading, re, im in rows:
            if float(k) > 0:
                j = int(j) - 1
                scale = rho * g * self.radius ** (1 + exponents[j])
                key = (self.modes[j], float(heading) % 360.0)
                values.setdefault(key, []).append((float(k), complex(float(re), float(im)) * scale))
        self.values = {key: sorted(v) for key, v in values.items()}
        self.headings = sorted({h for _, h in self.values})
        first = next(iter(self.values.values()))
        self.kr = np.array([k for k, _ in first])
        self.band = (math.sqrt(self.kr[0] * g / self.radius), math.sqrt(self.kr[-1] * g / self.radius))

    def x(self, dof: str, heading: float, omega) -> np.ndarray:
        """X_j(omega) per unit wave amplitude, SI: cubic spline of re and im in ln kR (close to
        the FMU's cubic Hermite; the grid is the FMU's own)."""
        from scipy.interpolate import CubicSpline

        values = np.array([x for _, x in self.values[(dof, heading % 360.0)]])
        log_kr = np.log(np.asarray(omega) ** 2 * self.radius / self.g)
        re = CubicSpline(np.log(self.kr), values.real)(log_kr)
        im = CubicSpline(np.log(self.kr), values.imag)(log_kr)
        return re + 1j * im


def spectral_statistics(table: ExcitationTable, dof, hs, tp, gamma, heading, duration, points=20001) -> dict:
    """Frequency-domain expectation of one case and DOF (module docstring)."""
    wp = 2 * math.pi / tp
    lo, hi = max(0.5 * wp, table.band[0]), min(6 * wp, table.band[1])
    if lo >= hi:
        return dict(spectral_std=math.nan, spectral_tz=math.nan, gaussian_scatter=math.nan, band_fraction=0.0)
    full = np.linspace(0.5 * wp, 6 * wp, points)
    omega = np.linspace(lo, hi, points)
    s = jonswap(omega, hs, tp, gamma)
    sf = s * np.abs(table.x(dof, heading, omega)) ** 2
    m0 = np.trapezoid(sf, omega)
    m2 = np.trapezoid(omega**2 * sf, omega)
    scatter = math.sqrt(2 * math.pi * np.trapezoid(sf**2, omega) / duration) / (2 * m0) if m0 > 0 else math.nan
    return dict(
        spectral_std=math.sqrt(m0),
        spectral_tz=2 * math.pi * math.sqrt(m0 / m2) if m2 > 0 else math.nan,
        gaussian_scatter=scatter,
        band_fraction=float(np.trapezoid(s, omega) / np.trapezoid(jonswap(full, hs, tp, gamma), full)),
    )


def add_spectral(rows, archives: dict) -> list[dict]:
    """Adds the spectral columns and the ratio std / spectral_std to every row."""
    tables = {name: ExcitationTable(path) for name, path in archives.items()}
    out = []
    for row in rows:
        spectral = spectral_statistics(
            tables[row["hull"]], row["dof"], row["hs"], row["tp"], row["gamma"], row["heading"], row["duration"]
        )
        ratio = row["std"] / spectral["spectral_std"] if spectral["spectral_std"] > 0 else math.nan
        out.append(dict(row, **spectral, ratio=ratio))
    return out


# --------------------------------------------------------------------------- output


def write_csv(rows, path):
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def plot(rows, path):
    """Significant force vs Tp, one line per heading, one panel per hull and DOF."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    hulls = list(dict.fromkeys(r["hull"] for r in rows))
    dofs = list(dict.fromkeys(r["dof"] for r in rows))
    fig, axes = plt.subplots(len(hulls), len(dofs), figsize=(4.2 * len(dofs), 3.2 * len(hulls)), squeeze=False)
    for a, hull in enumerate(hulls):
        for b, dof in enumerate(dofs):
            ax = axes[a][b]
            mine = [r for r in rows if r["hull"] == hull and r["dof"] == dof]
            for k, heading in enumerate(sorted({r["heading"] for r in mine})):
                line = sorted((r["tp"], r["significant"], r.get("spectral_std", math.nan)) for r in mine if r["heading"] == heading)
                tp = [p[0] for p in line]
                (handle,) = ax.plot(
                    tp, [p[1] for p in line], "osD^v"[k % 5], ms=7 - k % 5, mfc="none" if k % 2 else None,
                    label=f"{heading:g} deg",
                )
                ax.plot(tp, [4 * p[2] for p in line], "-", color=handle.get_color(), lw=0.8)
            unit = "N" if dof in ("sway", "heave") else "N m"
            hs = sorted({r["hs"] for r in mine})
            ax.set_title(f"{hull}: {dof} (Hs {', '.join(f'{h:g}' for h in hs)} m)", fontsize=9)
            ax.set_xlabel("Tp (s)")
            ax.set_ylabel(f"4 std of force_excitation.{dof} ({unit})")
            ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7, title="heading (markers: records,\nlines: 4 sqrt(m0) of the table)", title_fontsize=6)
    fig.tight_layout()
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, metadata={"Date": None})
    plt.close(fig)
