"""Time ``workbench a2l update``/``merge`` against the a2ltool PyPI package (Rust), in the same run.

    python benchmarks/a2l_bench.py [--workdir benchmarks/build/a2l] [--repeat 5]

Generates the large case first (``a2l_generate.py``: ~50,000 C variables, gcc -g, an
A2L of ~11 MB), then runs each command ``--repeat`` times as a separate process and
reports the best wall time and the peak resident memory of that process (``wait4``),
plus the in-process time and tracemalloc peak of our library calls. Ratios are ours
divided by a2ltool's. Our commands run with compiled bytecode, as an installed package
has it (the first run writes it into a temporary pycache, whatever
PYTHONDONTWRITEBYTECODE says). Nothing here asserts a time: it prints.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from a2l_generate import generate  # noqa: E402

HERE = Path(__file__).resolve().parent
A2LTOOL = shutil.which("a2ltool") or str(Path(sys.executable).with_name("a2ltool"))
_SCRIPT = Path(sys.executable).with_name("workbench")
WORKBENCH = [str(_SCRIPT)] if _SCRIPT.exists() else [
    sys.executable, "-c", "import sys; from workbench.cli import main; sys.exit(main(sys.argv[1:]))"]


def run_process(command: list[str], repeat: int, env: dict | None = None) -> tuple[float, float]:
    """Best wall time (s) and the peak RSS (MiB) of that run, over ``repeat`` runs."""
    best = None
    for _ in range(repeat):
        start = time.perf_counter()
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
        _, status, usage = os.wait4(process.pid, 0)
        elapsed = time.perf_counter() - start
        stderr = process.stderr.read().decode(errors="replace")
        process.stderr.close()
        if os.waitstatus_to_exitcode(status) != 0:
            raise SystemExit(f"failed: {' '.join(command)}\n{stderr}")
        peak = usage.ru_maxrss / 1024  # KiB on Linux
        if best is None or elapsed < best[0]:
            best = (elapsed, peak)
    return best


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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--workdir", type=Path, default=HERE / "build" / "a2l")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    work = args.workdir
    if not (work / "big.elf").exists():
        print(f"generating the case in {work} ...", file=sys.stderr)
        generate(work)
    a2l, elf = work / "big.a2l", work / "big.elf"
    fragments = sorted((work / "fragments").glob("*.a2l"))
    out = Path(tempfile.mkdtemp(prefix="a2l-bench-"))
    cache = out / "cache"
    print(f"case: {a2l.stat().st_size / 2**20:.1f} MiB A2L, {elf.stat().st_size / 2**20:.1f} MiB ELF, "
          f"{len(fragments)} fragments; best of {args.repeat}\n")

    env = {**os.environ, "PYTHONPYCACHEPREFIX": str(out / "pycache")}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    ours = [*WORKBENCH, "a2l"]
    run_process([*ours, "--help"], 1, env)  # compiles the bytecode

    rows = []
    reference = run_process([A2LTOOL, str(a2l), "-e", str(elf), "-u", "ADDRESSES", "-o", str(out / "ref.a2l")],
                            args.repeat)
    rows.append(("a2ltool update (addresses)", *reference, None))
    cold = run_process([*ours, "update", str(a2l), str(elf), "-o", str(out / "cold.a2l"), "--no-cache"],
                       args.repeat, env)
    rows.append(("workbench update, no index cache", *cold, cold[0] / reference[0]))
    update = [*ours, "update", str(a2l), str(elf), "-o", str(out / "warm.a2l"), "--cache-dir", str(cache)]
    run_process(update, 1, env)  # fills the cache
    warm = run_process(update, args.repeat, env)
    rows.append(("workbench update, cached index", *warm, warm[0] / reference[0]))
    checked = run_process([*update, "--validate"], args.repeat, env)
    rows.append(("workbench update --validate, cached", *checked, checked[0] / reference[0]))
    # the CI case: the A2L was updated before, few addresses move
    again = run_process([A2LTOOL, str(out / "ref.a2l"), "-e", str(elf), "-u", "ADDRESSES", "-o", str(out / "ref2.a2l")],
                        args.repeat)
    rows.append(("a2ltool update of an updated file", *again, None))
    ours_again = run_process([*ours, "update", str(out / "warm.a2l"), str(elf), "-o", str(out / "again.a2l"),
                              "--cache-dir", str(cache)], args.repeat, env)
    rows.append(("workbench update of an updated file, cached", *ours_again, ours_again[0] / again[0]))

    merge_reference = run_process([A2LTOOL, str(work / "master.a2l"), *(x for f in fragments for x in ("-m", str(f))),
                                   "-o", str(out / "ref_merged.a2l")], args.repeat)
    rows.append(("a2ltool merge", *merge_reference, None))
    merged = run_process([*ours, "merge", str(work / "master.a2l"), *map(str, fragments),
                          "-o", str(out / "merged.a2l")], args.repeat, env)
    rows.append(("workbench merge", *merged, merged[0] / merge_reference[0]))

    print(f"{'command':46s} {'wall s':>8s} {'peak RSS MiB':>13s} {'ratio':>7s}")
    for name, seconds, peak, ratio in rows:
        print(f"{name:46s} {seconds:8.3f} {peak:13.0f} {'' if ratio is None else f'{ratio:6.2f}x':>7s}")

    from workbench.a2l import load_a2l
    from workbench.a2l.update import update_document
    from workbench.elf.debugdata import DebugData

    doc = load_a2l(a2l, validate=False)
    library = [
        ("load (structure only)", lambda: load_a2l(a2l, validate=False)),
        ("load + full validation", lambda: load_a2l(a2l)),
        ("DWARF index, no cache", lambda: DebugData(elf, use_cache=False)),
        ("DWARF index from the cache", lambda: DebugData(elf, cache_dir=cache)),
    ]
    debug = DebugData(elf, cache_dir=cache)
    library.append(("update_document() in memory", lambda: update_document(doc, debug, report_addresses=False)))
    print(f"\n{'library call':40s} {'best s':>8s} {'tracemalloc peak MiB':>21s}")
    for name, function in library:
        seconds, peak = in_process(function, args.repeat)
        print(f"{name:40s} {seconds:8.3f} {peak:21.0f}")
    same = _addresses(out / "warm.a2l") == _addresses(out / "ref.a2l")
    print(f"\nevery ECU_ADDRESS and CHARACTERISTIC address equals a2ltool's: {same}")
    shutil.rmtree(out, ignore_errors=True)


def _addresses(path: Path) -> list[int]:
    import re

    data = path.read_bytes()
    return [int(value, 16) for value in re.findall(rb"(?:ECU_ADDRESS|VALUE) (0x[0-9A-Fa-f]+)", data)]


if __name__ == "__main__":
    main()
