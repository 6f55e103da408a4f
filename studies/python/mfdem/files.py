"""The readers of what mfdem writes: packing.h5, push.h5, a run store, compare's outputs.

Each returns plain dicts of numpy arrays and numbers, named as in the files (the layouts are
described in studies/railway/packing.hpp, studies/railway/push_output.hpp,
studies/runs/run_store.hpp and studies/campaigns/compare_figures.hpp).
"""
import csv
import tomllib
from pathlib import Path

import h5py
import numpy as np


def _attrs(node) -> dict:
    return {k: (v.decode() if isinstance(v, bytes) else v) for k, v in node.attrs.items()}


def _group(node) -> dict:
    return {k: node[k][...] for k in node if isinstance(node[k], h5py.Dataset)}


def _in_folder(path, name) -> Path:
    """`path` itself, or the file `name` in it when it is a folder."""
    path = Path(path)
    return path / name if path.is_dir() else path


def read_push(path) -> dict:
    """A push.h5 (or the folder holding it): attrs, curve, network, end_state, model."""
    path = _in_folder(path, "push.h5")
    with h5py.File(path, "r") as f:
        if "curve" not in f:
            raise ValueError(f"{path}: no /curve group (not a push.h5)")
        run = {"path": path, "attrs": _attrs(f), "curve": _group(f["curve"])}
        for name in ("network", "end_state"):
            run[name] = _group(f[name]) if name in f else {}
        run["model"] = _attrs(f["model"]) if "model" in f else {}
    return run


def packing_path(folder) -> Path:
    """The packing a push folder ran on: its own packing.h5, else its parent's (a `pack` folder)."""
    folder = Path(folder)
    for candidate in (folder / "packing.h5", folder.parent / "packing.h5"):
        if candidate.exists():
            return candidate
    raise FileNotFoundError(f"{folder}: no packing.h5 in it or its parent")


def read_packing(path, frames: bool = False) -> dict:
    """A packing.h5 (or checkpoint.h5): the packing attrs, sleeper, sizes, stages, last frame."""
    path = _in_folder(path, "packing.h5")
    with h5py.File(path, "r") as f:
        if "packing" not in f:
            raise ValueError(f"{path}: no /packing group (not a packing file)")
        g = f["packing"]
        attrs = _attrs(g)
        packing = {"path": path, "attrs": attrs,
                   "size": g["size"][...],
                   "sleeper_centre": np.array([attrs[f"sleeper_centre_{a}"] for a in "xyz"]),
                   "sleeper_half_extent": np.array([attrs[f"sleeper_half_extent_{a}"] for a in "xyz"]),
                   "stages": {}}
        for name, stage in g.get("stages", {}).items():
            packing["stages"][name] = {"attrs": _attrs(stage), **_group(stage)}
        names = sorted(f["frames"]) if "frames" in f else []
        packing["frame_names"] = names
        if names:
            packing["last_frame"] = _group(f["frames"][names[-1]])
            packing["last_frame_attrs"] = _attrs(f["frames"][names[-1]])
        if frames:
            packing["frames"] = {n: _group(f["frames"][n]) for n in names}
    return packing


def read_run_record(path) -> dict:
    """A run store's run.toml (or the run folder holding it)."""
    path = _in_folder(path, "run.toml")
    with open(path, "rb") as f:
        return tomllib.load(f)


def read_store(out) -> list:
    """Every run record of a run store (OUT/runs/*/run.toml), by key."""
    runs = Path(out) / "runs"
    return [read_run_record(p) for p in sorted(runs.glob("*/run.toml"))]


def read_csv(path) -> list:
    """A CSV written by mfdem (compare.csv, index.csv): one dict per row, numbers as floats."""
    def value(text):
        try:
            return float(text)
        except ValueError:
            return text if text else float("nan")
    with open(path, newline="") as f:
        return [{k: value(v) for k, v in row.items()} for row in csv.DictReader(f)]


def read_compare_figures(out) -> dict:
    """OUT/figures.h5 of `mfdem compare`: curves and section views, in the models' order."""
    path = Path(out) / "figures.h5"
    with h5py.File(path, "r") as f:
        labels = _attrs(f)
        curves = [{**_attrs(f["curves"][k]), **_group(f["curves"][k])} for k in sorted(f["curves"])]
        section = _attrs(f["section"])
        views = [{**_attrs(f["section"][k]), **_group(f["section"][k])}
                 for k in sorted(f["section"]) if isinstance(f["section"][k], h5py.Group)]
    return {"labels": labels, "curves": curves, "section": section, "views": views}


def read_calibration(out) -> dict:
    """OUT/calibration.h5 of `mfdem calibrate` (layout in studies/campaigns/calibrate_figures.hpp)."""
    path = _in_folder(out, "calibration.h5")
    with h5py.File(path, "r") as f:
        data = {"attrs": _attrs(f)}
        for name in ("parameters", "grid", "runs", "history"):
            data[name] = _group(f[name])
    data["attrs"]["parameter_names"] = data["attrs"]["parameter_names"].split(",")
    return data


def read_stats(out) -> dict:
    """OUT/stats.h5 of `mfdem stats` (layout in studies/campaigns/stats.hpp): labels, outputs, curve."""
    path = _in_folder(out, "stats.h5")
    with h5py.File(path, "r") as f:
        labels = _attrs(f)
        outputs = [{**_attrs(f["outputs"][k]), **_group(f["outputs"][k])} for k in sorted(f["outputs"])]
        curve = _group(f["curve"])
    return {"labels": labels, "outputs": outputs, "curve": curve}
