"""A flexible barge in head seas: heave, pitch and the two lowest vertical bending modes of a
beam model, coupled to the barge's strip-theory FMU under fmpy, against the frequency-domain
response of the ship's own tables; the wet 2-node bending frequency and its damping.

Run (from the repository root, with the .venv of tests/python/requirements.txt):

    .venv/bin/python examples/cosim/flexible_barge.py            # 10 wave frequencies, writes target/reports/figures/cosim-flexible-barge.svg (--update-docs: docs/figures/)
    .venv/bin/python examples/cosim/flexible_barge.py --quick    # 3 wave frequencies, shorter decays, no figure (the test)

The FMU examples/cosim/fmus/FlexibleBargeVertical.fmu is packed on first use with
`fmu-pack pack examples/ships/flexible_barge_vertical.xml --omega 0.2:5:200 --headings 180
--panels 128 --band 0.2:5rad/s`: the barge of examples/ships/flexible_barge.xml (100 m x 10 m
x 5 m, Lewis sections of area coefficient 0.95 on 21 stations) in heave, pitch and its computed
girder modes vb1, vb2, for head seas only; the band holds the wet 2-node frequency (4.01
rad/s) with margin; 128 panels per section (the default 64 leaves fewer than 10 panels per
wavelength above 4.2 rad/s and puts the vb1 added mass 1.9 % high at 3.9 rad/s; 128 agree with
256 to 1e-4 up to 4.7 rad/s; a grid to 6 rad/s would need more: there the 128-panel sweep
has a 3 % spike in added mass, and the fit's largest error rises from 0.22 % to 0.98 %).

Structure (the "beam model"; coordinates p = the FMU's heave, pitch, vb1, vb2, so T = I):

* the hull girder of the ship file: a free-free Euler-Bernoulli beam on the 21 stations,
  mass 48,700 kg/m, EI = 3e11 N m^2, Hermite cubic elements with consistent mass, as
  fmu-pack's girder model (src/ship/girder.rs); computed again here, and its modal mass and
  stiffness checked against what fmu-pack prints (the FMU's documentation/scene.txt);
* M_s = Phi^T M_FE Phi with Phi = [heave w = 1, pitch w = -x, vb1, vb2]: the total mass m L,
  the pitch inertia m L^3 / 12 about the origin and the modal masses; the elastic modes are
  mass-orthogonal to the rigid motions, so M_s is diagonal. The mass is lumped on the
  centreline at the still waterline: centre of gravity z_G = 0 (a choice; no rotary inertia, as
  the girder model);
* K = the girder's modal stiffness + the FMU's stiffness_hydrostatic (buoyancy: rho g B L in
  heave, rho g (I_wp + V z_B) in pitch, the waterplane part rho g int B w_i w_j dx of the
  modes) + the weight's -m g z_G in pitch (zero for z_G = 0) + the initial-stress terms of the
  sections' rotations w'(x) that the ship gives rigid pitch only (docs/SHIPS.md, "Restoring"):
  rho g z_B int A w_i' w_j' dx for every pair except pitch-pitch, with z_B from the FMU's pitch
  entry (z_B = -2.40 m); -0.38 % of vb1's modal stiffness (the girder's compression by the
  static pressure on its ends);
* C_s = structural damping of the girder modes, 1 % of critical of each dry mode (an assumed
  value; potential flow damps the 2-node mode by almost nothing, see below).

The barge weighs 48,700 kg/m, its Lewis sections displace rho 0.95 B T = 48,687.5 kg/m: the
linear model is about the equilibrium, which lies 1.2 mm deeper (left out).

Frequency domain (convention exp(+i omega t)), per unit wave amplitude, head seas (180 deg):

    [K - omega^2 (M_s + A~(omega)) + i omega C_s] P = X(omega, 180)

A~ and X from `fmu-pack sweep SHIP --omega 0.2:5:200 --headings 180 --panels 128 --excitation`
("table"), or A~ the FMU's network H(i omega) ("network": what the time domain solves). The wet
2-node mode: the frequency-dependent eigenproblem det[K + i Omega C - Omega^2 (M_s + A~(Omega))]
= 0 (A~ continued to the complex root to first order, iterated), the receptance peak |vb1 / f_vb1| (frequency and
half-power width, A~ interpolated between the table's frequencies), and the eigenvalue of the
coupled structure + network (Schilder et al., eq. 19), beside the dry frequency.

Time domain (hydrocosim.cosimulate under fmpy, scheme "ramp", h = 0.02 s, 78 steps per wet
2-node period): (a) regular head waves, amplitude 0.1 m, wave.ramp 20 s, 600 s; the RAO is the
least-squares harmonic of the last 60 s; (b) free decay in calm water from vb1 = 0.05 (5 cm at
the ends), at rest: a damped cosine fitted to vb1(t) gives the wet frequency and damping ratio;
once with the structural damping and once without it (the water's own share); the same fit on
the monolithic solution (Schilder et al., eq. 19) separates the coupling error from the fit's.

The FMU's table holds heading 180 only, and wave.heading starts at 0: the master sets the
heading before the other wave parameters (the FMU refuses any wave parameter while the heading
is one its table lacks).
"""
from __future__ import annotations

