"""Speed against error of the ship sweep's discretization (docs/SHIPS.md, "Default grid").

    python3 examples/ships/convergence.py [path/to/fmu-pack]

For the box barge (sections with corners) and the Wigley-like ship (smooth Lewis sections):
the largest relative error of a diagonal A~ entry over 8 frequencies 0.3 .. 1.7 rad/s against
a fine reference, and the wall time of each sweep (one run each; the machine's load shows).
"""
import csv
import io
import pathlib
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
FMU_PACK = sys.argv[1] if len(sys.argv) > 1 else str(HERE.parents[1] / "target" / "release" / "fmu-pack")


def sweep(ship, panels, levels):
    start = time.perf_counter()
    out = subprocess.run(
        [FMU_PACK, "sweep", str(HERE / ship), "--omega", "0.3:1.7:8", "--headings", "180",
         "--panels", str(panels), "--levels", str(levels), "-o", "-"],
        capture_output=True, text=True, check=True).stdout
    elapsed = time.perf_counter() - start
    rows = [r for r in csv.reader(io.StringIO(out))
            if r and not r[0].startswith(("#", "omega")) and r[0] != "inf"]
    return {(r[0], r[1], r[2]): complex(float(r[3]), float(r[4])) for r in rows}, elapsed


def main():
    cases = [
        ("box_barge.xml", (512, 3), [(64, 1), (128, 1), (128, 2), (256, 1), (64, 3), (128, 3), (256, 3)]),
        ("wigley.xml", (256, 3), [(32, 3), (64, 3), (64, 2), (128, 3)]),
    ]
    print("| ship | panels, levels | largest diagonal error | time |")
    print("| --- | --- | --- | --- |")
    for ship, reference, runs in cases:
        ref, _ = sweep(ship, *reference)
        for panels, levels in runs:
            values, elapsed = sweep(ship, panels, levels)
            worst = max(abs(values[k] - z) / abs(z) for k, z in ref.items() if k[1] == k[2] and z != 0)
            print(f"| {ship} | {panels}, {levels} | {100 * worst:.3f} % | {elapsed:.2f} s |")


if __name__ == "__main__":
    main()
