#!/usr/bin/python3
"""Figures of one or more push tests written by `mfdem push` / `mfdem push-test`.

    /usr/bin/python3 studies/railway/plot_push.py OUT [OUT2 ...] --save figure.png

OUT is a directory holding push.h5 (and packing.h5 for the sleeper outline, optional). The
figure has three panels: F(u) and the sleeper heave against u for every OUT, with the first
OUT's F split into the parts its base, crib sides and shoulder ends carry (thin lines; for a wide
bed also the upward force on the base, the load its friction works with); the
end-state force chains of the first OUT seen along the track (x-z), each stone-stone contact a
line between the stones' centres, width and shade by force; and the stones' displacement field at
u_end (x-z), arrows scaled up, coloured by magnitude (the colour scale ends at the 99th
percentile, so a few stones still falling do not wash out the rest). A bed much wider than deep
(a full-size section) gets its two section views stacked at full width below the curves. Uses matplotlib and h5py (Debian python3-matplotlib,
python3-h5py; run with /usr/bin/python3).
"""
import argparse
import sys
from pathlib import Path

try:
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    import numpy as np
except ImportError as exc:  # the pyenv python3 first on PATH may lack them
    sys.exit(f"plot_push.py needs h5py, numpy and matplotlib ({exc}); run it with /usr/bin/python3")


def load(out: Path) -> dict:
    with h5py.File(out / "push.h5", "r") as f:
        data = {k: f["curve"][k][...] for k in ("u", "force", "heave")}
        # Packings pushed before the split by face have no parts.
        data["parts"] = {k: f["curve"][k][...] for k in ("base", "crib", "shoulder") if k in f["curve"]}
        data["base_support"] = f["curve"]["support_base"][...] if "support_base" in f["curve"] else None
        data.update({k: f.attrs[k] for k in ("peak_force", "u_at_peak", "max_contact_force",
                                             "contact_force_q999", "velocity")})
        end = f["end_state"]
        data["a"] = end["contact_body_a"][...]
        data["b"] = end["contact_body_b"][...]
        data["force_vec"] = end["contact_force"][...]
        data["position"] = end["position"][...]
        data["displacement"] = end["displacement"][...]
    packing = out / "packing.h5"
    if not packing.exists() and (out.parent / "packing.h5").exists():
        packing = out.parent / "packing.h5"
    if packing.exists():
        with h5py.File(packing, "r") as f:
            g = f["packing"]
            data["sleeper"] = [g.attrs[f"sleeper_centre_{a}"] for a in "xz"] + \
                              [g.attrs[f"sleeper_half_extent_{a}"] for a in "xz"]
            data["section_length"] = g.attrs["domain_max_y"] - g.attrs["domain_min_y"]
    return data


def sleeper_outline(ax, data: dict, shift: float = 0.0) -> None:
    if "sleeper" not in data:
        return
    cx, cz, hx, hz = data["sleeper"]
    ax.add_patch(plt.Rectangle((cx - hx + shift, cz - hz), 2 * hx, 2 * hz, fill=False, lw=1.5,
                               ec="k", label="sleeper"))


