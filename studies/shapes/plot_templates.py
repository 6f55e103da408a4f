#!/usr/bin/env python3
"""Picture of clump templates: each stone's surface with its pebbles, at two resolutions.

Reads the template files written by `mfdem shapes build` (TOML; lengths in units of the stone's
size d, body frame) and draws, for each chosen template, the stone's surface (grey facets) and its
pebbles (coloured spheres), one row per library. Usage, from the repository's top folder:

    python3 studies/shapes/plot_templates.py \
        --library studies/shapes/library --library studies/shapes/library_24 \
        --out results/shapes/templates.png
"""
import argparse
import pathlib
import sys
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

DEFAULT_TEMPLATES = ["ballast_01", "ballast_04", "ballast_07", "ballast_10", "ballast_12"]
SPHERE_STEPS = 14  # mesh lines per sphere


def load(path):
    with open(path, "rb") as f:
        return tomllib.load(f)


def draw(ax, template):
    surface = template["surface"]
    vertices = np.array(surface["vertices"])
    faces = [vertices[list(t)] for t in surface["triangles"]]
    ax.add_collection3d(Poly3DCollection(faces, facecolor=(0.6, 0.6, 0.6, 0.18), edgecolor=(0.3, 0.3, 0.3, 0.5),
                                         linewidth=0.4))
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, SPHERE_STEPS), np.linspace(0, np.pi, SPHERE_STEPS))
    colours = plt.cm.viridis(np.linspace(0.1, 0.9, len(template["clump"]["pebbles"])))
    for (x, y, z, r), colour in zip(template["clump"]["pebbles"], colours):
        ax.plot_surface(x + r * np.cos(u) * np.sin(v), y + r * np.sin(u) * np.sin(v), z + r * np.cos(v),
                        color=colour, alpha=0.55, linewidth=0, shade=True)
    # Equal scale on the three axes, each just spanning the stone and its pebbles.
    pebbles = np.array(template["clump"]["pebbles"])
    lower = np.minimum(vertices.min(axis=0), (pebbles[:, :3] - pebbles[:, 3:]).min(axis=0))
    upper = np.maximum(vertices.max(axis=0), (pebbles[:, :3] + pebbles[:, 3:]).max(axis=0))
    for set_limits, lo, hi in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), lower, upper):
        set_limits(lo, hi)
    ax.set_box_aspect(upper - lower, zoom=1.1)
    ax.view_init(elev=28, azim=-55)
    ax.set_axis_off()
    fit = template["surface"]
    ax.set_title(f"{template['name']}: {len(template['clump']['pebbles'])} pebbles\n"
                 f"L/I {fit['length'] / fit['intermediate']:.2f}, S/I {fit['thickness'] / fit['intermediate']:.2f}, "
                 f"inertia err {100 * fit['inertia_error']:.1f} %", fontsize=8)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--library", action="append", type=pathlib.Path,
                        help="template directory; repeat for one row per library")
    parser.add_argument("--template", action="append", help=f"template names (default: {' '.join(DEFAULT_TEMPLATES)})")
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("results/shapes/templates.png"))
    args = parser.parse_args()
    libraries = args.library or [pathlib.Path("studies/shapes/library")]
    names = args.template or DEFAULT_TEMPLATES
    figure = plt.figure(figsize=(3.0 * len(names), 3.2 * len(libraries)))
    for row, library in enumerate(libraries):
        for column, name in enumerate(names):
            path = library / f"{name}.toml"
            if not path.is_file():
                sys.exit(f"plot_templates.py: {path}: no such template (build it with 'mfdem shapes build')")
            ax = figure.add_subplot(len(libraries), len(names), row * len(names) + column + 1, projection="3d")
            draw(ax, load(path))
    figure.suptitle("mfdem clump templates: stone surface (grey) and pebbles, body frame, lengths in units of d",
                    fontsize=10)
    figure.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