import argparse
import json
import pathlib
import re
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
import zipfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import hydrocosim as hc  # noqa: E402

SHIP = "examples/ships/flexible_barge_vertical.xml"  # relative to the repository root
OMEGA_GRID = "0.2:5:200"  # rad/s, log-spaced: the sweep's and the excitation table's
SWEEP_ARGS = [SHIP, "--omega", OMEGA_GRID, "--headings", "180", "--panels", "128"]
PACK_ARGS = SWEEP_ARGS + ["--band", "0.2:5rad/s"]
FMU_NAME = "FlexibleBargeVertical"
DOFS = ("heave", "pitch", "vb1", "vb2")
HEADING = 180.0  # deg, head seas
AMPLITUDE = 0.1  # m, wave amplitude (height 0.2 m)
RAMP = 20.0  # s
DURATION = 600.0  # s, each regular-wave run (the 2-node mode's transient decays as e^(-t / 36 s))
WINDOW = 60.0  # s, the last part of a run that the harmonic fit sees
STEP = 0.02  # s, communication step
STRUCTURAL_DAMPING = 0.01  # of critical, each dry girder mode
INITIAL_VB1 = 0.05  # m at the ends (vb1 amplitude), the free decay's start
DECAY = 40.0  # s, the free decay (quick: 16 s)
QUICK_DECAY = 16.0
# Wave frequencies (rad/s) of the co-simulated points; each is moved to the nearest frequency
# of the table, so that the FMU's excitation is the table's value (no interpolation).
# "wet": the table frequency nearest the wet 2-node frequency, "wet+": the next one above.
MARKERS = (0.5, 0.78, 1.1, 1.6, 2.4, 3.3, 3.8, "wet", "wet+", 4.5)
QUICK_MARKERS = (0.78, 1.1, "wet")
FIGURE = "cosim-flexible-barge.svg"


# --------------------------------------------------------------------------- structure


def ship_structure(path=hc.ROOT / SHIP):
    """Stations x (m), mass per length (kg/m), vertical EI (N m^2) and the sections' submerged
    area (m^2, B T sigma of the Lewis forms) of the ship file."""
    root = ET.parse(path).getroot()
    stations = root.findall("station")
    x = np.array([float(s.get("x")) for s in stations])
    mass = np.array([float(s.get("mass")) for s in stations])
    ei = np.array([float(s.get("bending_stiffness_vertical")) for s in stations])
    lewis = [s.find("lewis") for s in stations]
    area = np.array([float(e.get("breadth")) * float(e.get("draft")) * float(e.get("area_coefficient")) for e in lewis])
    return x, mass, ei, area


def beam_matrices(x, mass, ei):
    """Hermite cubic elements (w, w' per node), consistent mass, each element with the mean of
    its two stations' data (as src/ship/girder.rs): K, M (2n x 2n) and the geometric matrix
    G = int w_i' w_j' dx."""
    n = len(x)
    k, m, g = (np.zeros((2 * n, 2 * n)) for _ in range(3))
    for e in range(n - 1):
        l = x[e + 1] - x[e]
        stiffness, mu = (ei[e] + ei[e + 1]) / 2, (mass[e] + mass[e + 1]) / 2
        ke = np.array([[12, 6 * l, -12, 6 * l], [6 * l, 4 * l * l, -6 * l, 2 * l * l],
                       [-12, -6 * l, 12, -6 * l], [6 * l, 2 * l * l, -6 * l, 4 * l * l]])
        me = np.array([[156, 22 * l, 54, -13 * l], [22 * l, 4 * l * l, 13 * l, -3 * l * l],
                       [54, 13 * l, 156, -22 * l], [-13 * l, -3 * l * l, -22 * l, 4 * l * l]])
        ge = np.array([[36, 3 * l, -36, 3 * l], [3 * l, 4 * l * l, -3 * l, -l * l],
                       [-36, -3 * l, 36, -3 * l], [3 * l, -l * l, -3 * l, 4 * l * l]])
        s = slice(2 * e, 2 * e + 4)
        k[s, s] += stiffness / l**3 * ke
        m[s, s] += mu * l / 420 * me
        g[s, s] += ge / (30 * l)
    return k, m, g


