"""Writing a node's fix calibrations: ``<dbc stem>_fixcal.h/.c/.a2l`` in one folder.

The A2L fragment can name each signal's live MEASUREMENT (``COMPARISON_QUANTITY`` of its ``_VALUE``):
a DBC does not know the ECU's variables, so they are given, in Python as a mapping and from the
command line as a CSV file of ``signal,measurement`` rows (:func:`read_signal_measurements`)::

    signal,measurement
    FuelLevelLow,xsLEDEn
    PCM_TO_FLCU_001.EnableFLCU,csPCM_TO_FLCU_001_EnableFLCU
"""

from __future__ import annotations

import csv
import io
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from workbench.a2l.document import load_a2l
from workbench.can.dbc_file import DbcFile
from workbench.can.fixcal import FixCalibration, FixKind, fix_calibrations
from workbench.can.fixcal_a2l import a2l_fragment, mod_common_lines
from workbench.can.fixcal_c import c_header, c_source
from workbench.can.model import messages_of
from workbench.errors import InputError
from workbench.fileio import read_input, write_output

__all__ = ["FixcalFiles", "fixcal_files", "read_signal_measurements"]

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_.\[\]]*")
_HEADER = ["signal", "measurement"]


@dataclass(frozen=True)
class FixcalFiles:
    """The generated texts of one DBC and node, by file name."""

    calibrations: tuple[FixCalibration, ...]
    texts: dict[str, str]

    def write(self, directory: str | Path) -> list[Path]:
        """Write every file (atomically) into ``directory``; returns the paths.

        :raises InputError: ``directory`` exists and is not a folder, or a file cannot be written there.
        :raises WorkbenchError: a write failed otherwise (:func:`~workbench.fileio.write_output`).
        """
        directory = Path(directory)
        if directory.exists() and not directory.is_dir():
            raise InputError(f"{directory}: not a folder (the output folder of the fix calibrations)")
        written = []
        for name, text in self.texts.items():
            path = directory / name
            write_output(path, text.encode("utf-8"))
            written.append(path)
        return written


def fixcal_files(dbc: DbcFile, node: str, *, c: bool = True, a2l: bool = True,
                 master_a2l: str | Path | None = None, qualified: bool = False,
                 measurements: Mapping[str, str] | None = None) -> FixcalFiles:
    """The C pair and/or A2L fragment of ``node``'s fix calibrations in ``dbc`` (file order).

    :param master_a2l: the project's master A2L, whose MOD_COMMON the fragment repeats.
    :param qualified: message-qualified names ``cf<MESSAGE>_<SIGNAL>_EN``/``_VALUE``.
    :param measurements: signal (``Signal`` or ``Message.Signal``) -> the MEASUREMENT that shows its live
        value (a sent signal's source, a received signal's published value): the ``_VALUE``'s
        COMPARISON_QUANTITY in the fragment.
    :raises InputError: ``node`` is not in the DBC or has no messages, two signals map to one
        calibration name, the master A2L cannot be read or is malformed (file:line:column), or ``measurements`` names a signal
        the node's messages do not have (or one that several have, by its bare name).
    """
    calibrations = tuple(fix_calibrations(messages_of(dbc, None, node), qualified=qualified))
    if not calibrations:
        raise InputError(f"{dbc.path}: node {node} neither sends nor receives a message: no fix calibrations")
    basename = re.sub(r"[^A-Za-z0-9_]", "_", dbc.path.stem) + "_fixcal"  # a C and ASAP2 identifier: ASCII
    if basename[0].isdigit():  # C and A2L identifiers cannot start with a digit
        basename = f"dbc_{basename}"
    title = f"Fix calibrations of the CAN signals of {dbc.path.name} for node {node}"
    texts = {}
    if c:
        texts[f"{basename}.h"] = c_header(calibrations, basename, title)
        texts[f"{basename}.c"] = c_source(calibrations, basename, title)
    if a2l:
        mod_common = mod_common_lines(load_a2l(master_a2l, validate=False)) if master_a2l is not None else ()
        comparison = _comparison_quantities(calibrations, measurements or {}, dbc.path)
        texts[f"{basename}.a2l"] = a2l_fragment(calibrations, basename, title, mod_common, comparison)
    return FixcalFiles(calibrations, texts)


def _comparison_quantities(calibrations: Sequence[FixCalibration], measurements: Mapping[str, str],
                           dbc: Path) -> dict[str, str]:
    """``_VALUE`` calibration name -> measurement, for the signals ``measurements`` names."""
    values = [c for c in calibrations if c.kind is FixKind.FIX_VALUE]
    found = {}
    for signal, measurement in measurements.items():
        matches = [c for c in values if signal in (f"{c.message.name}.{c.signal.name}", c.signal.name)]
        if len(matches) != 1:
            qualified = [f"{c.message.name}.{c.signal.name}" for c in matches]
            why = (f"a signal of {len(matches)} messages ({', '.join(qualified)}): name it as Message.Signal"
                   if matches else "not a signal of the node's messages")
            raise InputError(f"{dbc}: {signal} (given the measurement {measurement}): {why}")
        found[matches[0].name] = measurement
    return found


def read_signal_measurements(path: str | Path) -> dict[str, str]:
    """The ``signal,measurement`` rows of a CSV file (a first row ``signal,measurement``; blank lines and lines
    starting with ``#`` are skipped): signal (``Signal`` or ``Message.Signal``) -> MEASUREMENT name.

    :raises InputError: the file cannot be read, or a row (``path:line``) is not two names or repeats a signal.
    """
    text = read_input(path, "a CSV file").decode("utf-8-sig", errors="replace")
    rows = [(number, row) for number, row in enumerate(csv.reader(io.StringIO(text)), start=1)
            if row and "".join(row).strip() and not row[0].lstrip().startswith("#")]
    if not rows or [cell.strip().lower() for cell in rows[0][1]] != _HEADER:
        raise InputError(f"{path}:{rows[0][0] if rows else 1}: the first row must be 'signal,measurement'")
    found: dict[str, str] = {}
    for number, row in rows[1:]:
        cells = [cell.strip() for cell in row]
        if len(cells) != 2 or not all(_IDENTIFIER.fullmatch(cell) for cell in cells):
            raise InputError(f"{path}:{number}: expected 'signal,measurement' (two names), got {','.join(row)!r}")
        if cells[0] in found:
            raise InputError(f"{path}:{number}: {cells[0]} is given twice")
        found[cells[0]] = cells[1]
    return found


