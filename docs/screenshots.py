"""Take the README's pictures of the window again: the demo, the compare view, an MF4 opened offline, the s19
edited offline.

    python docs/screenshots.py                              # docs/workbench-{demo,compare,offline,image}.png
    python docs/screenshots.py --size 1366x768 --out /tmp   # the window on a laptop's screen
    python docs/screenshots.py --scene offline              # one of them

Each picture is rendered offscreen in a process of its own (the screen's size is fixed before Qt starts),
with the simulated ECU in that process on a private virtual bus, as ``workbench demo --screenshot`` does:
demo     the window of ``workbench demo`` (live plots, numeric view, fix calibrations, an editor);
compare  three calibrations changed on the working page, then Calibration > Compare working <-> reference
         page, the map's differing elements below;
offline  nine seconds of rail pressure control recorded with the CAN2 bus (workbench.record), then
         File > Open measurement file with two cursors, no ECU connected;
image    no ECU: the project's s19 edited in the calibration editors (a scalar and a corner of a map), the
         window's title saying the image is modified (File > Save image writes it).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

SCENES = ("demo", "compare", "offline", "image")
DOCS = Path(__file__).resolve().parent
SETTLE_S = 3.0  # after the last change, before the picture: plots and legends catch up
CHANGES = (("xsSWITCH_TANK_THR", 27.5), ("xsPRV_KP", 6.0))  # the compare scene's edits (and a map's corner)
RECORDED = ("zsRailPressure", "xsDC", "csPCM_TO_FLCU_002_TargetRailPressure")
TARGETS = ((0.0, 35.0), (1.5, 20.0), (4.3, 30.0))  # (s after the recording's start, the PCM's target bar)
RECORD_S = 9.0
CURSORS_S = (2.3, 4.3)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", default="1600x1000", help="the screen, WIDTHxHEIGHT (default 1600x1000)")
    parser.add_argument("--out", type=Path, default=DOCS, help="folder of the pictures (default docs/)")
    parser.add_argument("--scene", choices=SCENES, action="append", help="only these (default all)")
    parser.add_argument("--suffix", default="", help="added to the file names, e.g. -1366")
    args = parser.parse_args(argv)
    width, height = (int(part) for part in args.size.lower().split("x"))
    args.out.mkdir(parents=True, exist_ok=True)
    failed = 0
    for scene in args.scene or SCENES:
        path = args.out / f"workbench-{scene}{args.suffix}.png"
        env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
        code = subprocess.call([sys.executable, __file__, "--one", scene, str(path), str(width), str(height)], env=env)
        print(f"{scene}: {path}" if code == 0 else f"{scene}: failed ({code})", flush=True)
        failed += code != 0
    return 1 if failed else 0


def one(scene: str, path: Path, size: tuple[int, int]) -> int:
    from workbench.gui.app import run_demo, screenshot_screen

    if scene == "demo":
        return run_demo(screenshot=path, settle_s=4.0, screen=size)
    screenshot_screen(size)
    return {"compare": compare_scene, "offline": offline_scene, "image": image_scene}[scene](path)


def shoot(window, path: Path, outcome: dict) -> None:
    from PySide6.QtWidgets import QApplication

    QApplication.processEvents()
    outcome["code"] = 0 if window.grab().save(str(path)) else 1
    window.close()


def compare_scene(path: Path) -> int:
    import numpy as np
    from PySide6.QtCore import QTimer

    from workbench.gui.app import application, demo_channel
    from workbench.gui.project import Connection, demo_project
    from workbench.gui.widgets.main_window import MainWindow
    from workbench.sim import serve_demo

    channel = demo_channel()
    project = demo_project()
    project.connection = Connection(interface="virtual", channel=channel)
    outcome = {"code": 1}
    with serve_demo({"interface": "virtual", "channel": channel}, pcm_target_bar=25.0):
        app = application()
        window = MainWindow(project)
        window.loaded.connect(window.connect_ecu)
        window.controller.failed.connect(lambda exc: (print(f"error: {exc}", file=sys.stderr), app.quit()))

        def live() -> None:
            window.live.disconnect(live)
            session = window.controller.session
            for name, value in CHANGES:
                session.write(name, value)
            table = np.array(session.read_value("xvPRV_DC_FF").value, dtype=np.float64)
            table[2:, 1:3] -= 6.0  # a corner of the map, tuned down
            session.write("xvPRV_DC_FF", table)
            for name in ("xsSWITCH_TANK_THR", "xvPRV_DC_FF"):
                window.controller.written.emit(name)
            window.parameter_sets.compared.connect(compared)
            window.parameter_sets.compare_pages()

        def compared(_diff) -> None:
            window.open_editor("xvPRV_DC_FF")
            rows = window.compare.rows_shown()
            if "xvPRV_DC_FF" in rows:
                window.compare.table.selectRow(rows.index("xvPRV_DC_FF"))
            QTimer.singleShot(int(SETTLE_S * 1000), lambda: shoot(window, path, outcome))

        window.live.connect(live)
        window.show()
        window.load()
        app.exec()
    return outcome["code"]


def offline_scene(path: Path) -> int:
    from PySide6.QtCore import QTimer

    from workbench import Session, demo
    from workbench.gui.app import application, demo_channel
    from workbench.gui.project import demo_project
    from workbench.gui.widgets.main_window import MainWindow
    from workbench.record import record
    from workbench.sim import serve_demo

    channel = demo_channel()
    recording = Path(tempfile.mkdtemp(prefix="workbench-shots-")) / "drive.mf4"
    with serve_demo({"interface": "virtual", "channel": channel}, pcm_target_bar=25.0) as simulator:
        with Session.open(interface="virtual", channel=channel) as ecu:
            started = time.monotonic()

            def steps() -> None:
                for at, target in TARGETS:
                    time.sleep(max(0.0, at - (time.monotonic() - started)))
                    simulator.pcm.target_bar = target

            threading.Thread(target=steps, daemon=True).start()
            record(ecu, recording, RECORDED, can2=demo.dbc_can2(), duration=RECORD_S)
    outcome = {"code": 1}
    app = application()
    window = MainWindow(demo_project())

    def opened(plot) -> None:
        for live in window.plots[:-1]:  # the project's live plots, empty without an ECU: closed
            live.close_requested.emit()
        plot.cursor.setPos(CURSORS_S[0])
        plot.cursor2_button.setChecked(True)
        plot.cursor2.setPos(CURSORS_S[1])
        QTimer.singleShot(int(SETTLE_S * 1000), lambda: shoot(window, path, outcome))

    window.measurement_opened.connect(opened)
    window.loaded.connect(lambda: window.open_measurement(recording))
    window.show()
    window.load()
    app.exec()
    return outcome["code"]


def image_scene(path: Path) -> int:
    import shutil

    import numpy as np
    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QMessageBox

    from workbench import demo
    from workbench.gui.app import application
    from workbench.gui.project import demo_project
    from workbench.gui.widgets.main_window import MainWindow

    project = demo_project()
    project.s19 = Path(tempfile.mkdtemp(prefix="workbench-shots-")) / "FLCU.s19"  # a copy: it may be saved
    shutil.copy(demo.s19(), project.s19)
    outcome = {"code": 1}
    app = application()
    window = MainWindow(project)

    def loaded() -> None:
        for live in list(window.plots):  # the project's live plots, empty without an ECU: closed
            live.close_requested.emit()
        editors = [window.open_editor(CHANGES[0][0]), window.open_editor("xvPRV_DC_FF")]
        edit_when_read(*editors)

    def edit_when_read(scalar, table) -> None:  # the editors read the image in a worker
        if scalar.value is None or table.value is None:
            QTimer.singleShot(100, lambda: edit_when_read(scalar, table))
            return
        scalar.edit(CHANGES[0][1])
        cells = np.array(table.value.value, dtype=np.float64)
        cells[2:, 1:3] -= 6.0  # a corner of the map, tuned down (as in the compare scene)
        table.edit(cells)
        QTimer.singleShot(int(SETTLE_S * 1000), lambda: shoot(window, path, outcome))

    # closing with the edits unsaved asks (modal) whether to save them: the picture taken, they are discarded
    QMessageBox.question = lambda *_args, **_kwargs: QMessageBox.Discard
    window.loaded.connect(loaded)
    window.show()
    window.load()
    app.exec()
    return outcome["code"]


if __name__ == "__main__":
    if sys.argv[1:2] == ["--one"]:
        scene, out, width, height = sys.argv[2:6]
        sys.exit(one(scene, Path(out), (int(width), int(height))))
    sys.exit(main())