def girder_modes(x, mass, ei, count=2):
    """The lowest `count` elastic free-free modes: (shapes over the FE DOFs, dry omega), each
    scaled to 1 m at its largest station, positive at the stern (as fmu-pack)."""
    k, m, _ = beam_matrices(x, mass, ei)
    chol = np.linalg.cholesky(m)
    inv = np.linalg.inv(chol)
    lam, vec = np.linalg.eigh(inv @ k @ inv.T)
    order = np.argsort(lam)[2 : 2 + count]  # the two rigid solutions first
    shapes = inv.T @ vec[:, order]
    w = shapes[0::2]
    scale = np.max(np.abs(w), axis=0) * np.where(w[0] < 0, -1.0, 1.0)
    return shapes / scale, np.sqrt(lam[order])


def scene_report(fmu) -> tuple[dict, float]:
    """What fmu-pack printed (the FMU's documentation/scene.txt): the girder modes' dry
    frequency, modal mass and stiffness, and the fit's largest error (a fraction)."""
    with zipfile.ZipFile(fmu) as archive:
        text = archive.read("documentation/scene.txt").decode()
    number = r"([\d.e+-]+)"
    pattern = rf"girder mode (\w+): dry natural frequency {number} rad/s, modal mass {number}, modal stiffness {number}"
    modes = {
        name: {"omega": float(w), "modal_mass": float(mm), "modal_stiffness": float(kk)}
        for name, w, mm, kk in re.findall(pattern, text)
    }
    return modes, float(re.search(rf"largest error {number} %", text).group(1)) / 100


def structure(hydrostatic: np.ndarray, damping_ratio: float = STRUCTURAL_DAMPING) -> tuple[hc.Structure, dict]:
    """The beam model in the FMU's coordinates (module docs) and its parts."""
    x, mass, ei, area = ship_structure()
    k_fe, m_fe, g_fe = beam_matrices(x, mass, ei)
    shapes, dry = girder_modes(x, mass, ei)
    rigid = np.zeros((2 * len(x), 2))
    rigid[0::2, 0] = 1.0  # heave: w = 1
    rigid[0::2, 1], rigid[1::2, 1] = -x, -1.0  # pitch: w = -x theta, w' = -theta
    phi = np.hstack([rigid, shapes])
    m_s = phi.T @ m_fe @ phi
    k_girder = phi.T @ k_fe @ phi
    # Initial stress: rho g z_B int A w_i' w_j' dx, with the (prismatic) section's area A and
    # z_B from the FMU's pitch entry C_pp = rho g (I_wp + V z_B) and its heave entry rho g B L.
    length = x[-1] - x[0]
    breadth = hydrostatic[0, 0] / (hc.RHO * hc.G * length)
    area = float(np.mean(area))
    z_b = (hydrostatic[1, 1] / (hc.RHO * hc.G) - breadth * length**3 / 12) / (area * length)
    initial_stress = hc.RHO * hc.G * area * z_b * (phi.T @ g_fe @ phi)
    initial_stress[1, 1] = 0.0  # the ship's rigid pitch holds rho g V z_B already
    z_g = 0.0
    weight = np.zeros((4, 4))
    weight[1, 1] = -m_s[0, 0] * hc.G * z_g
    stiffness = k_girder + hydrostatic + initial_stress + weight
    damping = np.zeros((4, 4))
    for j in (2, 3):
        damping[j, j] = 2 * damping_ratio * dry[j - 2] * m_s[j, j]
    parts = {
        "length": length,
        "mass_per_length": float(np.mean(mass)),
        "bending_stiffness": float(np.mean(ei)),
        "total_mass": m_s[0, 0],
        "pitch_inertia": m_s[1, 1],
        "modal_mass": np.diag(m_s)[2:],
        "modal_stiffness": np.diag(k_girder)[2:],
        "dry_omega": dry,
        "mass_offdiagonal": np.max(np.abs(m_s - np.diag(np.diag(m_s)))) / np.max(np.abs(m_s)),
        "stiffness_girder_rigid": np.max(np.abs(k_girder[:2])) / np.max(np.abs(k_girder)),
        "z_b": z_b,
        "z_g": z_g,
        "initial_stress": initial_stress,
        "initial_stress_vb1_relative": initial_stress[2, 2] / k_girder[2, 2],
        "station_shapes": shapes[0::2].T,
    }
    return hc.Structure(m_s, damping, stiffness, np.eye(4)), parts


# --------------------------------------------------------------------------- tables


