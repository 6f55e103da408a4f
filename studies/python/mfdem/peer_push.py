#!/usr/bin/python3
"""Peer cross-check of the lateral push: the same packing pushed by mfdem and by LAMMPS.

The sleeper does not turn and is held vertically (default) or free vertically under its weight
(`--sleeper free`) in both codes: mfdem's `[push] sleeper_vertical`, set in OUT/push.toml; in
LAMMPS a block region of fix wall/gran/region driven along x, whose height follows one extra
atom of the sleeper's mass (see in.push.lmp). Both start from the packing's positions and velocities without
contact history (LAMMPS cannot read mfdem's shear springs; mfdem is given a copy of the packing
without them). Contact law, masses, time step, velocity ramp and the force record (mean over
each record interval) are the same. LAMMPS runs once per rank count (default 1 and 2): those runs
differ only in the order of floating-point sums, and how far they drift apart is the yardstick
of chaos for the difference between the codes. Reported: F(u) of every run, the peak force, the
mean force over 1 mm windows, the vertical force on the sleeper, and the push loop's wall time,
as a figure (peer_push.png) and a report (report.md).

Usage: tools/mfdem-py peer_push PACKING_DIR --out DIR
       [--config TOML] [--velocity MM_S] [--distance MM] [--threads N] [--ranks N...] [--reuse]
Needs Debian's python3 (h5py, numpy, matplotlib) and the lammps package.
"""

from __future__ import annotations

import argparse
import math
import re
import shutil
import subprocess
import sys
import time
import tomllib
from pathlib import Path

from mfdem.bench import (
    REPO, BenchmarkError, machine_description, mfdem_env, mpi_prefix, peer_env, provenance_lines,
    rel, repo_path, run_main, set_toml_value, var_args)
from mfdem.clump_export import read_bed, write_clumps

try:
    import h5py
    import numpy as np
except ImportError as exc:
    sys.exit(f"peer_push: error: {exc}; run it with /usr/bin/python3 (Debian's, with "
             "python3-h5py and python3-numpy)")

# Table 1 (mfdem's defaults for the railway section, studies/railway/push_config.cpp)
BALLAST_K, WALL_K = 2e7, 5e9     # N/m per material, mixed in series
MU = 0.5
BETA = 0.2                       # normal viscous damping, fraction of critical, every pair
GRAVITY = 9.81


def series(a: float, b: float) -> float:
    return a * b / (a + b)


def tsuji_alpha(e: float) -> float:
    """LAMMPS `damping tsuji`: eta_n = alpha(e) sqrt(m_eff kn) (Tsuji et al. 1992 fit)."""
    return (1.2728 - 4.2783 * e + 11.087 * e ** 2 - 22.348 * e ** 3 + 27.467 * e ** 4
            - 18.022 * e ** 5 + 4.8218 * e ** 6)


def tsuji_restitution(alpha: float) -> float:
    """The e whose alpha(e) is `alpha` (alpha falls monotonically from 1.27 at e = 0)."""
    lo, hi = 0.0, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if tsuji_alpha(mid) > alpha else (lo, mid)
    return 0.5 * (lo + hi)


# --- the study's settings -------------------------------------------------------------------
def read_config(text: str, source: str) -> dict:
    """The [push] settings; refuses what the LAMMPS side does not model."""
    cfg = tomllib.loads(text)
    for table in ("materials", "pair"):
        if table in cfg:
            raise BenchmarkError(f"{source}: [{table}] is set; the peer push models Table 1's "
                                 "materials only (remove it or extend in.push.lmp)")
    push = cfg.get("push", {})
    if push.get("local_damping", 0.0) != 0.0:
        raise BenchmarkError(f"{source}: [push] local_damping = {push['local_damping']}: "
                             "expected 0 (LAMMPS has no PFC local damping)")
    # absent keys: mfdem's defaults (PushSettings in studies/railway/push_config.hpp)
    return {"velocity": push.get("velocity", 0.05), "distance": push.get("distance", 5e-3),
            "record_interval": push.get("record_interval", 1e-5),
            "ramp_distance": push.get("ramp_distance", 1e-4),
            "periodic": cfg.get("section", {}).get("along_track", "periodic") == "periodic"}


