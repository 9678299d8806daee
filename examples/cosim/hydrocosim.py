"""Shared pieces of the co-simulation examples (see docs/COSIMULATION.md).

A linear structure with generalized coordinates ``p`` (mass ``M_s``, damping ``C_s``,
stiffness ``K_s``) moves the hull; the hull's FMU coordinates are ``q = T p`` (``T``: the map
from structure coordinates to the FMU's DOFs ``velocity.<dof>``). The FMU returns the force on
the hull by the water without ``-A_inf q''`` (docs/DESIGN.md); generalized on the structure it is
``T^T F``.

Co-simulation master (the same scheme under fmpy and libcosimpy, Jacobi, zero-order hold):

* the master adds ``T^T A_inf T`` (FMU ``added_mass_inf``) to its mass matrix and
  ``T^T D T`` (FMU ``damping_direct``, the direct feedthrough ``F = ... - D v``) to its damping
  matrix, so the FMU output it still needs is the network state's force
  ``F_z = F + D v_held`` (smooth, no feedthrough);
* per communication step ``[t_n, t_n + h]`` the FMU steps with a held hull velocity and the
  structure steps exactly (matrix exponential) under ``T^T F_z``: scheme "zoh" holds
  ``v(t_n)`` and ``F_z(t_n)`` (first order in ``h``); scheme "ramp" holds the extrapolated
  mid-step velocity ``1.5 v(t_n) - 0.5 v(t_(n-1))`` and ramps the structure's force from
  ``F_z(t_n)`` to ``F_z(t_(n+1))``, read after the FMU's step (second order). Both need only
  held inputs, so libcosim's fixed-step algorithm runs them as well as fmpy.

Monolithic reference (seed paper, eq. 19): the network's augmented ``M, C, K`` over
``[q; auxiliary masses]`` (docs/NETWORK_FORMAT.md, ``realize::augmented_matrices``),
transformed by ``blockdiag(T, I)``, plus the structure; solved exactly on the communication
grid with one matrix exponential. The network starts at rest: every auxiliary mass of a
branch sits at the branch coordinate ``d^T q(0)`` (springs unstretched), which is the FMU's
zero initial state.
"""
from __future__ import annotations

import os
import pathlib
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass, field

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU_DIR = pathlib.Path(os.environ.get("HYDROFMU_COSIM_FMUS", ROOT / "examples" / "cosim" / "fmus"))
# Figures go to target/reports/figures; `--update-docs` (or HYDROFMU_UPDATE_DOCS=1) writes the
# tracked docs/figures instead.
DOC_FIGURES = ROOT / "docs" / "figures"
FIGURES = DOC_FIGURES if os.environ.get("HYDROFMU_UPDATE_DOCS") == "1" else ROOT / "target" / "reports" / "figures"

RHO = 1025.0  # water density, kg/m3
G = 9.81  # gravity, m/s2
RADIUS = 1.0  # semicircle radius R, m
# Wave parameters (docs/WAVES.md) that are FMI Integers; the others are Reals. The masters take
# them as a dict without the "wave." prefix, e.g. {"kind": 1, "height": 1.0, "period": 6.0}.
WAVE_INTEGERS = ("kind", "seed", "components")


# --------------------------------------------------------------------------- FMUs


def fmu_pack(args: list[str], echo: bool = False) -> str:
    """Runs fmu-pack with `args` and returns its standard output. The binary is
    $HYDROFMU_FMU_PACK when set, else `cargo run --release -p fmu-pack` (built on first use)."""
    binary = os.environ.get("HYDROFMU_FMU_PACK")
    command = [binary] if binary else ["cargo", "run", "--release", "-q", "-p", "fmu-pack", "--"]
    command = command + list(args)
    if echo:
        print("running:", " ".join(command), file=sys.stderr)
    return subprocess.run(command, cwd=ROOT, check=True, capture_output=True, text=True).stdout


def ensure_fmu(name: str, pack_args: list[str], path: str | os.PathLike | None = None) -> pathlib.Path:
    """The FMU at `path` (default FMU_DIR/name.fmu); packs it with fmu-pack when missing."""
    fmu = pathlib.Path(path) if path else FMU_DIR / f"{name}.fmu"
    if fmu.is_file():
        return fmu
    fmu.parent.mkdir(parents=True, exist_ok=True)
    fmu_pack(["pack", *pack_args, "-o", str(fmu)], echo=True)
    return fmu


