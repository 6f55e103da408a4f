#!/usr/bin/env python3
"""Sphere-bed performance benchmark: mfdem, LAMMPS and LIGGGHTS side by side.

One settled bed of equal spheres in a 1 m x 1 m box (floor and four side walls, open top)
is timed for a fixed number of steps in all three codes with the same contact law. The
bed is settled once with LAMMPS and cached under scratch/ (rerun with --resettle).
Reported: sphere-steps per second (median of the repeats, with min and max), contacts per
sphere, peak resident memory, and the ratio mfdem / peer; then the extra cost of rolling
resistance (mfdem mu_r, LIGGGHTS rolling_friction epsd2).

See README.md in this folder for the parameter mapping between the codes.
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
import json
import math
import os
import platform
import random
import re
import resource
import shlex
import shutil
import statistics
import subprocess
import sys
import time
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[2]

# --- the scene (fixed by the benchmark issue) ----------------------------------------
DIAMETER = 0.04            # m
RADIUS = DIAMETER / 2
DENSITY = 2800.0           # kg/m^3
KN = 1.0e7                 # N/m per contact (normal)
KT = 2.0 / 7.0 * KN        # N/m per contact (tangential)
MU = 0.5                   # Coulomb friction
BETA = 0.3                 # normal viscous damping, fraction of critical
MU_R = 0.3                 # rolling friction of the rolling-resistance variant
DT = 1.0e-5                # s
SKIN = 0.1 * DIAMETER      # m, neighbour skin of the peers
N_FULL = 20000
N_QUICK = 2000
MASS = DENSITY * 4.0 / 3.0 * math.pi * RADIUS ** 3
GAMMA_PP = 2.0 * BETA * math.sqrt(KN / (MASS / 2.0))   # 1/s, sphere-sphere (m_eff = m/2)
GAMMA_PW = 2.0 * BETA * math.sqrt(KN / MASS)           # 1/s, sphere-wall (m_eff = m)

# --- settling (LAMMPS, same contact law, larger step, extra drag in stage 2) ------------
SETTLE_DT = 2.5e-5         # s; about 8.6 steps per sphere-sphere contact duration
SETTLE_FALL_STEPS = 24000  # 0.6 s of free fall before the drag is switched on
SETTLE_TAU = 0.02          # s, time constant of the zero-temperature Langevin drag
SETTLE_CHUNK = 1000
SETTLE_MAX_CHUNKS = 200
SETTLE_VTOL = 1.0e-3       # m/s: a sphere faster than this is "moving"
SETTLE_MOVE_FRAC = 0.005   # settled when at most this fraction of the spheres moves
LATTICE_SPACING = 1.1 * DIAMETER
LATTICE_JITTER = 0.0015    # m, < (spacing - d) / 2 so that no two spheres overlap
INITIAL_SPEED = 0.05       # m/s, bound of the uniform random velocity components

DISTURBED = 0.1           # cores used by other processes above which a timing is disturbed
LOOP_RE = re.compile(
    r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")
CONTACTS_RE = re.compile(
    r"BENCH_CONTACTS_PER_SPHERE\s+([0-9.eE+-]+) WALL_CONTACTS_PER_SPHERE\s+([0-9.eE+-]+)")
MFDEM_KEYS = ("steps", "elements", "wall_seconds", "element_steps_per_second",
              "contacts_per_element", "peak_rss_bytes")


class BenchmarkError(RuntimeError):
    pass


def log(msg: str) -> None:
    print(msg, flush=True)


def rel(p: Path) -> str:
    try:
        return str(p.resolve().relative_to(REPO))
    except ValueError:
        return str(p)


# --- scene template --------------------------------------------------------------------
def load_template() -> tuple[str, dict]:
    path = HERE / "bed.toml"
    text = path.read_text()
    scene = tomllib.loads(text)
    series = lambda a, b: a * b / (a + b)
    bal, wall = scene["materials"]["ballast"], scene["materials"]["wall"]
    checks = [
        ("simulation.time_step", scene["simulation"]["time_step"], DT),
        ("materials.ballast.density", bal["density"], DENSITY),
        ("series(ballast, ballast) normal_stiffness",
         series(bal["normal_stiffness"], bal["normal_stiffness"]), KN),
        ("series(ballast, ballast) shear_stiffness",
         series(bal["shear_stiffness"], bal["shear_stiffness"]), KT),
        ("series(ballast, wall) normal_stiffness",
         series(bal["normal_stiffness"], wall["normal_stiffness"]), KN),
        ("series(ballast, wall) shear_stiffness",
         series(bal["shear_stiffness"], wall["shear_stiffness"]), KT),
        ("materials.ballast.friction", bal["friction"], MU),
        ("materials.wall.friction", wall["friction"], MU),
        ("materials.ballast.damping_ratio", bal["damping_ratio"], BETA),
        ("materials.wall.damping_ratio", wall["damping_ratio"], BETA),
    ]
    for name, got, want in checks:
        if not math.isclose(got, want, rel_tol=1e-12):
            raise BenchmarkError(f"{rel(path)}: {name} is {got}, the benchmark expects {want}")
    box = scene["wall"][0]
    if box.get("type") != "box" or box["min"][:2] != [0.0, 0.0] or box["max"][:2] != [1.0, 1.0] \
            or box["min"][2] != 0.0 or not box.get("open_top"):
        raise BenchmarkError(f"{rel(path)}: [[wall]] must be the open-top box "
                             "[0,0,0]..[1,1,top] that the peers' inputs use")
    return text, scene


def set_toml_value(text: str, section: str, key: str, literal: str,
                   comment: str | None = None) -> str:
    """Replace `key = ...` in table `section` (first [[section]] for arrays), keeping comments."""
    out, current, done = [], None, False
    for line in text.splitlines(keepends=True):
        m = re.match(r"\s*\[\[?\s*([^\]]+?)\s*\]\]?", line)
        if m:
            current = m.group(1)
        elif not done and current == section:
            km = re.match(rf"(\s*{re.escape(key)}\s*=\s*)([^#\n]*?)(\s*(#.*)?)$", line.rstrip("\n"))
            if km:
                rest = km.group(3) if comment is None else f"  # {comment}"
                line = km.group(1) + literal + rest + "\n"
                done = True
        out.append(line)
    if not done:
        raise BenchmarkError(f"bed.toml: no key {key} in [{section}]")
    return "".join(out)


def write_scene(template: str, path: Path, bed: Path, steps: int, mu_r: float) -> None:
    duration = repr(steps * DT)
    text = template
    text = set_toml_value(text, "simulation", "duration", duration,
                          f"s  ({steps} steps at dt = {DT:g})")
    text = set_toml_value(text, "simulation", "output_interval", duration)
    text = set_toml_value(text, "materials.ballast", "rolling_friction", repr(mu_r))
    text = set_toml_value(text, "materials.wall", "rolling_friction", repr(mu_r))
    bed_rel = os.path.relpath(bed, path.parent)
    text = set_toml_value(text, "sphere_file", "path", json.dumps(bed_rel))
    header = (f"# GENERATED by {rel(Path(__file__))} from bed.toml: {steps} steps, "
              f"rolling_friction = {mu_r}\n")
    path.write_text(header + text)
    scene = tomllib.loads(path.read_text())  # validate what the loader will see
    assert scene["materials"]["ballast"]["rolling_friction"] == mu_r
    assert (path.parent / scene["sphere_file"][0]["path"]).resolve() == bed.resolve()


# --- bed preparation -------------------------------------------------------------------
def settle_inputs_hash(n: int, seed: int) -> str:
    h = hashlib.sha256((HERE / "in.settle.lmp").read_bytes())
    h.update(repr((n, seed, DIAMETER, DENSITY, KN, KT, MU, BETA, SETTLE_DT, SETTLE_FALL_STEPS,
                   SETTLE_TAU, SETTLE_CHUNK, SETTLE_VTOL, SETTLE_MOVE_FRAC, LATTICE_SPACING, LATTICE_JITTER,
                   INITIAL_SPEED)).encode())
    return h.hexdigest()[:16]


def args_seed_langevin(seed: int) -> int:
    """Seed for fix langevin (required by LAMMPS; no noise at zero temperature)."""
    return 1 + seed % 900000


def write_initial_lattice(path: Path, n: int, seed: int, zlo: float) -> float:
    """Loose square lattice with small jitter and random velocities; returns the top z."""
    rng = random.Random(seed)
    lo = RADIUS + LATTICE_JITTER + 1e-4
    per_row = int((1.0 - 2 * lo) / LATTICE_SPACING) + 1
    atoms = []
    layer = 0
    while len(atoms) < n:
        z = lo + layer * LATTICE_SPACING
        for i in range(per_row):
            for j in range(per_row):
                if len(atoms) == n:
                    break
                jit = [rng.uniform(-LATTICE_JITTER, LATTICE_JITTER) for _ in range(3)]
                atoms.append((lo + i * LATTICE_SPACING + jit[0], lo + j * LATTICE_SPACING + jit[1],
                              z + jit[2]))
        layer += 1
    top = max(a[2] for a in atoms) + RADIUS
    with path.open("w") as f:
        f.write(f"sphere_bed benchmark: initial loose lattice, {n} spheres, seed {seed}\n\n")
        f.write(f"{n} atoms\n2 atom types\n\n")
        f.write(f"0.0 1.0 xlo xhi\n0.0 1.0 ylo yhi\n{zlo!r} {top + 0.1!r} zlo zhi\n\n")
        f.write("Atoms\n\n")
        for k, (x, y, z) in enumerate(atoms, 1):
            f.write(f"{k} 1 {DIAMETER!r} {DENSITY!r} {x!r} {y!r} {z!r}\n")
        f.write("\nVelocities\n\n")
        for k in range(1, n + 1):
            v = [rng.uniform(-INITIAL_SPEED, INITIAL_SPEED) for _ in range(3)]
            f.write(f"{k} {v[0]!r} {v[1]!r} {v[2]!r} 0.0 0.0 0.0\n")
    return top


def read_bed(path: Path) -> list[tuple[float, float, float, float]]:
    bed = []
    for line in path.read_text().splitlines():
        line = line.strip()
        if line and not line.startswith("#"):
            x, y, z, r = (float(v) for v in line.split())
            bed.append((x, y, z, r))
    return bed


def bed_statistics(bed: list[tuple[float, float, float, float]]) -> dict:
    """Geometric contacts of the bed as stored (before any code runs it)."""
    cell = DIAMETER
    grid: dict[tuple[int, int, int], list[int]] = {}
    for k, (x, y, z, _) in enumerate(bed):
        grid.setdefault((int(x // cell), int(y // cell), int(z // cell)), []).append(k)
    pairs = 0
    min_gap = math.inf
    for (cx, cy, cz), members in grid.items():
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    other = grid.get((cx + dx, cy + dy, cz + dz))
                    if not other:
                        continue
                    for a in members:
                        xa, ya, za, ra = bed[a]
                        for b in other:
                            if b <= a:
                                continue
                            xb, yb, zb, rb = bed[b]
                            d = math.sqrt((xa - xb) ** 2 + (ya - yb) ** 2 + (za - zb) ** 2)
                            gap = d - ra - rb
                            min_gap = min(min_gap, gap)
                            if gap < 0.0:
                                pairs += 1
    wall = 0
    for x, y, z, r in bed:
        wall += (x < r) + (1.0 - x < r) + (y < r) + (1.0 - y < r) + (z < r)
    n = len(bed)
    top = max(z + r for _, _, z, r in bed)
    volume = sum(4.0 / 3.0 * math.pi * r ** 3 for *_, r in bed)
    return {
        "spheres": n,
        "top": top,
        "solid_fraction": volume / (1.0 * 1.0 * top),
        "coordination": 2.0 * pairs / n,
        "pair_contacts": pairs,
        "wall_contacts": wall,
        "max_overlap": max(0.0, -min_gap),
    }


def settle(workdir: Path, n: int, seed: int, ranks: int, lmp: str) -> dict:
    workdir.mkdir(parents=True, exist_ok=True)
    init = workdir / "init.data"
    dump = workdir / "bed.dump"
    z_init_top = write_initial_lattice(init, n, seed, zlo=-0.1)
    var = {
        "initdata": init.name, "beddump": dump.name, "kn": KN, "kt": KT, "gn_pp": GAMMA_PP,
        "gn_pw": GAMMA_PW, "mu": MU, "dt": SETTLE_DT, "skin": SKIN,
        "tau": SETTLE_TAU, "fallsteps": SETTLE_FALL_STEPS, "chunk": SETTLE_CHUNK,
        "maxchunks": SETTLE_MAX_CHUNKS, "vtol": SETTLE_VTOL, "movefrac": SETTLE_MOVE_FRAC,
        "seed": args_seed_langevin(seed),
    }
    cmd = [lmp, "-in", str(HERE / "in.settle.lmp"), "-log", "settle.log", "-screen", "none",
           "-nocite"]
    for k, v in var.items():
        cmd += ["-var", k, repr(v) if isinstance(v, float) else str(v)]
    log(f"settling {n} spheres with LAMMPS on {ranks} rank(s) (initial lattice top "
        f"{z_init_top:.2f} m, dt {SETTLE_DT} s) ...")
    t0 = datetime.datetime.now()
    proc = subprocess.run(mpi_prefix(ranks) + cmd, cwd=workdir, env=peer_env(),
                          capture_output=True, text=True)
    seconds = (datetime.datetime.now() - t0).total_seconds()
    logtext = (workdir / "settle.log").read_text() if (workdir / "settle.log").exists() else ""
    if proc.returncode != 0 or "SETTLE_DONE" not in logtext:
        raise BenchmarkError(f"LAMMPS settling failed (exit {proc.returncode}); see "
                             f"{rel(workdir / 'settle.log')}\n{tail(logtext + proc.stderr)}")
    steps_total = sum(int(m.group(3)) for m in LOOP_RE.finditer(logtext))
    done = re.search(r"SETTLE_DONE energy_per_sphere\s+([0-9.eE+-]+) moving_fraction\s+([0-9.eE+-]+)", logtext)
    energy, moving = float(done.group(1)), float(done.group(2))
    rows = []
    for line in dump.read_text().splitlines():
        parts = line.split()
        if len(parts) == 5 and parts[0].isdigit():
            rows.append((int(parts[0]), parts[1:]))
    rows.sort()
    if len(rows) != n:
        raise BenchmarkError(f"settled dump has {len(rows)} spheres, expected {n}")
    bed_txt = workdir / "bed.txt"
    with bed_txt.open("w") as f:
        f.write(f"# sphere_bed benchmark: settled bed, {n} spheres, diameter {DIAMETER} m, "
                f"density {DENSITY} kg/m^3, seed {seed}\n")
        f.write(f"# settled by LAMMPS ({rel(HERE / 'in.settle.lmp')}): {steps_total} steps of "
                f"{SETTLE_DT} s; at the end {moving:.2%} of the spheres moved faster than "
                f"{SETTLE_VTOL} m/s, kinetic energy {energy:.3g} J per sphere\n")
        f.write("# box: walls x = 0 and 1, y = 0 and 1, floor z = 0, open top\n")
        f.write("# columns: x y z radius [m]\n")
        for _, (x, y, z, r) in rows:
            f.write(f"{x} {y} {z} {r}\n")
    meta = {
        "spheres": n, "seed": seed, "inputs_hash": settle_inputs_hash(n, seed),
        "settle_ranks": ranks, "settle_steps": steps_total, "settle_dt": SETTLE_DT,
        "settle_simulated_seconds": steps_total * SETTLE_DT, "settle_wall_seconds": seconds,
        "final_energy_per_sphere": energy, "final_moving_fraction": moving,
        "moving_speed": SETTLE_VTOL, "allowed_moving_fraction": SETTLE_MOVE_FRAC,
        "lammps": package_version("lammps"),
        "date": datetime.datetime.now().isoformat(timespec="seconds"),
    }
    (workdir / "settle.json").write_text(json.dumps(meta, indent=2) + "\n")
    log(f"settled in {seconds:.0f} s wall, {steps_total} steps "
        f"({steps_total * SETTLE_DT:.2f} s simulated); bed written to {rel(bed_txt)}")
    return meta


def prepare(args, n: int, workdir: Path, lmp: str) -> tuple[Path, dict]:
    bed_txt = workdir / "bed.txt"
    meta_path = workdir / "settle.json"
    if args.resettle or not bed_txt.exists() or not meta_path.exists():
        meta = settle(workdir, n, args.seed, min(2, max_ranks()), lmp)
    else:
        meta = json.loads(meta_path.read_text())
        log(f"using cached settled bed {rel(bed_txt)} (settled {meta['date']}; --resettle to redo)")
        if meta.get("inputs_hash") != settle_inputs_hash(n, args.seed):
            log("  note: the settling inputs changed since; pass --resettle to settle again")
    return bed_txt, meta


def write_peer_data(path: Path, bed, domain_min, domain_max) -> None:
    with path.open("w") as f:
        f.write("sphere_bed benchmark: settled bed for LAMMPS and LIGGGHTS "
                "(type 1 spheres, type 2 labels the walls)\n\n")
        f.write(f"{len(bed)} atoms\n2 atom types\n\n")
        for axis, lo, hi in zip("xyz", domain_min, domain_max):
            f.write(f"{lo!r} {hi!r} {axis}lo {axis}hi\n")
        f.write("\nAtoms\n\n")
        for k, (x, y, z, r) in enumerate(bed, 1):
            f.write(f"{k} 1 {2 * r!r} {DENSITY!r} {x!r} {y!r} {z!r}\n")


# --- running ---------------------------------------------------------------------------
def max_ranks() -> int:
    return os.cpu_count() or 1


def mpirun() -> str | None:
    return shutil.which("mpirun")


def mpi_prefix(ranks: int) -> list[str]:
    if ranks <= 1:
        return []
    cmd = [mpirun(), "-np", str(ranks)]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    return cmd


def peer_env() -> dict:
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = "1"
    return env


def tail(text: str, lines: int = 25) -> str:
    return "\n".join(text.strip().splitlines()[-lines:])


def cpu_ticks() -> tuple[int, int]:
    """(busy, total) clock ticks of all CPUs since boot, from /proc/stat."""
    try:
        fields = [int(v) for v in Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:9]]
    except (OSError, ValueError):
        return 0, 0
    user, nice, system, idle, iowait, irq, softirq, steal = fields
    return user + nice + system + irq + softirq + steal, sum(fields)


CLK_TCK = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100


def busy_cores(seconds: float) -> float:
    """CPU cores kept busy by all processes over the next `seconds`."""
    b0, _ = cpu_ticks()
    time.sleep(seconds)
    b1, _ = cpu_ticks()
    return (b1 - b0) / CLK_TCK / seconds


def wait_until_idle(max_wait: float, threshold: float = 0.15) -> float:
    """Waits (at most max_wait s) until other processes use less than `threshold` cores;
    returns the last measured load in cores."""
    deadline = time.monotonic() + max_wait
    load = busy_cores(1.0)
    announced = False
    while load > threshold and time.monotonic() < deadline:
        if not announced:
            log(f"  machine busy ({load:.2f} cores in use by other processes); waiting up to "
                f"{max_wait:.0f} s for it to calm down ...")
            announced = True
        load = busy_cores(2.0)
    return load


def run_measured(cmd: list[str], ranks: int, cwd: Path, tag: str, env: dict) -> tuple[str, dict]:
    """Runs cmd (under mpirun for ranks > 1), each process wrapped by /usr/bin/time -v.
    Returns stdout + stderr and {rss: summed per-process maximum resident set size in bytes,
    foreign: average CPU cores used by other processes during the run}."""
    timefile = cwd / f"{tag}.time"
    for old in cwd.glob(f"{tag}.time.*"):
        old.unlink()
    wrapper = ["sh", "-c",
               'exec /usr/bin/time -v -o "$0.${OMPI_COMM_WORLD_RANK:-${PMI_RANK:-0}}" "$@"',
               str(timefile)]
    busy0, _ = cpu_ticks()
    usage0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    proc = subprocess.run(mpi_prefix(ranks) + wrapper + cmd, cwd=cwd, env=env,
                          capture_output=True, text=True)
    wall = time.monotonic() - t0
    usage1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    busy1, _ = cpu_ticks()
    # CPU of everything started here (mpirun, the ranks, the time wrappers)
    own_cpu = (usage1.ru_utime - usage0.ru_utime) + (usage1.ru_stime - usage0.ru_stime)
    output = proc.stdout + proc.stderr
    (cwd / f"{tag}.out").write_text(output)
    if proc.returncode != 0:
        raise BenchmarkError(f"{tag} failed (exit {proc.returncode}): {shlex.join(cmd)}\n"
                             f"{tail(output)}")
    rss = 0
    files = sorted(cwd.glob(f"{tag}.time.*"))
    if len(files) != ranks:
        raise BenchmarkError(f"{tag}: expected {ranks} /usr/bin/time reports, found {len(files)}")
    for tf in files:
        text = tf.read_text()
        m = re.search(r"Maximum resident set size \(kbytes\):\s*(\d+)", text)
        if not m:
            raise BenchmarkError(f"{tag}: no maximum resident set size in {tf}")
        rss += int(m.group(1)) * 1024
    foreign = max(0.0, (busy1 - busy0) / CLK_TCK - own_cpu) / wall if wall > 0 else 0.0
    return output, {"rss": rss, "foreign": foreign, "cpu_seconds": own_cpu}


def run_peer(code: str, exe: str, ranks: int, rolling: bool, data: Path, steps: int, n: int,
             rundir: Path, tag: str) -> dict:
    script = HERE / ("in.bench.lmp" if code == "lammps" else "in.bench.liggghts")
    var = {"datafile": str(data), "steps": steps, "dt": DT, "kn": KN, "kt": KT,
           "gn_pp": GAMMA_PP, "gn_pw": GAMMA_PW, "mu": MU, "skin": SKIN, "radius": RADIUS}
    if code == "liggghts":
        var.update(mur=MU_R, rolling=int(rolling))
    cmd = [exe, "-in", str(script), "-log", f"{tag}.log"]
    if code == "lammps":
        cmd.append("-nocite")
    for k, v in var.items():
        cmd += ["-var", k, repr(v) if isinstance(v, float) else str(v)]
    output, measured = run_measured(cmd, ranks, rundir, tag, peer_env())
    loop = LOOP_RE.search(output)
    contacts = CONTACTS_RE.search(output)
    if not loop or not contacts:
        raise BenchmarkError(f"{tag}: no 'Loop time' or contacts line in the output\n{tail(output)}")
    seconds, procs, got_steps, atoms = (float(loop.group(1)), int(loop.group(2)),
                                        int(loop.group(3)), int(loop.group(4)))
    if procs != ranks or got_steps != steps or atoms != n:
        raise BenchmarkError(f"{tag}: ran {got_steps} steps with {atoms} atoms on {procs} procs, "
                             f"expected {steps}, {n}, {ranks}")
    coordination, wall = float(contacts.group(1)), float(contacts.group(2))
    return {"seconds": seconds, "sps": n * steps / seconds,
            "contacts": coordination / 2.0 + wall, "coordination": coordination, **measured}


def run_mfdem(exe: str, threads: int, scene: Path, steps: int, n: int, rundir: Path,
              tag: str) -> dict:
    out = rundir / tag
    if out.exists():
        shutil.rmtree(out)
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = str(threads)
    # An idle machine: spinning waits are fastest (mfdem defaults to passive for shared machines).
    env.setdefault("OMP_WAIT_POLICY", "active")
    cmd = [exe, "run", str(scene), "--out", str(out), "--threads", str(threads), "--quiet"]
    _, measured = run_measured(cmd, 1, rundir, tag, env)
    summary_path = out / "summary.toml"
    if not summary_path.exists():
        raise BenchmarkError(f"{tag}: mfdem wrote no {rel(summary_path)}")
    summary = tomllib.loads(summary_path.read_text())
    missing = [k for k in MFDEM_KEYS if k not in summary]
    if missing:
        raise BenchmarkError(f"{tag}: {rel(summary_path)} lacks the key(s) {', '.join(missing)}; "
                             f"the benchmark needs {', '.join(MFDEM_KEYS)}")
    if int(summary["steps"]) != steps or int(summary["elements"]) != n:
        raise BenchmarkError(f"{tag}: mfdem ran {summary['steps']} steps with "
                             f"{summary['elements']} elements, expected {steps} and {n}")
    sps = float(summary["element_steps_per_second"])
    check = n * steps / float(summary["wall_seconds"])
    if not math.isclose(sps, check, rel_tol=0.01):
        log(f"  warning: {tag}: element_steps_per_second {sps:.4g} differs from "
            f"steps*elements/wall_seconds {check:.4g}")
    return {"seconds": float(summary["wall_seconds"]), "sps": sps,
            "contacts": float(summary["contacts_per_element"]),
            "rss_self": int(summary["peak_rss_bytes"]), **measured}


# --- contact-law check --------------------------------------------------------------
LAW_CHECK_SPHERES = [  # x y z, vx vy vz: a floor impact and an oblique head-on pair impact
    ((0.5, 0.5, 0.03), (0.3, 0.0, -1.0)),
    ((0.2, 0.5, 0.5), (0.5, 0.0, 0.0)),
    ((0.3, 0.5, 0.52), (-0.5, 0.0, 0.0)),
]
LAW_CHECK_STEPS = 8000


def check_law(exes: dict, workdir: Path) -> list[str]:
    """Single impacts without gravity in LAMMPS and LIGGGHTS; returns report lines."""
    workdir.mkdir(parents=True, exist_ok=True)
    data = workdir / "law_check.data"
    with data.open("w") as f:
        f.write("sphere_bed benchmark: contact-law check\n\n3 atoms\n2 atom types\n\n"
                "0.0 1.0 xlo xhi\n0.0 1.0 ylo yhi\n-0.1 1.5 zlo zhi\n\nAtoms\n\n")
        for k, ((x, y, z), _) in enumerate(LAW_CHECK_SPHERES, 1):
            f.write(f"{k} 1 {DIAMETER!r} {DENSITY!r} {x!r} {y!r} {z!r}\n")
        f.write("\nVelocities\n\n")
        for k, (_, (vx, vy, vz)) in enumerate(LAW_CHECK_SPHERES, 1):
            f.write(f"{k} {vx!r} {vy!r} {vz!r} 0.0 0.0 0.0\n")
    finals = {}
    for code in ("lammps", "liggghts"):
        if code not in exes:
            continue
        script = HERE / ("in.bench.lmp" if code == "lammps" else "in.bench.liggghts")
        dump = workdir / f"law_check_{code}.dump"
        cmd = [exes[code], "-in", str(script), "-log", "none", "-var", "datafile", str(data),
               "-var", "steps", str(LAW_CHECK_STEPS), "-var", "gravity", "0.0",
               "-var", "finaldump", str(dump), "-var", "dumpfinal", "1"]
        proc = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, env=peer_env())
        if proc.returncode != 0 or not dump.exists():
            raise BenchmarkError(f"contact-law check failed in {code}\n"
                                 f"{tail(proc.stdout + proc.stderr)}")
        rows = {}
        for line in dump.read_text().splitlines():
            parts = line.split()
            if len(parts) == 7 and parts[0].isdigit():
                rows[int(parts[0])] = [float(v) for v in parts[1:]]
        finals[code] = rows
    lines = [f"Single impacts, no gravity, {LAW_CHECK_STEPS} steps of {DT:g} s: sphere 1 hits "
             "the floor at (vx, vz) = (0.3, -1) m/s; spheres 2 and 3 meet at +-0.5 m/s in x with "
             "a 20 mm offset in z. Final velocities (m/s) and spins (rad/s):", "",
             "| code | 1: vx | 1: vz | 1: wy | 2: vx | 2: vz | 2: wy |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for code, rows in finals.items():
        a, b = rows[1], rows[2]
        lines.append(f"| {CODE_NAMES[code]} | {a[0]:.5f} | {a[2]:.5f} | {a[4]:.4f} | "
                     f"{b[0]:.5f} | {b[2]:.5f} | {b[4]:.4f} |")
    lines += ["", "Normal restitution without tension is 0.4611 (LAMMPS and LIGGGHTS agree); with "
              "the tensile damping tail it would be exp(-pi beta / sqrt(1 - beta^2)) = "
              f"{math.exp(-math.pi * BETA / math.sqrt(1 - BETA ** 2)):.4f}.", ""]
    return lines


# --- reporting -------------------------------------------------------------------------
def command_output(cmd: list[str]) -> str:
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=30).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


def package_version(pkg: str) -> str:
    return command_output(["dpkg-query", "-W", "-f=${Version}", pkg]) or "not installed"


def machine_description(mfdem: Path | None) -> list[str]:
    lscpu = command_output(["lscpu"])
    field = lambda name: next((l.split(":", 1)[1].strip() for l in lscpu.splitlines()
                               if l.startswith(name + ":")), "?")
    os_name = "?"
    if Path("/etc/os-release").exists():
        m = re.search(r'PRETTY_NAME="([^"]+)"', Path("/etc/os-release").read_text())
        os_name = m.group(1) if m else "?"
    mem = "?"
    if Path("/proc/meminfo").exists():
        m = re.search(r"MemTotal:\s+(\d+)", Path("/proc/meminfo").read_text())
        mem = f"{int(m.group(1)) / 1024 ** 2:.1f} GiB" if m else "?"
    lines = [
        f"- CPU: {field('Model name')}, {field('CPU(s)')} logical CPUs "
        f"({field('Core(s) per socket')} cores per socket, {field('Thread(s) per core')} "
        f"thread(s) per core), {field('Hypervisor vendor')} hypervisor" if field('Hypervisor vendor') != "?"
        else f"- CPU: {field('Model name')}, {field('CPU(s)')} logical CPUs",
        f"- memory: {mem}; OS: {os_name}, kernel {platform.release()}",
        f"- compiler: {command_output(['c++', '--version']).splitlines()[0] if shutil.which('c++') else '?'}",
        "- packages: " + ", ".join(f"{p} {package_version(p)}"
                                   for p in ("lammps", "liggghts", "openmpi-bin")),
        f"- this script ran on Python {platform.python_version()} ({sys.executable})",
    ]
    if mfdem is not None:
        cache = None
        for parent in mfdem.resolve().parents:
            if (parent / "CMakeCache.txt").exists():
                cache = (parent / "CMakeCache.txt").read_text()
                break
        if cache:
            get = lambda k: (re.search(rf"^{k}:[A-Z]+=(.*)$", cache, re.M) or [None, "?"])[1]
            build_type = get("CMAKE_BUILD_TYPE")
            flags = " ".join(f for f in (get("CMAKE_CXX_FLAGS"),
                                         get(f"CMAKE_CXX_FLAGS_{build_type.upper()}"))
                             if f and f != "?")
            lines.append(f"- mfdem build: CMAKE_BUILD_TYPE={build_type}, compiler "
                         f"{get('CMAKE_CXX_COMPILER')}, flags `{flags or '(none)'}`")
        version = command_output([str(mfdem), "version"]).splitlines()
        built = datetime.datetime.fromtimestamp(mfdem.stat().st_mtime).isoformat(timespec="seconds")
        lines.append(f"- mfdem binary: {version[0] if version else '(mfdem version gave nothing)'}"
                     f", built {built}")
    return lines


def fmt_msps(x: float) -> str:
    return f"{x / 1e6:.2f}"


def summarise(samples: list[dict]) -> dict:
    sps = [s["sps"] for s in samples]
    return {"median": statistics.median(sps), "min": min(sps), "max": max(sps),
            "contacts": statistics.median(s["contacts"] for s in samples),
            "rss": max(s["rss"] for s in samples),
            "rss_self": max((s.get("rss_self", 0) for s in samples), default=0),
            "foreign": max(s["foreign"] for s in samples),
            "cpu_median": statistics.median(s["sps_cpu"] for s in samples),
            "repeats": len(samples)}


CODE_NAMES = {"mfdem": "mfdem", "lammps": "LAMMPS", "liggghts": "LIGGGHTS"}


def report(args, n, steps, results, configs, bed_stats, settle_meta, mfdem_path, notes,
           law: list[str]) -> str:
    def label(code, rolling):
        if not rolling:
            return CODE_NAMES[code]
        return f"{CODE_NAMES[code]} + rolling ({'epsd2' if code == 'liggghts' else 'mu_r'} {MU_R})"

    out = ["# Sphere-bed benchmark: mfdem, LAMMPS and LIGGGHTS", ""]
    out += [f"Generated {datetime.datetime.now().isoformat(timespec='seconds')} by", "",
            "```", "python3 " + shlex.join([rel(Path(sys.argv[0]))] + sys.argv[1:]), "```", ""]
    out += ["## Scene", "",
            f"{n} spheres, diameter {DIAMETER * 1000:.0f} mm, density {DENSITY:.0f} kg/m^3, "
            f"settled in a 1 m x 1 m box (floor and four side walls, open top); bed top "
            f"{bed_stats['top']:.3f} m, solid fraction {bed_stats['solid_fraction']:.3f}. "
            f"Timed: {steps} steps of dt = {DT:g} s with gravity -9.81 m/s^2, starting at rest "
            "from the stored positions (no contact history). Contact law below; the settling "
            "(LAMMPS) added tangential damping and a drag, see README.md.",
            "",
            f"Contact law, per contact: linear spring kn = {KN:.3g} N/m, incremental tangential "
            f"spring kt = 2/7 kn = {KT:.6g} N/m capped by Coulomb mu = {MU}, viscous normal "
            f"damping at beta = {BETA} of critical (cn = 2 beta sqrt(m_eff kn); LAMMPS/LIGGGHTS "
            f"gamma_n = {GAMMA_PP:.1f} 1/s sphere-sphere with m_eff = m/2, {GAMMA_PW:.1f} 1/s "
            "sphere-wall with m_eff = m), no tangential damping. mfdem mixes material stiffnesses "
            "in series, so both of its materials carry 2 kn and 2 kt. Rolling variant: mfdem "
            f"rolling_friction = {MU_R} on both materials; LIGGGHTS rolling_friction epsd2 with "
            f"coefficientRollingFriction = {MU_R} on all pairs.",
            "",
            f"Settled bed (geometry as stored): "
            f"{(bed_stats['pair_contacts'] + bed_stats['wall_contacts']) / n:.3f} contacts per "
            f"sphere ({bed_stats['pair_contacts']} sphere-sphere, {bed_stats['wall_contacts']} "
            f"sphere-wall; coordination number {bed_stats['coordination']:.2f}), "
            f"largest overlap {bed_stats['max_overlap'] * 1e6:.2f} um. Settled once by LAMMPS "
            f"on {settle_meta['settle_ranks']} rank(s): {settle_meta['settle_steps']} steps of "
            f"{settle_meta['settle_dt']:g} s ({settle_meta['settle_simulated_seconds']:.2f} s "
            f"simulated) in {settle_meta['settle_wall_seconds']:.0f} s wall, with a final drag "
            f"stage until no more than "
            f"{settle_meta.get('allowed_moving_fraction', SETTLE_MOVE_FRAC):.1%} of the spheres "
            f"moved faster than {settle_meta.get('moving_speed', SETTLE_VTOL) * 1000:g} mm/s "
            f"(at the end: "
            f"{settle_meta['final_moving_fraction']:.2%}, kinetic energy "
            f"{settle_meta['final_energy_per_sphere']:.2g} J per sphere).", ""]

    out += ["## Throughput", "",
            "Sphere-steps per second = spheres x steps / seconds of the stepping loop (LAMMPS and "
            "LIGGGHTS: their 'Loop time'; mfdem: wall_seconds of summary.toml). "
            f"Median of {args.repeats} repeat(s), run interleaved. Threads/ranks: mfdem OpenMP "
            "threads, peers MPI ranks. Contacts per sphere at the last step, as mfdem counts them: "
            "(sphere-sphere + sphere-wall contacts) / spheres, each contact once (mfdem: "
            "contacts_per_element; peers: compute contact/atom coordination / 2 + walls touched "
            "per sphere). Peak RSS: /usr/bin/time -v maximum resident "
            "set size, summed over ranks; it includes each process's fixed libraries and "
            "buffers, so bytes per sphere overstate the per-sphere cost at small N. Other load: "
            "CPU cores used by other processes during the run (from /proc/stat minus the run's "
            f"own CPU time), largest over the repeats; above {DISTURBED} the timing is disturbed "
            f"(such a run is repeated up to {args.retries} more time(s), the least disturbed "
            "attempt is kept). "
            "Sphere-steps per CPU-s (one process only): spheres x steps / (user + system CPU "
            "time of the whole process, including reading the bed and writing output, a few "
            "per cent); much less sensitive to other load than the wall-clock figure, so it is "
            "the fairer single-thread comparison on a shared machine.",
            ""]
    out += ["| code | threads/ranks | median M sphere-steps/s | min - max | speed-up vs 1 | "
            "contacts/sphere | peak RSS MB | bytes/sphere | mfdem / this | other load | "
            "M sphere-steps per CPU-s | mfdem / this (CPU) |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for (code, procs, rolling) in configs:
        s = results.get((code, procs, rolling))
        if s is None:
            continue
        one = results.get((code, 1, rolling))
        speedup = f"{s['median'] / one['median']:.2f}" if one and procs != 1 else "-"
        mf = results.get(("mfdem", procs, rolling))
        ratio = "-" if code == "mfdem" or mf is None else f"{mf['median'] / s['median']:.2f}"
        cpu = fmt_msps(s["cpu_median"]) if procs == 1 else "-"
        cpu_ratio = ("-" if code == "mfdem" or mf is None or procs != 1
                     else f"{mf['cpu_median'] / s['cpu_median']:.2f}")
        out.append(f"| {label(code, rolling)} | {procs} | {fmt_msps(s['median'])} | "
                   f"{fmt_msps(s['min'])} - {fmt_msps(s['max'])} | {speedup} | "
                   f"{s['contacts']:.3f} | {s['rss'] / 1e6:.1f} | {s['rss'] / n:.0f} | {ratio} | "
                   f"{s['foreign']:.2f} | {cpu} | {cpu_ratio} |")
    out.append("")
    rows = []
    for (code, procs, rolling) in configs:
        if rolling and (code, procs, True) in results and (code, procs, False) in results:
            base, roll = results[(code, procs, False)], results[(code, procs, True)]
            rows.append(f"| {label(code, True)} | {procs} | {fmt_msps(base['median'])} | "
                        f"{fmt_msps(roll['median'])} | {base['median'] / roll['median']:.2f} |")
    if rows:
        out += ["## Extra cost of rolling resistance", "",
                "Cost ratio = time with rolling resistance / time without (same code, same "
                "threads/ranks) = median speed without / median speed with.", "",
                "| code | threads/ranks | M sphere-steps/s without | with | cost ratio |",
                "|---|---:|---:|---:|---:|"] + rows + [""]
    if any(s.get("rss_self") for s in results.values()):
        out += ["mfdem's own peak_rss_bytes (summary.toml): " + ", ".join(
            f"{label(c, r)} {p}: {results[(c, p, r)]['rss_self'] / 1e6:.1f} MB"
            for (c, p, r) in configs if c == "mfdem" and (c, p, r) in results), ""]
    out += ["## Contact-law check (peers)", ""] + law
    out += ["## Machine", ""] + machine_description(mfdem_path) + [""]
    if notes:
        out += ["## Notes", ""] + [f"- {x}" for x in notes] + [""]
    out += ["Inputs: `studies/benchmarks/sphere_bed/` (bed.toml, in.bench.lmp, in.bench.liggghts, "
            "in.settle.lmp); method and parameter mapping in its README.md.", ""]
    return "\n".join(out)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=None, help="timed repeats per configuration, "
                    "median reported (default 3; 1 with --quick)")
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2],
                    help="mfdem OpenMP threads and peer MPI ranks to time (default 1 2)")
    ap.add_argument("--steps", type=int, default=None,
                    help="timed steps (default 5000; 1000 with --quick)")
    ap.add_argument("--mfdem", default="build/studies/mfdem", help="the mfdem executable")
    ap.add_argument("--lammps", default="lmp", help="the LAMMPS executable")
    ap.add_argument("--liggghts", default="liggghts", help="the LIGGGHTS executable")
    ap.add_argument("--codes", nargs="+", default=["mfdem", "lammps", "liggghts"],
                    choices=["mfdem", "lammps", "liggghts"], help="codes to time (default all)")
    ap.add_argument("--no-rolling", action="store_true",
                    help="skip the rolling-resistance variants")
    ap.add_argument("--out", default=None, help="markdown report (default "
                    "results/benchmarks/sphere_bed.md; scratch/ with --quick)")
    ap.add_argument("--resettle", action="store_true", help="settle the bed again")
    ap.add_argument("--check-law", action="store_true",
                    help="only run the single-impact check of the contact law in the peers")
    ap.add_argument("--prepare-only", action="store_true",
                    help="settle (if not cached) and write the inputs, then stop")
    ap.add_argument("--quick", action="store_true",
                    help=f"smoke run: {N_QUICK} spheres, 1000 steps, 1 repeat")
    ap.add_argument("--seed", type=int, default=12345, help="seed of the initial lattice")
    ap.add_argument("--retries", type=int, default=2,
                    help="run a timing again (at most this often) when other processes used "
                    f"more than {DISTURBED} cores during it; the least disturbed one is kept "
                    "(default 2)")
    ap.add_argument("--wait-idle", type=float, default=120.0, metavar="SECONDS",
                    help="before each timed run, wait up to this long for other processes to "
                    "leave the CPUs idle (default 120; 0 = do not wait)")
    ap.add_argument("--scratch", default="scratch/benchmarks/sphere_bed",
                    help="cache and run folder (default scratch/benchmarks/sphere_bed)")
    args = ap.parse_args()

    n = N_QUICK if args.quick else N_FULL
    steps = args.steps if args.steps is not None else (1000 if args.quick else 5000)
    args.repeats = args.repeats if args.repeats is not None else (1 if args.quick else 3)
    resolve = lambda p: Path(p) if Path(p).is_absolute() else REPO / p
    scratch = resolve(args.scratch)
    out_path = resolve(args.out) if args.out else (
        scratch / "sphere_bed_quick.md" if args.quick else REPO / "results/benchmarks/sphere_bed.md")
    workdir = scratch / f"n{n}_seed{args.seed}"
    rundir = workdir / "runs"
    notes: list[str] = []

    if not Path("/usr/bin/time").exists():
        raise BenchmarkError("/usr/bin/time is needed to measure peak memory "
                             "(Debian package 'time')")
    lmp = shutil.which(args.lammps)
    if lmp is None:
        raise BenchmarkError(f"LAMMPS executable '{args.lammps}' not found; it also settles the "
                             "bed (Debian package 'lammps')")
    exes = {"lammps": lmp}
    if "liggghts" in args.codes:
        exes["liggghts"] = shutil.which(args.liggghts)
        if exes["liggghts"] is None:
            raise BenchmarkError(f"LIGGGHTS executable '{args.liggghts}' not found "
                                 "(Debian package 'liggghts'), or leave it out with --codes")
    mfdem_path = None
    if "mfdem" in args.codes:
        mfdem_path = resolve(args.mfdem)
        if not (mfdem_path.is_file() and os.access(mfdem_path, os.X_OK)):
            raise BenchmarkError(
                f"mfdem executable {rel(mfdem_path)} not found; build it first "
                "(cmake -B build && cmake --build build) or pass --mfdem PATH, "
                "or time the peers only with --codes lammps liggghts")
        exes["mfdem"] = str(mfdem_path)
    threads = sorted(set(args.threads))
    if max(threads) > 1 and mpirun() is None:
        notes.append("mpirun not found: LAMMPS and LIGGGHTS ran as 1 process only.")
    if max(threads) > max_ranks():
        notes.append(f"more threads/ranks requested than the {max_ranks()} logical CPUs.")

    if args.check_law:
        log("\n".join(check_law(exes, scratch / "law_check")))
        return 0
    template, scene = load_template()
    rundir.mkdir(parents=True, exist_ok=True)
    bed_txt, settle_meta = prepare(args, n, workdir, lmp)
    bed = read_bed(bed_txt)
    if len(bed) != n:
        raise BenchmarkError(f"{rel(bed_txt)} has {len(bed)} spheres, expected {n}")
    stats = bed_statistics(bed)
    dmin, dmax = scene["domain"]["min"], scene["domain"]["max"]
    wall_top = scene["wall"][0]["max"][2]
    if stats["top"] > min(dmax[2], wall_top) - DIAMETER:
        raise BenchmarkError(f"the bed top {stats['top']:.3f} m does not fit under the domain/box "
                             f"top of bed.toml ({dmax[2]} m, {wall_top} m)")
    log(f"bed: {n} spheres, top {stats['top']:.3f} m, solid fraction "
        f"{stats['solid_fraction']:.3f}, {stats['pair_contacts']} sphere-sphere and "
        f"{stats['wall_contacts']} wall contacts "
        f"({(stats['pair_contacts'] + stats['wall_contacts']) / n:.3f} per sphere), max overlap "
        f"{stats['max_overlap'] * 1e6:.2f} um")
    data = workdir / "bed.data"
    write_peer_data(data, bed, dmin, dmax)
    scenes = {}
    for rolling in (False, True):
        scenes[rolling] = workdir / ("bed_rolling.toml" if rolling else "bed.toml")
        write_scene(template, scenes[rolling], bed_txt, steps, MU_R if rolling else 0.0)

    if args.prepare_only:
        log(f"prepared {rel(workdir)}: bed.txt, bed.data, bed.toml, bed_rolling.toml")
        return 0

    configs = []
    for code in ("mfdem", "lammps", "liggghts"):
        if code not in args.codes:
            continue
        for procs in threads:
            if code != "mfdem" and procs > 1 and mpirun() is None:
                continue
            configs.append((code, procs, False))
    for code in ("mfdem", "liggghts"):
        if code in args.codes and not args.no_rolling:
            for procs in threads:
                if code != "mfdem" and procs > 1 and mpirun() is None:
                    continue
                configs.append((code, procs, True))

    samples: dict[tuple, list[dict]] = {c: [] for c in configs}
    total = len(configs) * args.repeats
    k = 0
    for rep in range(1, args.repeats + 1):
        for code, procs, rolling in configs:
            k += 1
            best = None
            for attempt in range(args.retries + 1):
                if args.wait_idle > 0:
                    wait_until_idle(args.wait_idle)
                tag = f"{code}_{'roll' if rolling else 'base'}_p{procs}_rep{rep}"
                if code == "mfdem":
                    res = run_mfdem(exes["mfdem"], procs, scenes[rolling], steps, n, rundir, tag)
                else:
                    res = run_peer(code, exes[code], procs, rolling, data, steps, n, rundir, tag)
                res["sps_cpu"] = n * steps / res["cpu_seconds"] if res["cpu_seconds"] > 0 else 0.0
                res["attempts"] = attempt + 1
                if best is None or res["foreign"] < best["foreign"]:
                    best = res
                log(f"[{k}/{total}] {CODE_NAMES[code]:8s} {'rolling' if rolling else 'base   '} "
                    f"{procs} {'thread(s)' if code == 'mfdem' else 'rank(s)  '} rep {rep}: "
                    f"{res['sps'] / 1e6:6.2f} M sphere-steps/s ({res['seconds']:.2f} s), "
                    f"{res['contacts']:.3f} contacts/sphere, peak RSS {res['rss'] / 1e6:.1f} MB, "
                    f"other processes {res['foreign']:.2f} cores"
                    + (" -> disturbed, again" if res["foreign"] > DISTURBED
                       and attempt < args.retries else ""))
                if res["foreign"] <= DISTURBED:
                    break
            samples[(code, procs, rolling)].append(best)
    results = {c: summarise(s) for c, s in samples.items()}
    for procs in threads:
        mf, peer = results.get(("mfdem", procs, False)), results.get(("lammps", procs, False))
        if mf and peer and peer["contacts"] > 0 and abs(mf["contacts"] / peer["contacts"] - 1) > 0.05:
            notes.append(f"contacts per sphere differ by more than 5 %: mfdem {mf['contacts']:.3f}, "
                         f"LAMMPS {peer['contacts']:.3f} ({procs} threads/ranks); the codes do "
                         "not see the same contacts, or count them differently.")
            break
    busy = [f"{CODE_NAMES[c]} {p}" for (c, p, r), v in results.items()
            if v["foreign"] > DISTURBED]
    if busy:
        notes.append(f"other processes used more than {DISTURBED} core during some runs ("
                     + ", ".join(sorted(set(busy))) + "): those timings are disturbed.")
    law = check_law(exes, scratch / "law_check")
    text = report(args, n, steps, results, configs, stats, settle_meta, mfdem_path, notes, law)
    out_path.parent.mkdir(parents=True, exist_ok=True)
    out_path.write_text(text)
    (workdir / "results.json").write_text(json.dumps(
        {"spheres": n, "steps": steps, "bed": stats, "settle": settle_meta,
         "samples": {f"{c}|{p}|{'rolling' if r else 'base'}": s
                     for (c, p, r), s in samples.items()}}, indent=2) + "\n")
    log("")
    log(text)
    log(f"report written to {rel(out_path)}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except BenchmarkError as e:
        print(f"run_benchmark.py: error: {e}", file=sys.stderr)
        sys.exit(1)