def with_sleeper(text: str, vertical: str) -> str:
    """The config with [push] sleeper_vertical = `vertical` ("held" or "free")."""
    if re.search(r"^\s*sleeper_vertical\s*=", text, re.M):
        return set_toml_value(text, "push", "sleeper_vertical", f'"{vertical}"')
    if not re.search(r"^\[push\]", text, re.M):
        return text + f'\n[push]\nsleeper_vertical = "{vertical}"\n'
    return re.sub(r"^(\[push\][^\n]*\n)", rf'\1sleeper_vertical = "{vertical}"  # peer push\n', text,
                  count=1, flags=re.M)


def packing_without_history(src: Path, dst: Path) -> None:
    dst.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(src, dst)
    with h5py.File(dst, "r+") as f:
        if "springs" in f["packing"]:
            del f["packing/springs"]


# --- the two runs ---------------------------------------------------------------------------
def run_mfdem(exe: Path, packing: Path, config: Path, s: dict, threads: int, out: Path,
              reuse: bool) -> dict:
    if not (reuse and (out / "push.h5").exists()):
        cmd = [str(exe), "push", str(packing), "--config", str(config), "--threads", str(threads),
               "--velocity", repr(s["velocity"] * 1e3), "--distance", repr(s["distance"] * 1e3),
               "--out", str(out)]
        print("mfdem:", " ".join(cmd), flush=True)
        if subprocess.run(cmd, env=mfdem_env(threads)).returncode != 0:
            raise BenchmarkError("mfdem push failed; see above")
    with h5py.File(out / "push.h5", "r") as f:
        status = f.attrs["status"]
        vertical = f.attrs["sleeper_vertical"]
        vertical = vertical.decode() if isinstance(vertical, bytes) else str(vertical)
        if vertical != s["sleeper"]:
            raise BenchmarkError(f"{rel(out / 'push.h5')}: a push with the sleeper {vertical}, not "
                                 f"{s['sleeper']}; give another --out")
        # seconds: the push loop's own timer, as LAMMPS's "Loop time" (no start-up, no output).
        return {"u": f["curve/u"][...], "F": f["curve/force"][...], "heave": f["curve/heave"][...],
                "support": sum(f[f"curve/support_{p}"][...] for p in ("base", "crib", "shoulder", "top")),
                "dt": float(f.attrs["time_step"]), "steps": int(f.attrs["steps"]),
                "elements": int(f.attrs["elements"]), "seconds": float(f.attrs["wall_seconds"]),
                "status": status.decode() if isinstance(status, bytes) else str(status)}


def lammps_variables(attrs, s: dict, dt: float, steps: int, nrec: int) -> dict:
    """-var values of in.push.lmp."""
    kn, kw = series(BALLAST_K, BALLAST_K), series(BALLAST_K, WALL_K)
    c = [attrs[f"sleeper_centre_{a}"] for a in "xyz"]
    h = [attrs[f"sleeper_half_extent_{a}"] for a in "xyz"]
    v = {"dt": dt, "steps": steps, "nrec": nrec, "kn": kn, "kt": kn, "kn_wall": kw, "kt_wall": kw,
         "e_tsuji": tsuji_restitution(2.0 * BETA), "mu": MU, "mu_wall": MU, "gravity": GRAVITY,
         "vel": s["velocity"], "tr": 2.0 * min(s["ramp_distance"], s["distance"]) / s["velocity"],
         "boundary": "f p f" if s["periodic"] else "f f f", "track_walls": 0 if s["periodic"] else 1,
         "track_lo": attrs["domain_min_y"], "track_hi": attrs["domain_max_y"],
         "sleeper_free": 1 if s["sleeper"] == "free" else 0, "sleeper_mass": attrs["sleeper_mass"]}
    for i, a in enumerate("xyz"):
        v[f"{a}lo"], v[f"{a}hi"] = c[i] - h[i], c[i] + h[i]
    if v["tr"] <= 0.0:
        raise BenchmarkError("[push] ramp_distance must be positive for the LAMMPS ramp")
    return v


