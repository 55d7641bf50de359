"""A2L files: a fast reader that keeps the original text, merge, update from ELF, EPK, check, diff.

``load_a2l(path)`` gives an :class:`A2lDocument` (the file's bytes plus token and block
indexes); ``doc.model()`` its typed, read-only objects (:class:`A2lModel`: ``characteristic(name)``,
``measurement(name)`` ..., the frozen classes of :mod:`workbench.a2l.objects`) and
``model.conversion(obj)`` their COMPU_METHODs both ways; ``read_xcp_config(doc)`` the XCP settings of its IF_DATA XCP; ``merge_documents``,
``update_document``, ``insert_document`` (new objects from the ELF's variables), ``check_document`` and
``diff_documents``, ``remove_document``
and ``cleanup_document`` (objects and what nothing uses taken out) (and their ``*_file(s)`` forms, which read and
write paths), ``flatten_file`` (every ``/include`` inline) and ``create_file`` (a new A2L from an ELF) are the tool
chain, each returning its findings as data
(:class:`~workbench.findings.Report` of :class:`~workbench.findings.Finding`, shared with the
other packages).

The names are imported on first use (as python-can does with its interfaces), so a
command that only updates does not pay for loading the checker, the differ or the
XCP reader.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.a2l.check": ("check_document", "check_file"),
    "workbench.a2l.compu": ("Conversion", "conversion_for"),
    "workbench.a2l.create": ("create_file", "new_document"),
    "workbench.a2l.diff": ("DiffEntry", "FieldChange", "diff_documents", "diff_files"),
    "workbench.a2l.document": ("A2lDocument", "Block", "EpkAddress", "MemorySegment", "load_a2l", "load_a2l_string"),
    "workbench.a2l.epk": ("ElfEpk", "read_elf_epk"),
    "workbench.a2l.formula": ("Formula", "compile_formula"),
    "workbench.a2l.ifdata": ("IfDataNode", "Word", "read_if_data"),
    "workbench.a2l.includes": ("flatten_file",),
    "workbench.a2l.insert": ("InsertReport", "InsertResult", "Selection", "insert_document", "insert_file"),
    "workbench.a2l.merge": ("MergeFailed", "MergeResult", "merge_documents", "merge_files"),
    "workbench.a2l.model": ("A2lModel", "ObjectSummary"),
    "workbench.a2l.objects": ("AxisDescr", "AxisPts", "Blob", "Characteristic", "CompuMethod", "CompuTab", "CompuVtab",
                              "CompuVtabRange", "Function", "Group", "LayoutEntry", "Location", "Measurement",
                              "ModCommon", "RecordLayout", "Unit"),
    "workbench.a2l.prune": ("PruneFailed", "PruneReport", "PruneResult", "cleanup_document", "cleanup_file",
                            "remove_document", "remove_file"),
    "workbench.a2l.reports": ("ConflictPolicy", "IncludeMode", "UpdateMode"),
    "workbench.a2l.update": ("UpdateFailed", "UpdateReport", "UpdateResult", "update_document", "update_file"),
    "workbench.a2l.xcp": ("XcpConfig", "read_xcp_config"),
}
__all__, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.a2l.check import check_document, check_file
    from workbench.a2l.compu import Conversion, conversion_for
    from workbench.a2l.create import create_file, new_document
    from workbench.a2l.diff import DiffEntry, FieldChange, diff_documents, diff_files
    from workbench.a2l.document import A2lDocument, Block, EpkAddress, MemorySegment, load_a2l, load_a2l_string
    from workbench.a2l.epk import ElfEpk, read_elf_epk
    from workbench.a2l.formula import Formula, compile_formula
    from workbench.a2l.ifdata import IfDataNode, Word, read_if_data
    from workbench.a2l.includes import flatten_file
    from workbench.a2l.insert import InsertReport, InsertResult, Selection, insert_document, insert_file
    from workbench.a2l.merge import MergeFailed, MergeResult, merge_documents, merge_files
    from workbench.a2l.model import A2lModel, ObjectSummary
    from workbench.a2l.objects import (
        AxisDescr, AxisPts, Blob, Characteristic, CompuMethod, CompuTab, CompuVtab, CompuVtabRange, Function, Group,
        LayoutEntry, Location, Measurement, ModCommon, RecordLayout, Unit,
    )
    from workbench.a2l.prune import (
        PruneFailed, PruneReport, PruneResult, cleanup_document, cleanup_file, remove_document, remove_file,
    )
    from workbench.a2l.reports import ConflictPolicy, IncludeMode, UpdateMode
    from workbench.a2l.update import UpdateFailed, UpdateReport, UpdateResult, update_document, update_file
    from workbench.a2l.xcp import XcpConfig, read_xcp_config
