#!/usr/bin/python3
"""How far the bed's resistance lags the sleeper: F(u) of one packing pushed at several velocities.

    /usr/bin/python3 studies/railway/rate_lag.py DIR [DIR ...] [--window-mm 0.05] [--up-to-mm 0.4]

Each DIR is an `mfdem push` directory of the same packing, each at its own velocity. The two
slowest give the quasi-static curve by linear extrapolation to v -> 0 of the window means,
F_qs = F(v_min) - (F(v_2) - F(v_min)) v_min / (v_2 - v_min). If the force exceeds F_qs because the
bed answers the sleeper's motion a time tau late, F(u, v) = F_qs(u + v tau), so the excess is
about tau v dF_qs/du: the table gives, per window, F_qs, its slope and, for each faster velocity,
the excess and tau = excess / (v dF_qs/du), and the median tau of each over the windows up to
--up-to-mm where F_qs rises (slope > 0). (The two slowest have the same tau by construction:
only the faster ones test the reading.) A tau the same at every faster velocity says the rate
effect is this lag. Needs h5py and numpy (Debian python3-h5py).
"""
import argparse
import sys
from pathlib import Path

import numpy as np

from rate_table import load, window_means


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dirs", nargs="+", type=Path, help="push directories of one packing at different velocities")
    parser.add_argument("--window-mm", type=float, default=0.05, help="window of the window means, mm (default 0.05)")
    parser.add_argument("--up-to-mm", type=float, default=0.4, help="last u of the median tau, mm (default 0.4)")
    args = parser.parse_args()
    if len(args.dirs) < 3:
        sys.exit(f"rate_lag.py: give three or more velocities (two for F_qs, one more to compare), got {len(args.dirs)}")
    if args.window_mm <= 0 or args.up_to_mm <= 0:
        sys.exit(f"rate_lag.py: --window-mm and --up-to-mm must be > 0, got {args.window_mm} and {args.up_to_mm}")
    width = args.window_mm * 1e-3
    runs = sorted((load(d) for d in args.dirs), key=lambda r: r["velocity"])
    if len({r["velocity"] for r in runs}) != len(runs):
        sys.exit("rate_lag.py: two directories ran at the same velocity")
    means = [np.array(window_means(r["u"], r["force"], width)) for r in runs]
    n = min(len(m) for m in means)
    means = [m[:n] for m in means]
    v = [r["velocity"] for r in runs]
    quasi_static = means[0] - (means[1] - means[0]) * v[0] / (v[1] - v[0])
    slope = np.gradient(quasi_static, width)
    excess = [m - quasi_static for m in means[2:]]
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = [e / (vel * slope) for e, vel in zip(excess, v[2:])]

    speeds = [f"{vel * 1e3:g}" for vel in v[2:]]
    print(f"| u (mm) | F_qs (kN) | dF_qs/du (kN/mm) | " + " | ".join(f"excess at {s} mm/s (N)" for s in speeds)
          + " | " + " | ".join(f"tau at {s} (ms)" for s in speeds) + " |")
    print("|" + "---:|" * (3 + 2 * len(speeds)))
    for i in range(n):
        cells = [f"{(i + 0.5) * args.window_mm:.3f}", f"{quasi_static[i] * 1e-3:.3f}", f"{slope[i] * 1e-6:.2f}"]
        cells += [f"{e[i]:.1f}" for e in excess] + [f"{t[i] * 1e3:.2f}" for t in tau]
        print("| " + " | ".join(cells) + " |")
    rising = [i for i in range(n) if (i + 1) * width <= args.up_to_mm * 1e-3 + 1e-12 and slope[i] > 0]
    print()
    for s, t in zip(speeds, tau):
        if rising:
            print(f"{s} mm/s: median tau over u <= {args.up_to_mm:g} mm ({len(rising)} windows) "
                  f"{np.median(t[rising]) * 1e3:.2f} ms")
    print(f"(the two slowest, {v[0] * 1e3:g} and {v[1] * 1e3:g} mm/s, define F_qs)")


if __name__ == "__main__":
    main()