def ship_tables(sweep_args=SWEEP_ARGS):
    """`fmu-pack sweep SHIP ... --excitation`: (omega, A~ [n, 4, 4], X at HEADING [n, 4]), SI."""
    with tempfile.TemporaryDirectory() as tmp:
        radiation, excitation = pathlib.Path(tmp) / "a.csv", pathlib.Path(tmp) / "x.csv"
        hc.fmu_pack(["sweep", *sweep_args, "-o", str(radiation), "--excitation", str(excitation)])
        a_rows = [r.split(",") for r in radiation.read_text().splitlines() if r and r[0] not in "#o"]
        x_rows = [r.split(",") for r in excitation.read_text().splitlines() if r and r[0] not in "#o"]
    omegas = np.array(sorted({float(r[0]) for r in a_rows if r[0] != "inf"}))
    index = {w: k for k, w in enumerate(omegas)}
    added = np.zeros((len(omegas), 4, 4), complex)
    for w, i, j, re_, im in a_rows:
        if w != "inf":
            added[index[float(w)], int(i) - 1, int(j) - 1] = complex(float(re_), float(im))
    force = np.zeros((len(omegas), 4), complex)
    for w, j, heading, re_, im in x_rows:
        if float(heading) % 360 == HEADING:
            force[index[float(w)], int(j) - 1] = complex(float(re_), float(im))
    return omegas, added, force


def rao(st: hc.Structure, omega: float, added_mass: np.ndarray, excitation: np.ndarray) -> np.ndarray:
    dynamic = st.stiffness - omega**2 * (st.mass + added_mass) + 1j * omega * st.damping
    return np.linalg.solve(dynamic, excitation)


def interpolated(omegas: np.ndarray, added: np.ndarray, omega: float) -> np.ndarray:
    """A~ at omega, linear between the table's frequencies."""
    k = int(np.clip(np.searchsorted(omegas, omega) - 1, 0, len(omegas) - 2))
    f = (omega - omegas[k]) / (omegas[k + 1] - omegas[k])
    return (1 - f) * added[k] + f * added[k + 1]


def slope(omegas: np.ndarray, added: np.ndarray, omega: float) -> np.ndarray:
    """dA~/domega at omega: the difference over the table interval that holds it."""
    k = int(np.clip(np.searchsorted(omegas, omega) - 1, 0, len(omegas) - 2))
    return (added[k + 1] - added[k]) / (omegas[k + 1] - omegas[k])


def wet_mode_table(st: hc.Structure, omegas, added, mode: int = 2, iterations: int = 50):
    """The wet eigenvalue lambda = i Omega of `mode` from the table: the root of
    det[K + lambda C_s + lambda^2 (M_s + A~(Omega))] = 0 nearest the mode, with A~ continued
    to the complex Omega to first order from the real axis, A~(w) + (Omega - w) dA~/dw at
    w = Re Omega (A~ = a - i b / w carries the radiation damping), iterated. The slope term
    matters for a lightly damped mode: with a' = 2e4 kg s/rad at 4 rad/s it lowers the 2-node
    mode's decay rate by omega a' / (2 (M + a)) = 1.5 %, as it narrows the receptance peak."""
    n = len(st.mass)
    lam = 1j * np.sqrt(st.stiffness[mode, mode] / (st.mass[mode, mode] + added[-1, mode, mode].real))
    for _ in range(iterations):
        omega = lam.imag
        big_omega = -1j * lam
        mass = st.mass + interpolated(omegas, added, omega) + (big_omega - omega) * slope(omegas, added, omega)
        inv = np.linalg.inv(mass)
        companion = np.block([[np.zeros((n, n)), np.eye(n)], [-inv @ st.stiffness, -inv @ st.damping]])
        values, vectors = np.linalg.eig(companion)
        weight = np.abs(vectors[mode]) / np.linalg.norm(vectors[:n], axis=0)
        candidates = np.where((values.imag > 0) & (weight > 0.5))[0]
        new = values[candidates[np.argmin(np.abs(values[candidates] - lam))]]
        if abs(new - lam) < 1e-14 * abs(lam):
            return new
        lam = new
    return lam


def wet_mode_network(st: hc.Structure, network: hc.Network, near: complex) -> complex:
    """The eigenvalue of structure + network (Schilder et al., eq. 19) nearest `near`."""
    values = np.linalg.eigvals(hc.coupled_system(st, network))
    return values[np.argmin(np.abs(values - near))]


