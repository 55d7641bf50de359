"""Writing a node's fix calibrations: ``<dbc stem>_fixcal.h/.c/.a2l`` in one folder."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from workbench.can.dbc_file import DbcFile
from workbench.can.fixcal import FixCalibration, fix_calibrations
from workbench.can.fixcal_a2l import a2l_fragment, mod_common_lines
from workbench.can.fixcal_c import c_header, c_source
from workbench.can.model import messages_of
from workbench.errors import InputError
from workbench.fileio import read_input, write_output

_PROJECT = re.compile(r"/begin\s+PROJECT\b")


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
                 master_a2l: str | Path | None = None, qualified: bool = False) -> FixcalFiles:
    """The C pair and/or A2L fragment of ``node``'s fix calibrations in ``dbc`` (file order).

    :param master_a2l: the project's master A2L, whose MOD_COMMON the fragment repeats.
    :param qualified: message-qualified names ``cf<MESSAGE>_<SIGNAL>_EN``/``_VALUE``.
    :raises InputError: ``node`` is not in the DBC or has no messages, two signals map to one
        calibration name, or the master A2L cannot be read or is no A2L.
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
        mod_common = mod_common_lines(_read_a2l(master_a2l)) if master_a2l is not None else ()
        texts[f"{basename}.a2l"] = a2l_fragment(calibrations, basename, title, mod_common)
    return FixcalFiles(calibrations, texts)


def _read_a2l(path: str | Path) -> str:
    text = read_input(path, "an A2L file").decode("utf-8", errors="replace")
    if not _PROJECT.search(text):
        raise InputError(f"{path}: not an A2L file (no /begin PROJECT)")
    return text
