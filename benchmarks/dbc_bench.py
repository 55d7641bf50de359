"""Time ``workbench dbc table|check|fixcal|callbacks`` against one cantools load of the same file, in the same run.

    python benchmarks/dbc_bench.py [--sizes 10,100,300,1000] [--repeat 5] [--workdir benchmarks/build/dbc]

Generates powertrain-like DBCs of each size in KiB (``dbc_generate.py``: hundreds of messages,
multiplexed signals, value tables, attributes, comments), each also with the defects cantools
refuses (which the workbench reads with a warning each). Every command runs as its own process,
in turn with the reference, a process that only loads the file with cantools
(``cantools.database.load_file(f, strict=False)``; for a file with defects, which cantools refuses,
its clean twin of the same size): ours, reference, ours, reference ... ``--repeat`` times. The
ratio is taken pair by pair, on the processes' CPU time (user + system, from ``wait4``: steady when
others load the machine) and on wall time; the medians and the best are printed. Both sides run
with compiled bytecode, as an installed package has it (a temporary pycache, whatever
PYTHONDONTWRITEBYTECODE says). The goal of issue 25 guards each row: ``table`` at most one
cantools load (1.0x), the other commands at most 1.2x; the exit status is 1 when a median is
above its goal (0 otherwise), so a run before a release shows a regression. Tests never assert
times; this script is run by hand, on a quiet machine.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from dbc_generate import generate  # noqa: E402

HERE = Path(__file__).resolve().parent
_SCRIPT = Path(sys.executable).with_name("workbench")
WORKBENCH = [str(_SCRIPT)] if _SCRIPT.exists() else [
    sys.executable, "-c", "import sys; from workbench.cli import main; sys.exit(main(sys.argv[1:]))"]
CANTOOLS_LOAD = [sys.executable, "-c",
                 "import sys, cantools; cantools.database.load_file(sys.argv[1], strict=False)"]
NODE = "ECM"
GOALS = {"table": 1.0, "check": 1.2, "fixcal": 1.2, "callbacks": 1.2}  # CPU time / one cantools load
API_C = "#include \"api.h\"\n\nvoid Api_Init(void)\n{\n    // <initCbk>\n    // </initCbk>\n}\n"


def run_process(command: list[str], env: dict, ok_codes: tuple[int, ...] = (0,)) -> tuple[float, float]:
    """Wall and CPU (user + system) seconds of one run of ``command``."""
    with tempfile.TemporaryFile() as stderr:  # a file, not a pipe: hundreds of warnings would fill a pipe
        start = time.perf_counter()
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=stderr, env=env)
        _, status, usage = os.wait4(process.pid, 0)
        elapsed = time.perf_counter() - start
        if os.waitstatus_to_exitcode(status) not in ok_codes:
            stderr.seek(0)
            raise SystemExit(f"failed: {' '.join(command)}\n{stderr.read().decode(errors='replace')}")
    return elapsed, usage.ru_utime + usage.ru_stime


def compare(ours: list[str], reference: list[str], repeat: int, env: dict, ok_codes: tuple[int, ...]) -> dict:
    """``ours`` and ``reference`` in turn, ``repeat`` pairs: medians and ratios (ours / reference)."""
    pairs = []
    for _ in range(repeat):
        pairs.append((run_process(ours, env, ok_codes), run_process(reference, env)))
    cpu_ratios = [a[1] / b[1] for a, b in pairs]
    wall_ratios = [a[0] / b[0] for a, b in pairs]
    return {
        "ours_cpu": statistics.median(a[1] for a, _ in pairs),
        "reference_cpu": statistics.median(b[1] for _, b in pairs),
        "cpu_ratio": statistics.median(cpu_ratios),
        "best_cpu_ratio": min(cpu_ratios),
        "wall_ratio": statistics.median(wall_ratios),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", default="10,100,300,1000", help="file sizes in KiB, comma-separated")
    parser.add_argument("--repeat", type=int, default=5, help="pairs (ours, reference) per command and file")
    parser.add_argument("--workdir", type=Path, default=HERE / "build" / "dbc")
    args = parser.parse_args()
    work = args.workdir
    work.mkdir(parents=True, exist_ok=True)
    out = Path(tempfile.mkdtemp(prefix="dbc-bench-"))
    env = {**os.environ, "PYTHONPYCACHEPREFIX": str(out / "pycache")}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    (out / "api.c").write_text(API_C)

    files = []
    for kib in (int(size) for size in args.sizes.split(",")):
        for defects in (False, True):
            path = work / f"powertrain_{kib}k{'_defects' if defects else ''}.dbc"
            if not path.exists():
                path.write_text(generate(kib, defects), encoding="utf-8")
            files.append((kib, defects, path))
    clean = {kib: path for kib, defects, path in files if not defects}
    run_process([*WORKBENCH, "dbc", "table", str(clean[min(clean)]), "--json"], env)  # compiles the bytecode
    run_process([*CANTOOLS_LOAD, str(clean[min(clean)])], env)

    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())} on {os.cpu_count()} cores; "
          f"{args.repeat} pairs each; ratio = ours / one cantools load (CPU time, medians; best; wall median)\n")
    print(f"{'file':34s} {'KiB':>5s} {'command':10s} {'ours s':>7s} {'cantools s':>10s} {'ratio':>6s} "
          f"{'best':>6s} {'wall':>6s} {'goal':>6s}")
    over = 0
    for kib, defects, path in files:
        commands = {
            "table": (["table", str(path), "--json"], (0,)),
            "check": (["check", str(path)], (0, 1)),
            "fixcal": (["fixcal", str(path), "--node", NODE, "-o", str(out / "fixcal")], (0,)),
            "callbacks": (["callbacks", str(path), "--node", NODE, "--network", "CAN2", "--api", str(out / "api.c")],
                          (0,)),
        }
        for name, (arguments, ok_codes) in commands.items():
            result = compare([*WORKBENCH, "dbc", *arguments], [*CANTOOLS_LOAD, str(clean[kib])], args.repeat, env,
                             ok_codes)
            verdict = "ok" if result["cpu_ratio"] <= GOALS[name] else "OVER"
            over += verdict == "OVER"
            print(f"{path.name:34s} {path.stat().st_size / 1024:5.0f} {name:10s} {result['ours_cpu']:7.3f} "
                  f"{result['reference_cpu']:10.3f} {result['cpu_ratio']:5.2f}x {result['best_cpu_ratio']:5.2f}x "
                  f"{result['wall_ratio']:5.2f}x {GOALS[name]:4.1f}x {verdict}", flush=True)
    print(f"\nload average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    print(f"{over} of {len(files) * len(GOALS)} above their goal" if over else "every command within its goal")
    shutil.rmtree(out, ignore_errors=True)
    sys.exit(1 if over else 0)


if __name__ == "__main__":
    main()
