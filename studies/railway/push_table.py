#!/usr/bin/python3
"""Table of several push tests (seeds, velocities), with mean and spread, for results/ pages.

    /usr/bin/python3 studies/railway/push_table.py OUT [OUT2 ...] [--window-mm 0.25]

OUT is a directory written by `mfdem push` or `mfdem push-test` (push.h5). Prints a Markdown
table: seed, the model (fidelity policy; runs before the multi-layer model: all-clump), velocity,
stones, balls, elements and their ratio to the same stones as all clumps, the re-settling's wall
time after a conversion, peak F and where, the peak of F(u) after a moving mean
over --window-mm of displacement (the record interval is 0.01-0.02 mm, so the raw peak can be one
stick-slip spike; the smoothed peak shows how much), F at u_end, the maximum contact force and its
99.9 % quantile, the shares of the peak carried by the sleeper's base, crib sides and shoulder
ends (nan for runs written before that split), the share of the sleeper's weight its base
carries at u = 0 and the base's lateral force over that load at the peak (the friction it
mobilises; mu = 0.5 when it slides), the normal force on the crib sides at the peak and the
crib's part of F over it (runs written before the pressing split have nan), the heave, the largest inertial number and the wall time. With two or more rows
it adds the mean and the sample standard deviation. Needs h5py and numpy (Debian python3-h5py).
"""
import argparse
import sys
from pathlib import Path

try:
    import h5py
    import numpy as np
except ImportError as exc:  # the pyenv python3 first on PATH may lack them
    sys.exit(f"push_table.py needs h5py and numpy ({exc}); run it with /usr/bin/python3")

COLUMNS = [  # (header, key, scale, format)
    ("balls", "balls", 1.0, "{:,.0f}"),
    ("elements / all-clump", "element_ratio", 1.0, "{:.2f}"),
    ("re-settle (min)", "resettle_wall_seconds", 1 / 60, "{:.1f}"),
    ("peak F (kN)", "peak_force", 1e-3, "{:.3f}"),
    ("at u (mm)", "u_at_peak", 1e3, "{:.2f}"),
    ("smoothed peak (kN)", "smoothed_peak", 1e-3, "{:.3f}"),
    ("F(u_end) (kN)", "end_force", 1e-3, "{:.3f}"),
    ("mean F, work/u_end (kN)", "mean_force", 1e-3, "{:.3f}"),
    ("base at peak (%)", "base_share", 100.0, "{:.0f}"),
    ("crib (%)", "crib_share", 100.0, "{:.0f}"),
    ("shoulder (%)", "shoulder_share", 100.0, "{:.0f}"),
    ("weight on base at u=0 (%)", "base_load_share", 100.0, "{:.0f}"),
    ("base / its load at peak", "base_mobilised", 1.0, "{:.2f}"),
    ("crib sides pressed at peak (kN)", "crib_pressing", 1e-3, "{:.3f}"),
    ("crib / its pressing", "crib_mobilised", 1.0, "{:.2f}"),
    ("max contact (kN)", "max_contact_force", 1e-3, "{:.3f}"),
    ("q99.9 (kN)", "contact_force_q999", 1e-3, "{:.3f}"),
    ("heave (mm)", "final_heave", 1e3, "{:+.2f}"),
    ("max I", "max_inertial_number", 1.0, "{:.1e}"),
    ("wall (min)", "wall_seconds", 1 / 60, "{:.1f}"),
]


def moving_mean_peak(u: np.ndarray, force: np.ndarray, window: float) -> float:
    """Largest mean of F over any run of samples spanning `window` of displacement."""
    if len(u) < 2:
        return float(force.max()) if len(force) else float("nan")
    spacing = float(np.median(np.diff(u)))
    width = max(1, int(round(window / spacing)))
    if width >= len(force):
        return float(force.mean())
    return float(np.convolve(force, np.ones(width) / width, mode="valid").max())


def work_per_displacement(u: np.ndarray, force: np.ndarray) -> float:
    """Mean F over the push as mfdem defines it (push_test.hpp): sum F_k (u_k - u_k-1) / u_last,
    from the curve so that runs written before the mean_force attribute have it too."""
    if not len(u) or u[-1] <= 0:
        return float("nan")
    return float(np.sum(force * np.diff(u, prepend=0.0)) / u[-1])


