#!/usr/bin/python3
"""Where a prepared bed is still moving: the unbalanced force and the stone speeds by region.

    /usr/bin/python3 studies/railway/settling_table.py OUT [OUT ...]

OUT is a directory written by `mfdem pack` (its packing.h5). The pack summary gives one number,
the unbalanced force ratio (mean |unbalanced force| over the stones / mean |contact force| over
the element contacts); when it stays above the equilibrium target, this table says which part
of the bed holds the remainder. Regions, by each stone's centre: under the sleeper (within its
length, below its base), the crib (within its length, above its base) and the shoulders (beyond
its ends), the crib and shoulders split into their surface (within --surface-m of the highest
stone centre of each 0.1 m wide strip across the track) and the rest. Then the settling
stage's ratio over its simulated time. Needs h5py and numpy (Debian python3-h5py).
"""
import argparse
import sys
from pathlib import Path

try:
    import h5py
    import numpy as np
except ImportError as exc:  # the pyenv python3 first on PATH may lack them
    sys.exit(f"settling_table.py needs h5py and numpy ({exc}); run it with /usr/bin/python3")

STRIP_M = 0.1  # width of the strips across the track whose highest stone marks the surface


def load(out: Path) -> dict:
    path = out / "packing.h5"
    if not path.exists():
        sys.exit(f"settling_table.py: {path} not found (expected the directory of a pack run)")
    with h5py.File(path, "r") as f:
        attrs = f["packing"].attrs
        frame = f["frames/000000"]
        d = {k: frame[k][...] for k in ("position", "velocity", "unbalanced_force")}
        d["sleeper_x"] = (float(attrs["sleeper_centre_x"]), float(attrs["sleeper_half_extent_x"]))
        d["base_z"] = float(attrs["sleeper_centre_z"] - attrs["sleeper_half_extent_z"])
        d["ratio"] = float(attrs["unbalanced_force_ratio"])
        settle = f.get("packing/stages/settle")
        d["history"] = (settle["time"][...], settle["unbalanced_force_ratio"][...]) if settle else None
        d["name"] = str(out)
    return d


def surface_mask(position: np.ndarray, depth: float) -> np.ndarray:
    strip = np.floor(position[:, 0] / STRIP_M).astype(int)
    top = np.full(strip.max() - strip.min() + 1, -np.inf)
    np.maximum.at(top, strip - strip.min(), position[:, 2])
    return position[:, 2] > top[strip - strip.min()] - depth


def regions(d: dict, depth: float) -> dict:
    x = d["position"]
    centre, half = d["sleeper_x"]
    within = np.abs(x[:, 0] - centre) < half
    above = x[:, 2] >= d["base_z"]
    surface = surface_mask(x, depth)
    return {"under the sleeper": within & ~above,
            "crib, surface": within & above & surface,
            "crib, below the surface": within & above & ~surface,
            "shoulders, surface": ~within & surface,
            "shoulders, below the surface": ~within & ~surface}


def table(d: dict, depth: float) -> None:
    unbalanced = np.linalg.norm(d["unbalanced_force"], axis=1)
    speed = np.linalg.norm(d["velocity"], axis=1) * 1e3
    sink = -d["velocity"][:, 2] * 1e3
    print(f"\n{d['name']}: {len(unbalanced)} stones, unbalanced force ratio {d['ratio']:.2e}\n")
    print("| region | stones | share of the unbalanced force | mean unbalanced force (mN) | "
          "median speed (mm/s) | 99 % speed (mm/s) | median sinking (mm/s) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, s in regions(d, depth).items():
        if not s.any():
            continue
        print(f"| {name} | {s.sum()} | {unbalanced[s].sum() / unbalanced.sum():.2f} | "
              f"{1e3 * unbalanced[s].mean():.2f} | {np.median(speed[s]):.3f} | "
              f"{np.quantile(speed[s], 0.99):.2f} | {np.median(sink[s]):.3f} |")
    if d["history"] is not None:
        time, ratio = d["history"]
        picks = np.unique(np.linspace(0, len(time) - 1, 7).astype(int))
        print("\nsettling: ratio at t (s) " + ", ".join(f"{time[i]:.2f}: {ratio[i]:.1e}" for i in picks))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("outs", type=Path, nargs="+", help="directories of pack runs")
    parser.add_argument("--surface-m", type=float, default=0.06,
                        help="depth of the surface layer, m (default 0.06, about a stone)")
    args = parser.parse_args()
    if args.surface_m <= 0:
        sys.exit(f"settling_table.py: --surface-m must be > 0, got {args.surface_m}")
    for out in args.outs:
        table(load(out), args.surface_m)


if __name__ == "__main__":
    main()
