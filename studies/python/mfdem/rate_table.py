"""Rate checks side by side: what `mfdem push --check-rate` measured, one row per run.

    tools/mfdem-py rate_table OUT [OUT ...]

OUT is a folder of `mfdem push --check-rate` (or `push-test --check-rate`'s push/ folder): its
rate_check.toml holds the push repeated at half the velocity compared with the first, computed
by mfdem: the change (half - full) / full of the peak force, of the mean force (work / u_end) and
of the mean F over each window of u, and the largest window change. Prints them as a Markdown
table, with the seed and both pushes' peak forces.
"""
import argparse
import sys
import tomllib
from pathlib import Path

from mfdem import files, tables


def row_of(out: Path) -> dict:
    check_file = out / "rate_check.toml"
    if not check_file.exists():
        sys.exit(f"rate_table: {check_file} not found: run `mfdem push BED --check-rate --out {out}` "
                 "(it pushes again at half the velocity and writes the comparison)")
    with open(check_file, "rb") as f:
        check = tomllib.load(f)
    full, half = files.read_push(out), files.read_push(out / "half_velocity")
    return {"check": check, "seed": full["attrs"].get("seed", float("nan")),
            "peak": full["attrs"]["peak_force"], "peak_half": half["attrs"]["peak_force"]}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("outs", nargs="+", type=Path, help="folders of push --check-rate runs")
    args = parser.parse_args(argv)
    rows = [row_of(out) for out in args.outs]
    width_mm = rows[0]["check"]["window"] * 1e3
    count = min(len(r["check"]["window_change"]) for r in rows)
    pct = "{:+.2f} %".format
    header = ["run", "seed", "v (mm/s)", "peak F (kN)", "peak change", "mean change"] + [
        f"{k * width_mm:g}-{(k + 1) * width_mm:g} mm" for k in range(count)] + ["largest window change", "within 2 %"]
    cells = []
    for out, r in zip(args.outs, rows):
        c = r["check"]
        cells.append([str(out), f"{r['seed']:.0f}", f"{c['velocity'] * 1e3:g} -> {c['half_velocity'] * 1e3:g}",
                      f"{r['peak'] * 1e-3:.3f} -> {r['peak_half'] * 1e-3:.3f}", pct(100 * c["peak_change"]),
                      pct(100 * c["mean_change"])] + [pct(100 * w) for w in c["window_change"][:count]]
                     + [pct(100 * c["largest_window_change"]), "yes" if c["within_criterion"] else "no"])
    tables.print_table(header, cells, "ll" + "r" * (len(header) - 2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
