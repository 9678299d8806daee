"""The fixed ship's mean sway drift by strip theory against Capytaine 3.0's 3D far-field drift.

What is compared. A box ship L x B x T = 60 m x 10 m x 5 m (L/B = 6), deep water,
rho = 1025 kg/m^3, g = 9.81 m/s^2, held fixed, in regular waves of wavenumber k with
kB/2 = 0.5, 1, 1.5, 2 and headings 90, 60, 30 deg (0 = waves towards +x): the mean sway force
per square metre of wave amplitude (SI, N/m^2).

- Ours: `fmu-pack sweep examples/ships/box_sway.xml --drift` (25 stations of the exact
  rectangular section examples/ships/box_section.xml): each section's 2D fixed drift at the
  wave's frequency, scaled by sin^2(beta), integrated along the ship (docs/SHIPS.md "Mean wave
  drift"). Also the alternative that takes the 2D drift at the transverse wavenumber
  k sin(beta) (our beam-sea sweep at omega' = sqrt(g k sin beta), times sin^2 beta).
- Capytaine: the fixed body's diffraction (indirect method, a lid on the waterplane against
  the irregular frequencies, 30 x 5 x 3 panels on the hull, 2 m squares, 360 hull and 124 lid
  panels) and the far-field mean drift from its Kochin function
  `H(theta) = 1/(4 pi) integral sigma e^{kz} e^{-ik(x cos theta + y sin theta)} dS`
  (`capytaine.post_pro.kochin.compute_kochin`, over hull and lid). Capytaine's Green function
  is -1/(4 pi) (1/r + ...), the far field of its wave part -(ik/2) e^{k(z+zeta)} H0^(1)(kR);
  with Capytaine's unit-amplitude incident wave (exp(-i omega t)) the scattered elevation
  far off is `eta_s = F(theta) e^{ikr} / sqrt(r)` with
  `F = (omega/g) 2 sqrt(2 pi k) e^{-i pi/4} H`. A scattered wave carries the momentum flux
  `rho g |F|^2 / 4` per radian in deep water (energy flux times c_g / c / c_g), and the fixed
  body scatters what it removes from the incident wave, so the mean force is Maruo's
  `D = (rho g / 4) integral |F|^2 ((cos b, sin b) - (cos theta, sin theta)) dtheta
     = 2 pi rho k^2 integral |H|^2 ((cos b, sin b) - (cos theta, sin theta)) dtheta`.
  The normalization is checked by the optical theorem of the fixed body (energy:
  `integral |F|^2 dtheta = -2 sqrt(2 pi / k) Re(e^{i pi/4} F(beta))`), within 2.2 % on this
  mesh (the conjugate phase convention misses by far), and by beam seas in short waves, where
  the long box reflects nearly all: our 2D section's `(rho g / 2) |R|^2 L` = 301.7 kN/m^2
  (|R| = 1.000) against Capytaine's 289.0.

Tolerances (measured 2026-11-29; ratio = Capytaine / strip theory):
- optical theorem: 3 % (at most 2.2 %, kB/2 = 2; a mesh of 48 x 8 x 4 panels gives 1.5 %, and
  its drift is within 1.5 % of this mesh's);
- the drift: each ratio within about +-3 % of the measured one (RATIO_BOUNDS), twice the mesh's
  own uncertainty. Beam seas 0.95 .. 0.98: strip theory has no end effects (waves diffracted
  round the ends of a ship 6 beams long) and is a few per cent high. 60 deg: 0.97 .. 0.99 from
  kB/2 = 1, 0.87 at 0.5. 30 deg: strip theory at the wave's own frequency is 36 % high at
  kB/2 = 0.5 (ratio 0.74), 13 % at 1 and 3 % at 2: best at beam seas and in short waves;
- the transverse-wavenumber alternative is closer in some long-wave cases and far worse in
  the longest oblique one (test_transverse_wavenumber_alternative).

The whole test runs in about 6 s (2 cores).
"""
import math
import subprocess

import numpy as np
import pytest

from conftest import ROOT

