"""mfdem clumps to LAMMPS: read a state file's last frame and write a data file and a
fix rigid/small infile.

Shared by the clump-bed benchmark (studies/benchmarks/clump_bed/run_benchmark.py) and the peer
push of the railway section (mfdem.peer_push). Needs h5py and numpy (Debian's python3).
"""

from __future__ import annotations

import math
from pathlib import Path

import h5py
import numpy as np


def read_bed(state: Path) -> dict:
    """Mass properties of the clumps and the last frame of an mfdem state file (or packing.h5)."""
    with h5py.File(state, "r") as f:
        names = sorted(f["frames"].keys())
        fr = f["frames"][names[-1]]
        bed = {k: f[p][...] for k, p in [("mass", "bodies/mass"), ("inertia", "bodies/inertia"),
                                          ("body", "elements/body"), ("radius", "elements/radius"),
                                          ("offset", "elements/offset")]}
        for k in ("position", "velocity", "angular_velocity", "orientation", "element_position"):
            bed[k] = fr[k][...]
        bed["time"] = float(fr.attrs["time"])
    return bed


def rotation(q) -> np.ndarray:
    """Rotation matrix of the quaternion (w, x, y, z)."""
    w, x, y, z = np.asarray(q) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def write_clumps(bed: dict, data: Path, bodies: Path, lo, hi, title: str) -> None:
    """data: pebbles as atom_style sphere (type 1, 2 atom types), molecule = clump, in the box
    [lo, hi]; every pebble of a clump gets the density that makes the pebble masses add up to
    mfdem's clump mass (the overlaps of the pebbles are not counted twice).
    bodies: fix rigid/small infile with mfdem's mass, centre of mass, inertia tensor (principal
    moments turned by the orientation), velocity and angular momentum."""
    body, radius, xe = bed["body"], bed["radius"], bed["element_position"]
    nb, ne = len(bed["mass"]), len(radius)
    pebble_volume = 4.0 / 3.0 * math.pi * radius ** 3
    density = bed["mass"] / np.bincount(body, weights=pebble_volume, minlength=nb)
    with data.open("w") as f:
        f.write(f"{title}: {nb} clumps of pebbles (type 1 pebbles, type 2 unused)\n\n")
        f.write(f"{ne} atoms\n2 atom types\n\n")
        for axis, a, b in zip("xyz", lo, hi):
            f.write(f"{float(a)!r} {float(b)!r} {axis}lo {axis}hi\n")
        f.write("\nAtoms\n\n")
        for e in range(ne):
            f.write(f"{e + 1} 1 {2.0 * radius[e]!r} {density[body[e]]!r} "
                    f"{xe[e, 0]!r} {xe[e, 1]!r} {xe[e, 2]!r}\n")
        f.write("\nMolecules\n\n")
        for e in range(ne):
            f.write(f"{e + 1} {body[e] + 1}\n")
    with bodies.open("w") as f:
        f.write(f"# {title}: fix rigid/small infile\n"
                "# ID masstotal xcm ycm zcm ixx iyy izz ixy ixz iyz vxcm vycm vzcm lx ly lz "
                "ixcm iycm izcm\n")
        f.write(f"{nb}\n")
        for b in range(nb):
            r = rotation(bed["orientation"][b])
            t = r @ np.diag(bed["inertia"][b]) @ r.T
            ang = t @ bed["angular_velocity"][b]
            x, v = bed["position"][b], bed["velocity"][b]
            vals = [bed["mass"][b], *x, t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2], *v, *ang]
            f.write(f"{b + 1} " + " ".join(repr(float(z)) for z in vals) + " 0 0 0\n")
