"""A campaign of hull FMUs in irregular seas on Dask: sea states x headings x hulls (docs/CAMPAIGNS.md).

Run (from the repository root, with the .venv of tests/python/requirements.txt):

    .venv/bin/python examples/campaigns/campaign.py                 # full matrix, local cluster
    .venv/bin/python examples/campaigns/campaign.py --quick         # a small matrix, short records
    .venv/bin/python examples/campaigns/campaign.py --scheduler tcp://host:8786
    .venv/bin/python examples/campaigns/campaign.py --serial        # also run serially: timing and equality

Hulls (one FMU each, packed ONCE before the campaign into examples/campaigns/fmus/ when missing,
or given with --fmu NAME=PATH): the 100 m barge (examples/ships/barge.xml) and the Wigley-like
ship (examples/ships/wigley.xml), both `fmu-pack pack SHIP --dofs heave,pitch` (headings 0, 45,
90, 135, 180). Each case is one fmpy simulation of the FMU alone, hull held fixed, in a JONSWAP
sea (examples/campaigns/hydrocampaign.py). Writes the table (one row per case x DOF; default
examples/campaigns/out/campaign.csv) and, in the full run, target/reports/figures/campaign.svg (docs/figures/ with --update-docs).
"""
from __future__ import annotations

import argparse
import math
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "cosim"))
import hydrocampaign as hc  # noqa: E402

ROOT = HERE.parents[1]
FMU_DIR = HERE / "fmus"
HULLS = {
    # name: fmu-pack arguments
    "barge": ["examples/ships/barge.xml", "--dofs", "heave,pitch"],
    "wigley": ["examples/ships/wigley.xml", "--dofs", "heave,pitch"],
}
HS = 4.0
TPS = (5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 12.0, 14.0)
GAMMA = 3.3
HEADINGS = (0.0, 45.0, 90.0, 135.0, 180.0)
QUICK = dict(tps=(7.0, 10.0), headings=(90.0, 180.0), hulls=("barge",), duration=200.0)


