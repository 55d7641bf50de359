"""``workbench gui [PROJECT]``: the calibration workbench window, on a project file or an ECU."""

from __future__ import annotations

import argparse
import os
import re
from pathlib import Path

from workbench.cli.ecu_options import add_ecu_arguments
from workbench.cli.options import bus_settings
from workbench.errors import InputError, WorkbenchError
from workbench.gui.display import display_problem

__all__ = ["add_screenshot_arguments", "add_subparser", "require_gui", "run", "screen_size"]

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
    parser.add_argument("project", nargs="?", type=Path, help="a project file (.toml or .json), or an A2L (as --a2l)")
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
    group.add_argument("--live-timeout", type=float, default=30.0, metavar="S",
                       help="no live sample within S seconds (an ECU in its boot loader, nothing measured): the "
                            "screenshot shows the window as it is, exit 1 (default 30)")
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


def run(args: argparse.Namespace) -> int:
    require_gui(args.screenshot is not None)
    from workbench.gui.app import run_window
    from workbench.gui.project import Connection, Project, load_project

    if args.project is not None and args.project.suffix.lower() == ".a2l":  # `gui FLCU.a2l`, as CANape opens one
        if args.a2l:
            raise InputError(f"{args.project}: an A2L, and --a2l names another; give one")
        args.project, args.a2l = None, str(args.project)
    project = load_project(args.project) if args.project else Project()
    if args.a2l:
        project.a2l = Path(args.a2l).resolve()
    settings = {k: v for k, v in (bus_settings(args) or {}).items() if v is not None}
    if settings or args.host or args.port or args.protocol:
        interface, channel, bitrate = settings.pop("interface", None), settings.pop("channel", None), settings.pop(
            "bitrate", None)
        project.connection = Connection(interface, channel, bitrate, settings, args.host, args.port, args.protocol)
    if args.daq_can_ids:
        project.connection.daq_can_ids = dict(args.daq_can_ids)
    return run_window(project, connect=args.connect or args.screenshot is not None, screenshot=args.screenshot,
                      settle_s=args.settle, live_timeout_s=args.live_timeout, screen=args.size)