def receptance_peak(st: hc.Structure, added_of, centre: float, mode: int = 2, points: int = 4001):
    """Peak of |p_mode / f_mode| near `centre`: (omega, height, half-power damping ratio)."""
    grid = np.linspace(0.95 * centre, 1.05 * centre, points)
    unit = np.zeros(4)
    unit[mode] = 1.0
    values = np.array([abs(rao(st, w, added_of(w), unit)[mode]) for w in grid])
    k = int(np.argmax(values))
    if k in (0, points - 1):
        raise ValueError("receptance peak at the edge of its grid")
    half = values[k] / np.sqrt(2)
    lo = np.interp(half, values[: k + 1], grid[: k + 1])
    hi = np.interp(-half, -values[k:], grid[k:])
    return float(grid[k]), float(values[k]), float((hi - lo) / (2 * grid[k]))


# --------------------------------------------------------------------------- time domain


def damped_cosine(t: np.ndarray, x: np.ndarray):
    """Least-squares fit x = e^(-sigma t) (c cos w t + s sin w t): (w, sigma, rms residual
    relative to the first amplitude). Variable projection: c, s linear; (w, sigma) by
    Gauss-Newton from the zero crossings and the peak envelope."""
    crossings = t[:-1][np.sign(x[:-1]) != np.sign(x[1:])]
    w = np.pi * (len(crossings) - 1) / (crossings[-1] - crossings[0])
    peaks = [i for i in range(1, len(x) - 1) if x[i] > x[i - 1] and x[i] >= x[i + 1] and x[i] > 0]
    sigma = -np.polyfit(t[peaks], np.log(x[peaks]), 1)[0] if len(peaks) > 2 else 0.0

    def residual(p):
        w_, s_ = p
        e = np.exp(-s_ * t)
        basis = np.column_stack([e * np.cos(w_ * t), e * np.sin(w_ * t)])
        coefficients, *_ = np.linalg.lstsq(basis, x, rcond=None)
        return x - basis @ coefficients

    p = np.array([w, sigma])
    for _ in range(50):
        r = residual(p)
        jac = np.column_stack([(residual(p + d) - r) / d[k] for k, d in enumerate(np.diag([1e-7 * p[0], 1e-9]))])
        step, *_ = np.linalg.lstsq(jac, -r, rcond=None)
        p = p + step
        if np.all(np.abs(step) < [1e-12 * p[0], 1e-13]):
            break
    rms = np.sqrt(np.mean(residual(p) ** 2)) / abs(x[0])
    return float(p[0]), float(p[1]), float(rms)


def steady_amplitudes(p: np.ndarray, h: float, omega: float, duration: float):
    """(RAO over the window, the two half-window RAOs' difference), per unit amplitude."""
    t = np.arange(len(p)) * h
    window = t > duration - WINDOW - 1e-9
    middle = t > duration - WINDOW / 2 - 1e-9
    whole = hc.harmonic_fit(t[window], p[window], omega) / AMPLITUDE
    first = hc.harmonic_fit(t[window & ~middle], p[window & ~middle], omega) / AMPLITUDE
    second = hc.harmonic_fit(t[middle], p[middle], omega) / AMPLITUDE
    return whole, np.abs(first - second)


# --------------------------------------------------------------------------- run


