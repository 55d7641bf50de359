"""``insert --create``: a new A2L from an ELF alone (a2ltool's ``--create``), the objects inserted into it.

The new file is ASAP2 1.71: a PROJECT and a MODULE named after the ELF (or the name given), MOD_COMMON
with the ELF's byte order (a2ltool writes none, and ASAP2's default MSB_FIRST is wrong for a little-endian
ECU), and MOD_PAR with the EPK string and ADDR_EPK when the ELF has an EPK (:func:`read_elf_epk`). The
objects are inserted as :func:`~workbench.a2l.insert.insert_document` inserts them into a file.
"""

from __future__ import annotations

import re
from pathlib import Path

from workbench.a2l.document import A2lDocument, load_a2l_string
from workbench.a2l.edits import write_source
from workbench.a2l.epk import read_elf_epk
from workbench.a2l.insert import InsertReport, Selection, insert_document
from workbench.a2l.values import is_ident, quote_string
from workbench.elf.debugdata import DebugData
from workbench.errors import InputError
from workbench.progress import Progress

__all__ = ["create_file", "new_document"]


def new_document(debug: DebugData, module: str | None = None, path: str | Path | None = None) -> A2lDocument:
    """A new A2L for ``debug``'s program (see the module docstring); ``module`` names its PROJECT and MODULE
    (default: the ELF's name as an A2L name), ``path`` where it will be written (errors name it).

    :raises InputError: ``module`` is not an A2L name.
    """
    name = module if module is not None else _ident(debug.path.stem)
    if not is_ident(name.encode("latin-1", "replace")):
        raise InputError(f"--module {name!r}: not an A2L name")
    little = debug.elf.little_endian
    about = quote_string(f"created from {debug.path.name}", "utf-8").decode("utf-8")
    lines = ["ASAP2_VERSION 1 71", f'/begin PROJECT {name} ""', f"  /begin MODULE {name} {about}",
             '    /begin MOD_COMMON ""',
             f"      BYTE_ORDER {'MSB_LAST' if little else 'MSB_FIRST'}  /* {debug.path.name} is "
             f"{'little' if little else 'big'}-endian */",
             "    /end MOD_COMMON"]
    epk = read_elf_epk(debug)
    if epk is not None:
        lines += ['    /begin MOD_PAR ""', f"      EPK {quote_string(epk.text, 'utf-8').decode('utf-8')}",
                  f"      ADDR_EPK 0x{epk.address:X}", "    /end MOD_PAR"]
    lines += ["  /end MODULE", "/end PROJECT", ""]
    return load_a2l_string("\n".join(lines), path)


def create_file(elf: str | Path, output: str | Path | None, *, measurements: Selection = Selection(),
                characteristics: Selection = Selection(), target_group: str | None = None,
                module: str | None = None, structures: bool = False, old_arrays: bool = False,
                cache_dir: str | Path | None = None, use_cache: bool = True,
                progress: Progress | None = None) -> InsertReport:
    """Make a new A2L for ``elf`` (:func:`new_document`), insert what the selections name and write ``output``
    atomically (None: a dry run, nothing written)."""
    with DebugData(elf, cache_dir=cache_dir, use_cache=use_cache, progress=progress) as debug:
        doc = new_document(debug, module, output)
        result = insert_document(doc, debug, measurements=measurements, characteristics=characteristics,
                                 target_group=target_group, structures=structures, old_arrays=old_arrays,
                                 progress=progress)
    if output is not None:
        write_source(doc.source, result.data, output)
    return result.report


def _ident(text: str) -> str:
    """``text`` as an A2L name: other characters become ``_``, a leading digit gets one in front."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", text) or "ECU"
    return f"_{name}" if name[0].isdigit() else name
