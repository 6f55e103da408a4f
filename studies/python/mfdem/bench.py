"""Helpers shared by the benchmark drivers (studies/benchmarks/*/run_benchmark.py) and the peer push.

Both benchmarks time mfdem, LAMMPS and LIGGGHTS with one contact law on a shared machine, so
they share that law, the way a run is launched and measured (MPI ranks, /usr/bin/time, load of
other processes), the median summary and the parts of the report that describe the machine.
The drivers are run as files; each puts studies/python on sys.path to import this package.
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import re
import resource
import shlex
import shutil
import statistics
import subprocess
import sys
import time
import tomllib
from collections.abc import Callable
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]  # studies/python/mfdem/bench.py

# --- the contact law of every benchmark (one law, so that their throughputs compare) --------
DENSITY = 2800.0           # kg/m^3
KN = 1.0e7                 # N/m per contact (normal)
KT = 2.0 / 7.0 * KN        # N/m per contact (tangential)
MU = 0.5                   # Coulomb friction
BETA = 0.3                 # normal viscous damping, fraction of critical

# What the benchmark inputs print (in.bench.lmp, in.bench.liggghts, in.settle.*).
LOOP_RE = re.compile(
    r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")
CONTACTS_RE = re.compile(
    r"BENCH_CONTACTS_PER_SPHERE\s+([0-9.eE+-]+) WALL_CONTACTS_PER_SPHERE\s+([0-9.eE+-]+)")
# summary.toml keys a timed mfdem run must report
MFDEM_KEYS = ("steps", "elements", "wall_seconds", "element_steps_per_second",
              "contacts_per_element", "peak_rss_bytes")


class BenchmarkError(RuntimeError):
    pass


# --- messages and paths ---------------------------------------------------------------------
def log(msg: str) -> None:
    print(msg, flush=True)


def rel(p: Path) -> str:
    """p relative to the repository where it lies inside it, so that reports do not name the
    checkout's location."""
    try:
        return str(p.resolve().relative_to(REPO))
    except ValueError:
        return str(p)


def repo_path(p: str) -> Path:
    """A command-line path: absolute as given, otherwise relative to the repository root."""
    return Path(p) if Path(p).is_absolute() else REPO / p


def tail(text: str, lines: int = 25) -> str:
    return "\n".join(text.strip().splitlines()[-lines:])


def timestamp() -> str:
    return datetime.datetime.now().isoformat(timespec="seconds")


def command_line(python: str) -> str:
    """How this run was started, to be pasted again (python names the interpreter to show)."""
    return python + " " + shlex.join([rel(Path(sys.argv[0]))] + sys.argv[1:])


def run_main(main: Callable[[], int]) -> None:
    """Exits with main's status; a BenchmarkError is a user-facing message, not a traceback."""
    try:
        sys.exit(main())
    except BenchmarkError as e:
        print(f"{Path(sys.argv[0]).name}: error: {e}", file=sys.stderr)
        sys.exit(1)


# --- command line ---------------------------------------------------------------------------
def add_run_options(ap: argparse.ArgumentParser) -> None:
    """The options every benchmark starts with: repeats, threads, steps and executables."""
    ap.add_argument("--repeats", type=int, default=None, help="timed repeats per configuration, "
                    "median reported (default 3; 1 with --quick)")
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2],
                    help="mfdem OpenMP threads and peer MPI ranks to time (default 1 2)")
    ap.add_argument("--steps", type=int, default=None,
                    help="timed steps (default 5000; 1000 with --quick)")
    ap.add_argument("--mfdem", default="build/studies/mfdem", help="the mfdem executable")
    ap.add_argument("--lammps", default="lmp", help="the LAMMPS executable")
    ap.add_argument("--liggghts", default="liggghts", help="the LIGGGHTS executable")


def add_machine_options(ap: argparse.ArgumentParser, name: str) -> None:
    """The options every benchmark ends with: idle wait and the scratch folder of `name`."""
    ap.add_argument("--wait-idle", type=float, default=120.0, metavar="SECONDS",
                    help="before each timed run, wait up to this long for other processes to "
                    "leave the CPUs idle (default 120; 0 = do not wait)")
    ap.add_argument("--scratch", default=f"scratch/benchmarks/{name}",
                    help=f"cache and run folder (default scratch/benchmarks/{name})")