def run(quick: bool = False, fmu=None, plot: bool = True) -> dict:
    started = time.perf_counter()
    fmu = hc.ensure_fmu(FMU_NAME, PACK_ARGS, fmu)
    network = hc.Network.from_fmu(fmu).scaled(hc.RHO, hc.G)
    probe = hc.FmpyHull(fmu)
    added_mass_inf, damping_direct = probe.matrix("added_mass_inf"), probe.matrix("damping_direct")
    hydrostatic = probe.matrix("stiffness_hydrostatic")
    dofs = probe.dofs
    probe.close()
    assert tuple(dofs) == tuple(network.dofs) == DOFS, dofs
    st, parts = structure(hydrostatic)
    st_water, _ = structure(hydrostatic, damping_ratio=0.0)
    printed, pack_fit_error = scene_report(fmu)
    sweep_start = time.perf_counter()
    omegas, added, force = ship_tables()
    sweep_seconds = time.perf_counter() - sweep_start

    # Frequency domain.
    table_rao = np.array([rao(st, w, a, x) for w, a, x in zip(omegas, added, force)])
    network_rao = np.array([rao(st, w, network.complex_added_mass(w), x) for w, x in zip(omegas, force)])
    wet = {}
    for name, s in (("structural", st), ("water_only", st_water)):
        lam_table = wet_mode_table(s, omegas, added)
        lam_network = wet_mode_network(s, network, lam_table)
        wet[name] = {
            "table_omega": abs(lam_table),
            "table_damped_omega": lam_table.imag,
            "table_zeta": -lam_table.real / abs(lam_table),
            "network_omega": abs(lam_network),
            "network_damped_omega": lam_network.imag,
            "network_zeta": -lam_network.real / abs(lam_network),
        }
    centre = wet["structural"]["table_damped_omega"]
    peak_table = receptance_peak(st, lambda w: interpolated(omegas, added, w), centre)
    peak_network = receptance_peak(st, network.complex_added_mass, centre)
    wet["structural"].update(
        {
            "table_peak_omega": peak_table[0], "table_peak": peak_table[1], "table_peak_zeta": peak_table[2],
            "network_peak_omega": peak_network[0], "network_peak": peak_network[1],
            "network_peak_zeta": peak_network[2],
        }
    )
    # The fit's error as fmu-pack states it (pack_fit_error), and per frequency: |H - A~| over
    # sqrt(|A~_ii A~_jj|) at the same frequency (larger where A~ is smallest).
    fit_error_local = np.max(
        [np.max(np.abs(network.complex_added_mass(w) - a) / np.sqrt(np.outer(np.abs(np.diag(a)), np.abs(np.diag(a)))))
         for w, a in zip(omegas, added)]
    )

    # Time domain (a): regular head waves.
    points = []
    cosim_seconds = 0.0
    for marker in QUICK_MARKERS if quick else MARKERS:
        target = centre if str(marker).startswith("wet") else marker
        k = int(np.argmin(np.abs(omegas - target))) + (marker == "wet+")
        omega = omegas[k]
        period = 2 * np.pi / omega
        steps = int(round(DURATION / STEP))
        # The heading first: the FMU's table holds 180 only, and while wave.heading is still its
        # start value 0 every other wave parameter is refused (naming wave.heading).
        waves = {"heading": HEADING, "kind": 1, "height": 2 * AMPLITUDE, "period": period, "ramp": RAMP}
        hull = hc.FmpyHull(fmu, waves=waves)
        t0 = time.perf_counter()
        try:
            p = hc.cosimulate(hull, st, added_mass_inf, damping_direct, np.zeros(4), STEP, steps, "ramp")
        finally:
            hull.close()
        cosim_seconds += time.perf_counter() - t0
        measured, halves = steady_amplitudes(p, STEP, omega, DURATION)
        points.append(
            {"marker": marker, "omega": omega, "period": period, "cosim": measured, "halves": halves,
             "table": table_rao[k], "network": network_rao[k], "steps": steps}
        )
    scale = np.max(np.abs(table_rao), axis=0)

    def worst(key_a, key_b):
        return dict(zip(DOFS, np.max([np.abs(q[key_a] - q[key_b]) / scale for q in points], axis=0).tolist()))

    # Time domain (b): free decay of vb1 in calm water.
    decays = {}
    duration = QUICK_DECAY if quick else DECAY
    steps = int(round(duration / STEP))
    p0 = np.array([0.0, 0.0, INITIAL_VB1, 0.0])
    for name, s in (("structural", st), ("water_only", st_water)):
        hull = hc.FmpyHull(fmu)
        t0 = time.perf_counter()
        try:
            p = hc.cosimulate(hull, s, added_mass_inf, damping_direct, p0, STEP, steps, "ramp")
        finally:
            hull.close()
        cosim_seconds += time.perf_counter() - t0
        mono = hc.monolithic(s, network, p0, STEP, steps)
        t = np.arange(steps + 1) * STEP
        w_d, sigma, rms = damped_cosine(t, p[:, 2])
        w_mono, sigma_mono, _ = damped_cosine(t, mono[:, 2])
        decays[name] = {
            "duration": duration,
            "damped_omega": w_d,
            "omega": float(np.hypot(w_d, sigma)),
            "zeta": float(sigma / np.hypot(w_d, sigma)),
            "fit_rms_relative": rms,
            "monolithic_omega": float(np.hypot(w_mono, sigma_mono)),
            "monolithic_zeta": float(sigma_mono / np.hypot(w_mono, sigma_mono)),
            "coupling_error_vb1": float(np.max(np.abs(p[:, 2] - mono[:, 2])) / INITIAL_VB1),
            "largest_heave_m": float(np.max(np.abs(p[:, 0]))),
            "largest_pitch_rad": float(np.max(np.abs(p[:, 1]))),
            "largest_vb2": float(np.max(np.abs(p[:, 3]))),
            "series": p,
        }

    result = {
        "quick": quick,
        "step": STEP,
        "amplitude": AMPLITUDE,
        "heading": HEADING,
        "duration": DURATION,
        "window": WINDOW,
        "structural_damping": STRUCTURAL_DAMPING,
        "structure": parts,
        "printed_girder_modes": printed,
        "stiffness_hydrostatic": hydrostatic,
        "added_mass_inf": added_mass_inf,
        "fit_error": pack_fit_error,
        "fit_error_local": float(fit_error_local),
        "wet": wet,
        "curves": {"omega": omegas, "table": table_rao, "network": network_rao},
        "largest_rao": dict(zip(DOFS, scale.tolist())),
        "points": points,
        "cosim_minus_network": worst("cosim", "network"),
        "cosim_minus_table": worst("cosim", "table"),
        "network_minus_table": worst("network", "table"),
        "transient_left": dict(zip(DOFS, np.max([q["halves"] / scale for q in points], axis=0).tolist())),
        # Per point, relative to that point's own |RAO|: what a resonance does to the errors.
        "local": [
            {
                "omega": q["omega"],
                "cosim_minus_network": (np.abs(q["cosim"] - q["network"]) / np.abs(q["network"])).tolist(),
                "cosim_minus_table": (np.abs(q["cosim"] - q["table"]) / np.abs(q["table"])).tolist(),
            }
            for q in points
        ],
        "decay": decays,
        "seconds": {"sweep": sweep_seconds, "cosimulation": cosim_seconds},
    }
    if plot and not quick:
        result["figure"] = str(figure(result))
    result["seconds"]["total"] = time.perf_counter() - started
    return result


