"""``update --types``: an object whose C element type is an enum gets the enum's values as its conversion.

As a2ltool writes it: an object without a conversion (NO_COMPU_METHOD) is given a
COMPU_METHOD named after the enum (its tag, else its typedef, else ``<object>_compu_method``);
when the MODULE has no COMPU_METHOD of that name, one is added (TAB_VERB, ``COMPU_TAB_REF``
to a COMPU_VTAB of the same name), and with it the COMPU_VTAB listing the enumerators
(unless a COMPU_VTAB or COMPU_VTAB_RANGE has the name already). Each is added once, after
the MODULE's last block of its kind.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.a2l.addressed import Target
from workbench.a2l.edits import Edit, indentation_of, newline_bytes, replace_token
from workbench.a2l.reports import finding_at
from workbench.a2l.values import quote_string
from workbench.findings import Finding

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument, Block
    from workbench.elf.ctypes_model import CType

__all__ = ["NO_COMPU_METHOD", "EnumConversions", "enum_conversion_blocks", "enum_conversion_name", "indented"]

NO_COMPU_METHOD = "NO_COMPU_METHOD"


class EnumConversions:
    """The COMPU_METHODs and COMPU_VTABs an update adds for enums, each once per MODULE and name."""

    def __init__(self, doc: "A2lDocument"):
        self.doc = doc
        self._added: set[tuple[int, str]] = set()  # (MODULE block, name)

    def convert(self, target: Target, conversion_token: int, enum: "CType") -> tuple[list[Edit], list[Finding]]:
        """Edits that make ``target`` (whose conversion is at ``conversion_token``) show ``enum``'s names."""
        doc = self.doc
        name = doc.text(conversion_token)
        edits, findings = [], []
        if name == NO_COMPU_METHOD:
            name = enum_conversion_name(enum, target.name)
            edits.append(replace_token(doc, conversion_token, name.encode(doc.encoding)))
            findings.append(finding_at(doc, conversion_token, "conversion-updated", target.name,
                                       f"{target.name}: conversion {NO_COMPU_METHOD} -> {name} (enum "
                                       f"{enum.display_name})", target.keyword))
        module = doc.block(target.block).parent
        if module is None or (module.index, name) in self._added or _named(module, "COMPU_METHOD", name):
            return edits, findings
        self._added.add((module.index, name))
        (_, method), *vtab = enum_conversion_blocks(module, name, enum)
        method_anchor = _after_last(module, ("COMPU_METHOD",))
        edits.append(self._block(method_anchor, method))
        added = f"COMPU_METHOD {name}"
        if vtab:
            anchor = _after_last(module, ("COMPU_VTAB", "COMPU_VTAB_RANGE")) or method_anchor
            edits.append(self._block(anchor, vtab[0][1]))
            added += f" and COMPU_VTAB {name}"
        findings.append(finding_at(doc, conversion_token, "conversion-added", target.name,
                                   f"{target.name}: {added} added ({len(enum.enumerators)} values of enum "
                                   f"{enum.display_name})", target.keyword))
        return edits, findings

    def _block(self, anchor: tuple[int, bytes], lines: list[bytes]) -> Edit:
        offset, indent = anchor
        newline = newline_bytes(self.doc)
        return Edit(offset, offset, newline.join([b"", b"", *indented(lines, indent)]))  # a blank line before it


def enum_conversion_name(enum: "CType", object_name: str) -> str:
    """The COMPU_METHOD (and COMPU_VTAB) name of an enum, as a2ltool names it: its tag, else its typedef,
    else ``<object>_compu_method``."""
    return enum.name or enum.typedef or f"{object_name}_compu_method"


def enum_conversion_blocks(module: "Block", name: str, enum: "CType") -> list[tuple[str, list[bytes]]]:
    """The COMPU_METHOD ``name`` (TAB_VERB) and the COMPU_VTAB of ``enum``'s values it refers to, as
    (keyword, lines): the /begin line, the items, the /end line, not indented. A COMPU_VTAB (or
    COMPU_VTAB_RANGE) the MODULE has of that name is not made again."""
    encoding = module.doc.encoding
    title = quote_string(f"Conversion table for enum {name}", encoding)
    head = name.encode(encoding) + b" " + title
    blocks = [("COMPU_METHOD", [b"/begin COMPU_METHOD " + head, b'TAB_VERB "%.4" ""',
                                b"COMPU_TAB_REF " + name.encode(encoding), b"/end COMPU_METHOD"])]
    if not _named(module, "COMPU_VTAB", name) and not _named(module, "COMPU_VTAB_RANGE", name):
        pairs = [b"%d " % value + quote_string(text, encoding) for text, value in enum.enumerators]
        blocks.append(("COMPU_VTAB", [b"/begin COMPU_VTAB " + head, b"TAB_VERB %d" % len(pairs), *pairs,
                                      b"/end COMPU_VTAB"]))
    return blocks


def indented(lines: list[bytes], indent: bytes) -> list[bytes]:
    """A block's lines at ``indent``, its items two blanks further in."""
    return [indent + lines[0], *(indent + b"  " + line for line in lines[1:-1]), indent + lines[-1]]


def _named(module: "Block", keyword: str, name: str) -> bool:
    return any(block.name == name for block in module.children_named(keyword))


def _after_last(module: "Block", keywords: tuple[str, ...]) -> tuple[int, bytes] | None:
    """Where a block goes after the MODULE's last block of these kinds, and its indentation; without
    one, at the end of the MODULE (for COMPU_METHOD) - None for the others."""
    doc = module.doc
    found = [block for keyword in keywords for block in module.children_named(keyword)]
    if found:
        last = max(found, key=lambda block: block.index)
        return last.span[1], indentation_of(doc.data, last.span[0])
    if keywords != ("COMPU_METHOD",):
        return None
    return doc.tokens.span(module.end_token - 1)[1], indentation_of(doc.data, module.span[0]) + b"  "
