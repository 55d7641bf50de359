"""``workbench cal``: calibrations by name — in the ECU, and in dataset files (DCM, CDFX) without one.

The commands live in one module per concern, each with ``add_commands(commands)``:
:mod:`workbench.cli.cal_ecu` (get, set, list, fix, page), :mod:`workbench.cli.cal_sync` (save, load,
sync, and diff's ECU and image sides) and :mod:`workbench.cli.cal_files` (convert, diff).
"""

from __future__ import annotations

import argparse

from workbench.cli import cal_ecu, cal_files, cal_sync

__all__ = ["add_subparser"]

_DESCRIPTION = """\
Calibrations by name, physical values.
In the ECU (the common ECU options: --a2l, the CAN bus or --host, --key-function ...):
  get      read calibrations (curves and maps with their axes) and measurements
  set      write one (NAME[x,y]: one value of a map): checked before connecting, then only what
           changes written and read back
  list     the calibrations matching a pattern, with their values
  fix      override a signal with its _EN/_VALUE fix calibration, release it, list them all
  page     show or switch the calibration page (working/reference), copy reference to working
           (says what it overwrites, asks in a terminal: --yes, --dry-run)
Between the ECU and files:
  save     the calibrations as a dataset (DCM, CDFX), or the working page as an s19/hex (--region CALIB)
  load     apply a dataset: every object checked first, then only what changes written (--dry-run)
  sync     cache sync: compare with an s19/hex or dataset by checksums, then --upload or --download
Offline, in an s19/hex instead of the ECU (no bus): get, set, list, fix, save DATASET and load take --image FILE;
  set, fix and load write -o NEW (only the records of changed bytes rewritten; naming the input changes it)
Dataset files (DCM, CDFX; no ECU needed):
  convert  DCM <-> CDFX by the files' extensions, every value exact
  diff     compare two datasets object by object: files, an s19/hex, or 'ecu' (exit 1 when they differ)
Exit codes: 0 success (diff, sync: equal), 1 the operation failed (the ECU refused or did not answer;
diff, sync: they differ), 2 bad input (unknown name, a value beyond the limits, a file that cannot be
read, a bad option); load --dry-run exits as the load would."""


def add_subparser(subparsers: argparse._SubParsersAction, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, description=_DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(title="commands", dest="command", metavar="COMMAND", required=True)
    cal_ecu.add_commands(commands)
    cal_sync.add_commands(commands)
    cal_files.add_commands(commands)