def load(out: Path, window: float) -> dict:
    path = out / "push.h5"
    if not path.exists():
        sys.exit(f"push_table.py: {path} not found (expected the directory of a push run)")
    with h5py.File(path, "r") as f:
        row = {k: float(f.attrs[k]) for k in ("peak_force", "u_at_peak", "max_contact_force",
                                               "contact_force_q999", "final_heave",
                                               "max_inertial_number", "wall_seconds", "velocity",
                                               "stones", "elements")}
        model = f["model"].attrs if "model" in f else {}
        row["model"] = model["policy"].decode() if isinstance(model.get("policy"), bytes) else str(model.get("policy", "all-clump"))
        for key, absent in (("balls", 0.0), ("element_ratio", 1.0), ("resettle_wall_seconds", 0.0)):
            row[key] = float(model[key]) if key in model else absent
        u, force = f["curve/u"][...], f["curve/force"][...]
        peak = int(np.argmax(force)) if len(force) else 0
        for part in ("base", "crib", "shoulder"):
            key = f"curve/{part}"
            row[f"{part}_share"] = float(f[key][peak] / force[peak]) if key in f and len(force) else float("nan")
        # How much of the weight the base carries, and how much of mu it uses (runs written
        # before the split of the weight have nan).
        has_support = "curve/support_base" in f and "sleeper_weight" in f.attrs and len(force)
        support = f["curve/support_base"][...] if has_support else None
        row["base_load_share"] = float(support[0] / f.attrs["sleeper_weight"]) if has_support else float("nan")
        row["base_mobilised"] = float(f["curve/base"][peak] / support[peak]) if has_support else float("nan")
        has_pressing = "curve/pressing_crib" in f and len(force)
        pressing = f["curve/pressing_crib"][peak] if has_pressing else float("nan")
        row["crib_pressing"] = float(pressing)
        row["crib_mobilised"] = float(f["curve/crib"][peak] / pressing) if has_pressing else float("nan")
    row["end_force"] = float(force[-1]) if len(force) else float("nan")
    row["smoothed_peak"] = moving_mean_peak(u, force, window)
    row["mean_force"] = work_per_displacement(u, force)
    summary = out / "push_summary.toml"
    row["seed"] = "?"
    if summary.exists():
        for line in summary.read_text().splitlines():
            if line.startswith("seed"):
                row["seed"] = line.split("=", 1)[1].strip()
    row["name"] = str(out)
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("outs", nargs="+", type=Path, help="directories of push runs")
    parser.add_argument("--window-mm", type=float, default=0.25,
                        help="displacement window of the smoothed peak, mm (default 0.25)")
    args = parser.parse_args()
    if args.window_mm <= 0:
        sys.exit(f"push_table.py: --window-mm must be > 0, got {args.window_mm}")
    rows = [load(out, args.window_mm * 1e-3) for out in args.outs]
    headers = ["run", "seed", "model", "v (mm/s)", "stones", "elements"] + [c[0] for c in COLUMNS]
    print("| " + " | ".join(headers) + " |")
    print("|" + "---|" * len(headers))
    for r in rows:
        cells = [r["name"], r["seed"], r["model"], f"{r['velocity'] * 1e3:g}", f"{r['stones']:,.0f}",
                 f"{r['elements']:,.0f}"]
        cells += [fmt.format(r[key] * scale) for _, key, scale, fmt in COLUMNS]
        print("| " + " | ".join(cells) + " |")
    if len(rows) >= 2:
        # numpy, not statistics: a column of runs from before a field existed is nan, which
        # statistics.stdev cannot take.
        for label, reduce in (("mean", np.mean), ("std", lambda x: np.std(x, ddof=1))):
            cells = [label, "", "", "", "", ""]
            cells += [fmt.format(reduce([r[key] for r in rows]) * scale).replace("+", "")
                      for _, key, scale, fmt in COLUMNS]
            print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