# --------------------------------------------------------------------------- sweep tables


@dataclass
class Coefficients:
    """The panel method's frequency-domain coefficients at one kR, in SI per metre, for the
    hull's DOFs: complex added mass A~ = a - i b / omega and the exciting force X per unit
    wave amplitude of each heading (docs/WAVES.md; convention exp(+i omega t))."""

    kr: float
    omega: float
    dofs: list[str]
    added_mass: np.ndarray  # complex (n, n)
    excitation: dict  # heading (deg) -> complex (n,)


def _header_and_rows(text: str):
    header, rows = {}, []
    for line in text.splitlines():
        if line.startswith("#"):
            key, _, value = line[1:].partition(":")
            header[key.strip()] = value.strip()
        elif line and not line.startswith("kR"):
            rows.append(line.split(","))
    return header, rows


def sweep_coefficients(hull_args: list[str], kr_grid: str, rho: float = RHO, g: float = G) -> list[Coefficients]:
    """`fmu-pack sweep HULL_ARGS --kr KR_GRID --excitation` (the panel method's own values at
    each kR of the grid, `lo:hi:n` log-spaced), read into SI: A~ = value rho pi R^2 (docs/DESIGN.md,
    as `FrequencyResponse::from_sweep`), X = value rho g R^(1 + e_j) (docs/WAVES.md; e_j the
    DOF's length exponent)."""
    with tempfile.TemporaryDirectory() as tmp:
        radiation_path = pathlib.Path(tmp) / "added_mass.csv"
        excitation_text = fmu_pack(
            ["sweep", *hull_args, "--kr", kr_grid, "-o", str(radiation_path), "--excitation", "-"]
        )
        radiation_text = radiation_path.read_text()
    header, rows = _header_and_rows(excitation_text)
    dofs = header["modes"].split()
    radius = float(header["R"].split()[0])
    exponents = [int(e) for e in header["length exponents"].split()]
    n = len(dofs)
    by_kr: dict[float, Coefficients] = {}

    def at(kr: float) -> Coefficients:
        if kr not in by_kr:
            omega = float(np.sqrt(kr * g / radius))
            by_kr[kr] = Coefficients(kr, omega, dofs, np.zeros((n, n), dtype=complex), {})
        return by_kr[kr]

    for k, j, heading, re, im in rows:
        if float(k) == 0.0:
            continue  # long-wave rows
        x = at(float(k)).excitation.setdefault(float(heading) % 360.0, np.zeros(n, dtype=complex))
        j = int(j) - 1
        x[j] = complex(float(re), float(im)) * rho * g * radius ** (1 + exponents[j])
    _, rows = _header_and_rows(radiation_text)
    for k, i, j, re, im in rows:
        if float(k) == 0.0 or not np.isfinite(float(k)):
            continue  # the limits' rows
        i, j = int(i) - 1, int(j) - 1
        at(float(k)).added_mass[i, j] = complex(float(re), float(im)) * rho * np.pi * radius**2
    return [by_kr[kr] for kr in sorted(by_kr)]


def harmonic_fit(t: np.ndarray, x: np.ndarray, omega: float) -> np.ndarray:
    """Complex amplitudes c (per column of x) of the least-squares fit
    x(t) = x0 + x1 t + Re[c e^(i omega t)] (the linear part takes up a slow drift)."""
    basis = np.column_stack([np.ones_like(t), t - t.mean(), np.cos(omega * t), np.sin(omega * t)])
    coefficients, *_ = np.linalg.lstsq(basis, x, rcond=None)
    return coefficients[2] - 1j * coefficients[3]


# --------------------------------------------------------------------------- network


