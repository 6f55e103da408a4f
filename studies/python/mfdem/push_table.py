"""Push runs side by side (seeds, velocities, models), one row each, for results pages.

    tools/mfdem-py push_table OUT [OUT ...]

OUT is a folder holding push.h5 (`mfdem push`, `push-test`, or a run store's runs/KEY). Prints a
Markdown table of what mfdem wrote: seed, model, velocity, stones, balls, elements and their
ratio to the same stones as all clumps, the re-settling's wall time, peak F and where, F at
u_end, the mean force (work / u_end), the shares of the peak carried by the sleeper's base, crib
sides and shoulder ends, the share of the sleeper's weight its base carries at u = 0 and the
base's lateral force over that load at the peak (the friction it mobilises; mu = 0.5 when it
slides), the maximum contact force and its 99.9 % quantile, the heave, the largest inertial
number and the wall time. A value a run did not write (an older run) shows as nan. Statistics
over seeds, with intervals, come from `mfdem compare` (computed there, not here).
"""
import argparse
import math
import sys
from pathlib import Path

from mfdem import files, tables

NAN = float("nan")
COLUMNS = [  # (header, key, scale, format)
    ("balls", "balls", 1.0, "{:,.0f}"),
    ("elements / all-clump", "element_ratio", 1.0, "{:.2f}"),
    ("re-settle (min)", "resettle_wall_seconds", 1 / 60, "{:.1f}"),
    ("peak F (kN)", "peak_force", 1e-3, "{:.3f}"),
    ("at u (mm)", "u_at_peak", 1e3, "{:.2f}"),
    ("F(u_end) (kN)", "end_force", 1e-3, "{:.3f}"),
    ("mean F, work/u_end (kN)", "mean_force", 1e-3, "{:.3f}"),
    ("base at peak (%)", "base_share", 100.0, "{:.0f}"),
    ("crib (%)", "crib_share", 100.0, "{:.0f}"),
    ("shoulder (%)", "shoulder_share", 100.0, "{:.0f}"),
    ("weight on base at u=0 (%)", "base_load_share", 100.0, "{:.0f}"),
    ("base / its load at peak", "base_mobilised", 1.0, "{:.2f}"),
    ("max contact (kN)", "max_contact_force", 1e-3, "{:.3f}"),
    ("q99.9 (kN)", "contact_force_q999", 1e-3, "{:.3f}"),
    ("heave (mm)", "final_heave", 1e3, "{:+.2f}"),
    ("max I", "max_inertial_number", 1.0, "{:.1e}"),
    ("wall (min)", "wall_seconds", 1 / 60, "{:.1f}"),
]


def row_of(out: Path) -> dict:
    """The table's values of one run: attributes as written, curve samples read at the peak."""
    push = files.read_push(out)
    attrs, curve, model = push["attrs"], push["curve"], push["model"]
    row = {k: float(attrs.get(k, NAN)) for k in ("peak_force", "u_at_peak", "max_contact_force", "contact_force_q999",
                                                 "final_heave", "max_inertial_number", "wall_seconds", "velocity",
                                                 "stones", "elements", "mean_force", "seed", "sleeper_weight")}
    row["model"] = str(model.get("policy", "all-clump"))
    for key, absent in (("balls", 0.0), ("element_ratio", 1.0), ("resettle_wall_seconds", 0.0)):
        row[key] = float(model.get(key, absent))
    force = curve["force"]
    # The peak sample: the first at the peak force mfdem reports.
    peak = next((k for k, f in enumerate(force) if f == row["peak_force"]), None) if len(force) else None
    at_peak = lambda name: float(curve[name][peak]) if peak is not None and name in curve else NAN  # noqa: E731
    for part in ("base", "crib", "shoulder"):
        row[f"{part}_share"] = at_peak(part) / row["peak_force"]
    support = curve.get("support_base")
    row["base_load_share"] = float(support[0]) / row["sleeper_weight"] if support is not None else NAN
    row["base_mobilised"] = at_peak("base") / at_peak("support_base")
    row["end_force"] = float(force[-1]) if len(force) else NAN
    row["name"] = str(out)
    return row


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("outs", nargs="+", type=Path, help="folders of push runs")
    args = parser.parse_args(argv)
    rows = [row_of(out) for out in args.outs]
    header = ["run", "seed", "model", "v (mm/s)", "stones", "elements"] + [c[0] for c in COLUMNS]
    cells = [[r["name"], "?" if math.isnan(r["seed"]) else f"{r['seed']:.0f}", r["model"],
              f"{r['velocity'] * 1e3:g}", f"{r['stones']:,.0f}", f"{r['elements']:,.0f}"]
             + [fmt.format(r[key] * scale) for _, key, scale, fmt in COLUMNS] for r in rows]
    tables.print_table(header, cells, "lll" + "r" * (len(header) - 3))
    return 0


if __name__ == "__main__":
    sys.exit(main())
