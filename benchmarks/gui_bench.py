"""The window's speed: redraw rate of a measurement window with 20 signals sampled at 1 kHz each, and
the time from ``workbench demo`` to the first live sample on screen.

    QT_QPA_PLATFORM=offscreen .venv/bin/python benchmarks/gui_bench.py [--seconds 10] [--starts 3]

Redraw: a feeder thread appends 1 kHz samples of 20 signals (4 units: 4 y-axes) in 10 ms batches,
as DAQ delivers them, into the window's ring buffers while the window redraws back to back: one
frame = copy the visible 10 s of every signal out of its buffer, hand it to pyqtgraph (peak
downsampling to the pixels), paint the 1600x900 window into an image. The signals are noisy sines
(the worst case for line drawing: every pixel column holds a vertical stroke). The reference is the window's own refresh
timer (25 Hz): the ratio says how much of the GUI thread a refresh takes. Start: ``workbench demo
--screenshot`` in a new process, timed from the process start to the line it prints when every
measurement window shows samples (the simulated ECU, its A2L/DBC, connect, DAQ setup included).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

SIGNALS = 20
RATE_HZ = 1000
UNITS = ("bar", "%", "V", "rpm")


def redraw_rate(seconds: float) -> dict:
    from PySide6.QtGui import QImage
    from PySide6.QtWidgets import QApplication

    from workbench.gui.app import application
    from workbench.gui.signal_hub import SignalHub, SignalInfo
    from workbench.gui.widgets.plot_window import REFRESH_HZ, PlotWindow

    app: QApplication = application()
    hub = SignalHub()
    names = [f"signal_{i:02d}" for i in range(SIGNALS)]
    hub.add_signals(SignalInfo(name, "XCP", UNITS[i % len(UNITS)], decimals=2) for i, name in enumerate(names))
    window = PlotWindow(hub, "20 signals at 1 kHz", span_s=10.0)
    window.timer.stop()  # the benchmark drives the refreshes
    window.resize(1600, 900)
    window.show()
    window.add_signals(names)
    stop = threading.Event()
    fed = {"samples": 0}

    def feed() -> None:  # 10 ms batches of 10 samples per signal, on the hub's clock, as DAQ delivers them
        rng = np.random.default_rng(1)
        start = hub.now() - 10.0
        history = np.arange(start, hub.now(), 1 / RATE_HZ)  # a full window to begin with
        for i, name in enumerate(names):
            hub.sink(name, history, np.sin(history * (i + 1) * 0.7) * 10 + rng.normal(0, 0.3, len(history)))
        last = history[-1]
        while not stop.is_set():
            now = hub.now()
            t = np.arange(last + 1 / RATE_HZ, now, 1 / RATE_HZ)
            if len(t):
                for i, name in enumerate(names):
                    hub.sink(name, t, np.sin(t * (i + 1) * 0.7) * 10 + rng.normal(0, 0.3, len(t)))
                fed["samples"] += len(t) * SIGNALS
                last = t[-1]
            stop.wait(0.01)

    feeder = threading.Thread(target=feed, daemon=True)
    feeder.start()
    time.sleep(0.2)
    # paint each frame into one image (what the window's backing store gets): repaint() alone does not
    # make the offscreen platform paint the plot's graphics scene
    image = QImage(window.size(), QImage.Format_ARGB32_Premultiplied)
    frames, began, cpu_began = 0, time.perf_counter(), time.thread_time()
    refresh_s = []
    while time.perf_counter() - began < seconds:
        t0 = time.perf_counter()
        window.refresh()
        window.render(image)
        app.sendPostedEvents()
        refresh_s.append(time.perf_counter() - t0)
        frames += 1
    elapsed = time.perf_counter() - began
    cpu = time.thread_time() - cpu_began  # the GUI thread's own CPU time: what other processes take is not in it
    stop.set()
    feeder.join()
    shown = window.samples_shown()
    window.close()
    fps = frames / elapsed
    return {"fps": fps, "cpu_fps": frames / cpu, "cpu_ms": cpu / frames * 1000, "frame_ms_median": float(np.median(refresh_s) * 1000),
            "frame_ms_p95": float(np.percentile(refresh_s, 95) * 1000), "samples_per_s_fed": fed["samples"] / elapsed,
            "points_in_view": shown, "timer_hz": REFRESH_HZ, "gui_thread_share": REFRESH_HZ / fps}


def demo_start(starts: int) -> list[tuple[float, float]]:
    """(process start -> first live sample on screen, the demo's own count from its start) per run."""
    results = []
    env = {**os.environ, "QT_QPA_PLATFORM": os.environ.get("QT_QPA_PLATFORM", "offscreen")}
    command = [sys.executable, "-c", "import sys; from workbench.cli import main; sys.exit(main(sys.argv[1:]))",
               "demo", "--screenshot", "start.png", "--settle", "0"]
    for _ in range(starts):
        with tempfile.TemporaryDirectory() as folder:
            began = time.perf_counter()
            process = subprocess.Popen(command, cwd=folder, env=env, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                       text=True)
            first = own = None
            for line in process.stdout:
                found = re.search(r"first live sample on screen ([\d.]+) s", line)
                if found and first is None:
                    first, own = time.perf_counter() - began, float(found.group(1))
            process.wait(60)
            if first is None:
                raise SystemExit("workbench demo showed no live sample")
            results.append((first, own))
    return results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=10.0, help="how long to redraw (default 10)")
    parser.add_argument("--starts", type=int, default=3, help="how many demo starts to time (default 3)")
    args = parser.parse_args()
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
    result = redraw_rate(args.seconds)
    print(f"redraw, {SIGNALS} signals x {RATE_HZ} Hz, 10 s in view, 1600x900 ({os.environ['QT_QPA_PLATFORM']}):")
    print(f"  {result['fps']:.1f} frames/s (median frame {result['frame_ms_median']:.1f} ms, "
          f"95th percentile {result['frame_ms_p95']:.1f} ms); goal 30 frames/s: {result['fps'] / 30:.2f}x")
    print(f"  GUI thread CPU {result['cpu_ms']:.1f} ms a frame = {result['cpu_fps']:.1f} frames/s of its own CPU time "
          f"({result['cpu_fps'] / 30:.2f}x the goal; on a busy machine the wall-clock rate above is lower)")
    print(f"  fed {result['samples_per_s_fed']:,.0f} samples/s; {result['points_in_view']:,} points in view")
    print(f"  at the window's {result['timer_hz']} Hz refresh the redraws take {result['gui_thread_share']:.0%} "
          f"of the GUI thread")
    starts = demo_start(args.starts)
    best = min(starts)
    print(f"workbench demo -> first live sample on screen: best {best[0]:.2f} s from the process start "
          f"({best[1]:.2f} s of them after the command's own start), runs: "
          + ", ".join(f"{first:.2f}" for first, _ in starts))


if __name__ == "__main__":
    main()