@dataclass
class Substructure:
    """A passive substructure of a network (NETWORK_FORMAT.md): unit aux masses (velocities u)
    and unit springs (elongations e) over the hull velocities v:

        e' = -R e + E_u u + E_v v,   u' = -E_u^T e - C_uu u - C_uv v,
        F  = -E_v^T e - C_vu u - C_vv v   (the water's force on the hull, without -A_inf q'')."""

    masses: int
    spring_incidence: np.ndarray  # E = [E_u E_v], (Ns, Nm + n)
    spring_relaxation: np.ndarray  # R, (Ns, Ns)
    damping: np.ndarray  # C over [u; v], (Nm + n, Nm + n)

    @classmethod
    def from_xml(cls, element) -> "Substructure":
        def matrix(tag):
            return np.array([[float(x) for x in r.text.split()] for r in element.find(tag).findall("row")], ndmin=2)

        return cls(
            int(element.get("masses")),
            matrix("spring_incidence"),
            matrix("spring_relaxation"),
            matrix("damping"),
        )

    @property
    def states(self) -> int:
        return self.spring_incidence.shape[0] + self.masses

    def realization(self):
        """(A, B, C_Z, D): z' = A z + B v over z = [e; u], F = -(C_Z z + D v)."""
        nm, ns = self.masses, self.spring_incidence.shape[0]
        e_u, e_v = self.spring_incidence[:, :nm], self.spring_incidence[:, nm:]
        c_uu, c_uv = self.damping[:nm, :nm], self.damping[:nm, nm:]
        c_vu, c_vv = self.damping[nm:, :nm], self.damping[nm:, nm:]
        a = np.block([[-self.spring_relaxation, e_u], [-e_u.T, -c_uu]]) if ns + nm else np.zeros((0, 0))
        b = np.vstack([e_v, -c_uv])
        c = np.hstack([e_v.T, c_vu])
        return a, b, c, c_vv

    def scaled(self, r: float, s: float) -> "Substructure":
        """Other water: R, E_u, C_uu ~ sqrt(s); E_v, C_uv ~ sqrt(r s); C_vv ~ r sqrt(s)
        (r = rho / rho0, s = g / g0; the states are energy coordinates)."""
        nm, gamma = self.masses, np.sqrt(s)
        incidence = self.spring_incidence * gamma
        incidence[:, nm:] *= np.sqrt(r)
        damping = self.damping * gamma
        damping[:nm, nm:] *= np.sqrt(r)
        damping[nm:, :nm] *= np.sqrt(r)
        damping[nm:, nm:] *= r
        return Substructure(nm, incidence, self.spring_relaxation * gamma, damping)