def fill_quick_defaults(args: argparse.Namespace) -> None:
    """Steps and repeats not given: a full run, or a short smoke run with --quick."""
    if args.steps is None:
        args.steps = 1000 if args.quick else 5000
    if args.repeats is None:
        args.repeats = 1 if args.quick else 3


def report_path(args: argparse.Namespace, scratch: Path, name: str) -> Path:
    """--out, else results/benchmarks/<name>.md; a --quick report stays in scratch/."""
    if args.out:
        return repo_path(args.out)
    return scratch / f"{name}_quick.md" if args.quick else REPO / f"results/benchmarks/{name}.md"


def require_time_tool() -> None:
    if not Path("/usr/bin/time").exists():
        raise BenchmarkError("/usr/bin/time is needed to measure peak memory "
                             "(Debian package 'time')")


def parallel_notes(threads: list[int]) -> list[str]:
    """Report notes on requested parallelism the machine cannot give as asked."""
    notes = []
    if max(threads) > 1 and mpirun() is None:
        notes.append("mpirun not found: LAMMPS and LIGGGHTS ran as 1 process only.")
    if max(threads) > 1:
        notes.append("With more than one thread, mfdem's threads are pinned one per core "
                     "(OMP_PROC_BIND=spread, OMP_PLACES=cores), as Open MPI binds the peers' "
                     "ranks to cores when there are at most two.")
    if max(threads) > max_ranks():
        notes.append(f"more threads/ranks requested than the {max_ranks()} logical CPUs.")
    return notes


# --- scene files ----------------------------------------------------------------------------
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


