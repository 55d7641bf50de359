"""Time ``workbench a2l update``/``merge``/``remove``/``cleanup``/``insert`` against the a2ltool PyPI package
(Rust), in the same run.

    python benchmarks/a2l_bench.py [--units 50] [--repeat 5] [--baseline REV] [--skip-merge]
                                   [--library] [--workdir DIR]

Generates the case first (``a2l_generate.py``; 50 units: ~50,000 C variables, gcc -g, an A2L
of 65,000 objects, 10.4 MiB; ``--units 10`` and ``--units 100`` scale it), then times every
command as a process of its own. The implementations run in turn, round after round (a2ltool,
this checkout, the baseline, a2ltool, ...), so a machine that others load slows all of them
alike; each reports its best wall time, the CPU time (user + system) of that run and its peak
resident memory (``wait4``). Ratios are against a2ltool, and this checkout against the baseline.

``--baseline REV`` unpacks that commit's ``workbench`` package (``git archive``) into a temporary
folder and runs it first on PYTHONPATH, with the same interpreter and libraries: a slowdown shows
before it lands. Both checkouts run with compiled bytecode, as an installed package has it (the
first run writes it into a temporary pycache, whatever PYTHONDONTWRITEBYTECODE says), and each
keeps its own ELF index cache. The script checks that every address equals a2ltool's, reports the
import time of an update process (``-X importtime``: what it imports before it reads a byte) and,
with ``--library``, times the library calls in-process. Nothing here asserts a time: it prints.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import tracemalloc
from dataclasses import dataclass, field
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from a2l_generate import generate  # noqa: E402

HERE = Path(__file__).resolve().parent
CHECKOUT = HERE.parent
A2LTOOL = shutil.which("a2ltool") or str(Path(sys.executable).with_name("a2ltool"))
_LAUNCH = "from workbench.cli import entry_point; entry_point()"  # what the console script runs
_REMOVED = "u0[67]_var0[0-4].*"  # the objects ``remove`` takes out: 1,000 of units 6 and 7
_INSERTED = "u0[0-9]_var00[0-9][0-9]"  # the variables ``insert`` makes MEASUREMENTs of: 1,000 of units 0-9


@dataclass
class Implementation:
    """One way to run the commands: a2ltool, or a checkout of the workbench."""

    name: str
    prefix: list[str]  # the command line up to the tool's own arguments
    env: dict | None = None
    cache: Path | None = None  # the workbench's ELF index cache folder (for the library's figures)


@dataclass
class Timing:
    wall: float = float("inf")
    cpu: float = 0.0
    peak_mib: float = 0.0
    runs: list[float] = field(default_factory=list)

    def add(self, wall: float, cpu: float, peak_mib: float) -> None:
        self.runs.append(wall)
        if wall < self.wall:
            self.wall, self.cpu, self.peak_mib = wall, cpu, peak_mib


def run_once(command: list[str], env: dict | None = None) -> tuple[float, float, float]:
    """Wall time (s), CPU time (user + system, s) and peak RSS (MiB) of one run of ``command``."""
    with tempfile.TemporaryFile() as errors:  # a file, not a pipe: a pipe nobody reads stops a talkative child
        start = time.perf_counter()
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=errors, env=env)
        _, status, usage = os.wait4(process.pid, 0)
        elapsed = time.perf_counter() - start
        errors.seek(0)
        stderr = errors.read().decode(errors="replace")
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"failed: {' '.join(command)}\n{stderr}")
    return elapsed, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024  # ru_maxrss: KiB on Linux


def alternate(commands: dict[str, tuple[list[str], dict | None]], repeat: int) -> dict[str, Timing]:
    """Run every command once per round, in turn, ``repeat`` rounds; the best run of each."""
    timings = {name: Timing() for name in commands}
    for _ in range(repeat):
        for name, (command, env) in commands.items():
            timings[name].add(*run_once(command, env))
    return timings


def has_command(implementation: Implementation, command: str) -> bool:
    """Whether ``workbench a2l COMMAND`` exists in this checkout (a baseline may predate it)."""
    return subprocess.run([*implementation.prefix, "a2l", command, "--help"], stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL, env=implementation.env).returncode == 0


def in_process(function, repeat: int) -> tuple[float, float]:
    """Best time of ``function()`` and the tracemalloc peak (MiB) of one extra traced call."""
    best = min(_timed(function) for _ in range(repeat))
    tracemalloc.start()
    function()
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return best, peak / 2**20


def _timed(function) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def workbench_checkout(name: str, root: Path, scratch: Path) -> Implementation:
    """The workbench package under ``root`` (put first on PYTHONPATH), with its own pycache and index cache
    (its user cache folder, ``$XDG_CACHE_HOME``: the commands are timed as users type them, without --cache-dir)."""
    env = {**os.environ, "PYTHONPATH": str(root), "PYTHONPYCACHEPREFIX": str(scratch / f"pycache-{name}"),
           "XDG_CACHE_HOME": str(scratch / f"cache-{name}")}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env.pop("WORKBENCH_CACHE_DIR", None)  # it would take precedence over XDG_CACHE_HOME
    return Implementation(name, [sys.executable, "-P", "-c", _LAUNCH], env, scratch / f"cache-{name}" / "library")


def unpack_revision(revision: str, into: Path) -> str:
    """``git archive`` the ``workbench`` package of ``revision`` into ``into``; returns its short hash."""
    commit = subprocess.run(["git", "-C", str(CHECKOUT), "rev-parse", "--short", revision], check=True,
                            capture_output=True, text=True).stdout.strip()
    into.mkdir(parents=True)
    archive = subprocess.run(["git", "-C", str(CHECKOUT), "archive", commit, "workbench"], check=True,
                             capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    return commit


def load_average() -> str:
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "unknown"


def import_time(implementation: Implementation, arguments: list[str]) -> tuple[float, int, list[tuple[str, float]]]:
    """What one ``workbench`` process imports (``-X importtime``): total seconds, module count, and the
    top-level imports that take more than 2 ms (name, seconds)."""
    command = [implementation.prefix[0], "-X", "importtime", *implementation.prefix[1:], *arguments]
    result = subprocess.run(command, env=implementation.env, capture_output=True, text=True)
    total, count, heavy = 0.0, 0, []
    for line in result.stderr.splitlines():
        match = re.match(r"import time:\s+(\d+) \|\s+(\d+) \|( *)(\S+)", line)
        if match is None:
            continue
        count += 1
        if len(match.group(3)) == 1:  # a top-level import (nested ones are indented further)
            total += int(match.group(2)) / 1e6
            if int(match.group(2)) > 2000:
                heavy.append((match.group(4), int(match.group(2)) / 1e6))
    return total, count, sorted(heavy, key=lambda item: -item[1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--units", type=int, default=50, help="C units of the generated case (1,300 objects each)")
    parser.add_argument("--workdir", type=Path, help="folder of the case (default: benchmarks/build/a2l, "
                        "a2l-unitsN for other sizes)")
    parser.add_argument("--repeat", type=int, default=5, help="rounds (each command runs once a round)")
    parser.add_argument("--baseline", metavar="REV", help="also time this commit's workbench in the same rounds")
    parser.add_argument("--skip-merge", action="store_true", help="time the updates only")
    parser.add_argument("--library", action="store_true", help="also time the library calls in-process")
    args = parser.parse_args()
    work = args.workdir or HERE / "build" / ("a2l" if args.units == 50 else f"a2l-units{args.units}")
    print(f"generating the case in {work} (unless it is there) ...", file=sys.stderr)
    generate(work, units=args.units)
    a2l, elf = work / "big.a2l", work / "big.elf"
    fragments = sorted((work / "fragments").glob("*.a2l"))
    out = Path(tempfile.mkdtemp(prefix="a2l-bench-"))
    try:
        _bench(args, work, a2l, elf, fragments, out)
    finally:
        shutil.rmtree(out, ignore_errors=True)


def _bench(args, work: Path, a2l: Path, elf: Path, fragments: list[Path], out: Path) -> None:
    objects = len(re.findall(rb"/begin (?:MEASUREMENT|CHARACTERISTIC) ", a2l.read_bytes()))
    reference = Implementation("a2ltool", [A2LTOOL])
    ours = [workbench_checkout("current", CHECKOUT, out)]
    if args.baseline:
        commit = unpack_revision(args.baseline, out / "baseline")
        ours.append(workbench_checkout(f"baseline {commit}", out / "baseline", out))
    print(f"case: {a2l.stat().st_size / 2**20:.1f} MiB A2L, {objects:,} objects, {elf.stat().st_size / 2**20:.1f} "
          f"MiB ELF, {len(fragments)} fragments; best of {args.repeat} rounds; load average {load_average()}")

    def update(implementation: Implementation, source: Path, target: str, *extra: str) -> list[str]:
        if implementation is reference:
            # PRESERVE: keep objects whose symbol is gone, as ``workbench a2l update`` does by default
            return [A2LTOOL, str(source), "-e", str(elf), "-u", "ADDRESSES", "--update-mode", "PRESERVE", "-o",
                    str(out / target)]
        return [*implementation.prefix, "a2l", "update", str(source), str(elf), "-o",
                str(out / f"{target}-{implementation.name}"), *extra]

    for implementation in ours:  # compile the bytecode, fill the index cache
        run_once(update(implementation, a2l, "warm"), implementation.env)
        shutil.copy(out / f"warm-{implementation.name}", out / f"updated-{implementation.name}")
    run_once(update(reference, a2l, "ref"))
    shutil.copy(out / "ref", out / "updated-a2ltool")
    jobs: list[tuple[str, dict]] = [
        ("update, no index cache", {i.name: (update(i, a2l, "cold", "--no-cache"), i.env) for i in ours}),
        ("update, cached ELF index", {i.name: (update(i, a2l, "warm"), i.env) for i in ours}),
        ("update --validate, cached", {i.name: (update(i, a2l, "valid", "--validate"), i.env) for i in ours}),
        ("update of an updated file, cached", {i.name: (update(i, out / f"updated-{i.name}", "again"), i.env)
                                               for i in ours}),
    ]
    references = {"update, no index cache": update(reference, a2l, "ref"),
                  "update of an updated file, cached": update(reference, out / "updated-a2ltool", "ref2")}
    if not args.skip_merge:
        merge_reference = [A2LTOOL, str(work / "master.a2l"), *(x for f in fragments for x in ("-m", str(f))),
                           "-o", str(out / "ref_merged.a2l")]
        references["merge (inputs validated)"] = merge_reference
        jobs.append(("merge (inputs validated)", {
            i.name: ([*i.prefix, "a2l", "merge", str(work / "master.a2l"), *map(str, fragments), "-o",
                      str(out / f"merged-{i.name}")], i.env) for i in ours}))
    # a2ltool's --remove and --cleanup: 1,000 objects out by name (two units' first 500), then what nothing uses
    # (a baseline older than these commands has no row of its own)
    for label, options in (("remove 1,000 objects (regex)", ["remove", "-R", _REMOVED]), ("cleanup", ["cleanup"])):
        references[label] = [A2LTOOL, str(a2l), *(["-R", _REMOVED] if options[0] == "remove" else ["--cleanup"]),
                             "-o", str(out / "ref_pruned.a2l")]
        jobs.append((label, {i.name: ([*i.prefix, "a2l", options[0], str(a2l), *options[1:], "-o",
                                       str(out / f"pruned-{i.name}")], i.env) for i in ours
                             if has_command(i, options[0])}))
    # a2ltool's --measurement-regex: 1,000 variables (ten units' first 100) into the empty master, of the ELF's
    # 50,000 whose names start alike (ours with the index cache the updates above left)
    label = "insert 1,000 variables (regex)"
    references[label] = [A2LTOOL, str(work / "master.a2l"), "-e", str(elf), "--measurement-regex", _INSERTED, "-o",
                         str(out / "ref_inserted.a2l")]
    jobs.append((label, {i.name: ([*i.prefix, "a2l", "insert", str(work / "master.a2l"), str(elf),
                                   "--measurement-regex", _INSERTED, "-o", str(out / f"inserted-{i.name}")], i.env)
                         for i in ours}))

    names = [i.name for i in ours]
    header = f"{'command':36s} {'a2ltool s':>9s} {'cpu s':>6s}"
    for name in names:
        header += f" {name + ' s':>18s} {'cpu s':>6s} {'MiB':>4s} {'x a2ltool':>9s}"
    if args.baseline:
        header += f" {'current/baseline':>16s}"
    print("\n" + header)
    reference_time = reference_cpu = None
    for label, commands in jobs:
        if label in references:  # a2ltool's figure for this and the following rows (it has no index cache)
            commands = {"a2ltool": (references[label], None), **commands}
        timings = alternate(commands, args.repeat)
        if "a2ltool" in timings:
            reference_time, reference_cpu = timings["a2ltool"].wall, timings["a2ltool"].cpu
        line = f"{label:36s} {reference_time:9.3f} {reference_cpu:6.2f}"
        for name in names:
            timing = timings.get(name)
            line += (f" {'-':>18s} {'-':>6s} {'-':>4s} {'-':>9s}" if timing is None else
                     f" {timing.wall:18.3f} {timing.cpu:6.2f} {timing.peak_mib:4.0f} {timing.wall / reference_time:8.2f}x")
        if args.baseline and all(name in timings for name in names):
            line += f" {timings[names[0]].wall / timings[names[1]].wall:15.2f}x"
        print(line)
    print(f"load average after: {load_average()}")

    reference_addresses = _addresses(out / "ref")  # a2ltool drops the address of an object whose symbol is gone
    for name in names:
        warm, cold = _addresses(out / f"warm-{name}"), _addresses(out / f"cold-{name}")
        same = warm == cold and all(warm.get(key) == value for key, value in reference_addresses.items())
        print(f"{name}: the {len(reference_addresses):,} addresses a2ltool sets are equal to ours: {same}")
    imports = {}
    for _ in range(args.repeat):  # in turn, the best of each
        for implementation in ours:
            measured = import_time(implementation, ["a2l", "update", str(a2l), str(elf), "-o",
                                                    str(out / "imports.a2l")])
            if implementation.name not in imports or measured[0] < imports[implementation.name][0]:
                imports[implementation.name] = measured
    for implementation in ours:
        total, count, heavy = imports[implementation.name]
        shown = ", ".join(f"{name} {seconds * 1000:.0f}" for name, seconds in heavy[:6])
        print(f"{implementation.name}: a cached update imports {count} modules in {total * 1000:.0f} ms "
              f"(-X importtime; ms: {shown})")
    if args.library:
        _library(a2l, elf, ours[0].cache, args.repeat)


def _library(a2l: Path, elf: Path, cache: Path, repeat: int) -> None:
    """In-process figures of this checkout's library calls."""
    from workbench.a2l import load_a2l
    from workbench.a2l.update import update_document
    from workbench.elf.debugdata import DebugData

    doc = load_a2l(a2l, validate=False)
    debug = DebugData(elf, cache_dir=cache)
    library = [
        ("load (structure only)", lambda: load_a2l(a2l, validate=False)),
        ("load + full validation", lambda: load_a2l(a2l)),
        ("DWARF index, no cache", lambda: DebugData(elf, use_cache=False)),
        ("DWARF index from the cache", lambda: DebugData(elf, cache_dir=cache)),
        ("update_document() in memory", lambda: update_document(doc, debug, report_addresses=False)),
    ]
    print(f"\n{'library call':40s} {'best s':>8s} {'tracemalloc peak MiB':>21s}")
    for name, function in library:
        seconds, peak = in_process(function, repeat)
        print(f"{name:40s} {seconds:8.3f} {peak:21.0f}")


def _addresses(path: Path) -> dict[bytes, int]:
    """Object name -> its ECU_ADDRESS or CHARACTERISTIC address."""
    found = re.findall(rb"/begin (?:MEASUREMENT|CHARACTERISTIC) (\S+)[^/]*?(?:ECU_ADDRESS|VALUE) (0x[0-9A-Fa-f]+)",
                       path.read_bytes())
    return {name: int(value, 16) for name, value in found}


if __name__ == "__main__":
    main()
