"""``update --remove-missing``: drop objects whose symbol the ELF lacks, and the references to them.

References in name lists (a GROUP's REF_MEASUREMENT, a FUNCTION's DEF_CHARACTERISTIC
...) are removed with the object so that the result stays consistent; other
references (an AXIS_DESCR's AXIS_PTS_REF) cannot be dropped alone and are reported.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.a2l import grammar
from workbench.a2l.edits import Edit, remove_block, remove_span
from workbench.a2l.reports import finding_at
from workbench.findings import Finding, Severity

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument

__all__ = ["removal_edits"]

_NAME_LISTS = frozenset(name for name, spec in grammar.BLOCKS.items() if spec.items == "ident")
_REFERENCING_OPTIONS = ("AXIS_PTS_REF", "CURVE_AXIS_REF", "COMPARISON_QUANTITY", "INPUT_QUANTITY")


def removal_edits(doc: "A2lDocument", removed: dict[str, int]) -> tuple[list[Edit], list[Finding]]:
    """Edits that delete the blocks in ``removed`` (name -> block index) and their name-list entries."""
    edits = [remove_block(doc, doc.block(block)) for block in removed.values()]
    findings: list[Finding] = []
    for list_keyword in _NAME_LISTS:
        for block in doc.blocks_named(list_keyword):
            for token in block.own_tokens:
                name = doc.raw(token).decode(doc.encoding)
                if name in removed:
                    edits.append(remove_span(doc, doc.tokens.starts_list[token], doc.tokens.ends_list[token]))
                    findings.append(finding_at(doc, token, "reference-removed", name,
                                               f"{name} removed from {list_keyword}", list_keyword))
    gone = set(removed.values())
    for keyword in ("CHARACTERISTIC", "AXIS_DESCR"):
        for block in doc.blocks_named(keyword):
            if block.index in gone or (block.parent is not None and block.parent.index in gone):
                continue
            for option in _REFERENCING_OPTIONS:
                params = block.option(option)
                if params and doc.text(params[0]) in removed:
                    findings.append(finding_at(doc, params[0], "dangling-reference", doc.text(params[0]),
                                               f"{option} still refers to the removed {doc.text(params[0])}",
                                               keyword, Severity.WARNING))
    return edits, findings