def parse(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--fmu", action="append", default=[], metavar="NAME=PATH", help="a packed hull FMU (repeatable)")
    p.add_argument("--scheduler", help="address of a running Dask scheduler (default: a LocalCluster)")
    p.add_argument("--workers", type=int, default=2, help="LocalCluster workers (one thread each)")
    p.add_argument("--hs", type=float, default=HS)
    p.add_argument("--tp", type=float, nargs="+")
    p.add_argument("--gamma", type=float, default=GAMMA)
    p.add_argument("--headings", type=float, nargs="+")
    p.add_argument("--seeds", type=int, nargs="+", default=[1])
    p.add_argument("--duration", type=float, help="recorded seconds after the ramp (default 600; quick 200)")
    p.add_argument("--ramp", type=float, default=20.0)
    p.add_argument("--step", type=float, default=0.1)
    p.add_argument("--components", type=int, default=64)
    p.add_argument("--quick", action="store_true", help="2 Tp x 2 headings x the barge, 200 s records, no figure")
    p.add_argument("--serial", action="store_true", help="also run the cases serially here; compare and time")
    p.add_argument("--csv", type=pathlib.Path, default=HERE / "out" / "campaign.csv")
    p.add_argument("--verbose", action="store_true", help="print every row")
    p.add_argument("--figure", type=pathlib.Path,
                   help="default target/reports/figures/campaign.svg in the full run (docs/figures/ with --update-docs)")
    p.add_argument("--update-docs", action="store_true", help="write the full run's figure into the tracked docs/figures")
    return p.parse_args(argv)


def archives(args) -> dict:
    given = dict(item.split("=", 1) for item in args.fmu)
    if given:
        return {name: pathlib.Path(path) for name, path in given.items()}
    from hydrocosim import ensure_fmu  # packs with fmu-pack when missing (cargo run --release)

    names = QUICK["hulls"] if args.quick else tuple(HULLS)
    return {name: ensure_fmu(name, HULLS[name], FMU_DIR / f"{name}.fmu") for name in names}


def significant_rows(rows):
    """Rows whose spectral std is not negligible (1e-6 of the largest of their hull and DOF):
    the others are zero by symmetry (pitch in beam seas of a fore-aft symmetric hull)."""
    largest = {}
    for r in rows:
        key = (r["hull"], r["dof"])
        largest[key] = max(largest.get(key, 0.0), r["spectral_std"])
    return [r for r in rows if r["spectral_std"] > 1e-6 * largest[(r["hull"], r["dof"])]]


def summary(rows) -> str:
    kept = significant_rows(rows)
    ratios = np.array([r["ratio"] for r in kept])
    scatter = np.array([r["gaussian_scatter"] for r in kept])
    tz = np.array([r["tz"] / r["spectral_tz"] for r in kept])
    return "\n".join([
        f"{len(rows)} rows; {len(rows) - len(kept)} zero by symmetry (spectral std < 1e-6 of the hull's DOF's largest); "
        f"over the other {len(kept)}:",
        f"  std / spectral std: mean {ratios.mean():.4f}, rms deviation from 1 {np.sqrt(np.mean((ratios - 1) ** 2)):.4f}, "
        f"range {ratios.min():.4f} .. {ratios.max():.4f}",
        f"  Gaussian-sea rms scatter of the std for these records: median {np.median(scatter):.4f}",
        f"  Tz / spectral Tz: mean {tz.mean():.4f}, range {tz.min():.4f} .. {tz.max():.4f}",
    ])


def main(argv=None):
    args = parse(argv)
    tps = args.tp or (QUICK["tps"] if args.quick else TPS)
    headings = args.headings or (QUICK["headings"] if args.quick else HEADINGS)
    duration = args.duration or (QUICK["duration"] if args.quick else 600.0)
    fmus = archives(args)
    mtimes = {name: path.stat().st_mtime_ns for name, path in fmus.items()}
    cases = hc.make_cases(
        fmus, [(args.hs, tp, args.gamma) for tp in tps], headings, args.seeds,
        duration=duration, ramp=args.ramp, step=args.step, components=args.components,
    )
    print(f"{len(cases)} cases: hulls {list(fmus)}, Hs {args.hs} m, Tp {list(tps)} s, gamma {args.gamma}, "
          f"headings {list(headings)}, seeds {args.seeds}, {duration:g} s after a {args.ramp:g} s ramp, step {args.step} s")

    from distributed import Client, LocalCluster

    if args.scheduler:
        client, cluster = Client(args.scheduler), None
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, dashboard_address=":0")
        client = Client(cluster)
    try:
        workers = len(client.scheduler_info()["workers"])
        start = time.perf_counter()
        rows = hc.run_dask(client, cases, fmus, show_progress=True)
        dask_seconds = time.perf_counter() - start
        extractions = client.run(hc.extraction_count)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    print(f"Dask ({workers} workers): {dask_seconds:.1f} s wall; extractions per worker: "
          f"{[e['extractions'] for e in extractions.values()]}")
    if args.serial:
        start = time.perf_counter()
        serial = hc.run_serial(cases, fmus)
        serial_seconds = time.perf_counter() - start
        same = all(
            a["record_sha256"] == b["record_sha256"] and all(a[k] == b[k] for k in hc.STAT_COLUMNS)
            for a, b in zip(rows, serial)
        )
        print(f"serial: {serial_seconds:.1f} s wall; Dask rows equal the serial rows bit for bit: {same}")
    assert all(mtimes[name] == path.stat().st_mtime_ns for name, path in fmus.items()), "an archive changed"
    rows = hc.add_spectral(rows, fmus)
    hc.write_csv(rows, args.csv)
    print(f"table: {args.csv}")
    print(summary(rows))
    for r in rows if args.verbose else ():
        print(f"  {r['hull']:7s} {r['dof']:6s} Tp {r['tp']:5.1f} head {r['heading']:5.1f}: 4 std {r['significant']:11.4g}, "
              f"max {r['max']:11.4g}, min {r['min']:11.4g}, Tz {r['tz']:5.2f} s (spectral {r['spectral_tz']:5.2f}), "
              f"std/spectral {r['ratio']:.4f}" + ("" if math.isfinite(r["gaussian_scatter"]) else " (no spectral value)"))
    figures = ROOT / "docs" / "figures" if args.update_docs else ROOT / "target" / "reports" / "figures"
    figure = args.figure or (None if args.quick else figures / "campaign.svg")
    if figure:
        figure.parent.mkdir(parents=True, exist_ok=True)
        hc.plot(rows, figure)
        print(f"figure: {figure}")
    return rows


if __name__ == "__main__":
    main()
