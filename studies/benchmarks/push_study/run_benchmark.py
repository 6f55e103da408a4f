#!/usr/bin/python3
"""Time to a finished push study: the lateral push of one packing in mfdem and in LAMMPS.

The same push as the peer cross-check (studies/railway/peer_push/: the same bed, contact law,
sleeper drive, time step and number of steps, no contact history at the start), each code run
`--repeats` times on each thread/rank count, interleaved, on an idle machine. Reported per code
and thread/rank count: the median wall time of the whole run (start-up, bed input, push, output:
what a user waits for), the median of the code's own push-loop timer, element-steps per second
of the loop, and the ratio LAMMPS / mfdem. Every repeat's F(u) is compared with the first
repeat's: mfdem must give bitwise the same curve on every repeat and thread count, LAMMPS on
every repeat of one rank count.

Usage: /usr/bin/python3 studies/benchmarks/push_study/run_benchmark.py [PACKING]
       [--sleeper free|held] [--repeats 3] [--threads 1 2] [--quick] [--out REPORT]
Without PACKING, the mini preset of seed 1 is packed first (about a minute, not timed).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1] / "python"))  # the mfdem package
from mfdem.bench import (  # noqa: E402  (needs the path above)
    BenchmarkError, add_machine_options, closing_sections, log, mfdem_env, parallel_notes,
    provenance_lines, publish_report, rel, repo_path, report_path, run_main, wait_until_idle)
from mfdem.peer_push import (  # noqa: E402
    lammps_bed, packing_without_history, read_config, run_lammps, run_mfdem, with_sleeper)

import numpy as np  # noqa: E402  (mfdem.peer_push has checked that it is there)
import h5py  # noqa: E402


def default_packing(scratch: Path, mfdem: Path) -> Path:
    """The mini preset of seed 1, packed once into the scratch folder."""
    bed = scratch / "mini_seed1"
    if not (bed / "packing.h5").exists():
        log(f"packing the mini preset (seed 1) into {rel(bed)} (not timed) ...")
        cmd = [str(mfdem), "pack", "mini", "--seed", "1", "--threads", "2", "-q", "--out", str(bed)]
        if subprocess.run(cmd, env=mfdem_env(2)).returncode != 0:
            raise BenchmarkError("mfdem pack mini failed; see above")
    return bed / "packing.h5"


def timed(run) -> dict:
    """Runs `run()` (one push); adds its wall time, start to results read, in seconds."""
    start = time.monotonic()
    result = run()
    result["wall"] = time.monotonic() - start
    return result


def same_curve(a: dict, b: dict) -> bool:
    return a["F"].shape == b["F"].shape and bool(np.array_equal(a["F"], b["F"], equal_nan=True))


def table(rows: list[dict], elements: int, steps: int) -> list[str]:
    """Median wall and loop times per code and thread/rank count, with the peer's ratio."""
    wall = {(r["code"], r["procs"]): r["wall"] for r in rows}
    lines = ["| code | threads/ranks | run wall time (s), median | min - max | push loop (s), median "
             "| M element-steps/s (loop) | this / mfdem (wall) | speed-up vs 1 | machine load before (cores) |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        mfdem, one = wall.get(("mfdem", r["procs"])), wall.get((r["code"], 1))
        ratio = f"{r['wall'] / mfdem:.2f}" if r["code"] != "mfdem" and mfdem else "-"
        speedup = f"{one / r['wall']:.2f}" if one and r["procs"] > 1 else "-"
        load = f"{r['load']:.2f}" if r["load"] == r["load"] else "not measured"  # nan: --wait-idle 0
        lines.append(f"| {r['code']} | {r['procs']} | {r['wall']:.2f} | {r['min']:.2f} - {r['max']:.2f} | "
                     f"{r['loop']:.2f} | {elements * steps / r['loop'] / 1e6:.2f} | {ratio} | {speedup} | "
                     f"{load} |")
    return lines


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("packing", nargs="?", help="packing.h5 or the directory `mfdem pack` wrote "
                    "(default: mini, seed 1, packed into the scratch folder)")
    ap.add_argument("--sleeper", choices=("free", "held"), default="free",
                    help="the sleeper's vertical motion (default free, the push test's own)")
    ap.add_argument("--distance", type=float, help="push distance in mm (default: the packing's config)")
    ap.add_argument("--repeats", type=int, default=None, help="runs per code and thread count, median "
                    "reported (default 3; 1 with --quick)")
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2],
                    help="mfdem OpenMP threads and LAMMPS MPI ranks (default 1 2)")
    ap.add_argument("--quick", action="store_true", help="one repeat, report in the scratch folder")
    ap.add_argument("--out", help="report file (default results/benchmarks/push_study.md)")
    ap.add_argument("--mfdem", default="build/studies/mfdem", help="the mfdem executable")
    ap.add_argument("--lammps", default="lmp", help="the LAMMPS executable")
    add_machine_options(ap, "push_study")
    args = ap.parse_args()
    args.repeats = args.repeats or (1 if args.quick else 3)
    if args.repeats < 1 or min(args.threads) < 1:
        raise BenchmarkError("--repeats and --threads must be at least 1")

    mfdem = repo_path(args.mfdem)
    scratch = repo_path(args.scratch)
    scratch.mkdir(parents=True, exist_ok=True)
    packing = repo_path(args.packing) if args.packing else default_packing(scratch, mfdem)
    packing = packing / "packing.h5" if packing.is_dir() else packing
    if not packing.exists():
        raise BenchmarkError(f"{args.packing}: no packing.h5 (expected what `mfdem pack` wrote)")
    with h5py.File(packing, "r") as f:
        own = f["packing"].attrs["config"]
    text = own.decode() if isinstance(own, bytes) else str(own)
    s = read_config(text, f"{rel(packing)} (its config)")
    s["sleeper"] = args.sleeper
    if args.distance:
        s["distance"] = args.distance * 1e-3
    runs = scratch / "runs"
    runs.mkdir(exist_ok=True)
    (runs / "push.toml").write_text(with_sleeper(text, args.sleeper))
    bare = runs / "packing_without_history" / "packing.h5"
    packing_without_history(packing, bare)
    bed = lammps_bed(packing, runs, reuse=False)

    samples: dict[tuple[str, int], list[dict]] = {}
    for rep in range(args.repeats):
        for procs in args.threads:
            for code in ("mfdem", "LAMMPS"):
                load = wait_until_idle(args.wait_idle) if args.wait_idle > 0 else float("nan")
                log(f"repeat {rep + 1}/{args.repeats}: {code} on {procs} thread(s)/rank(s)")
                out = runs / f"{code.lower()}_p{procs}_rep{rep}"
                if code == "mfdem":
                    r = timed(lambda: run_mfdem(mfdem, bare, runs / "push.toml", s, procs, out, False))
                    if r["status"] != "finished":
                        raise BenchmarkError(f"mfdem's push ended '{r['status']}' ({rel(out)})")
                else:
                    ref = samples[("mfdem", args.threads[0])][0]
                    r = timed(lambda: run_lammps(args.lammps, bed, s, ref["dt"], ref["steps"], procs,
                                                 out, False))
                r["load"] = load
                samples.setdefault((code, procs), []).append(r)

    first = samples[("mfdem", args.threads[0])][0]
    rows = []
    for (code, procs), rs in samples.items():
        walls = [r["wall"] for r in rs]
        rows.append({"code": code, "procs": procs, "wall": statistics.median(walls), "min": min(walls),
                     "max": max(walls), "loop": statistics.median(r["seconds"] for r in rs),
                     "load": max(r["load"] for r in rs), "peak": rs[0]["F"][np.isfinite(rs[0]["F"])].max()})
    rows.sort(key=lambda r: (r["code"] != "mfdem", r["procs"]))
    mfdem_same = all(same_curve(first, r) for (code, _), rs in samples.items() if code == "mfdem" for r in rs)
    lammps_same = {procs: all(same_curve(rs[0], r) for r in rs)
                   for (code, procs), rs in samples.items() if code == "LAMMPS"}

    lines = ["# Push-study benchmark: time to a finished lateral push, mfdem and LAMMPS", ""]
    lines += provenance_lines("/usr/bin/python3")
    lines += [f"Packing `{rel(packing)}`: {first['elements']} elements; sleeper {args.sleeper} vertically, "
              f"pushed {s['distance'] * 1e3:g} mm at {s['velocity'] * 1e3:g} mm/s: {first['steps']} steps of "
              f"{first['dt']:.4g} s in both codes, from the packing without contact history (the "
              "peer push of studies/railway/peer_push/, where what the two codes share is listed). "
              f"Median of {args.repeats} repeat(s), interleaved. Run wall time: from starting the "
              "code to its results read back (start-up, reading the bed, the push, writing the "
              "results): what a user waits for. Push loop: the code's own timer (mfdem's "
              "wall_seconds, LAMMPS's \"Loop time\"). Machine load: CPU cores busy before a run, "
              "the largest over the repeats; above about 0.1 the timing is disturbed.", ""]
    lines += table(rows, first["elements"], first["steps"])
    lines += ["", "| code | threads/ranks | peak lateral force (kN) | F(u) bitwise the same on every repeat |",
              "|---|---:|---:|---|"]
    for r in rows:
        runs = len(samples[(r["code"], r["procs"])])
        if r["code"] == "mfdem":
            counts = len(args.threads)
            same = ("NO" if not mfdem_same else
                    f"yes ({runs} run(s) each; the same curve on all {counts} thread counts)" if counts > 1 else
                    f"yes ({runs} runs)" if runs > 1 else "one run: nothing to compare")
        else:
            same = ("yes" if lammps_same[r["procs"]] else "no") if runs > 1 else "one run: nothing to compare"
        lines.append(f"| {r['code']} | {r['procs']} | {r['peak'] * 1e-3:.4f} | {same} |")
    lines.append("")
    notes = parallel_notes(args.threads)
    notes.append("LAMMPS on 1 and 2 ranks sums in another order: its two curves part after a "
                 "millimetre or two (chaos), so its peaks differ; mfdem gives one curve on any "
                 "thread count.")
    lines += closing_sections(mfdem, notes)
    if not mfdem_same:
        lines.insert(0, "**mfdem's curves differ between repeats or thread counts: a reproducibility "
                        "defect.**\n")
    publish_report("\n".join(lines), report_path(args, scratch, "push_study"))
    return 0 if mfdem_same else 1


if __name__ == "__main__":
    run_main(main)
