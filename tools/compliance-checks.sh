#!/usr/bin/env bash
# Runs the FMU Compliance Checker (built by tools/compliance-checker.sh) on FMI 2.0 archives, twice each:
#   calm: no input file (inputs at their start values, 0), -h 0.01 -s 10: every output must stay 0;
#   heave: velocity.heave = 0.1 m/s sin(2 t), ramped in over 2 s, -h 0.01 -s 20: the force must
#          follow the hull's damping (mean power = B33 v^2 / 2 > 0), the other DOFs' forces only
#          where the hull couples them.
# Usage: tools/compliance-checks.sh FMUCHECK OUT_DIR ARCHIVE.fmu...
# Prints each run's checker summary and the output checks; exits 1 if any check fails or the
# checker reports an error or a warning (but the one on DefaultExperiment/@tolerance, see below).
set -euo pipefail
checker=$1
out=$2
shift 2
mkdir -p "$out"
python3 - "$out/heave_input.csv" <<'EOF'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write('time,"velocity.heave"\n')
    for i in range(2001):
        t = i * 0.01
        f.write(f"{t:.2f},{0.1 * min(t / 2.0, 1.0) * math.sin(2.0 * t):.12g}\n")
EOF
status=0
for fmu in "$@"; do
    name=$(basename "$fmu" .fmu)
    for run in calm heave; do
        args=(-h 0.01 -s 10)
        [ "$run" = heave ] && args=(-h 0.01 -s 20 -n 0 -i "$out/heave_input.csv")
        start=$(date +%s.%N)
        code=0
        "$checker" "${args[@]}" -l 4 -t "$out" -o "$out/$name-$run.csv" -e "$out/$name-$run.log" "$fmu" || code=$?
        wall=$(echo "$(date +%s.%N) - $start" | bc)
        echo "== $name ($run): exit $code, ${wall} s"
        [ "$code" = 0 ] || status=1
        grep -E '^\[(WARNING|ERROR|FATAL)\]|^\s+[0-9]+ (warning|Warning|Error)' "$out/$name-$run.log" | sed 's/^/   /'
        # FMI Library >= 2.1 warns whenever the checker asks for the optional
        # DefaultExperiment/@tolerance, which these archives leave out: not counted.
        if grep -E '^\[(WARNING|ERROR|FATAL)\]' "$out/$name-$run.log" |
            grep -vq 'fmi2_xml_get_default_experiment_tolerance: returning default value'; then
            status=1
        fi
        grep -qE '^\s+0 Error\(s\)' "$out/$name-$run.log" || status=1
    done
    python3 - "$out/$name-calm.csv" "$out/$name-heave.csv" <<'EOF' || status=1
import csv, math, sys
def table(path):
    rows = list(csv.reader(open(path)))
    return rows[0], [[float(x) for x in r] for r in rows[1:]]
head, calm = table(sys.argv[1])
largest = max(abs(v) for r in calm for v in r[1:])
print(f"   calm: {len(calm)} rows, t = {calm[0][0]} .. {calm[-1][0]}, largest |output| {largest:.3g}")
ok = largest == 0.0 and calm[-1][0] == 10.0
head, heave = table(sys.argv[2])
col = {k: i for i, k in enumerate(head)}
t = [r[0] for r in heave]
last = [i for i, x in enumerate(t) if x >= 20.0 - 2.0 * math.pi - 1e-9]
force = [heave[i][col["force.heave"]] for i in last]
sin_part = 2.0 * sum(f * math.sin(2.0 * t[i]) for f, i in zip(force, last)) / len(last)
cos_part = 2.0 * sum(f * math.cos(2.0 * t[i]) for f, i in zip(force, last)) / len(last)
power = sum(heave[i][col["power"]] for i in last) / len(last)
energy = min(r[col["energy"]] for r in heave)
# The checker holds each input over a step at its value at the step's start: the output at t
# saw v(t - h). power = -force_radiation . velocity must hold exactly with that velocity.
held = lambda x: 0.1 * min(x / 2.0, 1.0) * math.sin(2.0 * x)
radiation = col.get("force_radiation.heave", col["force.heave"])
power_scale = max(abs(r[col["power"]]) for r in heave)
power_error = max(abs(r[col["power"]] + r[radiation] * held(r[0] - 0.01)) for r in heave[1:]) / power_scale
others = {k: max(abs(r[i]) for r in heave) for k, i in col.items()
          if k.startswith("force.") and k != "force.heave"}
print(f"   heave: force.heave = {sin_part:.4g} sin(2t) + {cos_part:.4g} cos(2t): B33 = {-sin_part / 0.1:.4g},"
      f" A33 - A33(inf) = {-cos_part / 0.2:.4g}; mean power {power:.4g} (B33 v^2/2 = {-sin_part * 0.1 / 2:.4g}),"
      f" min energy {energy:.3g}; |power + force_radiation.heave v(t-h)| / max|power| = {power_error:.2g}")
print("   largest |force| of the other DOFs: " + ", ".join(f"{k[6:]} {v:.3g}" for k, v in others.items()))
ok = ok and sin_part < 0.0 and power > 0.0 and energy >= 0.0 and t[-1] == 20.0 and power_error < 1e-9
print("   output checks:", "passed" if ok else "FAILED")
sys.exit(0 if ok else 1)
EOF
done
exit $status
