"""A2L files: a fast reader that keeps the original text, merge, update from ELF, EPK, check, diff.

``load(path)`` gives an :class:`A2lDocument` (the file's bytes plus token and block
indexes); ``read_xcp_config(doc)`` the XCP settings of its IF_DATA XCP; ``merge``,
``update``, ``check`` and ``diff`` (and their ``*_file`` forms) are the tool chain, each
returning its findings as data (:class:`Report`, :class:`Finding`).
"""

from workbench.a2l.check import check, check_file
from workbench.a2l.diff import DiffEntry, FieldChange, diff, diff_files
from workbench.a2l.document import A2lDocument, Block, MemorySegment, load, loads
from workbench.a2l.epk import ElfEpk, read_elf_epk
from workbench.a2l.ifdata import IfDataNode, Word, read_if_data
from workbench.a2l.merge import MergeFailed, MergeResult, merge, merge_files
from workbench.a2l.reports import ConflictPolicy, Finding, IncludeMode, Report, Severity, UpdateMode
from workbench.a2l.update import UpdateFailed, UpdateReport, UpdateResult, update, update_file
from workbench.a2l.xcp import XcpConfig, read_xcp_config

__all__ = [
    "A2lDocument", "Block", "ConflictPolicy", "DiffEntry", "ElfEpk", "FieldChange", "Finding", "IfDataNode",
    "IncludeMode",
    "MemorySegment", "MergeFailed", "MergeResult", "Report", "Severity", "UpdateFailed", "UpdateMode",
    "UpdateReport", "UpdateResult", "Word", "XcpConfig", "check", "check_file", "diff", "diff_files", "load",
    "loads", "merge", "merge_files", "read_elf_epk", "read_if_data", "read_xcp_config", "update", "update_file",
]
