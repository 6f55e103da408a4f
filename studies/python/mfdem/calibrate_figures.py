"""Draws `mfdem calibrate`'s figures from OUT/calibration.h5.

OUT/figures/misfit_surface: the predicted misfit over the first two parameters, the candidates
run (cheap ones hollow), the calibrated point and its 90 % intervals; with two levels a second
panel from the expensive runs alone (what the cheap runs add). OUT/figures/posterior: the
posterior density of the parameters. OUT/figures/convergence: the predicted misfit at the
returned point and the next expected improvement against the candidates spent.
"""
import argparse
from pathlib import Path

import numpy as np

from mfdem import figures
from mfdem.files import read_calibration


def _interval_box(ax, p) -> None:
    x0, x1 = p["interval_low"][0], p["interval_high"][0]
    if len(p["interval_low"]) > 1:
        y0, y1 = p["interval_low"][1], p["interval_high"][1]
        ax.add_patch(figures.plt.Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, ec="k", ls="--", lw=1,
                                           label="90 % intervals"))
    else:
        ax.axvspan(x0, x1, color="grey", alpha=0.2, label="90 % interval")


def _runs(ax, runs, two_d: bool, with_cheap: bool = True) -> None:
    p = runs["parameters"]
    expensive = runs["level"] > 0.5
    y = p[:, 1] if two_d else runs["misfit"]
    ax.scatter(p[expensive, 0], y[expensive], s=22, c="k", label="candidates run")
    if with_cheap and (~expensive).any():
        ax.scatter(p[~expensive, 0], y[~expensive], s=22, facecolors="none", edgecolors="k", label="cheap runs")


def misfit_surface(data, out: Path, quiet: bool) -> None:
    grid, names, par = data["grid"], data["attrs"]["parameter_names"], data["parameters"]
    two_d = "y" in grid
    panels = [("misfit", "every run")]
    if "misfit_expensive_only" in grid:
        panels.append(("misfit_expensive_only", "the expensive runs alone"))
    fig, axes = figures.plt.subplots(1, len(panels), figsize=(5.6 * len(panels), 4.4), squeeze=False)
    for ax, (key, title) in zip(axes[0], panels):
        surface = np.maximum(grid[key], 1e-6)
        if two_d:
            levels = np.logspace(np.log10(surface.min()), np.log10(surface.max()), 16)
            c = ax.contourf(grid["x"], grid["y"], surface, levels=levels, norm=figures.matplotlib.colors.LogNorm(),
                            cmap="viridis_r")
            # Ticks at every third level: a log scale within one decade would otherwise label two.
            bar = fig.colorbar(c, ax=ax, ticks=levels[::3], format="%.2g",
                               label="predicted misfit (sum of squared relative errors)")
            bar.minorticks_off()
            ax.set_ylabel(names[1])
        else:
            ax.semilogy(grid["x"], surface[0], color="C0", label="predicted misfit")
            ax.set_ylabel("misfit (sum of squared relative errors)")
        _runs(ax, data["runs"], two_d, with_cheap=key == "misfit")
        cal = par["calibrated"]
        ax.plot(cal[0], cal[1] if two_d else np.interp(cal[0], grid["x"], surface[0]), "r*", ms=14, label="calibrated")
        if "truth" in par:
            t = par["truth"]
            ax.plot(t[0], t[1] if two_d else np.interp(t[0], grid["x"], surface[0]), "wX", ms=11, mec="k",
                    label="truth (the reference model's)")
        _interval_box(ax, par)
        ax.set_xlabel(names[0])
        ax.set_title(f"predicted from {title}", fontsize=9)
    axes[0][0].legend(fontsize=7, loc="best")
    a = data["attrs"]
    fig.suptitle(f"mfdem calibrate {a['config']}, {a['policy']}\ntargets {a['target_peak']:.4g} N peak, "
                 f"{a['target_contact']:.4g} N contact (means of {a['seeds']:.0f} seeds)", fontsize=9)
    fig.tight_layout()
    figures.save(fig, out / "misfit_surface", quiet)


def posterior(data, out: Path, quiet: bool) -> None:
    grid, names, par = data["grid"], data["attrs"]["parameter_names"], data["parameters"]
    fig, ax = figures.plt.subplots(figsize=(5.6, 4.4))
    if "y" in grid:
        c = ax.contourf(grid["x"], grid["y"], grid["posterior"], levels=12, cmap="Blues")
        fig.colorbar(c, ax=ax, label="posterior density / its maximum")
        ax.set_ylabel(names[1])
    else:
        ax.plot(grid["x"], grid["posterior"][0], color="C0")
        ax.set_ylabel("posterior density / its maximum")
    _interval_box(ax, par)
    ax.plot(par["calibrated"][0], par["calibrated"][1] if "y" in grid else 1.0, "r*", ms=14, label="calibrated")
    if "truth" in par:
        ax.plot(par["truth"][0], par["truth"][1] if "y" in grid else 1.0, "wX", ms=11, mec="k",
                label="truth (the reference model's)")
    ax.set_xlabel(names[0])
    ax.legend(fontsize=7)
    ax.set_title("posterior of the parameters (uniform prior on the ranges)", fontsize=9)
    fig.tight_layout()
    figures.save(fig, out / "posterior", quiet)


def convergence(data, out: Path, quiet: bool) -> None:
    h = data["history"]
    fig, ax = figures.plt.subplots(figsize=(5.6, 3.8))
    ax.semilogy(h["cost"], np.maximum(h["predicted_misfit"], 1e-8), "o-", label="predicted misfit at the returned point")
    ei = h["expected_improvement"]
    ax.semilogy(h["cost"][ei > 0], ei[ei > 0], "s--", label="expected improvement of the next candidate")
    ax.set_xlabel("candidates spent (a cheap one counts its cost)")
    ax.set_ylabel("misfit (sum of squared relative errors)")
    ax.legend(fontsize=7)
    ax.set_title("convergence of the calibration", fontsize=9)
    fig.tight_layout()
    figures.save(fig, out / "convergence", quiet)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", help="the calibration's --out folder")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    data = read_calibration(args.out)
    target = Path(args.out) / "figures"
    misfit_surface(data, target, args.quiet)
    posterior(data, target, args.quiet)
    convergence(data, target, args.quiet)


if __name__ == "__main__":
    main()
