#!/usr/bin/python3
"""Clump-bed performance benchmark: mfdem, LAMMPS (fix rigid/small) and LIGGGHTS (fix multisphere).

About 5,000 rigid clumps of 6 pebbles (the shipped shape library, one sieve size) settled in the
1 m x 1 m box of the sphere benchmark are timed for a fixed number of steps in all three codes
with the same contact law. mfdem settles the bed (cached under scratch/); LAMMPS starts from the
same bed; LIGGGHTS settles its own bed of the same templates (fix multisphere bodies can only be
created by insertion). Reported: pebble-steps and clump-steps per second (median of the repeats),
contacts per pebble, peak memory, and the two targets of the clump-speed issue: (a) mfdem at
least 1.5x the faster peer per pebble-step on one thread; (b) an mfdem clump pebble costing at
most 1.5x a free sphere of the sphere benchmark (its 20,000-sphere mfdem scene, timed here too).

Needs Debian's python3 (/usr/bin/python3: h5py, numpy). See README.md in this folder.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent

# The helpers shared with the other benchmarks live in the mfdem package (studies/python/mfdem/
# bench.py); this script is run as a file, so the package's folder goes on the import path, and
# the benchmarks' folder too: the sphere benchmark's script gives the scene of target (b).
sys.path.insert(0, str(HERE.parents[1] / "python"))  # the mfdem package
sys.path.insert(0, str(HERE.parent))
from mfdem.bench import (  # noqa: E402  (needs the path above)
    BETA, DENSITY, KN, KT, MU, REPO, BenchmarkError, add_machine_options, add_run_options,
    closing_sections, command_line, contact_law_checks, fill_quick_defaults, fmt_millions, log,
    loop_steps, max_ranks, mfdem_env, mpi_prefix, mpirun, package_version, parallel_notes,
    peer_env, provenance_lines, publish_report, rel, repo_path, report_path, require_time_tool,
    require_values, run_main, run_mfdem, run_peer_timed, set_toml_value, summarise, tail,
    timestamp, var_args, wait_until_idle)
from mfdem.clump_export import read_bed, write_clumps  # noqa: E402
from sphere_bed import run_benchmark as sphere_bench  # noqa: E402

try:
    import h5py
    import numpy as np
except ImportError as exc:  # the pyenv python3 first on PATH has neither
    sys.exit(f"run_benchmark.py: error: {exc}; run it with /usr/bin/python3 (Debian's, with "
             "python3-h5py and python3-numpy)")

# --- the scene (fixed by the benchmark issue; contact law and density in mfdem.bench) ------
SIZE = 0.045               # m, sieve size d of every stone
DT = 1.0e-5                # s, timed runs
SKIN = 0.004               # m, neighbour skin of all three codes in the timed runs
N_FULL = 5000
N_QUICK = 500
LIBRARY = REPO / "studies/shapes/library"
SPHERE_CACHE = REPO / "scratch/benchmarks/sphere_bed/n20000_seed12345"  # the sphere benchmark's bed
SPHERE_N = 20000

# --- settling -------------------------------------------------------------------------
FIRST_STAGE_EXTRA = 1.0    # s, mfdem: the first stage lasts the fall time plus this
STAGE_SECONDS = 0.5        # s, mfdem: length of each later stage (a restart resets the springs)
MAX_STAGES = 24
VTOL = 1.0e-3              # m/s: a pebble faster than this is "moving"
MOVE_FRAC = 0.005          # settled when at most this fraction of the pebbles moves
LIG_SETTLE_DT = 1.25e-5    # s, LIGGGHTS settling step (mfdem's automatic step is about 1.29e-5)
LIG_TAU = 0.02             # s, drag time constant of LIGGGHTS's second settling stage
LIG_CHUNK = 4000
LIG_MAX_CHUNKS = 100

CODE_NAMES = {"mfdem": "mfdem", "lammps": "LAMMPS", "liggghts": "LIGGGHTS",
              "sphere": "mfdem spheres"}


# --- shape library ---------------------------------------------------------------------
def load_library() -> list[dict]:
    """The shipped templates: pebbles (units of d, principal frame), volume, inertia."""
    out = []
    for path in sorted(LIBRARY.glob("*.toml")):
        t = tomllib.loads(path.read_text())
        c = t["clump"]
        out.append({
            "name": t["name"], "pebbles": [tuple(p) for p in c["pebbles"]],
            "mass": DENSITY * c["volume"] * SIZE ** 3,
            "inertia": [DENSITY * i * SIZE ** 5 for i in c["principal_inertia"]],
            "reach": max(math.sqrt(x * x + y * y + z * z) + r for x, y, z, r in c["pebbles"]),
        })
    if not out:
        raise BenchmarkError(f"no clump templates in {rel(LIBRARY)}")
    return out


def lattice_top(templates: list[dict], n: int) -> float:
    """Top of mfdem's [[stone_group]] lattice for n stones in the 1 m x 1 m box (the pitch rule
    of studies/scene/stone_sources.cpp: twice the largest reach, plus 2 %)."""
    pitch = 2.0 * max(t["reach"] for t in templates) * SIZE * 1.02
    per_layer = int(1.0 // pitch) ** 2
    return math.ceil(n / per_layer) * pitch


def gammas(mean_mass: float) -> tuple[float, float]:
    """LAMMPS/LIGGGHTS gamma_n (1/s) for beta at the mean clump mass: pair, wall."""
    return (2.0 * BETA * math.sqrt(KN / (mean_mass / 2.0)), 2.0 * BETA * math.sqrt(KN / mean_mass))


# --- TOML helpers ---------------------------------------------------------------------------
def replace_table(text: str, table: str, block: str) -> str:
    """Replaces the [[table]] block (up to the next table header) by `block`."""
    m = re.search(rf"^\[\[{re.escape(table)}\]\]\n(?:(?!\[).*\n|\n)*", text, re.M)
    if not m:
        raise BenchmarkError(f"no [[{table}]] in the template")
    return text[:m.start()] + block + text[m.end():]


def vec(v) -> str:
    return "[" + ", ".join(repr(float(x)) for x in v) + "]"


def check_materials(scene: dict, path: Path, local_damping: bool) -> None:
    """The shared contact law; local damping only where allowed (settling, not timing)."""
    require_values(path, contact_law_checks(scene))
    bal, wall = scene["materials"]["ballast"], scene["materials"]["wall"]
    if not local_damping and (bal.get("local_damping", 0.0) or wall.get("local_damping", 0.0)):
        raise BenchmarkError(f"{rel(path)}: the timed scene must not have local_damping")


# --- mfdem settling -------------------------------------------------------------------------
def settle_hash(n: int, seed: int) -> str:
    h = hashlib.sha256((HERE / "settle.toml").read_bytes())
    for p in sorted(LIBRARY.glob("*.toml")):
        h.update(p.read_bytes())
    h.update(repr((n, seed, SIZE, FIRST_STAGE_EXTRA, STAGE_SECONDS, VTOL, MOVE_FRAC)).encode())
    return h.hexdigest()[:16]


def moving_fraction(state: Path) -> tuple[float, float, int]:
    """(fraction of pebbles faster than VTOL, largest pebble speed, frame) of the last frame."""
    with h5py.File(state, "r") as f:
        names = sorted(f["frames"].keys())
        v = f["frames"][names[-1]]["element_velocity"][...]
    speed = np.sqrt((v * v).sum(axis=1))
    return float((speed > VTOL).mean()), float(speed.max()), len(names) - 1


def settle_mfdem(exe: str, n: int, seed: int, workdir: Path, templates: list[dict],
                 threads: int) -> dict:
    """Settles in stages; finished stages of an interrupted or failed earlier call with the same
    inputs are reused (their scene text and record are kept in the stage folder)."""
    sdir = workdir / "mfdem_settle"
    stamp = sdir / "inputs_hash"
    inputs = settle_hash(n, seed)
    if sdir.exists() and (not stamp.exists() or stamp.read_text().strip() != inputs):
        shutil.rmtree(sdir)
    sdir.mkdir(parents=True, exist_ok=True)
    stamp.write_text(inputs + "\n")
    template = (HERE / "settle.toml").read_text()
    check_materials(tomllib.loads(template), HERE / "settle.toml", local_damping=True)
    alpha = tomllib.loads(template)["materials"]["ballast"]["local_damping"]
    ztop = lattice_top(templates, n)
    zbox = box_top(templates, n)
    fall = math.sqrt(2.0 * ztop / (9.81 * (1.0 - alpha))) + FIRST_STAGE_EXTRA  # local damping slows the fall
    text = template
    for sec, key, lit in [("simulation", "duration", repr(round(fall, 3))),
                          ("simulation", "output_interval", repr(round(fall, 3))),
                          ("simulation", "seed", str(seed)),
                          ("domain", "max", vec([1.0, 1.0, zbox])),
                          ("stone_group", "max", vec([1.0, 1.0, ztop * 1.0001])),
                          ("stone_group", "count", str(n)),
                          ("wall", "max", vec([1.0, 1.0, zbox]))]:
        text = set_toml_value(text, sec, key, lit)
    header = f"# GENERATED by {rel(Path(__file__))} from settle.toml: {n} clumps, seed {seed}\n"
    stages = []
    frac = 1.0
    for k in range(MAX_STAGES + 1):
        scene = sdir / f"stage{k:02d}.toml"
        out = sdir / f"stage{k:02d}"
        record = sdir / f"stage{k:02d}.json"
        if k == 0:
            scene_text = header + text
        else:
            later = replace_table(text, "stone_group",
                                  "[[state_file]]\n"
                                  f"path = \"stage{k - 1:02d}/state.h5\"   # the previous stage\n"
                                  "frame = -1\n\n")
            for key in ("duration", "output_interval"):
                later = set_toml_value(later, "simulation", key, repr(STAGE_SECONDS))
            scene_text = header.replace("settle.toml:", f"settle.toml, stage {k}:") + later
        tomllib.loads(scene_text)
        if (record.exists() and scene.exists() and scene.read_text() == scene_text
                and (out / "state.h5").exists()):
            stage = json.loads(record.read_text())
            log(f"  mfdem settling stage {k}: reusing {rel(out)}")
        else:
            scene.write_text(scene_text)
            cmd = [exe, "run", str(scene), "--out", str(out), "--threads", str(threads), "--quiet"]
            log(f"  mfdem settling stage {k} ({'pour' if k == 0 else 'continue'}, "
                f"{fall if k == 0 else STAGE_SECONDS:.2f} s simulated) ...")
            t0 = time.monotonic()
            proc = subprocess.run(cmd, cwd=REPO, env=mfdem_env(threads), capture_output=True,
                                  text=True)
            seconds = time.monotonic() - t0
            (sdir / f"stage{k:02d}.out").write_text(proc.stdout + proc.stderr)
            summary_path = out / "summary.toml"
            if proc.returncode != 0 or not summary_path.exists():
                raise BenchmarkError(f"mfdem settling stage {k} failed (exit {proc.returncode}): "
                                     f"{shlex.join(cmd)}\n{tail(proc.stdout + proc.stderr)}")
            summary = tomllib.loads(summary_path.read_text())
            frac, vmax, _ = moving_fraction(out / "state.h5")
            stage = {"stage": k, "steps": int(summary["steps"]),
                     "simulated_seconds": float(summary["final_time"]),
                     "wall_seconds": summary["wall_seconds"], "process_seconds": seconds,
                     "kinetic_energy": summary["kinetic_energy"], "moving_fraction": frac,
                     "max_pebble_speed": vmax,
                     "contacts_per_element": summary["contacts_per_element"],
                     "time_step": float(summary["time_step"]),
                     "critical_time_step": summary["critical_time_step"]}
            record.write_text(json.dumps(stage, indent=2) + "\n")
        stages.append(stage)
        frac = stage["moving_fraction"]
        log(f"    KE {stage['kinetic_energy']:.3g} J ({stage['kinetic_energy'] / n:.2g} J per "
            f"clump), {frac:.2%} of the pebbles faster than {VTOL * 1000:g} mm/s (max "
            f"{stage['max_pebble_speed']:.3g} m/s), {stage['contacts_per_element']:.3f} contacts "
            f"per pebble, {stage['wall_seconds']:.0f} s wall")
        if frac <= MOVE_FRAC:
            break
    else:
        raise BenchmarkError(f"the mfdem bed did not settle in {MAX_STAGES + 1} stages: "
                             f"{frac:.2%} of the pebbles still move; see {rel(sdir)} (a rerun "
                             "continues from the last stage if MAX_STAGES is raised)")
    final = sdir / f"stage{len(stages) - 1:02d}" / "state.h5"
    meta = {"clumps": n, "seed": seed, "inputs_hash": inputs, "threads": threads,
            "stages": stages, "steps": sum(s["steps"] for s in stages),
            "simulated_seconds": sum(s["simulated_seconds"] for s in stages),
            "time_step": stages[0]["time_step"], "critical_time_step": stages[0]["critical_time_step"],
            "local_damping": alpha,
            "wall_seconds": sum(s.get("process_seconds", s["wall_seconds"]) for s in stages),
            "state": rel(final), "lattice_top": ztop, "box_top": zbox, "date": timestamp()}
    (workdir / "mfdem_settle.json").write_text(json.dumps(meta, indent=2) + "\n")
    log(f"  mfdem bed settled: {meta['steps']} steps ({meta['simulated_seconds']:.2f} s simulated, "
        f"dt {meta['time_step']:.3g} s) in {meta['wall_seconds']:.0f} s wall on {threads} thread(s)")
    return meta


def box_top(templates: list[dict], n: int) -> float:
    """Top of the simulation box (all codes): the lattice top plus 0.2 m."""
    return round(lattice_top(templates, n) + 0.2, 4)


# --- the settled bed ---------------------------------------------------------------------------
def template_counts(bed: dict, templates: list[dict]) -> list[int]:
    """How many clumps of each template the bed holds (matched by mass: all volumes differ)."""
    masses = np.array([t["mass"] for t in templates])
    counts = [0] * len(templates)
    for m in bed["mass"]:
        k = int(np.argmin(abs(masses - m)))
        if abs(masses[k] - m) > 1e-9 * m:
            raise BenchmarkError(f"a clump of mass {m} kg matches no template of {rel(LIBRARY)} "
                                 f"at d = {SIZE} m")
        counts[k] += 1
    return counts


def bed_geometry(bed: dict) -> dict:
    top = float((bed["element_position"][:, 2] + bed["radius"]).max())
    solid = float(bed["mass"].sum()) / DENSITY
    return {"clumps": len(bed["mass"]), "pebbles": len(bed["radius"]), "top": top,
            "top_centre": float(bed["element_position"][:, 2].max()),
            "solid_fraction": solid / top, "mean_mass": float(bed["mass"].mean()),
            "min_mass": float(bed["mass"].min()), "max_mass": float(bed["mass"].max())}


def write_timed_scene(path: Path, state: Path, steps: int, zbox: float) -> None:
    template = (HERE / "bed.toml").read_text()
    scene = tomllib.loads(template)
    check_materials(scene, HERE / "bed.toml", local_damping=False)
    if scene["simulation"]["time_step"] != DT or scene["simulation"].get("skin") != SKIN:
        raise BenchmarkError(f"{rel(HERE / 'bed.toml')}: time_step must be {DT} and skin {SKIN}")
    duration = repr(steps * DT)
    text = template
    for sec, key, lit in [("simulation", "duration", duration),
                          ("simulation", "output_interval", duration),
                          ("domain", "max", vec([1.0, 1.0, zbox])),
                          ("wall", "max", vec([1.0, 1.0, zbox])),
                          ("state_file", "path", json.dumps(os.path.relpath(state, path.parent)))]:
        text = set_toml_value(text, sec, key, lit)
    path.write_text(f"# GENERATED by {rel(Path(__file__))} from bed.toml: {steps} steps\n" + text)
    got = tomllib.loads(path.read_text())
    assert (path.parent / got["state_file"][0]["path"]).resolve() == state.resolve()


# --- LIGGGHTS settling --------------------------------------------------------------------
def primes_from(start: int, count: int) -> list[int]:
    out, k = [], max(start, 10007)
    while len(out) < count:
        if all(k % p for p in range(2, int(math.isqrt(k)) + 1)):
            out.append(k)
        k += 1
    return out


def write_liggghts_templates(path: Path, templates: list[dict], counts: list[int], seed: int) -> None:
    seeds = primes_from(15485000 + 1000 * (seed % 1000), len(templates) + 1)
    total = sum(counts)
    lines = ["# clump_bed benchmark: the shipped shape library at d = %g m (generated)" % SIZE,
             "# pebbles x y z r in the principal frame (m); mass and principal moments as mfdem"]
    used = []
    for k, (t, c) in enumerate(zip(templates, counts)):
        if c == 0:
            continue
        spheres = " ".join(f"{x * SIZE!r} {y * SIZE!r} {z * SIZE!r} {r * SIZE!r}"
                           for x, y, z, r in t["pebbles"])
        ixx, iyy, izz = t["inertia"]
        lines.append(f"# {t['name']}: {c} of {total} clumps in mfdem's bed")
        lines.append(f"fix pts{k + 1} all particletemplate/multisphere {seeds[k]} atom_type 1 "
                     f"density constant {DENSITY!r} nspheres {len(t['pebbles'])} ntry 1000000 "
                     f"spheres {spheres} type {len(used) + 1} mass {t['mass']!r} inertia_tensor {ixx!r} 0.0 0.0 "
                     f"{iyy!r} 0.0 {izz!r} use_density")
        used.append((k, c))
    weights = " ".join(f"pts{k + 1} {c / total!r}" for k, c in used)
    lines.append(f"fix pdd all particledistribution/discrete/numberbased {seeds[-1]} {len(used)} "
                 f"{weights}")
    path.write_text("\n".join(lines) + "\n")


def liggghts_settle_hash(n: int, seed: int, counts: list[int]) -> str:
    h = hashlib.sha256((HERE / "in.settle.liggghts").read_bytes())
    for p in sorted(LIBRARY.glob("*.toml")):
        h.update(p.read_bytes())
    h.update(repr((n, seed, counts, SIZE, LIG_SETTLE_DT, LIG_TAU, LIG_CHUNK, VTOL, MOVE_FRAC)).encode())
    return h.hexdigest()[:16]


def settle_liggghts(exe: str, n: int, seed: int, workdir: Path, templates: list[dict],
                    counts: list[int], mean_mass: float, ranks: int) -> dict:
    ldir = workdir / "liggghts_settle"
    if ldir.exists():
        shutil.rmtree(ldir)
    ldir.mkdir(parents=True)
    write_liggghts_templates(ldir / "templates.liggghts", templates, counts, seed)
    gn_pp, gn_pw = gammas(mean_mass)
    ztop = lattice_top(templates, n)
    fall_steps = int(round((math.sqrt(2.0 * ztop / 9.81) + 0.2) / LIG_SETTLE_DT / LIG_CHUNK)) * LIG_CHUNK
    var = {"templates": "templates.liggghts", "restartfile": "bed.restart", "nclumps": n,
           "ztop": box_top(templates, n), "zins": ztop,
           "seed": primes_from(49979000 + seed % 100000, 1)[0], "kn": KN, "kt": KT,
           "gn_pp": gn_pp, "gn_pw": gn_pw, "mu": MU, "dt": LIG_SETTLE_DT, "skin": SKIN,
           "fallsteps": fall_steps, "gvisc": mean_mass / (6.0 * LIG_TAU), "chunk": LIG_CHUNK,
           "maxchunks": LIG_MAX_CHUNKS, "vtol": VTOL, "movefrac": MOVE_FRAC}
    # not "-screen none": LIGGGHTS 3.8 then crashes in Region::reset_random (fprintf to screen)
    cmd = [exe, "-in", str(HERE / "in.settle.liggghts"), "-log", "settle.log"] + var_args(var)
    (ldir / "settle.cmd").write_text(shlex.join(mpi_prefix(ranks) + cmd) + "\n")
    log(f"  LIGGGHTS settling its own bed of {n} clumps on {ranks} rank(s) "
        f"(insertion region top {ztop:.2f} m, dt {LIG_SETTLE_DT:g} s) ...")
    t0 = time.monotonic()
    proc = subprocess.run(mpi_prefix(ranks) + cmd, cwd=ldir, env=peer_env(),
                          capture_output=True, text=True)
    seconds = time.monotonic() - t0
    logtext = ((ldir / "settle.log").read_text(errors="replace")
               if (ldir / "settle.log").exists() else "")
    done = re.search(r"SETTLE_DONE moving_fraction\s+([0-9.eE+-]+) top\s+([0-9.eE+-]+)", logtext)
    inserted = re.search(r"SETTLE_INSERTED atoms\s+(\d+)", logtext)
    if proc.returncode != 0 or not done:
        raise BenchmarkError(f"LIGGGHTS settling failed (exit {proc.returncode}); see "
                             f"{rel(ldir / 'settle.log')}\n{tail(logtext + proc.stdout + proc.stderr)}")
    pebbles = sum(c * len(t["pebbles"]) for t, c in zip(templates, counts))
    if not inserted or int(inserted.group(1)) != pebbles:
        raise BenchmarkError(f"LIGGGHTS inserted {inserted.group(1) if inserted else '?'} pebbles, "
                             f"expected about {pebbles}; see {rel(ldir / 'settle.log')}")
    steps = loop_steps(logtext)
    meta = {"clumps": n, "pebbles": int(inserted.group(1)), "seed": seed,
            "inputs_hash": liggghts_settle_hash(n, seed, counts), "ranks": ranks, "steps": steps,
            "time_step": LIG_SETTLE_DT, "simulated_seconds": steps * LIG_SETTLE_DT,
            "wall_seconds": seconds, "moving_fraction": float(done.group(1)),
            "top": float(done.group(2)), "drag_tau": LIG_TAU,
            "liggghts": package_version("liggghts"), "date": timestamp()}
    (workdir / "liggghts_settle.json").write_text(json.dumps(meta, indent=2) + "\n")
    log(f"  LIGGGHTS bed settled: {steps} steps ({steps * LIG_SETTLE_DT:.2f} s simulated) in "
        f"{seconds:.0f} s wall; {float(done.group(1)):.2%} of the pebbles still move")
    return meta


# --- timed runs -----------------------------------------------------------------------------
def run_peer(code: str, exe: str, ranks: int, workdir: Path, steps: int, pebbles: int,
             gn: tuple[float, float], rundir: Path, tag: str) -> dict:
    var = {"steps": steps, "dt": DT, "kn": KN, "kt": KT, "gn_pp": gn[0], "gn_pw": gn[1], "mu": MU,
           "skin": SKIN}
    if code == "lammps":
        script = HERE / "in.bench.lmp"
        var.update(datafile=str(workdir / "bed.data"), bodyfile=str(workdir / "bodies.txt"))
    else:
        script = HERE / "in.bench.liggghts"
        var.update(restartfile=str(workdir / "liggghts_settle" / "bed.restart"))
    return run_peer_timed(code, exe, script, var, ranks, rundir, tag, steps, pebbles)


# --- report ---------------------------------------------------------------------------------
def report(args, ctx: dict, results: dict, configs: list, notes: list[str]) -> str:
    n, pebbles, steps = ctx["clumps"], ctx["pebbles"], ctx["steps"]
    geo, mset, lset = ctx["geometry"], ctx["mfdem_settle"], ctx.get("liggghts_settle")
    per_clump = {"mfdem": pebbles / n, "lammps": pebbles / n,
                 "liggghts": (lset["pebbles"] / n) if lset else 6.0, "sphere": 1.0}
    elements = {"mfdem": pebbles, "lammps": pebbles,
                "liggghts": lset["pebbles"] if lset else pebbles, "sphere": SPHERE_N}
    gn_pp, gn_pw = ctx["gammas"]
    beta_lo = gn_pp / 2.0 * math.sqrt(geo["min_mass"] / 2.0 / KN)
    beta_hi = gn_pp / 2.0 * math.sqrt(geo["max_mass"] / 2.0 / KN)
    out = ["# Clump-bed benchmark: mfdem, LAMMPS (fix rigid/small) and LIGGGHTS (fix multisphere)",
           ""] + provenance_lines("/usr/bin/python3")
    out += ["## Scene", "",
            f"{n} rigid clumps of 6 pebbles ({pebbles} pebbles): the 12 templates of the shipped "
            f"shape library (`studies/shapes/library/`) at one sieve size d = {SIZE * 1000:g} mm, "
            f"density {DENSITY:g} kg/m^3 (clump masses {geo['min_mass'] * 1000:.1f} - "
            f"{geo['max_mass'] * 1000:.1f} g, mean {geo['mean_mass'] * 1000:.1f} g), settled in "
            "the 1 m x 1 m box of the sphere benchmark (floor and four side walls, open top). "
            f"mfdem's bed: top {geo['top']:.3f} m (highest pebble centre "
            f"{geo.get('top_centre', float('nan')):.3f} m), solid fraction "
            f"{geo['solid_fraction']:.3f} of the box up to the top. "
            f"Timed: {steps} steps of dt = {DT:g} s with gravity, from the settled bed (no "
            "contact history). Template mix (clumps per template, mfdem's bed, also LIGGGHTS's "
            "insertion weights): " + ", ".join(str(c) for c in ctx["counts"]) + ".", "",
            f"Contact law, per pebble contact: kn = {KN:.3g} N/m, incremental tangential spring "
            f"kt = 2/7 kn = {KT:.6g} N/m capped by Coulomb mu = {MU}, viscous normal damping "
            f"beta = {BETA} (mfdem: cn = 2 beta sqrt(m_eff kn) per pair, m_eff from the clump "
            "masses; mfdem mixes material stiffnesses in series, so its materials carry 2 kn and "
            f"2 kt), no tangential damping, never tensile. The peers take one gamma_n for all "
            f"pairs, set for the mean clump mass: {gn_pp:.1f} 1/s pebble-pebble (m_eff = M/2), "
            f"{gn_pw:.1f} 1/s pebble-wall (m_eff = M); their m_eff is also the clump mass, so "
            f"their beta ranges over {beta_lo:.3f} - {beta_hi:.3f} between the lightest and "
            f"heaviest clump. Neighbour skin {SKIN * 1000:g} mm in all three codes.", ""]
    out += ["## The beds", "",
            f"- mfdem (also LAMMPS's): poured from a lattice (`settle.toml`, top "
            f"{mset['lattice_top']:.2f} m) with local damping {mset['local_damping']} and the "
            f"automatic step {mset['time_step']:.3g} s (0.2 x the critical "
            f"{mset['critical_time_step']:.3g} s), {len(mset['stages'])} stage(s): "
            f"{mset['steps']} steps, {mset['simulated_seconds']:.2f} s simulated, "
            f"{mset['wall_seconds']:.0f} s wall on {mset['threads']} threads; at the end "
            f"{mset['stages'][-1]['moving_fraction']:.2%} of the pebbles moved faster than "
            f"{VTOL * 1000:g} mm/s, kinetic energy {mset['stages'][-1]['kinetic_energy']:.2g} J.",
            "- LAMMPS reads mfdem's last frame: pebbles as atoms (molecule = clump; per-clump "
            "density so that the pebble masses add up to mfdem's clump mass, which makes gravity "
            "right), and a `fix rigid/small` infile with mfdem's mass, centre of mass, inertia "
            "tensor, velocity and angular momentum of every clump, so its clumps are mfdem's "
            "exactly (without the infile LAMMPS would compute centre and inertia from the "
            "pebbles as separate solid spheres, counting their overlaps twice)."]
    if lset:
        out.append(
            f"- LIGGGHTS settles its own bed (fix multisphere bodies are created only by "
            f"insertion): the same templates, mass and inertia as mfdem's (given explicitly), "
            f"random positions and orientations from `fix insert/pack` in the same region, the "
            f"same template mix; {lset['steps']} steps of {lset['time_step']:g} s "
            f"({lset['simulated_seconds']:.2f} s simulated, free fall then a viscous drag, time "
            f"constant {lset['drag_tau']:g} s) in {lset['wall_seconds']:.0f} s wall on "
            f"{lset['ranks']} rank(s); top {lset['top']:.3f} m (highest pebble centre). Its "
            "contacts per pebble below show how close the two beds are.")
    out.append("")
    out += ["## Throughput", "",
            "Pebble-steps per second = pebbles x steps / seconds of the stepping loop (LAMMPS and "
            "LIGGGHTS: 'Loop time'; mfdem: wall_seconds of summary.toml); clump-steps per second = "
            "that / 6. `mfdem spheres` is the sphere benchmark's 20,000-sphere mfdem scene "
            "(sphere-steps per second), for target (b). Median of "
            f"{args.repeats} repeat(s), interleaved. Threads/ranks: mfdem OpenMP threads, peers "
            "MPI ranks. Contacts per pebble at the last step: (pebble-pebble contacts between "
            "different clumps + pebble-wall contacts) / pebbles, each contact once. Peak RSS: "
            "/usr/bin/time -v, summed over ranks (includes each process's ~20-30 MB of "
            "libraries and buffers). Other load: CPU cores used by other processes during the "
            "run, largest over the repeats (median in brackets); above about 0.1 the timing is "
            "disturbed. Per CPU-s (one process only): element-steps / (user + system CPU time of "
            "the whole process), less sensitive to other load.", "",
            "| code | threads/ranks | M pebble-steps/s (median) | min - max | M clump-steps/s | "
            "speed-up vs 1 | contacts/pebble | peak RSS MB | bytes/pebble | mfdem / this | "
            "other load | M pebble-steps per CPU-s |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for code, procs in configs:
        s = results.get((code, procs))
        if s is None:
            continue
        one = results.get((code, 1))
        speedup = f"{s['median'] / one['median']:.2f}" if one and procs != 1 else "-"
        mf = results.get(("mfdem", procs))
        ratio = "-" if code in ("mfdem", "sphere") or mf is None else f"{mf['median'] / s['median']:.2f}"
        clump = "-" if code == "sphere" else fmt_millions(s["median"] / per_clump[code])
        cpu = fmt_millions(s["cpu_median"]) if procs == 1 else "-"
        out.append(f"| {CODE_NAMES[code]} | {procs} | {fmt_millions(s['median'])} | "
                   f"{fmt_millions(s['min'])} - {fmt_millions(s['max'])} | {clump} | {speedup} | "
                   f"{s['contacts']:.3f} | "
                   f"{s['rss'] / 1e6:.1f} | {s['rss'] / elements[code]:.0f} | {ratio} | "
                   f"{s['foreign']:.2f} ({s['foreign_median']:.2f}) | {cpu} |")
    out.append("")
    # targets
    out += ["## Targets of the issue", ""]
    mf1 = results.get(("mfdem", 1))
    peers1 = {c: results[(c, 1)] for c in ("lammps", "liggghts") if (c, 1) in results}
    if mf1 and peers1:
        best = max(peers1, key=lambda c: peers1[c]["median"])
        r = mf1["median"] / peers1[best]["median"]
        r_cpu = mf1["cpu_median"] / peers1[best]["cpu_median"]
        out.append(f"- (a) mfdem at least 1.5x the faster peer per pebble-step on 1 thread: mfdem "
                   f"{fmt_millions(mf1['median'])} M/s, the faster peer is {CODE_NAMES[best]} with "
                   f"{fmt_millions(peers1[best]['median'])} M/s: ratio {r:.2f} -> "
                   f"**{'met' if r >= 1.5 else 'not met'}** (per CPU-second: {r_cpu:.2f}).")
    else:
        out.append("- (a) not evaluated (mfdem or both peers missing).")
    for procs in sorted({p for c, p in configs}):
        mf, sp = results.get(("mfdem", procs)), results.get(("sphere", procs))
        if mf and sp:
            cost = sp["median"] / mf["median"]
            out.append(f"- (b) {procs} thread(s): an mfdem clump pebble costs {cost:.2f}x a free "
                       f"sphere ({fmt_millions(mf['median'])} M pebble-steps/s against "
                       f"{fmt_millions(sp['median'])} M sphere-steps/s; contacts per element "
                       f"{mf['contacts']:.2f} against {sp['contacts']:.2f}) -> "
                       f"**{'met' if cost <= 1.5 else 'not met'}** (target at most 1.5x).")
    if not any(("sphere", p) in results for p in (1, 2)):
        out.append(f"- (b) not evaluated: {ctx.get('sphere_note', 'the sphere scene was not run')}.")
    else:
        out.append("  Target (b) compares cost per element, as the issue defines it. A pebble of this "
                   "bed has about a fifth of the contacts of a sphere of the sphere bed (the other "
                   "pebbles of its clump shield it), so per contact a clump pebble is much dearer; "
                   "a clump costs 6 pebbles.")
    out.append("")
    if any(s.get("rss_self") for s in results.values()):
        out += ["mfdem's own peak_rss_bytes (summary.toml): " + ", ".join(
            f"{CODE_NAMES[c]} {p}: {results[(c, p)]['rss_self'] / 1e6:.1f} MB"
            for (c, p) in configs if c in ("mfdem", "sphere") and (c, p) in results), ""]
    out += closing_sections(ctx.get("mfdem_path"), notes)
    out += ["Inputs: `studies/benchmarks/clump_bed/` (settle.toml, bed.toml, in.bench.lmp, "
            "in.settle.liggghts, in.bench.liggghts); method in its README.md.", ""]
    return "\n".join(out)


# --- main -----------------------------------------------------------------------------------
def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_run_options(ap)
    ap.add_argument("--codes", nargs="+", default=["mfdem", "lammps", "liggghts", "sphere"],
                    choices=["mfdem", "lammps", "liggghts", "sphere"],
                    help="what to time (default all; 'sphere' = the sphere benchmark's mfdem scene)")
    ap.add_argument("--out", default=None, help="markdown report (default "
                    "results/benchmarks/clump_bed.md; scratch/ with --quick)")
    ap.add_argument("--resettle", action="store_true", help="settle both beds again")
    ap.add_argument("--prepare-only", action="store_true",
                    help="settle (if not cached) and write the inputs, then stop")
    ap.add_argument("--quick", action="store_true",
                    help=f"smoke run: {N_QUICK} clumps, 1000 steps, 1 repeat")
    ap.add_argument("--seed", type=int, default=12345, help="seed of the stones")
    ap.add_argument("--settle-threads", type=int, default=2,
                    help="threads/ranks for settling (default 2)")
    add_machine_options(ap, "clump_bed")
    args = ap.parse_args()

    n = N_QUICK if args.quick else N_FULL
    fill_quick_defaults(args)
    steps = args.steps
    scratch = repo_path(args.scratch)
    out_path = report_path(args, scratch, "clump_bed")
    workdir = scratch / f"n{n}_seed{args.seed}"
    rundir = workdir / "runs"
    rundir.mkdir(parents=True, exist_ok=True)
    notes: list[str] = []

    require_time_tool()
    mfdem_path = repo_path(args.mfdem)
    if not (mfdem_path.is_file() and os.access(mfdem_path, os.X_OK)):
        raise BenchmarkError(f"mfdem executable {rel(mfdem_path)} not found; build it first "
                             "(cmake --build build); it also settles the bed")
    exes = {"mfdem": str(mfdem_path), "sphere": str(mfdem_path)}
    for code, name in (("lammps", args.lammps), ("liggghts", args.liggghts)):
        if code in args.codes:
            exes[code] = shutil.which(name)
            if exes[code] is None:
                raise BenchmarkError(f"{code} executable '{name}' not found (Debian package "
                                     f"'{code}'), or leave it out with --codes")
    threads = sorted(set(args.threads))
    notes += parallel_notes(threads)

    templates = load_library()
    zbox = box_top(templates, n)
    # 1. mfdem's bed
    meta_path = workdir / "mfdem_settle.json"
    if args.resettle or not meta_path.exists():
        if args.resettle and (workdir / "mfdem_settle").exists():
            shutil.rmtree(workdir / "mfdem_settle")
        log(f"settling {n} clumps with mfdem ...")
        mset = settle_mfdem(str(mfdem_path), n, args.seed, workdir, templates, args.settle_threads)
    else:
        mset = json.loads(meta_path.read_text())
        log(f"using mfdem's cached bed {mset['state']} (settled {mset['date']}; --resettle to redo)")
        if mset.get("inputs_hash") != settle_hash(n, args.seed):
            log("  note: settle.toml or the library changed since; pass --resettle to settle again")
    state = REPO / mset["state"]
    bed = read_bed(state)
    geo = bed_geometry(bed)
    counts = template_counts(bed, templates)
    pebbles = geo["pebbles"]
    gn = gammas(geo["mean_mass"])
    log(f"bed: {n} clumps, {pebbles} pebbles, top {geo['top']:.3f} m, solid fraction "
        f"{geo['solid_fraction']:.3f}; templates {counts}")
    if geo["top"] > zbox - 0.1:
        raise BenchmarkError(f"the bed top {geo['top']:.3f} m is too close to the box top {zbox} m")
    write_clumps(bed, workdir / "bed.data", workdir / "bodies.txt", (0.0, 0.0, -0.1), (1.0, 1.0, zbox),
                 "clump_bed benchmark: mfdem's settled bed")
    scene = workdir / "bed.toml"
    write_timed_scene(scene, state, steps, zbox)
    # 2. LIGGGHTS's bed
    lset = None
    if "liggghts" in args.codes:
        lmeta = workdir / "liggghts_settle.json"
        if args.resettle or not lmeta.exists() or not (workdir / "liggghts_settle/bed.restart").exists():
            lset = settle_liggghts(exes["liggghts"], n, args.seed, workdir, templates, counts,
                                   geo["mean_mass"], min(args.settle_threads, max_ranks())
                                   if mpirun() else 1)
        else:
            lset = json.loads(lmeta.read_text())
            log(f"using LIGGGHTS's cached bed (settled {lset['date']}; --resettle to redo)")
            if lset.get("inputs_hash") != liggghts_settle_hash(n, args.seed, counts):
                log("  note: the LIGGGHTS settling inputs changed since; pass --resettle")
    # 3. the sphere benchmark's mfdem scene (target b)
    ctx = {"clumps": n, "pebbles": pebbles, "steps": steps, "geometry": geo, "mfdem_settle": mset,
           "liggghts_settle": lset, "counts": counts, "gammas": gn, "mfdem_path": mfdem_path}
    sphere_scene = None
    if "sphere" in args.codes:
        bed_txt = SPHERE_CACHE / "bed.txt"
        if bed_txt.exists():
            template, _ = sphere_bench.load_template()
            sphere_scene = workdir / "sphere_bed.toml"
            sphere_bench.write_scene(template, sphere_scene, bed_txt, steps, 0.0)
        else:
            ctx["sphere_note"] = (f"the sphere benchmark's cached bed {rel(bed_txt)} does not exist "
                                  "(run studies/benchmarks/sphere_bed/run_benchmark.py first)")
            notes.append(ctx["sphere_note"])
    if args.prepare_only:
        log(f"prepared {rel(workdir)}: bed.toml, bed.data, bodies.txt"
            + (", liggghts_settle/bed.restart" if lset else "")
            + (", sphere_bed.toml" if sphere_scene else ""))
        return 0

    configs = []
    for code in ("mfdem", "lammps", "liggghts", "sphere"):
        if code not in args.codes or (code == "sphere" and sphere_scene is None):
            continue
        for procs in threads:
            if code in ("lammps", "liggghts") and procs > 1 and mpirun() is None:
                continue
            configs.append((code, procs))
    samples: dict[tuple, list[dict]] = {c: [] for c in configs}
    total, k = len(configs) * args.repeats, 0
    for rep in range(1, args.repeats + 1):
        for code, procs in configs:
            k += 1
            if args.wait_idle > 0:
                wait_until_idle(args.wait_idle)
            tag = f"{code}_p{procs}_rep{rep}"
            if code == "mfdem":
                res = run_mfdem(exes["mfdem"], procs, scene, steps, pebbles, rundir, tag)
                elements = pebbles
            elif code == "sphere":
                res = run_mfdem(exes["sphere"], procs, sphere_scene, steps, SPHERE_N, rundir, tag)
                elements = SPHERE_N
            else:
                elements = lset["pebbles"] if code == "liggghts" else pebbles
                res = run_peer(code, exes[code], procs, workdir, steps, elements, gn, rundir, tag)
            res["sps_cpu"] = elements * steps / res["cpu_seconds"] if res["cpu_seconds"] > 0 else 0.0
            samples[(code, procs)].append(res)
            log(f"[{k}/{total}] {CODE_NAMES[code]:13s} {procs} "
                f"{'thread(s)' if code in ('mfdem', 'sphere') else 'rank(s)  '} rep {rep}: "
                f"{res['sps'] / 1e6:6.2f} M element-steps/s ({res['seconds']:.2f} s), "
                f"{res['contacts']:.3f} contacts/element, peak RSS {res['rss'] / 1e6:.1f} MB, "
                f"other processes {res['foreign']:.2f} cores")
    results = {c: summarise(s) for c, s in samples.items()}
    busy = [f"{CODE_NAMES[c]} {p}" for (c, p), v in results.items() if v["foreign"] > 0.1]
    if busy:
        notes.append("other processes used more than 0.1 core during some runs ("
                     + ", ".join(sorted(set(busy))) + "): those timings are disturbed.")
    mf, lg = results.get(("mfdem", 1)), results.get(("liggghts", 1))
    if mf and lg and abs(lg["contacts"] / mf["contacts"] - 1.0) > 0.05:
        notes.append(f"LIGGGHTS's own bed has {lg['contacts']:.3f} contacts per pebble against "
                     f"{mf['contacts']:.3f} in mfdem's bed ({lg['contacts'] / mf['contacts'] - 1:+.0%}): "
                     "its timings are for a slightly different bed (more contacts cost more).")
    mf, lm = results.get(("mfdem", 1)), results.get(("lammps", 1))
    if mf and lm and abs(mf["contacts"] / lm["contacts"] - 1.0) > 0.05:
        notes.append(f"contacts per pebble differ by more than 5 % between mfdem "
                     f"({mf['contacts']:.3f}) and LAMMPS ({lm['contacts']:.3f}) on the same bed.")
    text = report(args, ctx, results, configs, notes)
    publish_report(text, out_path)
    (workdir / "results.json").write_text(json.dumps(
        {"command": command_line("/usr/bin/python3"),
         "clumps": n, "pebbles": pebbles, "steps": steps, "geometry": geo, "counts": counts,
         "mfdem_settle": mset, "liggghts_settle": lset,
         "samples": {f"{c}|{p}": s for (c, p), s in samples.items()}}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    run_main(main)