# --------------------------------------------------------------------------- output


def figure(result: dict) -> pathlib.Path:
    plt = hc.pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(8.5, 7.0))
    omega = result["curves"]["omega"]
    units = {"heave": "m/m", "pitch": "rad/m", "vb1": "m at the ends per m"}
    for k, name in enumerate(("heave", "pitch", "vb1")):
        ax = axes.flat[k]
        j = DOFS.index(name)
        ax.semilogy(omega, np.abs(result["curves"]["table"][:, j]), "-", color="C0", lw=1.2, label="table (sweep)")
        ax.semilogy(omega, np.abs(result["curves"]["network"][:, j]), ":", color="k", lw=0.9, label="network H(i omega)")
        w = [q["omega"] for q in result["points"]]
        ax.semilogy(w, [abs(q["cosim"][j]) for q in result["points"]], "o", mfc="none", color="C3", ms=6,
                    label="co-simulation (fmpy)")
        ax.set_title(f"{name} RAO ({units[name]}), head seas", fontsize=9)
        ax.set_xlim(0, 5.2)
        ax.set_xlabel("omega (rad/s)")
        ax.grid(True, lw=0.3, alpha=0.5)
        if name == "vb1":
            wet = result["wet"]["structural"]
            ax.axvline(wet["table_omega"], color="k", ls="--", lw=0.8,
                       label=f"wet 2-node {wet['table_omega']:.3f} rad/s (dry {result['structure']['dry_omega'][0]:.3f})")
        ax.legend(loc="lower left", fontsize=7)
    ax = axes.flat[3]
    wet = result["wet"]
    for name, colour, label in (("structural", "C0", "1 % structural damping"), ("water_only", "C1", "water only")):
        d = result["decay"][name]
        p = np.asarray(d["series"])
        t = np.arange(len(p)) * result["step"]
        text = f"{label}: measured {d['omega']:.4f} rad/s, zeta {d['zeta']:.2e}"
        if name == "structural":
            ax.plot(t, p[:, 2] * 100, "-", color=colour, lw=0.6, label=text)
        else:  # its crests only: the line would hide the other
            x = p[:, 2]
            crests = [i for i in range(1, len(x) - 1) if x[i] > x[i - 1] and x[i] >= x[i + 1] and x[i] > 0]
            ax.plot(t[crests], x[crests] * 100, ".", color=colour, ms=3, label=text + " (crests)")
        w = wet[name]
        envelope = 100 * INITIAL_VB1 * np.exp(-w["table_zeta"] * w["table_omega"] * t)
        ax.plot(t, envelope, "--", color="k", lw=0.9)
        ax.plot(t, -envelope, "--", color="k", lw=0.9)
    ax.plot([], [], "--", color="k", lw=0.9, label="envelope of the table's wet mode")
    ax.set_title(f"Free decay of vb1 in calm water (co-simulation, h = {result['step']} s)", fontsize=9)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("vb1 (cm at the ends)")
    ax.set_ylim(-8, 8)
    ax.legend(loc="upper center", fontsize=6.5, ncol=1)
    fig.suptitle("Flexible barge 100 m x 10 m x 5 m, head seas: heave, pitch, vb1 RAOs and the wet 2-node mode",
                 fontsize=9)
    fig.tight_layout()
    path = hc.save_svg(fig, FIGURE)
    plt.close(fig)
    return path


def _fmt(errors: dict) -> str:
    return ", ".join(f"{k} {v:.1e}" for k, v in errors.items())


