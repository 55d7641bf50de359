"""The window with a real ECU's A2L: 65,100 objects (``--units 100``: 130,200) against the demo's 156, same run.

    QT_QPA_PLATFORM=offscreen .venv/bin/python benchmarks/gui_big_bench.py [--units 50] [--rounds 3]
        [--baseline REV] [--profile OUT.prof] [--screenshot OUT.png]

The case is ``a2l_generate.py``'s (C units of 1,300 objects each, gcc -g), its addresses filled in from the ELF by
``workbench a2l update``, a FUNCTION of each 50 objects (1,350 FUNCTIONs: its calibrations DEF_CHARACTERISTIC, its
signals LOC_MEASUREMENT) and every third signal in bar (a function and a unit filter to choose), and an s19 of the
ELF's data (objcopy, .bss as zeros) for offline editing. Each case runs in a process of its own (its peak RSS is its own), the demo and
the big case in turn, round after round; the best of the rounds is printed, and the big case's ratio to the demo's.
``--baseline REV`` runs the big case on that commit's ``workbench`` too (``git archive``, as a2l_bench.py does), in
the same rounds: the figures before and after a change.

What is timed, as a user meets it in the window (offscreen, 1366 x 768, every step followed by a paint of the
window, so a step is over when the user sees its result):
  open       MainWindow.load() of the project (A2L, ELF, s19) until the window is painted with its objects;
             ``read`` is the worker's share (reading the A2L), ``gui`` the GUI thread's after it (a frozen window)
  keystroke  typing ``u07_var01`` into the search, letter by letter: the time until the table shows each result
             (the worst and the median letter); ``gui`` the GUI thread's busy time of the worst
  filter     the kind, function and unit boxes set, then back to all (the slowest)
  function typed   the end of a FUNCTION's name typed into the function box, letter by letter, lower case (it lists
             the functions containing it): the worst letter
  function chosen  Enter on the only function left: the table shows its objects
  sort       a click on the name header, twice (descending), then the A2L's order again (the slowest)
  scroll     to the end and back, and 20 page-downs (the slowest)
  editor     a calibration opened by name until its editor shows the s19's value
  plot       five signals added to a new plot by name
  image      File > Open image of the s19 again, the open editor showing its value
  compare    Calibration > Open parameter set: a DCM of every calibration (``cal save --image``) compared with the
             image until the compare view lists them (they are equal: "equal ones too" ticked is timed as well)
  compare sort  a click on the compare view's object header (twice; a QSortFilterProxyModel)
  gc         a full garbage collection (the window collects on the GUI thread: a long one is a freeze)
  close      the project closed (another one opens: every window bound to the A2L goes)
``--profile`` writes a cProfile of the big case's steps; ``--screenshot`` a PNG of the window with the big case
(what the browser shows after typing). Nothing here asserts a time: it prints.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
SEARCH = "u07_var01"
FUNCTION_SIZE = 50  # objects a FUNCTION names
STEPS = ("open", "open gui", "open read", "keystroke", "keystroke median", "keystroke gui", "filter",
         "function typed", "function chosen", "sort",
         "scroll", "editor", "plot", "image", "compare", "compare sort", "gc", "close")


# --- the case ------------------------------------------------------------------------------------

def prepare_case(workdir: Path, units: int) -> tuple[Path, Path, Path]:
    """(A2L, ELF, s19) of the big case in ``workdir`` (made once; the generator's case made again when it changed)."""
    from a2l_generate import generate

    generate(workdir, units=units)
    a2l, elf, s19 = workdir / "gui.a2l", workdir / "big.elf", workdir / "gui.s19"
    stamp = workdir / "gui.txt"
    expected = (workdir / "case.txt").read_text() + f"gui_big_bench: FUNCTIONs of {FUNCTION_SIZE}\n"
    if a2l.exists() and s19.exists() and stamp.exists() and stamp.read_text() == expected:
        return a2l, elf, s19
    updated = workdir / "gui-updated.a2l"
    subprocess.run([sys.executable, "-c", "from workbench.cli import entry_point; entry_point()", "a2l", "update",
                    str(workdir / "big.a2l"), str(elf), "-o", str(updated)], check=True, stdout=subprocess.DEVNULL)
    text = updated.read_text()
    count = iter(range(1 << 30))
    text = re.sub(r'(MEASUREMENT \S+ "[^"]*" \w+ )CM_Identity',
                  lambda m: m.group(1) + ("CM_Linear" if next(count) % 3 == 0 else "CM_Identity"), text)
    functions = []
    for unit in range(units):  # a FUNCTION of each 50 objects: 27 a unit, as a real ECU has thousands
        objects = re.findall(rf"/begin (CHARACTERISTIC|MEASUREMENT) (u{unit:02d}_\S+)", text)
        for first in range(0, len(objects), FUNCTION_SIZE):
            members = objects[first:first + FUNCTION_SIZE]
            lists = "".join(f"      /begin {block} {' '.join(n for k, n in members if k == kind)} /end {block}\n"
                            for kind, block in (("CHARACTERISTIC", "DEF_CHARACTERISTIC"), ("MEASUREMENT", "LOC_MEASUREMENT"))
                            if any(k == kind for k, _ in members))
            functions.append(f'    /begin FUNCTION Unit{unit:02d}_F{first // FUNCTION_SIZE:02d} "unit {unit}"\n{lists}'
                             "    /end FUNCTION\n")
    end = text.rindex("  /end MODULE")
    a2l.write_text(text[:end] + "".join(functions) + text[end:])
    updated.unlink()
    subprocess.run(["objcopy", "--set-section-flags", ".bss=alloc,load,contents", "-O", "srec", str(elf), str(s19)],
                   check=True)
    stamp.write_text(expected)
    return a2l, elf, s19


def parameter_set(a2l: Path | None, s19: Path | None, out: Path) -> Path:
    """A DCM of every calibration the image holds (``workbench cal save --image``; the demo's without files)."""
    if not out.exists():
        files = ["--image", str(s19), "--a2l", str(a2l)] if a2l else ["--image", str(_demo_s19())]
        subprocess.run([sys.executable, "-c", "from workbench.cli import entry_point; entry_point()", "cal", "save",
                        *files, str(out)], check=True, stdout=subprocess.DEVNULL)
    return out


def _demo_s19() -> Path:
    from workbench import demo

    return demo.s19()


# --- one case, in a process of its own -------------------------------------------------------------

def run_case(a2l: str | None, elf: str | None, s19: str | None, dcm: str, profile: str | None, screenshot: str | None
             ) -> dict:
    import gc

    from PySide6.QtCore import QEventLoop, QPoint, Qt, QTimer
    from PySide6.QtTest import QTest

    from workbench.gui.app import application, screenshot_screen
    from workbench.gui.project import PlotSpec, Project, demo_project
    from workbench.gui.widgets.main_window import MainWindow

    screenshot_screen((1366, 768))
    app = application()
    times: dict[str, float] = {}
    cpu: dict[str, float] = {}  # the GUI thread's CPU time of the same (what other processes take is not in it)
    collecting = {"began": 0.0, "full": 0, "full_s": 0.0}

    def collected(phase: str, info: dict) -> None:  # the window's own garbage collections, full ones counted
        if info["generation"] == 2:
            if phase == "start":
                collecting["began"] = time.perf_counter()
            else:
                collecting["full"] += 1
                collecting["full_s"] += time.perf_counter() - collecting["began"]

    gc.callbacks.append(collected)
    profiler = None
    if profile:
        import cProfile

        profiler = cProfile.Profile()

    def wait(signal, timeout_s: float = 120.0):
        loop, got = QEventLoop(), []

        def done(*args):
            got.append(args)
            loop.quit()

        signal.connect(done)
        QTimer.singleShot(int(timeout_s * 1000), loop.quit)
        loop.exec()
        signal.disconnect(done)
        if not got:
            raise SystemExit(f"timed out waiting for {signal}")
        return got[0]

    def shown() -> None:
        """Everything posted handled (a filter waiting for its timer too), the window painted."""
        browser = window.browser
        while getattr(browser, "pending", lambda: False)():
            app.processEvents(QEventLoop.AllEvents, 5)
        app.processEvents()
        window.grab()

    def timed(name: str, action) -> float:
        began, cpu_began = time.perf_counter(), time.thread_time()
        if profiler:
            profiler.enable()
        action()
        shown()
        if profiler:
            profiler.disable()
        elapsed, used = time.perf_counter() - began, time.thread_time() - cpu_began
        times[name], cpu[name] = max(times.get(name, 0.0), elapsed), max(cpu.get(name, 0.0), used)
        return elapsed

    if a2l is None:
        project = demo_project()
        project.plots, project.tables, project.editors = [], [], []
    else:
        project = Project(a2l=Path(a2l), elf=Path(elf), s19=Path(s19))
    window = MainWindow(project)
    window.show()
    shown()
    rss_before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    gui_busy = {}
    loaded = window._workspace_loaded

    def workspace_loaded(workspace):
        began, cpu_began = time.perf_counter(), time.thread_time()
        loaded(workspace)
        cpu["open gui"] = time.thread_time() - cpu_began
        gui_busy["read done"] = began

    window._workspace_loaded = workspace_loaded  # the bound method run_task calls
    began = time.perf_counter()
    if profiler:
        profiler.enable()
    window.load()
    wait(window.loaded)
    shown()
    if profiler:
        profiler.disable()
    times["open"] = time.perf_counter() - began
    times["open read"] = gui_busy["read done"] - began
    times["open gui"] = times["open"] - times["open read"]
    browser = window.browser
    objects = len(browser.model.all_rows)
    calibrations = [r.name for r in browser.model.all_rows if r.kind == "CHARACTERISTIC"]
    signals = [r.name for r in browser.model.all_rows if r.kind == "MEASUREMENT"]

    browser.search.setFocus()
    letters, busy = [], []

    def type_letter(letter: str) -> None:
        began = time.perf_counter()
        QTest.keyClick(browser.search, letter)
        busy.append(time.perf_counter() - began)

    for letter in SEARCH:
        letters.append(timed("keystroke", lambda letter=letter: type_letter(letter)))
    times["keystroke median"], times["keystroke gui"] = statistics.median(letters), max(busy)
    found = browser.model.rowCount()
    if screenshot:
        window.grab().save(screenshot)
    timed("keystroke", lambda: browser.search.clear())
    for box in (browser.kind_box, browser.function_box, browser.unit_box):
        timed("filter", lambda b=box: b.setCurrentIndex(b.count() - 1))
        timed("filter", lambda b=box: b.setCurrentIndex(0))
    functions = browser.function_box
    if functions.isEditable():  # a baseline before the box was searchable leaves the two steps out
        chosen = functions.itemText(functions.count() // 2)
        field = functions.lineEdit()
        field.setFocus()
        field.selectAll()
        for letter in chosen[-6:].lower():  # "Unit25_F00": "25_f00", only that one contains it
            timed("function typed", lambda letter=letter: QTest.keyClick(field, letter))
        timed("function chosen", lambda: QTest.keyClick(field, Qt.Key_Return))
        if functions.currentText() != chosen:
            raise SystemExit(f"typing {chosen[-6:].lower()!r} and Enter chose {functions.currentText()!r}")
        functions.setCurrentIndex(0)
        shown()
    header = browser.table.horizontalHeader()
    for _ in range(2):  # a click on the name's header: ascending, then descending
        timed("sort", lambda: QTest.mouseClick(header.viewport(), Qt.LeftButton, Qt.NoModifier,
                                               QPoint(header.sectionViewportPosition(0) + 8, header.height() // 2)))
    if browser.model.sorted_by != (0, Qt.DescendingOrder):
        raise SystemExit(f"two clicks on the name's header sorted by {browser.model.sorted_by}")
    timed("sort", lambda: browser.table.sortByColumn(-1, Qt.AscendingOrder))
    timed("scroll", browser.table.scrollToBottom)
    timed("scroll", browser.table.scrollToTop)
    browser.table.setFocus()
    for _ in range(20):
        timed("scroll", lambda: QTest.keyClick(browser.table, Qt.Key_PageDown))

    def open_editor():
        editor = window.open_editor(calibrations[len(calibrations) // 2])
        if editor.value is None:
            wait(editor.loaded)

    timed("editor", open_editor)
    timed("plot", lambda: window.add_plot(PlotSpec("by name", signals[-5:])))

    def open_image():
        editor = next(iter(window.editors.values()))
        editor.value = None
        window.offline_image.open(Path(s19 or project.s19))
        wait(editor.loaded)

    timed("image", open_image)

    def compare():  # Calibration > Open parameter set: every calibration of the DCM against the image
        window.parameter_sets.open(Path(dcm))
        wait(window.parameter_sets.compared)

    timed("compare", compare)
    window.compare.show_equal.setChecked(False)
    timed("compare", lambda: window.compare.show_equal.setChecked(True))  # every row shown (all equal)
    compare_header = window.compare.table.horizontalHeader()
    for _ in range(2):
        timed("compare sort", lambda: QTest.mouseClick(compare_header.viewport(), Qt.LeftButton, Qt.NoModifier, QPoint(
            compare_header.sectionViewportPosition(0) + 8, compare_header.height() // 2)))
    compared = window.compare.proxy.rowCount()
    timed("gc", gc.collect)
    timed("close", window._close_project)
    window.close()
    if profiler:
        profiler.dump_stats(profile)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return {"times": times, "cpu": cpu, "objects": objects, "found": found, "compared": compared, "rss_mib": rss,
            "rss_before_mib": rss_before, "full_collections": collecting["full"], "full_collections_s": collecting["full_s"]}


# --- the runs ------------------------------------------------------------------------------------

def child(args: list[str], tree: Path = HERE.parent) -> dict:
    env = {**os.environ, "QT_QPA_PLATFORM": os.environ.get("QT_QPA_PLATFORM", "offscreen")}
    output = subprocess.run([sys.executable, __file__, "--tree", str(tree), "--child", *args], env=env, check=True,
                            capture_output=True, text=True)
    return json.loads(output.stdout.strip().splitlines()[-1])


def best(runs: list[dict], values: str = "times") -> dict[str, float]:
    return {step: min((r[values].get(step, float("nan")) for r in runs), default=float("nan")) for step in STEPS}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--units", type=int, default=50, help="C units of the big case (1,302 objects each)")
    parser.add_argument("--rounds", type=int, default=3, help="runs of each case, in turn (default 3)")
    parser.add_argument("--workdir", type=Path, help="the case's folder (default: a2l_bench.py's, benchmarks/build/a2l, "
                        "a2l-unitsN for other sizes)")
    parser.add_argument("--baseline", metavar="REV", help="also run the big case on this commit's workbench, in turn")
    parser.add_argument("--profile", help="write a cProfile of the big case's steps (one extra run)")
    parser.add_argument("--screenshot", help="save a PNG of the window with the big case, the search typed")
    parser.add_argument("--tree", type=Path, default=HERE.parent, help=argparse.SUPPRESS)
    parser.add_argument("--child", nargs=6, help=argparse.SUPPRESS)
    args = parser.parse_args()
    sys.path.insert(0, str(args.tree))
    if args.child:
        files = [None if value == "-" else value for value in args.child]
        print(json.dumps(run_case(*files)))
        return
    workdir = args.workdir or HERE / "build" / ("a2l" if args.units == 50 else f"a2l-units{args.units}")
    a2l, elf, s19 = map(str, prepare_case(workdir, args.units))
    dcms = {"big": str(parameter_set(Path(a2l), Path(s19), workdir / "gui.dcm")),
            "demo": str(parameter_set(None, None, workdir / "demo.dcm"))}
    with tempfile.TemporaryDirectory() as scratch:
        baseline = None
        if args.baseline:
            from a2l_bench import unpack_revision

            baseline = unpack_revision(args.baseline, Path(scratch) / "baseline")
        runs: dict[str, list[dict]] = {"demo": [], "big": [], "baseline": []}
        for _ in range(args.rounds):
            runs["demo"].append(child(["-", "-", "-", dcms["demo"], "-", "-"]))
            runs["big"].append(child([a2l, elf, s19, dcms["big"], "-", "-"]))
            if baseline:
                runs["baseline"].append(child([a2l, elf, s19, dcms["big"], "-", "-"], Path(scratch) / "baseline"))
    if args.profile or args.screenshot:
        child([a2l, elf, s19, dcms["big"], args.profile or "-", args.screenshot or "-"])
    demo, big, big_cpu = best(runs["demo"]), best(runs["big"]), best(runs["big"], "cpu")
    print(f"the window with {runs['big'][0]['objects']:,} objects ({Path(a2l).stat().st_size / 2**20:.1f} MiB A2L) "
          f"against the demo's {runs['demo'][0]['objects']:,}, best of {args.rounds} "
          f"({os.environ.get('QT_QPA_PLATFORM', 'offscreen')}; load {os.getloadavg()[0]:.1f}):")
    before, before_cpu = best(runs["baseline"]), best(runs["baseline"], "cpu")
    print(f"  {'step':18} {'demo':>9} {'big':>9} {'ratio':>6} {'big CPU':>9}"
          + (f" {baseline + ':':>9} {'CPU':>9} {'CPU big/baseline':>16}" if baseline else ""))
    for step in STEPS:
        line = f"  {step:18} {demo[step] * 1000:7.1f}ms {big[step] * 1000:7.1f}ms {big[step] / demo[step]:5.1f}x"
        line += f" {big_cpu[step] * 1000:7.1f}ms" if big_cpu[step] == big_cpu[step] else " " * 10
        if baseline:
            line += f" {before[step] * 1000:7.1f}ms"
            if before_cpu[step] == before_cpu[step]:
                line += f" {before_cpu[step] * 1000:7.1f}ms {big_cpu[step] / before_cpu[step]:15.2f}x"
        print(line)
    print("  (CPU: the GUI thread's own CPU time of the step, what other processes take is not in it; a keystroke's: "
          "the worst letter's)")
    for case in ("demo", "big", "baseline") if baseline else ("demo", "big"):
        least = min(runs[case], key=lambda r: r["rss_mib"])
        print(f"  {case}: peak RSS {least['rss_mib']:.0f} MiB ({least['rss_before_mib']:.0f} MiB before the project "
              f"was read); '{SEARCH}' finds {least['found']:,}, the compare lists {least['compared']:,}; full garbage "
              f"collections during the steps: {least['full_collections']} taking {least['full_collections_s'] * 1000:.0f} ms")


if __name__ == "__main__":
    main()
