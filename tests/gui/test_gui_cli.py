"""``workbench demo`` and ``workbench gui`` end to end, in processes of their own (offscreen)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

from workbench.cli import main

RUN = [sys.executable, "-c", "import sys; from workbench.cli import main; sys.exit(main(sys.argv[1:]))"]


def run(*args: str, cwd) -> subprocess.CompletedProcess:
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    return subprocess.run([*RUN, *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=120)


def png_size(path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def test_demo_renders_the_window_with_live_samples_to_a_png(tmp_path):
    result = run("demo", "--screenshot", "demo.png", "--settle", "0.5", "--size", "1366x768", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stderr == ""  # not Qt's "This plugin does not support propagateSizeHints()" for every window
    assert "first live sample on screen" in result.stdout and "screenshot: demo.png" in result.stdout
    width, height = png_size(tmp_path / "demo.png")  # a laptop's screen, all of it and not more
    assert 1300 <= width <= 1366 and 700 <= height <= 768


def test_gui_on_a_project_file_connects_to_an_ecu_of_another_process(tmp_path, free_udp_port):
    from workbench.gui.project import Connection, demo_project, save_project
    from workbench.sim import serve_demo

    project = demo_project()
    project.connection = Connection("udp_multicast", "239.74.163.9", None, {"port": free_udp_port})
    save_project(project, tmp_path / "bench.toml")
    with serve_demo({"interface": "udp_multicast", "channel": "239.74.163.9", "port": free_udp_port},
                    pcm_target_bar=25.0):
        result = run("gui", "bench.toml", "--screenshot", "gui.png", "--settle", "0.2", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert png_size(tmp_path / "gui.png")[0] >= 1200


def test_a_project_that_cannot_be_read_is_one_line_and_exit_code_2(tmp_path, capsys):
    (tmp_path / "bad.toml").write_text("a2l = [")
    assert main(["gui", str(tmp_path / "bad.toml")]) == 2
    error = capsys.readouterr().err
    assert error.startswith("error: ") and "bad.toml: not a project file" in error and error.count("\n") == 1


def test_an_a2l_given_as_the_project_opens_as_a2l(tmp_path, capsys, monkeypatch):
    """`workbench gui FLCU.a2l`, as CANape opens a database: it said 'not a project file: Expecting value'."""
    import workbench.gui.app
    from workbench import demo

    opened = []
    monkeypatch.setattr(workbench.gui.app, "run_window", lambda project, **kwargs: opened.append(project) or 0)
    assert main(["gui", str(demo.a2l())]) == 0
    assert opened[0].a2l == demo.a2l().resolve()
    assert main(["gui", str(demo.a2l()), "--a2l", "other.a2l"]) == 2
    assert "an A2L, and --a2l names another; give one" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["demo", "gui"])
def test_without_the_gui_extra_the_commands_say_what_to_install(command, tmp_path):
    # a process of its own: once loaded, PySide6's import hook cannot be told the package is gone
    hide = "import sys; sys.modules['PySide6'] = None; from workbench.cli import main; sys.exit(main(sys.argv[1:]))"
    result = subprocess.run([sys.executable, "-c", hide, command], cwd=tmp_path, capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == 1
    assert result.stderr == "error: the GUI needs PySide6: install workbench[gui] (pip install 'workbench[gui]')\n"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="X11 and Wayland displays are Linux's")
@pytest.mark.parametrize("display", [None, ":97"])  # none set; one set where no X server answers
def test_without_a_display_the_window_is_one_line_not_a_qt_abort(display, tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("QT_QPA_PLATFORM", "DISPLAY", "WAYLAND_DISPLAY")}
    if display:
        env["DISPLAY"] = display
        assert not os.path.exists("/tmp/.X11-unix/X97") or pytest.skip("an X server may listen on :97")
    result = subprocess.run([*RUN, "demo"], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=60)
    assert result.returncode == 1 and result.stderr.startswith("error: ") and result.stderr.count("\n") == 1
    assert ("no display" in result.stderr) if display is None else (":97" in result.stderr)
    result = subprocess.run([*RUN, "demo", "--screenshot", "demo.png", "--settle", "0"], cwd=tmp_path, env=env,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr  # a screenshot needs no screen: rendered offscreen
    assert png_size(tmp_path / "demo.png")[0] >= 1200


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="X11 and Wayland displays are Linux's")
def test_a_display_whose_qt_platform_cannot_load_is_one_line_not_a_qt_abort(monkeypatch, tmp_path):
    """A desktop without one of the xcb libraries Qt's X11 plugin links (libxcb-icccm4 ...): Qt would abort."""
    from workbench.gui import display

    broken = tmp_path / "libqxcb.so"
    broken.write_bytes(b"not a shared library")
    monkeypatch.delenv("QT_QPA_PLATFORM", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setenv("DISPLAY", ":0")
    monkeypatch.setattr(display, "_x_server_answers", lambda name: True)
    monkeypatch.setattr(display.ctypes.util, "find_library", lambda name: f"lib{name}.so.0")
    monkeypatch.setattr(display, "_x11_plugin", lambda: broken)
    problem = display.display_problem()
    assert problem.startswith("Qt's X11 platform cannot load: ") and "libxcb-icccm4" in problem
    monkeypatch.setattr(display, "_x11_plugin", lambda: None)
    assert display.display_problem() is None  # no PySide6 to check: require_gui names the package


def test_a_screenshot_of_a_window_that_gets_no_live_sample_is_taken_at_its_deadline(tmp_path, free_udp_port):
    """An ECU in its boot loader measures nothing: the screenshot waited for a live sample for ever."""
    from workbench.sim import serve_demo

    bus = ["--interface", "udp_multicast", "--channel", "239.74.163.9", "--bus-kwargs", f"port={free_udp_port}"]
    with serve_demo({"interface": "udp_multicast", "channel": "239.74.163.9", "port": free_udp_port},
                    valid_key=False):
        result = run("gui", *bus, "--screenshot", "boot.png", "--live-timeout", "3", cwd=tmp_path)
    assert result.returncode == 1 and "error: no live sample within 3 s" in result.stderr
    assert png_size(tmp_path / "boot.png")[0] >= 1200


def test_what_lives_as_long_as_the_process_is_left_out_of_the_cycle_collector_and_no_project_is(tmp_path):
    """The window's application freezes what the imports made (gc.freeze: ~80,000 objects a full collection on the GUI
    thread no longer visits, ~100 ms of CPU each); the project it reads afterwards stays the collector's."""
    script = textwrap.dedent("""
        import gc
        from PySide6.QtCore import QEventLoop, QThreadPool, QTimer
        from workbench.gui.app import application
        from workbench.gui.project import demo_project
        from workbench.gui.widgets.main_window import MainWindow
        application()
        window = MainWindow(demo_project())
        loop = QEventLoop()
        window.loaded.connect(loop.quit)
        window.load()
        QTimer.singleShot(60000, loop.quit)
        loop.exec()
        print(gc.get_freeze_count(), id(window.workspace.model) in {id(o) for o in gc.get_objects()})
        QThreadPool.globalInstance().waitForDone(10000)  # the editors' reads: none ends after the window
    """)
    result = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, capture_output=True, text=True, timeout=120,
                            env={**os.environ, "QT_QPA_PLATFORM": "offscreen"})
    frozen, model_collectable = result.stdout.split()
    assert int(frozen) > 10_000 and model_collectable == "True", result.stderr
