"""``workbench cal``: calibrations by name — in dataset files (DCM, CDFX) without an ECU.

The commands live in one module per concern, each with ``add_commands(commands)``:
:mod:`workbench.cli.cal_files` (convert, diff). The ECU commands register here the same way.
"""

from __future__ import annotations

import argparse

from workbench.cli import cal_files

_DESCRIPTION = """\
Calibrations by name, physical values.
Dataset files (DCM, CDFX; no ECU needed):
  convert  DCM <-> CDFX by the files' extensions, every value exact
  diff     compare two dataset files object by object (exit 1 when they differ, like diff)
Exit codes: 0 success (diff: equal), 1 the operation failed (diff: the files differ), 2 bad input
(a file that cannot be read or parsed, a place that cannot be written, a bad option)."""


def add_subparser(subparsers: argparse._SubParsersAction, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, description=_DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(title="commands", dest="command", metavar="COMMAND", required=True)
    cal_files.add_commands(commands)