def report(result: dict) -> str:
    s = result["structure"]
    lines = [
        f"beam: L {s['length']:.0f} m, {s['mass_per_length']:.0f} kg/m, EI {s['bending_stiffness']:.3g} N m2; "
        f"mass {s['total_mass']:.5e} kg, pitch inertia {s['pitch_inertia']:.5e} kg m2; z_G = {s['z_g']} m, "
        f"z_B = {s['z_b']:.3f} m",
    ]
    for k, name in enumerate(("vb1", "vb2")):
        pr = result["printed_girder_modes"][name]
        lines.append(
            f"  {name}: dry {s['dry_omega'][k]:.4f} rad/s (fmu-pack {pr['omega']:.4f}), modal mass "
            f"{s['modal_mass'][k]:.6e} ({pr['modal_mass']:.6e}), modal stiffness {s['modal_stiffness'][k]:.6e} "
            f"({pr['modal_stiffness']:.6e})"
        )
    lines.append(f"  initial stress / vb1 modal stiffness: {s['initial_stress_vb1_relative']:.2e}")
    lines.append(
        f"fit: largest error {100 * result['fit_error']:.3f} % (fmu-pack); {100 * result['fit_error_local']:.3f} % of "
        "sqrt(|A_ii A_jj|) at the same frequency"
    )
    for name, w in result["wet"].items():
        lines.append(
            f"wet 2-node mode ({name}): table {w['table_omega']:.4f} rad/s zeta {w['table_zeta']:.3e}; "
            f"network {w['network_omega']:.4f} rad/s zeta {w['network_zeta']:.3e}"
        )
    w = result["wet"]["structural"]
    lines.append(
        f"  receptance peak: table {w['table_peak_omega']:.4f} rad/s zeta(half power) {w['table_peak_zeta']:.3e} "
        f"{w['table_peak']:.3e} m/N; network {w['network_peak_omega']:.4f} rad/s {w['network_peak_zeta']:.3e} "
        f"{w['network_peak']:.3e} m/N"
    )
    for name, d in result["decay"].items():
        lines.append(
            f"free decay ({name}, {d['duration']:.0f} s): {d['omega']:.4f} rad/s (damped {d['damped_omega']:.4f}), "
            f"zeta {d['zeta']:.3e} (monolithic {d['monolithic_omega']:.4f}, {d['monolithic_zeta']:.3e}), fit rms "
            f"{d['fit_rms_relative']:.1e}, coupling error {d['coupling_error_vb1']:.1e} "
            f"of vb1(0); largest heave {d['largest_heave_m']:.1e} m, pitch {d['largest_pitch_rad']:.1e}, vb2 "
            f"{d['largest_vb2']:.1e}"
        )
    lines.append(f"regular head waves, a = {result['amplitude']} m, h = {result['step']} s, largest RAO: "
                 + _fmt(result["largest_rao"]))
    lines.append("  omega    " + "  ".join(f"|{c}| cosim (table)      " for c in DOFS[:3]))
    for q in result["points"]:
        cells = "  ".join(f"{abs(q['cosim'][j]):.4e} ({abs(q['table'][j]):.4e})" for j in range(3))
        lines.append(f"  {q['omega']:.4f}  {cells}")
    lines.append("  relative to each coordinate's largest RAO:")
    lines.append("    co-simulation - network RAO: " + _fmt(result["cosim_minus_network"]))
    lines.append("    network - table RAO (fit):   " + _fmt(result["network_minus_table"]))
    lines.append("    co-simulation - table RAO:   " + _fmt(result["cosim_minus_table"]))
    lines.append("    transient left (halves):     " + _fmt(result["transient_left"]))
    lines.append("  relative to the point's own |RAO|, co-simulation - network | co-simulation - table:")
    for q in result["local"]:
        lines.append(
            f"    {q['omega']:.4f}: "
            + ", ".join(f"{c} {v:.1e}" for c, v in zip(DOFS, q["cosim_minus_network"]))
            + " | "
            + ", ".join(f"{c} {v:.1e}" for c, v in zip(DOFS, q["cosim_minus_table"]))
        )
    sec = result["seconds"]
    lines.append(f"seconds: sweep {sec['sweep']:.2f}, co-simulation {sec['cosimulation']:.1f}, total {sec['total']:.1f}")
    if "figure" in result:
        lines.append(f"figure: {result['figure']}")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="3 wave frequencies, 16 s decays, no figure")
    parser.add_argument("--fmu", help=f"the barge FMU (default: examples/cosim/fmus/{FMU_NAME}.fmu, packed if missing)")
    parser.add_argument("--json", help="also write the results to this JSON file")
    hc.add_update_docs(parser)
    args = parser.parse_args(argv)
    hc.apply_update_docs(args)
    result = run(args.quick, args.fmu)
    print(report(result))
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(hc.jsonable(result, skip=("series",)), indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
