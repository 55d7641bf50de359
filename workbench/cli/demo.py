"""``workbench demo``: the simulated FLCU ECU and the workbench window connected to it, no hardware needed."""

from __future__ import annotations

import argparse

from workbench.cli.gui import add_screenshot_arguments, require_gui
from workbench.cli.options import positive_float

__all__ = ["add_subparser", "run"]

EPILOG = """\
The demo ECU (the thesis's Fuel Line Control Unit) runs inside this process on a virtual CAN bus of
its own, with a simulated PCM that enables the FLCU and asks for a rail pressure that changes every
6 s (25, 35, 20, 30 bar; --pcm-target holds one). The window
opens connected: rail pressure and its target, tank pressures, valve states and the PRV duty are
plotted live; the fix calibrations and an editor on xsSWITCH_TANK_THR are open.

examples:
  workbench demo
  workbench demo --screenshot demo.png
  workbench demo --screenshot small.png --size 1366x768    # the window on a laptop's screen
"""


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
                                   description="Start the simulated FLCU ECU and the workbench window connected to it. "
                                               "Needs the gui extra (pip install 'workbench[gui]').")
    parser.add_argument("--pcm-target", type=float, metavar="BAR",
                        help="hold the simulated PCM's TargetRailPressure at BAR (default: it steps 25, 35, 20, 30 bar, "
                             "one every 6 s)")
    parser.add_argument("--time-scale", type=positive_float, default=1.0, metavar="X",
                        help="simulated seconds per real second (default 1)")
    add_screenshot_arguments(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    require_gui(args.screenshot is not None)
    from workbench.gui.app import run_demo

    return run_demo(screenshot=args.screenshot, settle_s=args.settle, live_timeout_s=args.live_timeout,
                    time_scale=args.time_scale, pcm_target_bar=args.pcm_target, screen=args.size)
