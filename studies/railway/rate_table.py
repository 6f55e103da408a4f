#!/usr/bin/python3
"""Rate checks of finished pushes side by side, for results/ pages.

    /usr/bin/python3 studies/railway/rate_table.py FULL HALF [FULL HALF ...] [--window-mm 1]

Each FULL HALF pair is two `mfdem push` directories of one packing, HALF pushed at half FULL's
velocity (a `push --check-rate` directory and its half_velocity/, or two separate pushes). Prints
a Markdown table with what `push --check-rate` writes to rate_check.toml: the change at half the
velocity, (half - full) / full, of the peak force, of the mean force (work / u_end) and of the
mean F over each window of u (consecutive windows of --window-mm; a last window of at least 0.4
of the width counts), and the largest window change. With two or more pairs it adds the mean of
each column and the change of the seed-averaged peak and mean force. It also reads pushes written
before rate_check.toml existed. Needs h5py and numpy (Debian python3-h5py).
"""
import argparse
import sys
from pathlib import Path

try:
    import h5py
    import numpy as np
except ImportError as exc:  # the pyenv python3 first on PATH may lack them
    sys.exit(f"rate_table.py needs h5py and numpy ({exc}); run it with /usr/bin/python3")


def window_means(u: np.ndarray, force: np.ndarray, width: float) -> list[float]:
    """Mean F per window of u, each sample's F spread over its record interval (as
    window_mean_forces in push_test.hpp)."""
    if not len(u) or width <= 0:
        return []
    count = int(np.floor(u[-1] / width))
    if u[-1] - count * width >= 0.4 * width:
        count += 1
    before = np.concatenate(([0.0], u[:-1]))
    means = []
    for w in range(count):
        overlap = np.clip(np.minimum(u, (w + 1) * width) - np.maximum(before, w * width), 0.0, None)
        means.append(float(np.sum(force * overlap) / np.sum(overlap)) if overlap.sum() > 0 else 0.0)
    return means


def load(out: Path) -> dict:
    path = out / "push.h5"
    if not path.exists():
        sys.exit(f"rate_table.py: {path} not found (give directories written by mfdem push)")
    with h5py.File(path, "r") as f:
        u, force = f["curve/u"][()], f["curve/force"][()]
        run = {"velocity": float(f.attrs["velocity"]), "peak": float(force.max()), "u": u, "force": force}
    run["mean"] = float(np.sum(force * np.diff(u, prepend=0.0)) / u[-1])
    run["seed"] = "?"
    summary = out / "push_summary.toml"
    if summary.exists():
        for line in summary.read_text().splitlines():
            if line.startswith("seed"):
                run["seed"] = line.split("=", 1)[1].strip()
    return run


def change(full: float, half: float) -> float:
    return (half - full) / full if full else float("nan")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dirs", nargs="+", type=Path, help="FULL HALF pairs of push directories")
    parser.add_argument("--window-mm", type=float, default=1.0, help="window of the window means, mm (default 1)")
    args = parser.parse_args()
    if len(args.dirs) % 2:
        sys.exit(f"rate_table.py: give FULL HALF pairs, got {len(args.dirs)} directories")
    if args.window_mm <= 0:
        sys.exit(f"rate_table.py: --window-mm must be > 0, got {args.window_mm}")
    width = args.window_mm * 1e-3
    rows = []
    for full_dir, half_dir in zip(args.dirs[::2], args.dirs[1::2]):
        full, half = load(full_dir), load(half_dir)
        if abs(half["velocity"] - 0.5 * full["velocity"]) > 1e-9 * full["velocity"]:
            sys.exit(f"rate_table.py: {half_dir} ran at {half['velocity'] * 1e3:g} mm/s, not half of "
                     f"{full_dir}'s {full['velocity'] * 1e3:g} mm/s")
        wf, wh = window_means(full["u"], full["force"], width), window_means(half["u"], half["force"], width)
        windows = [change(a, b) for a, b in zip(wf, wh)]
        rows.append({"full": full, "half": half, "peak": change(full["peak"], half["peak"]),
                     "mean": change(full["mean"], half["mean"]), "windows": windows,
                     "largest": max(windows, key=abs) if windows else float("nan")})
    count = min(len(r["windows"]) for r in rows)
    window_heads = [f"{k * args.window_mm:g}-{(k + 1) * args.window_mm:g} mm" for k in range(count)]
    heads = ["seed", "v (mm/s)", "peak F (kN)", "peak change", "mean F (kN)", "mean change"] + window_heads + [
        "largest window change"]
    print("| " + " | ".join(heads) + " |")
    print("|" + "---|" * len(heads))
    pct = "{:+.2f} %".format
    for r in rows:
        full, half = r["full"], r["half"]
        cells = [full["seed"], f"{full['velocity'] * 1e3:g} -> {half['velocity'] * 1e3:g}",
                 f"{full['peak'] * 1e-3:.3f} -> {half['peak'] * 1e-3:.3f}", pct(100 * r["peak"]),
                 f"{full['mean'] * 1e-3:.3f} -> {half['mean'] * 1e-3:.3f}", pct(100 * r["mean"])]
        cells += [pct(100 * w) for w in r["windows"][:count]] + [pct(100 * r["largest"])]
        print("| " + " | ".join(cells) + " |")
    if len(rows) >= 2:
        mean = lambda values: float(np.mean(values))
        cells = ["mean of the changes", "", "", pct(100 * mean([r["peak"] for r in rows])), "",
                 pct(100 * mean([r["mean"] for r in rows]))]
        cells += [pct(100 * mean([r["windows"][k] for r in rows])) for k in range(count)]
        cells += [pct(100 * mean([abs(r["largest"]) for r in rows])) + " (of |.|)"]
        print("| " + " | ".join(cells) + " |")
        averaged = {key: change(mean([r["full"][key] for r in rows]), mean([r["half"][key] for r in rows]))
                    for key in ("peak", "mean")}
        print(f"\nSeed-averaged: peak force {pct(100 * averaged['peak'])}, mean force {pct(100 * averaged['mean'])} "
              f"at half the velocity ({len(rows)} pairs).")


if __name__ == "__main__":
    main()
