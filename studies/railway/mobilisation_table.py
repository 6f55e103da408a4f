#!/usr/bin/python3
"""How much of its friction each face of the sleeper uses, millimetre by millimetre of a push.

    /usr/bin/python3 studies/railway/mobilisation_table.py OUT [--step-mm 1]

OUT is a directory written by `mfdem push` or `mfdem push-test` with the pressing split
(curve/pressing_*; runs from before it are refused). Prints a Markdown table, one row per
--step-mm of displacement (means over the row's samples): F; the base's part of F, the normal
force on the base and their ratio (the friction the base uses; mu when every base contact
slides); the same for the two crib sides; the ends' part; and the sliding bound
mu (N_base + N_crib) + ends, the F the sleeper would meet if base and crib slid at mu against the
same normal forces. Edge contacts count to one face with their whole force, so a ratio can
exceed mu by a little. Needs h5py and numpy (Debian python3-h5py).
"""
import argparse
import sys
from pathlib import Path

try:
    import h5py
    import numpy as np
except ImportError as exc:  # the pyenv python3 first on PATH may lack them
    sys.exit(f"mobilisation_table.py needs h5py and numpy ({exc}); run it with /usr/bin/python3")


def load(out: Path) -> dict:
    path = out / "push.h5"
    if not path.exists():
        sys.exit(f"mobilisation_table.py: {path} not found (expected the directory of a push run)")
    with h5py.File(path, "r") as f:
        if "curve/pressing_base" not in f:
            sys.exit(f"mobilisation_table.py: {path} has no curve/pressing_base (written before the "
                     "pressing split; push the packing again)")
        data = {k: f[f"curve/{k}"][...] for k in ("u", "force", "base", "crib", "shoulder",
                                                   "pressing_base", "pressing_crib")}
        data["mu"] = float(f.attrs["sleeper_friction"])
    return data


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="directory of a push run")
    parser.add_argument("--step-mm", type=float, default=1.0, help="row width, mm (default 1)")
    args = parser.parse_args()
    if args.step_mm <= 0:
        sys.exit(f"mobilisation_table.py: --step-mm must be > 0, got {args.step_mm}")
    d = load(args.out)
    mu = d["mu"]
    u_mm = d["u"] * 1e3
    # Rows of --step-mm; the last one also takes the ramp's overshoot past a whole step.
    edges = np.arange(0.0, u_mm.max() - 0.5 * args.step_mm, args.step_mm)
    edges = np.append(edges, u_mm.max())
    print(f"Stone-sleeper friction mu = {mu:g}. Forces in kN, means over each row.\n")
    print("| u (mm) | F | base | N base | base/N | crib | N crib | crib/N | ends | "
          "mu (N base + N crib) + ends |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for lo, hi in zip(edges[:-1], edges[1:]):
        rows = (u_mm > lo) & (u_mm <= hi)
        if not rows.any():
            continue
        m = {k: float(np.mean(v[rows])) for k, v in d.items() if k != "mu"}
        bound = mu * (m["pressing_base"] + m["pressing_crib"]) + m["shoulder"]
        ratio = lambda part, normal: f"{part / normal:.2f}" if normal > 0 else "-"
        print(f"| {lo:g}-{hi:.3g} | {m['force'] * 1e-3:.3f} | {m['base'] * 1e-3:.3f} | "
              f"{m['pressing_base'] * 1e-3:.3f} | {ratio(m['base'], m['pressing_base'])} | "
              f"{m['crib'] * 1e-3:.3f} | {m['pressing_crib'] * 1e-3:.3f} | "
              f"{ratio(m['crib'], m['pressing_crib'])} | {m['shoulder'] * 1e-3:.3f} | {bound * 1e-3:.3f} |")


if __name__ == "__main__":
    main()