@dataclass
class Network:
    """The equivalent network read from an FMU's resources/network.xml (SI, per metre)."""

    dofs: list[str]
    rho: float
    g: float
    added_mass_inf: np.ndarray
    # per branch: (direction (n,), stages [(mass, stiffness, damping), ...] from the hull out)
    branches: list[tuple[np.ndarray, list[tuple[float, float, float]]]] = field(default_factory=list)
    substructures: list[Substructure] = field(default_factory=list)

    @classmethod
    def from_fmu(cls, fmu: str | os.PathLike) -> "Network":
        with zipfile.ZipFile(fmu) as archive:
            root = ET.fromstring(archive.read("resources/network.xml"))
        dofs = [d.get("name") for d in root.findall("dof")]
        rows = [[float(x) for x in r.text.split()] for r in root.find("added_mass_inf").findall("row")]
        branches = []
        for b in root.findall("branch"):
            direction = np.array([float(x) for x in b.find("direction").text.split()])
            stages = [
                (float(s.get("mass")), float(s.get("stiffness")), float(s.get("damping"))) for s in b.findall("stage")
            ]
            branches.append((direction, stages))
        substructures = [Substructure.from_xml(e) for e in root.findall("substructure")]
        return cls(dofs, float(root.get("rho")), float(root.get("g")), np.array(rows), branches, substructures)

    def scaled(self, rho: float, g: float) -> "Network":
        """The same network in other water (NETWORK_FORMAT.md: masses ~ rho, springs ~ rho g,
        dampers ~ rho sqrt(g); substructures as in Substructure.scaled)."""
        r, s = rho / self.rho, g / self.g
        branches = [(d, [(m * r, k * r * s, c * r * np.sqrt(s)) for m, k, c in st]) for d, st in self.branches]
        subs = [sub.scaled(r, s) for sub in self.substructures]
        return Network(self.dofs, rho, g, self.added_mass_inf * r, branches, subs)

    @property
    def aux_count(self) -> int:
        """Aux masses of the branches (the second-order part of augmented_matrices)."""
        return sum(len(st) for _, st in self.branches)

    @property
    def substructure_states(self) -> int:
        return sum(sub.states for sub in self.substructures)

    def damping_direct(self) -> np.ndarray:
        """Sum over branches of c1 d d^T plus the substructures' C_vv (the FMU's damping_direct)."""
        out = sum((st[0][2] * np.outer(d, d) for d, st in self.branches), np.zeros_like(self.added_mass_inf))
        return out + sum((sub.realization()[3] for sub in self.substructures), np.zeros_like(out))

    def augmented_matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Schilder et al., eq. 19: M, C, K over [q; aux] (hull block of M = A_inf, no body mass), for the
        branches; the substructures are first-order states (coupled_system).

        Spring j's elongation is e_j = x_j - d^T q (first stage) or x_j - x_(j-1)."""
        n, na = len(self.dofs), self.aux_count
        mass = np.zeros((n + na, n + na))
        damping = np.zeros_like(mass)
        stiffness = np.zeros_like(mass)
        mass[:n, :n] = self.added_mass_inf
        row = 0
        for d, stages in self.branches:
            for j, (m, k, c) in enumerate(stages):
                e = np.zeros(n + na)
                if j == 0:
                    e[:n] = -d
                else:
                    e[n + row - 1] = -1.0
                e[n + row] = 1.0
                mass[n + row, n + row] = m
                damping += c * np.outer(e, e)
                stiffness += k * np.outer(e, e)
                row += 1
        return mass, damping, stiffness

    def complex_added_mass(self, omega: float) -> np.ndarray:
        """H(i omega) of the network (NETWORK_FORMAT.md): the A~(omega) the FMU realizes."""
        s = 1j * omega
        out = self.added_mass_inf.astype(complex)
        for d, stages in self.branches:
            g = 0.0
            for m, k, c in reversed(stages):
                big_m = m + g
                z = k + c * s
                g = big_m * z / (z + s * s * big_m)
            out = out + np.outer(d, d) * g
        for sub in self.substructures:
            a, b, c, d = sub.realization()
            impedance = c @ np.linalg.solve(s * np.eye(len(a)) - a, b) + d
            out = out + impedance / s
        return out

    def aux_at_rest(self, q0: np.ndarray) -> np.ndarray:
        """Branch aux positions with every spring unstretched for hull position q0 (the
        substructures' states are zero at rest for any q0)."""
        return np.concatenate([np.full(len(st), d @ q0) for d, st in self.branches] + [np.zeros(0)])


# --------------------------------------------------------------------------- linear algebra


def expm(a: np.ndarray) -> np.ndarray:
    """Matrix exponential: scaling and squaring with a degree-20 Taylor polynomial
    (|a / 2^s| <= 1/2, truncation < 1e-25 relative)."""
    norm = np.linalg.norm(a, 1)
    s = max(0, int(np.ceil(np.log2(norm))) + 1) if norm > 0 else 0
    x = a / 2.0**s
    term = np.eye(len(a))
    result = term.copy()
    for k in range(1, 21):
        term = term @ x / k
        result = result + term
    for _ in range(s):
        result = result @ result
    return result


def first_order(mass, damping, stiffness):
    """y = [p; p'], y' = A y + B f for M p'' + C p' + K p = f."""
    n = len(mass)
    inv = np.linalg.inv(mass)
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -inv @ stiffness
    a[n:, n:] = -inv @ damping
    b = np.vstack([np.zeros((n, n)), inv])
    return a, b


def hold_discretization(a: np.ndarray, b: np.ndarray, h: float):
    """Exact discretization over one step for an input ramped from f0 to f1:
    y(h) = Phi y(0) + Gamma0 f0 + Gamma1 (f1 - f0) (a held input: f1 = f0)."""
    n, m = b.shape
    big = np.zeros((n + 2 * m, n + 2 * m))
    big[:n, :n] = a * h
    big[:n, n : n + m] = b * h
    big[n : n + m, n + m :] = np.eye(m)
    e = expm(big)
    return e[:n, :n], e[:n, n : n + m], e[:n, n + m :]


