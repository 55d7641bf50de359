"""``workbench gui [PROJECT]``: the calibration workbench window, on a project file or an ECU."""

from __future__ import annotations

import argparse
import ctypes.util
import importlib.util
import os
import re
import socket
import sys
from pathlib import Path

from workbench.cli.ecu_options import add_ecu_arguments
from workbench.cli.options import bus_settings
from workbench.errors import WorkbenchError

EPILOG = """\
examples:
  workbench gui project.toml                      # the project's A2L, DBCs, windows and connection
  workbench gui --a2l out/FLCU.a2l --interface socketcan --channel can0 --connect
  workbench gui --host 127.0.0.1 --protocol tcp --connect --screenshot window.png
"""


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
                                   description="Open the workbench window: variable browser, live plots, calibration "
                                               "editors, fix calibrations, flashing. Needs the gui extra "
                                               "(pip install 'workbench[gui]').")
    parser.add_argument("project", nargs="?", type=Path, help="a project file (.toml or .json)")
    parser.add_argument("--connect", action="store_true", help="connect to the ECU at once")
    add_screenshot_arguments(parser)
    add_ecu_arguments(parser, json_output=False)
    parser.set_defaults(func=run)


def add_screenshot_arguments(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("screenshot")
    group.add_argument("--screenshot", type=Path, metavar="PNG",
                       help="render the window to PNG once live samples are on screen, then exit (implies --connect)")
    group.add_argument("--settle", type=float, default=4.0, metavar="S",
                       help="seconds of live data before the screenshot (default 4)")
    group.add_argument("--size", type=screen_size, metavar="WxH",
                       help="render the screenshot offscreen on a screen of WxH pixels, e.g. 1366x768 (default: the "
                            "display's screen, or 1600x1000 without a display); the window fits it")


def screen_size(text: str) -> tuple[int, int]:
    """argparse type: ``WxH`` in pixels, e.g. ``1366x768``."""
    match = re.fullmatch(r"\s*(\d+)\s*[xX×]\s*(\d+)\s*", text)
    if match is None or min(int(match[1]), int(match[2])) < 200:
        raise argparse.ArgumentTypeError(f"a screen size is WxH pixels (at least 200x200), e.g. 1366x768, not {text!r}")
    return int(match[1]), int(match[2])


def require_gui(screenshot: bool = False) -> None:
    """Import the window's code (Qt and its plotting) now, and check that Qt can open a window, so that
    a missing piece is one line (Qt itself aborts the process). A screenshot needs no screen: without
    one it is rendered offscreen.

    :raises WorkbenchError: a package of the gui extra is not installed, Qt cannot load a system
        library, or there is no display to open the window on.
    """
    problem = display_problem()
    if problem and screenshot:
        os.environ["QT_QPA_PLATFORM"] = "offscreen"  # workbench.gui.app.screenshot_screen sizes its screen
    elif problem:
        raise WorkbenchError(problem)
    try:
        import workbench.gui.app  # noqa: F401
    except ImportError as exc:
        if exc.name:  # a Python package
            raise WorkbenchError(f"the GUI needs {exc.name.split('.')[0]}: install workbench[gui] "
                                 "(pip install 'workbench[gui]')") from None
        raise WorkbenchError(f"the GUI cannot load Qt: {exc}") from None


def display_problem() -> str | None:
    """Why Qt could not open a window here (Linux without a display, or without the library Qt's X11
    platform needs since Qt 6.5), or None; an explicit QT_QPA_PLATFORM is the user's choice."""
    if not sys.platform.startswith("linux") or os.environ.get("QT_QPA_PLATFORM") or os.environ.get("WAYLAND_DISPLAY"):
        return None
    if not os.environ.get("DISPLAY"):
        return ("no display to open the window on (neither DISPLAY nor WAYLAND_DISPLAY is set): run it in a desktop "
                "session or over ssh -X, or add --screenshot PNG to render the window to a file")
    display = os.environ["DISPLAY"]
    if not _x_server_answers(display):
        return f"no X server answers on the display {display}: start one, or fix DISPLAY"
    if ctypes.util.find_library("xcb-cursor") is None:
        return "Qt's X11 platform needs libxcb-cursor0: install it (Debian/Ubuntu: sudo apt install libxcb-cursor0)"
    return _x11_plugin_problem()


def _x11_plugin_problem() -> str | None:
    """Why Qt's X11 platform plugin cannot be loaded (a system library it links is missing: Qt would abort the
    process), or None. Loading it is the one sure test; it loads the Qt libraries PySide6 loads anyway."""
    plugin = _x11_plugin()
    if plugin is None or not plugin.exists():
        return None  # no PySide6: require_gui names the package
    try:
        ctypes.CDLL(str(plugin))
    except OSError as exc:
        return (f"Qt's X11 platform cannot load: {exc}; install Qt's X11 libraries (Debian/Ubuntu: sudo apt install "
                "libxcb-cursor0 libxcb-icccm4 libxcb-keysyms1 libxcb-image0 libxcb-render-util0 libxkbcommon-x11-0)")
    return None


def _x11_plugin() -> Path | None:
    """PySide6's X11 platform plugin, found without importing Qt."""
    spec = importlib.util.find_spec("PySide6")
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(next(iter(spec.submodule_search_locations))) / "Qt" / "plugins" / "platforms" / "libqxcb.so"


def _x_server_answers(display: str) -> bool:
    """A local display (``:N``) has a socket an X server listens on; a remote one is not checked."""
    local = re.fullmatch(r"(?:unix)?:(\d+)(?:\.\d+)?", display)
    if local is None:
        return True
    path = f"/tmp/.X11-unix/X{local.group(1)}"
    for address in ("\0" + path, path):  # Linux's abstract socket first, as Xlib tries it
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as probe:
            try:
                probe.connect(address)
                return True
            except OSError:
                continue
    return False


def run(args: argparse.Namespace) -> int:
    require_gui(args.screenshot is not None)
    from workbench.gui.app import run_window
    from workbench.gui.project import Connection, Project, load_project

    project = load_project(args.project) if args.project else Project()
    if args.a2l:
        project.a2l = Path(args.a2l).resolve()
    settings = {k: v for k, v in (bus_settings(args) or {}).items() if v is not None}
    if settings or args.host or args.port or args.protocol:
        interface, channel, bitrate = settings.pop("interface", None), settings.pop("channel", None), settings.pop(
            "bitrate", None)
        project.connection = Connection(interface, channel, bitrate, settings, args.host, args.port, args.protocol)
    return run_window(project, connect=args.connect or args.screenshot is not None, screenshot=args.screenshot,
                      settle_s=args.settle, screen=args.size)