def contact_law_checks(scene: dict) -> list[tuple[str, float, float]]:
    """(what, value in the scene, value of the shared law) for an mfdem scene's materials.
    mfdem mixes the stiffnesses of two materials in series, so the pairs are checked."""
    series = lambda a, b: a * b / (a + b)
    bal, wall = scene["materials"]["ballast"], scene["materials"]["wall"]
    return [
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


def require_values(path: Path, checks: list[tuple[str, float, float]]) -> None:
    """Raises on the first (what, got, want) of `path` that is not want to rounding."""
    for name, got, want in checks:
        if not math.isclose(got, want, rel_tol=1e-12):
            raise BenchmarkError(f"{rel(path)}: {name} is {got}, the benchmark expects {want}")


# --- launching the codes --------------------------------------------------------------------
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
    """The peers parallelise with MPI ranks only; one OpenMP thread each."""
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = "1"
    return env


def mfdem_env(threads: int) -> dict:
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = str(threads)
    # An idle machine: spinning waits are fastest (mfdem defaults to passive for shared machines).
    env.setdefault("OMP_WAIT_POLICY", "active")
    if threads > 1:
        # One thread per core, pinned: as Open MPI pins the peers' ranks (it binds to cores
        # when there are at most two ranks), so that neither side is moved between cores.
        env.setdefault("OMP_PROC_BIND", "spread")
        env.setdefault("OMP_PLACES", "cores")
    return env


def var_args(variables: dict) -> list[str]:
    """`-var name value` arguments of LAMMPS/LIGGGHTS; floats as repr so no digit is lost."""
    out = []
    for k, v in variables.items():
        out += ["-var", k, repr(v) if isinstance(v, float) else str(v)]
    return out


def loop_steps(logtext: str) -> int:
    """Steps of all runs of a LAMMPS/LIGGGHTS log (one 'Loop time' line per run)."""
    return sum(int(m.group(3)) for m in LOOP_RE.finditer(logtext))


# --- machine load ---------------------------------------------------------------------------
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


# --- timed runs -----------------------------------------------------------------------------
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


def peer_timing(output: str, tag: str, steps: int, ranks: int, atoms: int) -> dict:
    """Loop time and contacts of a timed peer run, after checking that it ran what was asked."""
    loop = LOOP_RE.search(output)
    contacts = CONTACTS_RE.search(output)
    if not loop or not contacts:
        raise BenchmarkError(f"{tag}: no 'Loop time' or contacts line in the output\n{tail(output)}")
    seconds, procs, got_steps, got_atoms = (float(loop.group(1)), int(loop.group(2)),
                                            int(loop.group(3)), int(loop.group(4)))
    if procs != ranks or got_steps != steps or got_atoms != atoms:
        raise BenchmarkError(f"{tag}: ran {got_steps} steps with {got_atoms} atoms on {procs} "
                             f"procs, expected {steps}, {atoms}, {ranks}")
    coordination, wall = float(contacts.group(1)), float(contacts.group(2))
    # as mfdem counts them: each sphere-sphere contact once, plus the walls touched
    return {"seconds": seconds, "sps": atoms * steps / seconds,
            "contacts": coordination / 2.0 + wall, "coordination": coordination}


def run_peer_timed(code: str, exe: str, script: Path, variables: dict, ranks: int,
                   rundir: Path, tag: str, steps: int, atoms: int) -> dict:
    """One timed LAMMPS or LIGGGHTS run of `script`: timing, contacts and measurements."""
    cmd = [exe, "-in", str(script), "-log", f"{tag}.log"]
    if code == "lammps":
        cmd.append("-nocite")
    output, measured = run_measured(cmd + var_args(variables), ranks, rundir, tag, peer_env())
    return {**peer_timing(output, tag, steps, ranks, atoms), **measured}


def run_mfdem(exe: str, threads: int, scene: Path, steps: int, n: int, rundir: Path,
              tag: str) -> dict:
    """One timed mfdem run of n elements: speed and contacts from its summary.toml (its own
    stepping time, comparable to the peers' 'Loop time'), memory and load as measured."""
    out = rundir / tag
    if out.exists():
        shutil.rmtree(out)
    cmd = [exe, "run", str(scene), "--out", str(out), "--threads", str(threads), "--quiet"]
    _, measured = run_measured(cmd, 1, rundir, tag, mfdem_env(threads))
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


def summarise(samples: list[dict]) -> dict:
    """The repeats of one configuration: median speed (robust to one disturbed run), spread,
    and the worst memory and outside load."""
    sps = [s["sps"] for s in samples]
    return {"median": statistics.median(sps), "min": min(sps), "max": max(sps),
            "contacts": statistics.median(s["contacts"] for s in samples),
            "rss": max(s["rss"] for s in samples),
            "rss_self": max((s.get("rss_self", 0) for s in samples), default=0),
            "foreign": max(s["foreign"] for s in samples),
            "foreign_median": statistics.median(s["foreign"] for s in samples),
            "cpu_median": statistics.median(s["sps_cpu"] for s in samples),
            "repeats": len(samples)}


# --- report ---------------------------------------------------------------------------------
def fmt_millions(x: float) -> str:
    return f"{x / 1e6:.2f}"


def provenance_lines(python: str) -> list[str]:
    """When and by which command the report was made."""
    return [f"Generated {timestamp()} by", "", "```", command_line(python), "```", ""]


def command_output(cmd: list[str]) -> str:
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=30).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


def package_version(pkg: str) -> str:
    return command_output(["dpkg-query", "-W", "-f=${Version}", pkg]) or "not installed"


def machine_description(mfdem: Path | None) -> list[str]:
    """Report lines on the hardware and software the timings depend on."""
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
        lines += mfdem_build_description(mfdem)
    return lines


def mfdem_build_description(mfdem: Path) -> list[str]:
    """Build type and flags from the CMake cache above the binary, and the binary's version."""
    lines = []
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


def closing_sections(mfdem: Path | None, notes: list[str]) -> list[str]:
    """The report's Machine and Notes sections."""
    out = ["## Machine", ""] + machine_description(mfdem) + [""]
    if notes:
        out += ["## Notes", ""] + [f"- {x}" for x in notes] + [""]
    return out


def publish_report(text: str, path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    log("")
    log(text)
    log(f"report written to {rel(path)}")
