"""Writing a node's fix calibrations: ``<dbc stem>_fixcal.h/.c/.a2l`` in one folder."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from workbench.can.dbc_file import DbcFile
from workbench.can.fixcal import FixCalibration, fix_calibrations
from workbench.can.fixcal_a2l import a2l_fragment
from workbench.can.fixcal_c import c_header, c_source
from workbench.can.model import messages_of
from workbench.errors import WorkbenchError
from workbench.fileio import atomic_write_text


@dataclass(frozen=True)
class FixcalFiles:
    """The generated texts of one DBC and node, by file name."""

    calibrations: tuple[FixCalibration, ...]
    texts: dict[str, str]

    def write(self, directory: str | Path) -> list[Path]:
        """Write every file (atomically) into ``directory``; returns the paths.

        :raises WorkbenchError: a file cannot be written.
        """
        directory = Path(directory)
        written = []
        for name, text in self.texts.items():
            path = directory / name
            try:
                atomic_write_text(path, text)
            except OSError as exc:
                raise WorkbenchError(f"{path}: cannot write: {exc.strerror or exc}") from exc
            written.append(path)
        return written


def fixcal_files(dbc: DbcFile, node: str, *, c: bool = True, a2l: bool = True) -> FixcalFiles:
    """The C pair and/or A2L fragment of ``node``'s fix calibrations in ``dbc`` (file order).

    :raises InputError: ``node`` is not in the DBC, or two signals map to one calibration name.
    """
    calibrations = tuple(fix_calibrations(messages_of(dbc, None, node)))
    basename = re.sub(r"\W", "_", dbc.path.stem) + "_fixcal"
    if basename[0].isdigit():  # C and A2L identifiers cannot start with a digit
        basename = f"dbc_{basename}"
    title = f"Fix calibrations of the CAN signals of {dbc.path.name} for node {node}"
    texts = {}
    if c:
        texts[f"{basename}.h"] = c_header(calibrations, basename, title)
        texts[f"{basename}.c"] = c_source(calibrations, basename, title)
    if a2l:
        texts[f"{basename}.a2l"] = a2l_fragment(calibrations, basename, title)
    return FixcalFiles(calibrations, texts)