# --------------------------------------------------------------------------- models


@dataclass
class Structure:
    """M_s p'' + C_s p' + K_s p = T^T F_water, hull coordinates q = T p."""

    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    to_hull: np.ndarray  # T, (n_q, n_p)


def coupled_system(structure: Structure, network: Network) -> np.ndarray:
    """Schilder et al., eq. 19 with the structure, as y' = A y over y = [p; x; p'; x'; z]: structure
    coordinates p, branch aux positions x, substructure states z. Returns A."""
    t = structure.to_hull
    nq, np_ = t.shape
    na, nz = network.aux_count, network.substructure_states
    mass, damping, stiffness = network.augmented_matrices()
    big_t = np.zeros((nq + na, np_ + na))
    big_t[:nq, :np_] = t
    big_t[nq:, np_:] = np.eye(na)
    mats = [big_t.T @ m @ big_t for m in (mass, damping, stiffness)]
    for m, s in zip(mats, (structure.mass, structure.damping, structure.stiffness)):
        m[:np_, :np_] += s
    mass, damping, stiffness = mats
    n2 = np_ + na
    # Substructures: F = -(C_Z z + D v), z' = A_z z + B_z v, v = T p'.
    coupling = np.zeros((n2, nz))  # generalized force per z (before the minus sign)
    a_z = np.zeros((nz, nz))
    b_z = np.zeros((nz, n2))
    row = 0
    for sub in network.substructures:
        a, b, c, d = sub.realization()
        k = len(a)
        damping[:np_, :np_] += t.T @ d @ t
        coupling[:np_, row : row + k] = t.T @ c
        a_z[row : row + k, row : row + k] = a
        b_z[row : row + k, :np_] = b @ t
        row += k
    inv = np.linalg.inv(mass)
    out = np.zeros((2 * n2 + nz, 2 * n2 + nz))
    out[:n2, n2 : 2 * n2] = np.eye(n2)
    out[n2 : 2 * n2, :n2] = -inv @ stiffness
    out[n2 : 2 * n2, n2 : 2 * n2] = -inv @ damping
    out[n2 : 2 * n2, 2 * n2 :] = -inv @ coupling
    out[2 * n2 :, n2 : 2 * n2] = b_z
    out[2 * n2 :, 2 * n2 :] = a_z
    return out


def monolithic(structure: Structure, network: Network, p0, h: float, steps: int) -> np.ndarray:
    """Schilder et al., eq. 19 with the structure: p(t_n), n = 0..steps, t_n = n h; starts at rest at p0."""
    t = structure.to_hull
    np_ = t.shape[1]
    na, nz = network.aux_count, network.substructure_states
    phi = expm(coupled_system(structure, network) * h)
    p0 = np.asarray(p0, dtype=float)
    y = np.concatenate([p0, network.aux_at_rest(t @ p0), np.zeros(np_ + na + nz)])
    out = np.empty((steps + 1, np_))
    out[0] = p0
    for n in range(steps):
        y = phi @ y
        out[n + 1] = y[:np_]
    return out


def eigen_modes(mass, damping, stiffness):
    """Eigenvalues with Im > 0 of M p'' + C p' + K p = 0 and their eigenvectors (p part)."""
    a, _ = first_order(mass, damping, stiffness)
    lam, vec = np.linalg.eig(a)
    keep = lam.imag > 1e-9
    order = np.argsort(lam[keep].imag)
    return lam[keep][order], vec[: len(mass), keep][:, order]


# --------------------------------------------------------------------------- masters