SHIP = ROOT / "examples" / "ships" / "box_sway.xml"
LENGTH, BEAM, DRAFT = 60.0, 10.0, 5.0
RHO, G = 1025.0, 9.81
HALF_BEAM_K = (0.5, 1.0, 1.5, 2.0)  # kB/2
HEADINGS = (90.0, 60.0, 30.0)  # deg
RESOLUTION = (30, 5, 3)  # Capytaine's hull panels along x, y, z
THETAS = np.linspace(-math.pi, math.pi, 721)[:-1]  # the Kochin function's directions
SWAY = 1  # the sway row of the ship's drift table (1-based DOF index)


# (heading, kB/2) -> bounds on Capytaine / strip theory, about the measured ratio in brackets.
RATIO_BOUNDS = {
    (90.0, 0.5): (0.92, 0.98),  # 0.948
    (90.0, 1.0): (0.95, 1.01),  # 0.981
    (90.0, 1.5): (0.95, 1.01),  # 0.976
    (90.0, 2.0): (0.93, 0.99),  # 0.958
    (60.0, 0.5): (0.84, 0.90),  # 0.872: long oblique waves, 3D diffraction
    (60.0, 1.0): (0.96, 1.02),  # 0.992
    (60.0, 1.5): (0.94, 1.00),  # 0.973
    (60.0, 2.0): (0.94, 1.00),  # 0.966
    (30.0, 0.5): (0.70, 0.77),  # 0.736: strip theory 36 % high
    (30.0, 1.0): (0.85, 0.92),  # 0.885
    (30.0, 1.5): (0.89, 0.95),  # 0.917
    (30.0, 2.0): (0.94, 1.00),  # 0.969
}


def omega_of(k):
    return math.sqrt(G * k)


@pytest.fixture(scope="module")
def capytaine_drift():
    """{(kB/2, heading): (sway drift N/m^2, optical theorem's relative defect)}."""
    import logging

    import capytaine as cpt
    from capytaine.post_pro.kochin import compute_kochin

    logging.getLogger("capytaine").setLevel(logging.ERROR)
    mesh = cpt.mesh_parallelepiped(size=(LENGTH, BEAM, DRAFT), center=(0, 0, -DRAFT / 2),
                                   resolution=RESOLUTION, missing_sides={"top"})
    body = cpt.FloatingBody(mesh=mesh, lid_mesh=mesh.generate_lid(z=0.0),
                            dofs=cpt.rigid_body_dofs(rotation_center=(0.0, 0.0, 0.0)))
    solver = cpt.BEMSolver(method="indirect")
    step = THETAS[1] - THETAS[0]
    out = {}
    for kb2 in HALF_BEAM_K:
        k = 2 * kb2 / BEAM
        omega = omega_of(k)
        for heading in HEADINGS:
            beta = math.radians(heading)
            problem = cpt.DiffractionProblem(body=body, wave_direction=beta, omega=omega,
                                             rho=RHO, g=G)
            result = solver.solve(problem, keep_details=True)
            scale = (omega / G) * 2 * math.sqrt(2 * math.pi * k) * np.exp(-0.25j * math.pi)
            far = scale * compute_kochin(result, THETAS)
            forward = scale * compute_kochin(result, np.array([beta]))[0]
            scattered = np.sum(np.abs(far) ** 2) * step
            extinct = -2 * math.sqrt(2 * math.pi / k) * np.real(np.exp(0.25j * math.pi) * forward)
            sway = RHO * G / 4 * np.sum(np.abs(far) ** 2 * (math.sin(beta) - np.sin(THETAS))) * step
            out[(kb2, heading)] = (sway, scattered / extinct - 1)
    return out


def strip_sway_drift(binary, tmp_path, omega, headings):
    """Our ship's sway drift (N/m^2) at one frequency: {heading: value}."""
    table = tmp_path / f"drift-{omega:.9f}.csv"
    subprocess.run(
        [str(binary), "sweep", str(SHIP), "-o", str(tmp_path / "coefficients.csv"),
         "--omega", f"{omega!r}:{omega!r}:1", "--headings", ",".join(map(str, headings)),
         "--drift", str(table)],
        check=True, capture_output=True,
    )
    values = {}
    for line in table.read_text().splitlines():
        if line.startswith("#") or line.startswith("omega"):
            continue
        _, j, heading, value = line.split(",")
        if int(j) == SWAY:
            values[float(heading)] = float(value)
    return values


