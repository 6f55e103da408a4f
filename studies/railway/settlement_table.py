#!/usr/bin/python3
"""The sleeper's settlement under the traffic stage's load pulses, pulse by pulse.

    /usr/bin/python3 studies/railway/settlement_table.py OUT [OUT ...] [--plot FILE.png]

OUT is a directory written by `mfdem pack` with `traffic_cycles` > 0 (its packing.h5, or its
checkpoint.h5 while the pack runs). The settlement after pulse N is how far the sleeper's base
has sunk below where it stood as the traffic began, read at the check nearest the end of pulse
N (the load is zero there): the permanent settlement a ballast box test reports against the
number of load cycles. With --plot, settlement against N (log scale) for every OUT, and the
base height through the stage. Needs h5py and numpy (Debian python3-h5py); matplotlib for
--plot.
"""
import argparse
import sys
import tomllib
from pathlib import Path

try:
    import h5py
    import numpy as np
except ImportError as exc:  # the pyenv python3 first on PATH may lack them
    sys.exit(f"settlement_table.py needs h5py and numpy ({exc}); run it with /usr/bin/python3")


def load(out: Path) -> dict:
    path = next((p for p in (out / "packing.h5", out / "checkpoint.h5") if p.exists()), None)
    if path is None:
        sys.exit(f"settlement_table.py: no packing.h5 or checkpoint.h5 in {out} (expected a pack's --out)")
    with h5py.File(path, "r") as f:
        stages = f.get("packing/stages")
        # A packing continued with more traffic (`mfdem pack --continue-from`) has traffic_2, ...:
        # the config's traffic keys describe the last one, which is the one shown.
        runs = [s for name, s in (stages or {}).items()
                if name == "traffic" or (name.startswith("traffic_") and name[8:].isdigit())]
        if not runs:
            sys.exit(f"settlement_table.py: {path} has no traffic stage (set traffic_cycles > 0)")
        traffic = max(runs, key=lambda s: s.attrs["order"])
        if "sleeper_base" not in traffic:
            sys.exit(f"settlement_table.py: {path}: the traffic stage has no sleeper_base series "
                     "(packed before it was recorded)")
        order = traffic.attrs["order"]
        before = [s for s in stages.values() if s.attrs["order"] == order - 1]
        config = tomllib.loads(f["packing"].attrs["config"].decode())
        preparation = config.get("preparation", {})
        # Where the stage began; in packings from before that was stored, where the stage before
        # left it, or straight after the trimming the design place.
        if "sleeper_base_start" in traffic.attrs:
            start = float(traffic.attrs["sleeper_base_start"])
        elif before and "sleeper_base" in before[0].attrs:
            start = float(before[0].attrs["sleeper_base"])
        else:
            start = float(config.get("section", {}).get("depth_under_sleeper", 0.30))
        return {
            "name": str(out),
            "time": traffic["time"][...],
            "base": traffic["sleeper_base"][...],
            "start": start,
            "period": float(preparation.get("traffic_period", 0.05)),
            "load": float(preparation.get("traffic_load", 90e3)),
            "cycles": int(preparation["traffic_cycles"]),
        }


def settlement(d: dict) -> np.ndarray:
    """mm sunk after each pulse, at the check nearest its end."""
    ends = d["period"] * np.arange(1, d["cycles"] + 1)
    nearest = np.abs(d["time"][None, :] - ends[:, None]).argmin(axis=1)
    return 1e3 * (d["start"] - d["base"][nearest])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", nargs="+", type=Path)
    parser.add_argument("--plot", type=Path, help="write the settlement curves to this PNG")
    args = parser.parse_args()
    beds = [load(o) for o in args.out]
    curves = [settlement(d) for d in beds]
    for d, s in zip(beds, curves):
        print(f"{d['name']}: {d['cycles']} pulses of {d['load'] / 1e3:.3g} kN, {d['period']:.3g} s each; "
              f"sleeper base {d['start']:.5f} m before")
        print(f"{'pulse':>6} {'settlement (mm)':>16} {'this pulse (mm)':>16}")
        for n, (total, step) in enumerate(zip(s, np.diff(s, prepend=0.0)), start=1):
            print(f"{n:>6} {total:>16.3f} {step:>16.3f}")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import matplotlib.ticker
        fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
        for d, s in zip(beds, curves):
            n = np.arange(1, len(s) + 1)
            left.semilogx(n, s, "o-", label=d["name"])
            right.plot(d["time"] / d["period"], 1e3 * (d["start"] - d["base"]), lw=0.8, label=d["name"])
        left.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        left.set(xlabel="load pulses N", ylabel="permanent settlement (mm)", title="after each pulse")
        right.set(xlabel="t / pulse period", ylabel="sleeper sunk (mm)", title="through the traffic stage")
        for ax in (left, right):
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=130)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