class FmpyHull:
    """The hull FMU under fmpy's FMU2Slave (the Python loop is the master)."""

    def __init__(self, fmu, rho=RHO, g=G, name="hull", waves: dict | None = None):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.md = read_model_description(str(fmu))
        self.unzipped = extract(str(fmu))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.dofs = [v.name[len("velocity."):] for v in self.md.modelVariables if v.name.startswith("velocity.")]
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.unzipped,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate(loggingOn=False)
        self.fmu.setReal([self.vr["rho"], self.vr["g"]], [rho, g])
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        for name_, value in (waves or {}).items():
            ref = [self.vr[f"wave.{name_}"]]
            if name_ in WAVE_INTEGERS:
                self.fmu.setInteger(ref, [int(value)])
            else:
                self.fmu.setReal(ref, [float(value)])
        self.fmu.exitInitializationMode()
        self.v_in = [self.vr[f"velocity.{d}"] for d in self.dofs]
        self.f_out = [self.vr[f"force.{d}"] for d in self.dofs]

    def matrix(self, name: str) -> np.ndarray:
        n = len(self.dofs)
        refs = [self.vr[f"{name}[{i + 1},{j + 1}]"] for i in range(n) for j in range(n)]
        return np.array(self.fmu.getReal(refs)).reshape(n, n)

    def advance(self, time: float, h: float, velocity) -> np.ndarray:
        """Steps [time, time + h] with `velocity` held; returns force.<dof> after the step."""
        self.fmu.setReal(self.v_in, list(velocity))
        self.fmu.doStep(currentCommunicationPoint=time, communicationStepSize=h)
        return np.array(self.fmu.getReal(self.f_out))

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


class LibcosimHull:
    """The hull FMU as a libcosim local slave, stepped by libcosim's fixed-step algorithm.

    libcosim needs every model to be an FMU; the structure here is Python, so the loop sets the
    hull velocity through an override manipulator, steps the execution one communication step
    and reads the force through a last-value observer (libcosim applies the override before the
    FMU's doStep and samples outputs after it)."""

    def __init__(self, fmu, h: float, rho=RHO, g=G, name="hull", waves: dict | None = None):
        from fmpy import read_model_description
        from libcosimpy.CosimExecution import CosimExecution
        from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
        from libcosimpy.CosimManipulator import CosimManipulator
        from libcosimpy.CosimObserver import CosimObserver
        from libcosimpy.CosimSlave import CosimLocalSlave

        log_output_level(CosimLogLevel.WARNING)
        md = read_model_description(str(fmu))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.dofs = [v.name[len("velocity."):] for v in md.modelVariables if v.name.startswith("velocity.")]
        self.h_ns = round(h * 1e9)
        if abs(self.h_ns * 1e-9 - h) > 1e-15:
            raise ValueError(f"step {h} s is not a whole number of nanoseconds (libcosim time unit)")
        self.execution = CosimExecution.from_step_size(step_size=self.h_ns)
        self.slave = self.execution.add_local_slave(CosimLocalSlave(fmu_path=str(fmu), instance_name=name))
        self.execution.real_initial_value(self.slave, self.vr["rho"], rho)
        self.execution.real_initial_value(self.slave, self.vr["g"], g)
        for name_, value in (waves or {}).items():
            ref = self.vr[f"wave.{name_}"]
            if name_ in WAVE_INTEGERS:
                self.execution.integer_initial_value(self.slave, ref, int(value))
            else:
                self.execution.real_initial_value(self.slave, ref, float(value))
        self.manipulator = CosimManipulator.create_override()
        self.observer = CosimObserver.create_last_value()
        self.execution.add_manipulator(self.manipulator)
        self.execution.add_observer(self.observer)
        self.v_in = [self.vr[f"velocity.{d}"] for d in self.dofs]
        self.f_out = [self.vr[f"force.{d}"] for d in self.dofs]

    def advance(self, time: float, h: float, velocity) -> np.ndarray:
        """Steps [time, time + h] with `velocity` held; returns force.<dof> after the step."""
        self.manipulator.slave_real_values(self.slave, self.v_in, list(velocity))
        if not self.execution.step():
            raise RuntimeError(f"libcosim step failed at t = {time}")
        return np.array(self.observer.last_real_values(self.slave, self.f_out))

    def close(self):
        self.execution.stop()


SCHEMES = ("zoh", "ramp")


