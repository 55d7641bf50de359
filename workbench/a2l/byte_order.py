"""MOD_COMMON's BYTE_ORDER against the ELF's: a master reads every value of a big-endian ECU wrong through an
A2L that says little-endian, and the reverse. Read from the tokens (an update loads no object model)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.a2l.reports import finding_at
from workbench.findings import Finding, Severity

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument, Block

__all__ = ["BYTE_ORDERS", "byte_order_finding"]

# ASAP2's byte order words -> the two spellings the model uses (and the word-swapped variants of 1.7)
BYTE_ORDERS = {
    "MSB_FIRST": "MSB_FIRST", "BIG_ENDIAN": "MSB_FIRST", "MSB_LAST": "MSB_LAST", "LITTLE_ENDIAN": "MSB_LAST",
    "MSB_FIRST_MSW_LAST": "MSB_FIRST_MSW_LAST", "MSB_LAST_MSW_FIRST": "MSB_LAST_MSW_FIRST",
}


def byte_order_finding(doc: "A2lDocument", module: "Block", little_endian: bool, elf_name: str,
                       stated: Severity = Severity.ERROR) -> Finding | None:
    """A finding when the module's byte order (ASAP2's default MSB_FIRST when MOD_COMMON says none) is not the
    ELF's; ``stated``: its severity when BYTE_ORDER is written (a warning when it is the default)."""
    block = module.first("MOD_COMMON")
    option = block.option("BYTE_ORDER") if block is not None else None
    word = doc.raw(option[0]).decode("latin-1") if option else "MSB_FIRST"
    said = BYTE_ORDERS.get(word, word)
    if said.startswith("MSB_FIRST") == (not little_endian):
        return None
    wanted = "MSB_LAST (little-endian)" if little_endian else "MSB_FIRST (big-endian)"
    text = f"BYTE_ORDER {said}" if option else f"no BYTE_ORDER (ASAP2's default {said})"
    holder = block if block is not None else module
    return finding_at(doc, option[0] if option else holder.keyword_token, "byte-order-mismatch", "MOD_COMMON",
                      f"MODULE {module.name}: MOD_COMMON says {text}, {elf_name} is {wanted}: every value would be "
                      "read with its bytes swapped", holder.keyword, stated if option else Severity.WARNING)