def lammps_bed(packing: Path, out: Path, reuse: bool) -> dict:
    """The packing in LAMMPS's form, written once for every rank count: OUT/bed.data and
    OUT/bodies.txt; returns their paths and the packing's attributes."""
    with h5py.File(packing, "r") as f:
        attrs = dict(f["packing"].attrs)
    data, bodies = out / "bed.data", out / "bodies.txt"
    if not (reuse and data.exists() and bodies.exists()):
        bed = read_bed(packing)
        lo = [attrs[f"domain_min_{a}"] for a in "xyz"]
        hi = [attrs[f"domain_max_{a}"] for a in "xyz"]
        write_clumps(bed, data, bodies, lo, hi, f"peer push of {rel(packing)}")
    return {"attrs": attrs, "data": data, "bodies": bodies}


def run_lammps(exe: str, bed: dict, s: dict, dt: float, steps: int, ranks: int, out: Path,
               reuse: bool) -> dict:
    """The push in LAMMPS with mfdem's time step and number of steps."""
    if not (reuse and loop_seconds(out / "log.lammps") is not None):
        out.mkdir(parents=True, exist_ok=True)
        nrec = max(1, round(s["record_interval"] / (s["velocity"] * dt)))
        variables = lammps_variables(bed["attrs"], s, dt, steps, nrec)
        variables.update(datafile=str(bed["data"]), bodyfile=str(bed["bodies"]))
        cmd = mpi_prefix(ranks) + [exe, "-in", str(REPO / "studies/railway/peer_push/in.push.lmp"), "-log", "log.lammps",
                                   "-screen", "none"] + var_args(variables)
        print(f"LAMMPS: {steps} steps of {dt:.4g} s, {ranks} rank(s)", flush=True)
        start = time.monotonic()
        proc = subprocess.Popen(cmd, cwd=out, env=peer_env())
        while True:
            try:
                proc.wait(timeout=2.0)  # returns as soon as LAMMPS ends: the caller may time it
                break
            except subprocess.TimeoutExpired:
                show_progress(out / "displacement.txt", s["distance"], time.monotonic() - start)
        print(file=sys.stderr)
        if proc.returncode != 0:
            raise BenchmarkError(f"LAMMPS failed (exit {proc.returncode}); see {rel(out / 'log.lammps')}")
    # the executed command stands alone on its line; the "if" line that holds it is echoed too
    free = re.search(r"^fix sleeper_motion ", (out / "log.lammps").read_text(), re.M) is not None
    if free != (s["sleeper"] == "free"):
        raise BenchmarkError(f"{rel(out / 'log.lammps')}: a push with the sleeper "
                             f"{'free' if free else 'held'}, not {s['sleeper']}; give another --out")
    force = np.loadtxt(out / "force.txt", ndmin=2)
    disp = np.loadtxt(out / "displacement.txt", ndmin=2)
    n = min(len(force), len(disp) - 1)
    # Row k of force.txt is the mean over steps (k-1) nrec + 1 .. k nrec, as mfdem's record;
    # displacement.txt starts with step 0.
    return {"u": np.concatenate([[0.0], disp[1:n + 1, 1]]),
            "heave": np.concatenate([[0.0], disp[1:n + 1, 2]]),
            "F": np.concatenate([[math.nan], force[:n, 1]]),
            "support": np.concatenate([[math.nan], -force[:n, 2]]),
            "steps": steps, "seconds": loop_seconds(out / "log.lammps")}


def loop_seconds(log: Path) -> float | None:
    """LAMMPS's "Loop time of T on P procs": the run's own timer; None if it did not finish."""
    m = re.search(r"^Loop time of ([0-9.eE+-]+)", log.read_text(), re.M) if log.exists() else None
    return float(m.group(1)) if m else None


def show_progress(path: Path, distance: float, elapsed: float) -> None:
    try:
        last = path.read_text().strip().splitlines()[-1].split()
        u = float(last[1])
    except (OSError, IndexError, ValueError):
        return
    frac = min(1.0, max(u / distance, 1e-9))
    eta = elapsed * (1.0 - frac) / frac
    print(f"\rLAMMPS push {100 * frac:5.1f} %  u = {u * 1e3:.3f} mm  elapsed {elapsed:.0f} s  "
          f"ETA {eta:.0f} s   ", end="", file=sys.stderr, flush=True)