def cosimulate(
    hull, structure: Structure, added_mass_inf, damping_direct, p0, h: float, steps: int, scheme: str = "ramp"
) -> np.ndarray:
    """Runs the master (module docs) over `steps` communication steps of `h`; p(t_n).

    scheme "zoh": the FMU gets v(t_n), the structure F_z(t_n), both held (first order).
    scheme "ramp": the FMU gets the extrapolated mid-step velocity 1.5 v(t_n) - 0.5 v(t_(n-1))
    held, the structure F_z ramped from F_z(t_n) to F_z(t_(n+1)) (FMU first; second order)."""
    if scheme not in SCHEMES:
        raise ValueError(f"scheme {scheme!r}: expected one of {SCHEMES}")
    t = structure.to_hull
    mass = structure.mass + t.T @ added_mass_inf @ t
    damping = structure.damping + t.T @ damping_direct @ t
    a, b = first_order(mass, damping, structure.stiffness)
    phi, gamma0, gamma1 = hold_discretization(a, b, h)
    n = len(mass)
    y = np.concatenate([np.asarray(p0, dtype=float), np.zeros(n)])
    out = np.empty((steps + 1, n))
    out[0] = y[:n]
    force = np.zeros(len(t))  # F_z(0) = C z(0) = 0: the network starts at rest
    previous = t @ y[n:]
    for k in range(steps):
        velocity = t @ y[n:]
        held = velocity if scheme == "zoh" else 1.5 * velocity - 0.5 * previous
        next_force = hull.advance(k * h, h, held) + damping_direct @ held  # F_z(t_(n+1))
        if scheme == "zoh":
            y = phi @ y + gamma0 @ (t.T @ force)
        else:
            y = phi @ y + gamma0 @ (t.T @ force) + gamma1 @ (t.T @ (next_force - force))
        previous = velocity
        force = next_force
        out[k + 1] = y[:n]
    return out


# --------------------------------------------------------------------------- plots


def pyplot():
    import matplotlib

    matplotlib.use("svg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"svg.hashsalt": "hydrofmu", "figure.dpi": 100, "font.size": 9})
    return plt


def envelope(values: np.ndarray, h: float, window: float):
    """Window midpoints and the largest value in each window of `window` seconds."""
    per = max(1, int(round(window / h)))
    count = len(values) // per
    blocks = values[: count * per].reshape(count, per).max(axis=1)
    return (np.arange(count) + 0.5) * per * h, np.maximum(blocks, 1e-12)


def provenance() -> str:
    """The command, the machine and the date, for figure captions."""
    import datetime
    import platform

    script = pathlib.Path(sys.argv[0]).resolve()
    if script.is_relative_to(ROOT):
        script = script.relative_to(ROOT)
    command = " ".join([".venv/bin/python", script.as_posix(), *sys.argv[1:]])
    cpus = os.cpu_count() or 1
    machine = f"{platform.processor() or platform.machine()} ({cpus} cores)"
    return f"{command} on {machine}, {datetime.date.today().isoformat()}"


def add_update_docs(parser) -> None:
    """Adds ``--update-docs`` to an example's command line (see :func:`apply_update_docs`)."""
    parser.add_argument("--update-docs", action="store_true",
                        help="write the figure into docs/figures (default: target/reports/figures)")


def apply_update_docs(args) -> None:
    """Sends the figures to the tracked docs/figures when ``args.update_docs`` is set."""
    global FIGURES
    if getattr(args, "update_docs", False):
        FIGURES = DOC_FIGURES


def save_svg(fig, name: str) -> pathlib.Path:
    FIGURES.mkdir(parents=True, exist_ok=True)
    fig.text(0.01, -0.02, provenance(), fontsize=7, color="#555555", ha="left", va="top")
    path = FIGURES / name
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")
    return path


def jsonable(value, skip=()):
    """``value`` with numpy arrays, numpy scalars and complex numbers (as ``[re, im]``) turned
    into JSON types, leaving out dict entries whose key is in ``skip``."""
    if isinstance(value, dict):
        return {k: jsonable(v, skip) for k, v in value.items() if k not in skip}
    if isinstance(value, (list, tuple)):
        return [jsonable(v, skip) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist(), skip)
    if isinstance(value, complex):
        return [value.real, value.imag]
    if isinstance(value, np.generic):
        return jsonable(value.item(), skip)
    return value
