#!/usr/bin/env python3
"""Scenario B (freely floating section) of Sundsdal et al. (2025): first-harmonic motion amplitudes
and mean sway offset and force per (period, height), from the raw files of the public repository.

Usage: process_floating.py MIRROR_GIT_DIR CALIBRATION_CSV OUT_CSV

Motion amplitudes come from the camera (Sway, Heave, Roll): only amplitudes are used (the camera's
time base is slightly off, so its phases are not). The incident amplitude at the model `a` is the
mean of the calibration runs' `a_model_mm` at the same period and height. Each run is fitted by least
squares with a constant, a linear trend and harmonics 1-3 over whole periods of the steady window:
from the wave's arrival at the model (7 m / c_g after the wavemaker starts) plus the 5-period ramp
and one period of margin, to the arrival plus the reflection time of the repository's table.
"""
import subprocess
import sys

import numpy as np

RHO, G, L, B, C_SWAY = 1000.0, 9.81, 0.586, 0.40, 59.5
MODEL_DISTANCE = 7.0
# index: (xi_B, omega, T, c_g, h/lambda, reflection time)
PERIODS = {
    1: (0.350, 4.143, 1.516, 1.184, 0.279, 10.137),
    2: (0.500, 4.952, 1.269, 0.990, 0.398, 12.116),
    3: (0.525, 5.075, 1.238, 0.967, 0.418, 12.415),
    4: (0.550, 5.194, 1.210, 0.944, 0.438, 12.707),
    5: (0.575, 5.311, 1.183, 0.924, 0.458, 12.993),
    6: (0.600, 5.425, 1.158, 0.904, 0.477, 13.272),
    7: (0.650, 5.646, 1.113, 0.869, 0.517, 13.814),
    8: (0.700, 5.860, 1.072, 0.837, 0.557, 14.335),
    9: (0.750, 6.065, 1.036, 0.809, 0.597, 14.839),
    10: (1.000, 7.004, 0.897, 0.700, 0.796, 17.134),
    11: (1.250, 7.830, 0.802, 0.626, 0.995, 19.157),
    12: (1.500, 8.578, 0.733, 0.572, 1.194, 20.985),
    13: (1.750, 9.265, 0.678, 0.529, 1.393, 22.666),
    14: (2.000, 9.905, 0.634, 0.495, 1.592, 24.231),
}


def git(gitdir, *args):
    return subprocess.run(["git", "--git-dir", gitdir, *args], check=True,
                          capture_output=True).stdout


def stored_runs(gitdir):
    """Names of scenario B files whose content is stored (size not BAD)."""
    runs = []
    for line in git(gitdir, "ls-tree", "-l", "HEAD", "data/3PPH/").decode().splitlines():
        meta, path = line.split("\t")
        name = path.rsplit("/", 1)[1]
        if name.endswith(".csv") and meta.split()[3] != "BAD":
            runs.append(name[:-4])
    return sorted(runs)


def calibrated_amplitudes(path):
    """Mean incident amplitude at the model [m] per (period index, height index)."""
    rows = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    amps = {}
    for r in rows:
        amps.setdefault((int(r["period_index"]), int(r["height_index"])), []).append(r["a_model_mm"])
    return {key: 1e-3 * float(np.mean(v)) for key, v in amps.items()}


def fit(t, y, omega):
    """Least squares of constant + trend + harmonics 1-3: (mean at window centre, complex H1)."""
    tc = t - t.mean()
    cols = [np.ones_like(t), tc]
    for n in (1, 2, 3):
        cols += [np.cos(n * omega * t), np.sin(n * omega * t)]
    c, *_ = np.linalg.lstsq(np.column_stack(cols), y, rcond=None)
    return c[0], complex(c[2], -c[3])


def process_run(gitdir, run):
    period, height = int(run[1:3]), int(run[3])
    _, omega, T, cg, _, t_refl = PERIODS[period]
    text = git(gitdir, "show", f"HEAD:data/3PPH/{run}.csv").decode()
    header = text.split("\n", 1)[0].split(",")
    data = np.loadtxt(text.splitlines()[1:], delimiter=",")
    col = {name.split(" ")[0]: data[:, i] for i, name in enumerate(header)}
    t = col["Time"]
    wm = col["WM_Position"]
    still = t < 2.0
    wm_start = t[np.argmax(np.abs(wm - wm[still].mean()) > 0.2 * np.abs(wm - wm[still].mean()).max())]
    arrival = wm_start + MODEL_DISTANCE / cg
    start = arrival + 6.0 * T
    periods = max(int((arrival + t_refl - start) // T), 1)
    window = (t >= start) & (t < start + periods * T)
    out = {"period": period, "height": height, "periods": periods}
    before = t < wm_start
    for name in ("Sway", "Heave", "Roll", "Force_Sway", "Tension_SB", "Tension_PS"):
        mean, h1 = fit(t[window], col[name][window], omega)
        out[name] = (mean - col[name][before].mean(), abs(h1))
    return out


def main():
    gitdir, calibration, out_path = sys.argv[1:4]
    amps = calibrated_amplitudes(calibration)
    results = {}
    runs = stored_runs(gitdir)
    for run in runs:
        r = process_run(gitdir, run)
        results.setdefault((r["period"], r["height"]), []).append((run, r))
    cols = ["xi_B", "height_index", "omega", "a_mm", "Ka", "h_over_lambda", "runs", "periods",
            "sway_over_a", "sway_hr", "heave_over_a", "heave_hr", "roll_over_ka", "roll_hr",
            "sway_mean_mm", "sway_mean_hr", "drift_force_sway", "drift_force_sway_hr",
            "drift_tension", "drift_tension_hr", "drift_spring", "drift_spring_hr"]
    lines = [",".join(cols)]
    for (period, height), reps in sorted(results.items()):
        xi, omega, _, _, h_lambda, _ = PERIODS[period]
        a = amps[(period, height)]
        k = omega**2 / G
        drift_scale = 0.5 * RHO * G * a**2 * L

        def stat(values):
            v = np.array(values)
            return v.mean(), 0.5 * (v.max() - v.min())

        quantities = [
            stat([r["Sway"][1] / a for _, r in reps]),
            stat([r["Heave"][1] / a for _, r in reps]),
            stat([r["Roll"][1] / (k * a) for _, r in reps]),
            stat([1e3 * r["Sway"][0] for _, r in reps]),
            stat([r["Force_Sway"][0] / drift_scale for _, r in reps]),
            stat([(r["Tension_PS"][0] - r["Tension_SB"][0]) / drift_scale for _, r in reps]),
            stat([C_SWAY * abs(r["Sway"][0]) / drift_scale for _, r in reps]),
        ]
        row = [f"{xi:.3f}", str(height), f"{omega:.4f}", f"{1e3 * a:.3f}", f"{k * a:.4f}",
               f"{h_lambda:.3f}", " ".join(run for run, _ in reps),
               str(min(r["periods"] for _, r in reps))]
        row += [f"{v:.4f}" for q in quantities for v in q]
        lines.append(",".join(row))
    with open(out_path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