# --- comparison -----------------------------------------------------------------------------
# Every run is compared on mfdem's record points (the others interpolated in u). Two LAMMPS runs on
# different rank counts differ only in the order of floating-point sums: how far they drift apart
# is the yardstick of chaos against which the codes' difference is read.
WINDOW_MM = 1.0   # F is also compared as its mean over consecutive windows of u: less noisy than the peak


def on_grid(run: dict, u: np.ndarray, key: str) -> np.ndarray:
    ok = np.isfinite(run[key])
    return np.interp(u, run["u"][ok], run[key][ok])


def summary(run: dict, ref: dict) -> dict:
    f = np.where(np.isfinite(run["F"]), run["F"], -np.inf)
    i = int(np.argmax(f))
    i_ref = int(np.nanargmax(ref["F"]))
    return {"peak": float(run["F"][i]), "u_peak": float(run["u"][i]),
            "support": float(on_grid(run, ref["u"][i_ref:i_ref + 1], "support")[0]),
            "windows": window_means(run, ref)}


def window_means(run: dict, ref: dict) -> list[tuple[float, float, float]]:
    """(u_from, u_to, mean F) over consecutive windows of u, on the reference's points."""
    u = ref["u"][1:]
    f = on_grid(run, u, "F")
    edges = np.linspace(0.0, u[-1], max(1, round(u[-1] / (WINDOW_MM * 1e-3))) + 1)
    return [(a, b, float(f[(u > a) & (u <= b)].mean())) for a, b in zip(edges[:-1], edges[1:])]


def rms_apart(a: dict, b: dict, ref: dict) -> float:
    """RMS of the difference of two curves on the reference's points, as a fraction of its peak."""
    u = ref["u"][1:]
    d = on_grid(a, u, "F") - on_grid(b, u, "F")
    return float(np.sqrt(np.mean(d ** 2))) / float(np.nanmax(ref["F"]))


