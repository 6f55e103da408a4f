#!/usr/bin/python3
"""The cost of a ball: what one push step costs per element, model by model, on the beds of a compare study.

Every model of one seed of an `mfdem compare` store is pushed again from its own prepared bed
(runs/KEY/packing.h5), `--repeats` times, interleaved, on an idle machine, with the threads of
`--threads`. Reported per model: stones as clumps and balls, elements, the push's time step and
the contact that sets it, steps, active contacts per element at the peak, the median push wall
time (mfdem's own timer of the push loop), element-steps per second, the wall time per
element-step against the reference's (the first model), and the push's speedup against its
element ratio: a multi-layer model that costs no more per element-step than all clumps is as much
faster as it has fewer elements.

Usage: /usr/bin/python3 studies/benchmarks/cost_of_a_ball/run_benchmark.py STORE [--seed 1]
       [--repeats 3] [--threads 2] [--quick] [--out REPORT] [--name NAME]
STORE is the --out folder of `mfdem compare` (its runs of the seed, in compare.csv's model order).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1] / "python"))  # the mfdem package
from mfdem.bench import (  # noqa: E402  (needs the path above)
    BenchmarkError, add_machine_options, closing_sections, log, mfdem_env, provenance_lines, publish_report,
    rel, repo_path, report_path, run_main, wait_until_idle)
from mfdem import files, tables  # noqa: E402


def runs_of_seed(store: Path, seed: int) -> list[dict]:
    """The store's finished runs of `seed`, in the model order of compare.csv (the reference first)."""
    order = [row["model"] for row in files.read_csv(store / "compare.csv")] \
        if (store / "compare.csv").exists() else []
    runs = [{"model": r["labels"]["model"], "folder": store / "runs" / r["key"]} for r in files.read_store(store)
            if r["status"] == "finished" and int(r["numbers"]["seed"]) == seed]
    runs.sort(key=lambda r: order.index(r["model"]) if r["model"] in order else len(order))
    if not runs:
        raise BenchmarkError(f"{rel(store)}: no finished run of seed {seed} (run `mfdem compare` first)")
    return runs


def push_once(mfdem: Path, run: dict, out: Path, threads: int) -> dict:
    cmd = [str(mfdem), "push", str(run["folder"]), "--threads", str(threads), "-q", "--out", str(out)]
    if subprocess.run(cmd, env=mfdem_env(threads)).returncode != 0:
        raise BenchmarkError(f"mfdem push {rel(run['folder'])} failed; see above")
    push = files.read_push(out)
    a, model = push["attrs"], push["model"]
    peak = int(push["curve"]["force"].argmax())
    return {"seconds": float(a["wall_seconds"]), "dt": float(a["time_step"]), "steps": int(a["steps"]),
            "elements": int(a["elements"]), "reason": str(a.get("time_step_reason", "?")),
            "contacts": float(push["curve"]["contacts"][peak]) if "contacts" in push["curve"] else float("nan"),
            "clumps": int(model.get("clumps", a["stones"])), "balls": int(model.get("balls", 0))}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("store", help="the --out folder of an `mfdem compare` study")
    ap.add_argument("--seed", type=int, default=1, help="the seed whose beds are pushed (default 1)")
    ap.add_argument("--repeats", type=int, default=None, help="pushes per model, median reported (default 3)")
    ap.add_argument("--threads", type=int, default=2, help="OpenMP threads of each push (default 2)")
    ap.add_argument("--quick", action="store_true", help="one repeat, report in the scratch folder")
    ap.add_argument("--name", default="cost_of_a_ball", help="the report's name (default cost_of_a_ball)")
    ap.add_argument("--out", help="report file (default results/benchmarks/NAME.md)")
    ap.add_argument("--mfdem", default="build/studies/mfdem", help="the mfdem executable")
    add_machine_options(ap, "cost_of_a_ball")
    args = ap.parse_args()
    args.repeats = args.repeats or (1 if args.quick else 3)
    if args.repeats < 1 or args.threads < 1:
        raise BenchmarkError("--repeats and --threads must be at least 1")
    mfdem, store = repo_path(args.mfdem), repo_path(args.store)
    scratch = repo_path(args.scratch) / args.name
    scratch.mkdir(parents=True, exist_ok=True)
    runs = runs_of_seed(store, args.seed)

    samples: dict[str, list[dict]] = {r["model"]: [] for r in runs}
    loads = []
    for rep in range(args.repeats):
        for k, run in enumerate(runs):
            loads.append(wait_until_idle(args.wait_idle) if args.wait_idle > 0 else float("nan"))
            log(f"repeat {rep + 1}/{args.repeats}: {run['model']}")
            samples[run["model"]].append(push_once(mfdem, run, scratch / f"m{k}_rep{rep}", args.threads))

    rows = []
    for run in runs:
        s = samples[run["model"]]
        first = s[0]
        seconds = statistics.median(x["seconds"] for x in s)
        rows.append({**first, "model": run["model"], "seconds": seconds,
                     "rate": first["elements"] * first["steps"] / seconds})
    ref = rows[0]
    header = ["model", "clumps", "balls", "elements", "time step (s)", "set by", "steps", "contacts/element",
              "push (s)", "element-steps/s", "cost/element-step", "push speedup", "element ratio"]
    cells = [[r["model"], f"{r['clumps']:,}", f"{r['balls']:,}", f"{r['elements']:,}", f"{r['dt']:.3g}",
              r["reason"].split(" (")[0], f"{r['steps']:,}", f"{r['contacts'] / r['elements']:.2f}",
              f"{r['seconds']:.1f}", f"{r['rate']:.3g}", f"{ref['rate'] / r['rate']:.2f}x",
              f"{ref['seconds'] / r['seconds']:.2f}x", f"{ref['elements'] / r['elements']:.2f}x"] for r in rows]
    lines = [f"# The cost of a ball: {args.name}", ""]
    lines += provenance_lines("/usr/bin/python3")
    lines += [f"Store `{rel(store)}`, seed {args.seed}: each model's own bed pushed again, {args.repeats} "
              f"repeat(s), interleaved, median of mfdem's push-loop timer, {args.threads} thread(s). "
              "cost/element-step: the push wall time per element-step against the first model's; push "
              "speedup against the element ratio: equal when a ball costs what a pebble costs. Machine "
              f"load before the runs (cores busy, largest): {max(loads):.2f}.", ""]
    lines += [tables.markdown_table(header, cells, "lrrrrlrrrrrrr"), ""]
    lines += closing_sections(mfdem, [])
    publish_report("\n".join(lines), report_path(args, scratch, args.name))
    return 0


if __name__ == "__main__":
    run_main(main)