def section_view(ax, run: dict, pos) -> None:
    """The bed seen along the track (x-z), to scale, with the sleeper's outline."""
    sleeper_outline(ax, run)
    ax.set_xlim(pos[:, 0].min() - 0.05, pos[:, 0].max() + 0.05)
    ax.set_ylim(0, pos[:, 2].max() + 0.05)
    ax.set_aspect("equal")
    ax.set_xlabel("x across the track (m)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("outs", nargs="+", type=Path, help="directories holding push.h5")
    parser.add_argument("--save", type=Path, required=True, help="figure file (.png, .pdf, .svg)")
    parser.add_argument("--labels", nargs="*", help="one label per OUT (default: the directory names)")
    args = parser.parse_args()
    runs = [load(o) for o in args.outs]
    labels = args.labels or [str(o) for o in args.outs]

    pos0 = runs[0]["position"]
    wide = np.ptp(pos0[:, 0]) > 3.0 * np.ptp(pos0[:, 2])
    if wide:  # curves on top, each section view at full width below
        fig = plt.figure(figsize=(13, 11), constrained_layout=True)
        grid = fig.add_gridspec(3, 2, height_ratios=[1.3, 1, 1])
        axes = [fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[1, :]), fig.add_subplot(grid[2, :])]
        parts_ax = fig.add_subplot(grid[0, 1])
    else:
        fig = plt.figure(figsize=(15, 4.8), constrained_layout=True)
        axes = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1, 1.4, 1.4]})
        parts_ax = axes[0]
    ax = axes[0]
    heave_ax = ax.twinx()
    for run, label in zip(runs, labels):
        line, = ax.plot(run["u"] * 1e3, run["force"] * 1e-3, lw=1.2,
                        label=f"{label}: peak {run['peak_force'] * 1e-3:.2f} kN")
        heave_ax.plot(run["u"] * 1e3, run["heave"] * 1e3, lw=0.8, ls="--", color=line.get_color())
    ax.set_xlabel("sleeper displacement u (mm)")
    ax.set_ylabel("lateral force F(u) (kN)")
    heave_ax.set_ylabel("sleeper heave (mm), dashed")
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title("Lateral resistance")
    if runs[0]["parts"]:
        styles = {"base": ":", "crib": "-.", "shoulder": (0, (5, 1))}
        for name, part in runs[0]["parts"].items():
            parts_ax.plot(runs[0]["u"] * 1e3, part * 1e-3, lw=0.9, ls=styles[name], color="0.3" if not wide else None,
                          label=f"{labels[0]}: {name}")
        if wide:
            parts_ax.plot(runs[0]["u"] * 1e3, runs[0]["force"] * 1e-3, lw=1.2, color="k", label=f"{labels[0]}: F")
            if runs[0]["base_support"] is not None:  # the load the base friction works with
                parts_ax.plot(runs[0]["u"] * 1e3, runs[0]["base_support"] * 1e-3, lw=0.8, color="0.6",
                              label=f"{labels[0]}: weight on the base")
            parts_ax.set_xlabel("sleeper displacement u (mm)")
            parts_ax.set_ylabel("part of F (kN)")
            parts_ax.set_title("Where the resistance comes from: base, crib sides, shoulder ends")
            parts_ax.legend(fontsize=8, loc="upper left")

    run = runs[0]
    ax = axes[1]
    pos = run["position"]
    f = np.linalg.norm(run["force_vec"], axis=1)
    a, b = run["a"], run["b"]
    # Contacts across the periodic boundary would draw lines across the section: skip them.
    length = run.get("section_length", np.inf)
    short = np.abs(pos[a, 1] - pos[b, 1]) < 0.5 * length
    order = np.argsort(f[short])
    segs = np.stack([pos[a][short][:, [0, 2]], pos[b][short][:, [0, 2]]], axis=1)[order]
    fs = f[short][order]
    scale = fs / max(fs.max(), 1e-12)
    lc = LineCollection(segs, linewidths=0.2 + 3.0 * scale, cmap="inferno_r", array=fs * 1e-3)
    ax.add_collection(lc)
    fig.colorbar(lc, ax=ax, label="contact force (kN)", shrink=0.8)
    section_view(ax, run, pos)
    ax.set_ylabel("z (m)")
    ax.set_title(f"Force chains at u_end ({labels[0]}; max {run['max_contact_force']:.0f} N, "
                 f"q99.9 {run['contact_force_q999']:.0f} N)", fontsize=9)

    ax = axes[2]
    d = run["displacement"]
    mag = np.linalg.norm(d, axis=1) * 1e3
    top = max(np.percentile(mag, 99), 1e-9)
    arrow = top * 1e-3
    shown = d * np.minimum(1.0, top / np.maximum(mag, 1e-12))[:, None]  # arrows capped like the colours
    q = ax.quiver(pos[:, 0], pos[:, 2], shown[:, 0], shown[:, 2], np.minimum(mag, top), cmap="viridis", angles="xy",
                  scale_units="xy", scale=arrow / 0.04, width=0.0015 if wide else 0.003, clim=(0, top))
    fig.colorbar(q, ax=ax, label="stone displacement (mm, capped at the 99th percentile)", shrink=0.8)
    section_view(ax, run, pos)
    ax.set_title("Displacement field at u_end (x-z, arrows not to scale)", fontsize=9)
    fig.savefig(args.save, dpi=130)
    print(f"wrote {args.save}")


if __name__ == "__main__":
    main()