def plot(runs: list[tuple[str, dict]], png: Path, title: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for k, (label, run) in enumerate(runs):
        ax.plot(run["u"] * 1e3, run["F"] * 1e-3, label=label, lw=1.2 if k == 0 else 0.9)
    ax.set_xlabel("sleeper displacement u (mm)")
    ax.set_ylabel("lateral force F (kN)")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(png, dpi=130)


def report(args, packing: Path, s: dict, runs: list[tuple[str, dict]], png: Path) -> str:
    ref = runs[0][1]
    sums = [summary(run, ref) for _, run in runs]
    kn = lambda x: f"{x * 1e-3:.4f}"
    rel_to = lambda x, x0: f"{kn(x)} ({100 * (x / x0 - 1.0):+.1f} %)"
    lines = [f"# Peer push: mfdem and LAMMPS on one packing, sleeper {s['sleeper']} vertically", ""]
    lines += provenance_lines("/usr/bin/python3")
    lines += [f"Packing: `{rel(packing)}`; velocity {s['velocity'] * 1e3:g} mm/s to "
              f"{s['distance'] * 1e3:g} mm; {ref['elements']} pebbles; time step {ref['dt']:.4g} s, "
              f"{ref['steps']} steps in every run. All runs start without contact history. "
              "F(u): minus the sum of contact forces on the sleeper along the push, mean over each "
              "record interval. In brackets: the difference from mfdem.", "",
              "| | " + " | ".join(label for label, _ in runs) + " |",
              "|---|" + "---:|" * len(runs),
              "| peak lateral force (kN) | " + " | ".join(
                  rel_to(x["peak"], sums[0]["peak"]) for x in sums) + " |",
              "| u at the peak (mm) | " + " | ".join(f"{x['u_peak'] * 1e3:.3f}" for x in sums) + " |",
              "| vertical force of the stones on the sleeper at mfdem's peak (kN) | " + " | ".join(
                  rel_to(x["support"], sums[0]["support"]) for x in sums) + " |"]
    for k, (a, b, _) in enumerate(sums[0]["windows"]):
        lines.append(f"| mean F over u = {a * 1e3:.1f}-{b * 1e3:.1f} mm (kN) | " + " | ".join(
            rel_to(x["windows"][k][2], sums[0]["windows"][k][2]) for x in sums) + " |")
    lines.append("| heave at u_end (mm) | " + " | ".join(
        f"{run['heave'][np.isfinite(run['heave'])][-1] * 1e3:+.3f}" for _, run in runs) + " |")
    lines.append("| wall time of the push loop (s) | " + " | ".join(
        f"{run['seconds']:.1f}" + (f" ({run['seconds'] / ref['seconds']:.2f}x mfdem)" if k else "")
        for k, (_, run) in enumerate(runs)) + " |")
    lines += ["", "RMS of the difference of two curves over mfdem's record points, as a fraction "
              "of mfdem's peak:", ""]
    for i in range(len(runs)):
        for j in range(i + 1, len(runs)):
            lines.append(f"- {runs[i][0]} against {runs[j][0]}: "
                         f"{100 * rms_apart(runs[i][1], runs[j][1], ref):.2f} %")
    lines += ["", f"![F(u) of the runs]({png.name})", "", "## Machine", ""]
    lines += machine_description(repo_path(args.mfdem))
    return "\n".join(lines) + "\n"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("packing", help="packing.h5 or the directory `mfdem pack` wrote")
    ap.add_argument("--out", required=True, help="result folder (report.md, peer_push.png, runs)")
    ap.add_argument("--config", help="config whose [push] settings to use (default: the packing's)")
    ap.add_argument("--sleeper", choices=("held", "free"), default="held",
                    help="the sleeper's vertical motion in both codes (default held)")
    ap.add_argument("--velocity", type=float, help="mm/s (default: the config's)")
    ap.add_argument("--distance", type=float, help="mm (default: the config's)")
    ap.add_argument("--threads", type=int, default=1, help="mfdem OpenMP threads (default 1)")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2],
                    help="LAMMPS MPI rank counts, one run each (default 1 2: their difference is "
                    "the yardstick of chaos)")
    ap.add_argument("--reuse", action="store_true",
                    help="keep the runs already finished in --out (to add rank counts or redo the report)")
    ap.add_argument("--mfdem", default="build/studies/mfdem", help="the mfdem executable")
    ap.add_argument("--lammps", default="lmp", help="the LAMMPS executable")
    args = ap.parse_args()

    packing = repo_path(args.packing)
    packing = packing / "packing.h5" if packing.is_dir() else packing
    if not packing.exists():
        raise BenchmarkError(f"{args.packing}: no packing.h5 (expected what `mfdem pack` wrote)")
    with h5py.File(packing, "r") as f:
        own = f["packing"].attrs["config"]
    text = repo_path(args.config).read_text() if args.config else (
        own.decode() if isinstance(own, bytes) else str(own))
    s = read_config(text, args.config or f"{rel(packing)} (its config)")
    if args.velocity:
        s["velocity"] = args.velocity * 1e-3
    if args.distance:
        s["distance"] = args.distance * 1e-3
    out = repo_path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    s["sleeper"] = args.sleeper
    (out / "push.toml").write_text(with_sleeper(text, args.sleeper))
    bare = out / "packing_without_history" / "packing.h5"
    if not (args.reuse and (out / "mfdem" / "push.h5").exists()):
        packing_without_history(packing, bare)

    m = run_mfdem(repo_path(args.mfdem), bare, out / "push.toml", s, args.threads, out / "mfdem",
                  args.reuse)
    if m["status"] != "finished":
        raise BenchmarkError(f"mfdem's push ended '{m['status']}'")
    runs = [(f"mfdem, {args.threads} thread(s)", m)]
    bed = lammps_bed(packing, out, args.reuse)
    for ranks in args.ranks:
        runs.append((f"LAMMPS, {ranks} rank(s)",
                     run_lammps(args.lammps, bed, s, m["dt"], m["steps"], ranks, out / f"lammps_{ranks}",
                                args.reuse)))
    png = out / "peer_push.png"
    plot(runs, png, f"{rel(packing)}: sleeper {s['sleeper']} vertically, {s['velocity'] * 1e3:g} mm/s")
    text = report(args, packing, s, runs, png)
    (out / "report.md").write_text(text)
    print(text)
    print(f"written: {rel(out / 'report.md')}, {rel(png)}")
    return 0


if __name__ == "__main__":
    run_main(main)