@pytest.fixture(scope="module")
def strip_drift(fmu_pack_binary, tmp_path_factory):
    """{(kB/2, heading): (at the wave's frequency, at the transverse wavenumber k sin beta)}."""
    tmp = tmp_path_factory.mktemp("ship_drift")
    out = {}
    for kb2 in HALF_BEAM_K:
        k = 2 * kb2 / BEAM
        own = strip_sway_drift(fmu_pack_binary, tmp, omega_of(k), HEADINGS)
        for heading in HEADINGS:
            sine = math.sin(math.radians(heading))
            beam = strip_sway_drift(fmu_pack_binary, tmp, omega_of(k * sine), (90.0,))[90.0]
            out[(kb2, heading)] = (own[heading], beam * sine**2)
    return out


def table(capytaine_drift, strip_drift):
    rows = ["heading kB/2  Capytaine  strip  ratio  transverse-k  ratio"]
    for heading in HEADINGS:
        for kb2 in HALF_BEAM_K:
            cap = capytaine_drift[(kb2, heading)][0]
            own, transverse = strip_drift[(kb2, heading)]
            rows.append(f"{heading:5.0f} {kb2:5.2f} {cap / 1e3:9.1f} {own / 1e3:9.1f} "
                        f"{cap / own:6.3f} {transverse / 1e3:9.1f} {cap / transverse:6.3f}")
    return "\n".join(rows)


def test_kochin_normalization_by_the_optical_theorem(capytaine_drift):
    defects = {key: defect for key, (_, defect) in capytaine_drift.items()}
    assert max(abs(d) for d in defects.values()) < 0.03, defects


def test_beam_seas_short_waves_reflect_nearly_all(capytaine_drift, strip_drift):
    """A long box in short beam waves reflects nearly all: our (rho g / 2) |R|^2 L is within
    0.5 % of the full reflection rho g L / 2, Capytaine's 3D drift within 5 % of it."""
    wall = RHO * G * LENGTH / 2
    own = strip_drift[(2.0, 90.0)][0]
    cap = capytaine_drift[(2.0, 90.0)][0]
    assert abs(own / wall - 1) < 0.005, own
    assert abs(cap / wall - 1) < 0.05, cap


@pytest.mark.parametrize("heading, kb2", [(h, kb2) for h in HEADINGS for kb2 in HALF_BEAM_K])
def test_strip_theory_against_capytaine(capytaine_drift, strip_drift, heading, kb2):
    """Capytaine / strip theory within RATIO_BOUNDS (measured values in their comments)."""
    print("\n" + table(capytaine_drift, strip_drift))
    cap = capytaine_drift[(kb2, heading)][0]
    own = strip_drift[(kb2, heading)][0]
    low, high = RATIO_BOUNDS[(heading, kb2)]
    assert low < cap / own < high, (heading, kb2, cap, own)


def test_transverse_wavenumber_alternative(capytaine_drift, strip_drift):
    """The 2D drift at the transverse wavenumber k sin(beta) is closer to Capytaine at 60 deg in
    long waves (0.986 against 0.872 at kB/2 = 0.5) and at 30 deg for kB/2 = 1 and 1.5, the same
    within 0.5 % from kB/2 = 1.5 at 60 deg and at 2 at 30 deg, and twice too small at 30 deg,
    kB/2 = 0.5 (ratio 2.02 against 0.74): not better throughout, so the ship's drift keeps the
    wave's own frequency."""

    def error(key, which):
        return abs(capytaine_drift[key][0] / strip_drift[key][which] - 1)

    for key in [(0.5, 60.0), (1.0, 30.0), (1.5, 30.0)]:
        assert error(key, 1) < error(key, 0), key
    for key in [(1.5, 60.0), (2.0, 60.0), (2.0, 30.0)]:
        assert abs(error(key, 1) - error(key, 0)) < 0.005, key
    assert error((0.5, 30.0), 1) > 2 * error((0.5, 30.0), 0)
