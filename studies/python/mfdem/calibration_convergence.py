"""Draws the calibration benchmark's convergence (studies/benchmarks/calibration_functions).

Reads OUT/convergence.csv written by build/studies/mfdem_calibration_benchmark: for each function
and noise level, the median over seeds of the true gap of the point each method would return,
against the evaluations spent (cost-weighted for the two-level surrogate), with the quartiles of
the surrogate as a band; the 1 % and 0.1 % of the range marked. Writes OUT/convergence.png/.svg.
"""
import argparse
from collections import defaultdict
from pathlib import Path

import numpy as np

from mfdem import figures
from mfdem.files import read_csv


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", help="the benchmark's --out folder")
    args = parser.parse_args(argv)
    rows = read_csv(Path(args.out) / "convergence.csv")
    curves = defaultdict(lambda: defaultdict(list))
    for r in rows:
        key = (r["function"], float(r["noise"]))
        span = r["range"]  # gaps drawn as fractions of the function's range
        curves[key][r["method"]].append((r["cost"], r["median_gap"] / span, r["lower_quartile_gap"] / span,
                                         r["upper_quartile_gap"] / span))
    functions = list(dict.fromkeys(k[0] for k in curves))
    noises = sorted({k[1] for k in curves})
    fig, axes = figures.plt.subplots(len(noises), len(functions), figsize=(4.2 * len(functions), 3.2 * len(noises)),
                                     squeeze=False, sharex="col")
    methods = list(dict.fromkeys(m for c in curves.values() for m in c))
    colours = dict(zip(methods, figures.model_colours(len(methods))))
    for i, noise in enumerate(noises):
        for j, function in enumerate(functions):
            ax = axes[i][j]
            for method, points in curves[(function, noise)].items():
                p = np.array(points)
                finite = np.isfinite(p[:, 1])
                ax.plot(p[finite, 0], p[finite, 1], color=colours[method], lw=2.2 if method == "surrogate" else 1.2,
                        label=method)
                if method == "surrogate":
                    ok = np.isfinite(p[:, 2]) & np.isfinite(p[:, 3])
                    ax.fill_between(p[ok, 0], p[ok, 2], p[ok, 3], color=colours[method], alpha=0.15)
            for level, style in ((1e-2, "--"), (1e-3, ":")):
                ax.axhline(level, color="grey", ls=style, lw=0.8)
            ax.set_yscale("log")
            ax.set_xscale("log")
            ax.set_ylim(1e-6, 2)
            ax.set_title(f"{function}, noise {noise * 100:.0f} % of the range", fontsize=9)
            if j == 0:
                ax.set_ylabel("true gap of the returned point / range")
            if i == len(noises) - 1:
                ax.set_xlabel("evaluations (expensive-run equivalents)")
    axes[0][0].legend(fontsize=7, loc="lower left")
    seeds = "median over seeds; surrogate quartiles shaded; dashed 1 %, dotted 0.1 % of the range"
    fig.suptitle(f"Calibration loop against NLopt applied directly ({seeds})", fontsize=10)
    fig.tight_layout()
    figures.save(fig, Path(args.out) / "convergence")


if __name__ == "__main__":
    main()
