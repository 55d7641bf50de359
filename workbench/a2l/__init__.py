"""A2L files: a fast reader that keeps the original text, merge, update from ELF, EPK, check, diff.

``load_a2l(path)`` gives an :class:`A2lDocument` (the file's bytes plus token and block
indexes); ``read_xcp_config(doc)`` the XCP settings of its IF_DATA XCP; ``merge``,
``update``, ``check`` and ``diff`` (and their ``*_file`` forms) are the tool chain, each
returning its findings as data (:class:`~workbench.findings.Report` of
:class:`~workbench.findings.Finding`, shared with the other packages).

The names are imported on first use (as python-can does with its interfaces), so a
command that only updates does not pay for loading the checker, the differ or the
XCP reader.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

_EXPORTS = {
    "workbench.a2l.check": ("check", "check_file"),
    "workbench.a2l.diff": ("DiffEntry", "FieldChange", "diff", "diff_files"),
    "workbench.a2l.document": ("A2lDocument", "Block", "MemorySegment", "load_a2l", "load_a2l_string"),
    "workbench.a2l.epk": ("ElfEpk", "read_elf_epk"),
    "workbench.a2l.ifdata": ("IfDataNode", "Word", "read_if_data"),
    "workbench.a2l.merge": ("MergeFailed", "MergeResult", "merge", "merge_files"),
    "workbench.a2l.reports": ("ConflictPolicy", "IncludeMode", "UpdateMode"),
    "workbench.a2l.update": ("UpdateFailed", "UpdateReport", "UpdateResult", "update", "update_file"),
    "workbench.a2l.xcp": ("XcpConfig", "read_xcp_config"),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = sorted(_MODULE_OF)


def __getattr__(name: str):
    module = _MODULE_OF.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.a2l.check import check, check_file
    from workbench.a2l.diff import DiffEntry, FieldChange, diff, diff_files
    from workbench.a2l.document import A2lDocument, Block, MemorySegment, load_a2l, load_a2l_string
    from workbench.a2l.epk import ElfEpk, read_elf_epk
    from workbench.a2l.ifdata import IfDataNode, Word, read_if_data
    from workbench.a2l.merge import MergeFailed, MergeResult, merge, merge_files
    from workbench.a2l.reports import ConflictPolicy, IncludeMode, UpdateMode
    from workbench.a2l.update import UpdateFailed, UpdateReport, UpdateResult, update, update_file
    from workbench.a2l.xcp import XcpConfig, read_xcp_config
