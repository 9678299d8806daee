"""Scene-driven modelling: `fmu-pack pack --dofs --band --tol --max-step` builds the smallest
network the scene needs, and the archive says what was left out.

The sway-only narrow-band FMU must have at most a quarter of the full 9-DOF FMU's state size
and keep its error inside the band at or below --tol (checked here under fmpy against the
panel method at kR inside the band).
"""
import math
import re
import subprocess
import zipfile

import pytest

from test_harmonic import G, RADIUS, RHO, panel_method, steady_force_phasor

NARROW_BAND = (0.3, 2.0)  # kR
TOLERANCE = 0.01


def pack(fmu_pack_binary, path, *args):
    result = subprocess.run(
        [str(fmu_pack_binary), "pack", "semicircle", *args, "-o", str(path)],
        check=True,
        capture_output=True,
        text=True,
    )
    return result.stdout


def states(path):
    """The network state size from the model description's description text."""
    with zipfile.ZipFile(path) as z:
        text = z.read("modelDescription.xml").decode()
    return int(re.search(r"with (\d+) states", text).group(1))


def scene(path):
    with zipfile.ZipFile(path) as z:
        return z.read("documentation/scene.txt").decode()


def percent(text, label):
    return float(re.search(label + r"\s+([0-9.]+) %", text).group(1)) / 100


@pytest.fixture(scope="module")
def packed(fmu_pack_binary, tmp_path_factory):
    out = tmp_path_factory.mktemp("scene")
    full, narrow = out / "Full.fmu", out / "SwayNarrow.fmu"
    pack(fmu_pack_binary, full)
    band = f"{NARROW_BAND[0]}:{NARROW_BAND[1]}"
    pack(fmu_pack_binary, narrow, "--dofs", "sway", "--band", band, "--tol", str(TOLERANCE),
         "--max-step", "0.05")
    return full, narrow


def test_sway_narrow_band_fmu_is_at_most_a_quarter_of_the_full_one(packed):
    full, narrow = packed
    assert states(narrow) * 4 <= states(full), (states(narrow), states(full))


def test_the_archive_states_what_was_left_out(packed, fmu_pack_binary):
    _, narrow = packed
    text = scene(narrow)
    assert "DOFs modelled      sway" in text
    left_out = re.findall(r"^  (\w+)\s+coupling to the modelled DOFs up to ([0-9.]+) %", text, re.M)
    assert {name for name, _ in left_out} == {"heave", "roll", "cb1", "cb2", "cb3", "cb4", "cb5", "cb6"}
    # Mirror symmetry: sway and heave do not couple (0 to rounding); the CB modes do.
    coupling = {name: float(p) / 100 for name, p in left_out}
    assert coupling["heave"] < 1e-6 and coupling["cb1"] > 0.1
    assert percent(text, "error in the band") <= TOLERANCE
    # Outside the band the network was not fitted; the report gives the measured error.
    assert "error below the band" in text and "error above the band" in text
    inspected = subprocess.run([str(fmu_pack_binary), "inspect", str(narrow)], check=True,
                               capture_output=True, text=True).stdout
    assert "error in the band" in inspected and "DOFs left out      8" in inspected


@pytest.mark.parametrize("kr", [0.35, 1.0, 1.9])
def test_error_inside_the_band_stays_within_the_tolerance(packed, fmu_pack_binary, kr):
    _, narrow = packed
    omega = math.sqrt(kr * G / RADIUS)
    amplitude = 0.5
    added_mass, added_mass_inf = panel_method(fmu_pack_binary, kr)
    expected = -1j * omega * (added_mass - added_mass_inf) * (-1j * amplitude)
    measured = steady_force_phasor(narrow, omega, amplitude)
    # --tol is a fraction of the largest |A~_sway| in the band (at most A(0) = rho pi R^2/2),
    # times omega |V|; plus 0.2 % for the time discretization (see test_harmonic).
    largest = 0.55 * RHO * math.pi * RADIUS**2
    allowed = TOLERANCE * largest * omega * amplitude + 2e-3 * abs(expected)
    assert abs(measured - expected) <= allowed, (kr, measured, expected, allowed)


def test_max_step_cuts_the_band_at_nyquist(fmu_pack_binary, tmp_path):
    path = tmp_path / "Coarse.fmu"
    # Default band kR 0.05 .. 5 is 0.70 .. 7.0 rad/s; a 1 s step resolves up to pi rad/s.
    pack(fmu_pack_binary, path, "--dofs", "sway", "--max-step", "1.0")
    text = scene(path)
    top = float(re.search(r"band\s+[0-9.]+ \.\. ([0-9.]+) rad/s", text).group(1))
    assert abs(top - math.pi) < 1e-3, text
    assert "Nyquist" in text
    bad = subprocess.run([str(fmu_pack_binary), "pack", "semicircle", "--dofs", "sway",
                          "--max-step", "20", "-o", str(tmp_path / "X.fmu")],
                         capture_output=True, text=True)
    assert bad.returncode != 0 and "--max-step" in bad.stderr
