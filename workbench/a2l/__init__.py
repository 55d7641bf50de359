"""A2L files: a fast reader that keeps the original text, merge, update from ELF, EPK, check, diff.

``load(path)`` gives an :class:`A2lDocument` (the file's bytes plus token and block
indexes); ``read_xcp_config(doc)`` the XCP settings of its IF_DATA XCP.
"""

from workbench.a2l.document import A2lDocument, Block, MemorySegment, load, loads
from workbench.a2l.ifdata import IfDataNode, Word, read_if_data
from workbench.a2l.xcp import XcpConfig, read_xcp_config

__all__ = [
    "A2lDocument", "Block", "IfDataNode", "MemorySegment", "Word", "XcpConfig",
    "load", "loads", "read_if_data", "read_xcp_config",
]
