"""The objects an update touches: one row per MEASUREMENT, CHARACTERISTIC, AXIS_PTS, BLOB, INSTANCE.

Collected with the document's vectorized keyword search (``option_tokens``), so a
file with 50,000 objects costs a few microseconds per object.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from workbench.a2l import grammar
from workbench.a2l.values import is_int, parse_int

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument


@dataclass(frozen=True)
class Target:
    keyword: str
    block: int  # block index in the document
    name: str
    name_token: int
    symbol: str  # what to look up in the ELF: the SYMBOL_LINK name, else the object name
    symbol_offset: int  # SYMBOL_LINK offset in bytes
    address_token: int | None  # None: a MEASUREMENT without ECU_ADDRESS
    anchor_token: int  # the last positional parameter (an ECU_ADDRESS is inserted after it)


def collect_targets(doc: "A2lDocument", keyword: str) -> list[Target]:
    """Every ``keyword`` object that is a direct child of a MODULE, in document order."""
    address_arg = grammar.ADDRESSED_OBJECTS[keyword]
    positional = len(grammar.BLOCKS[keyword].params)
    links = doc.option_tokens(keyword, "SYMBOL_LINK")
    addresses = doc.option_tokens(keyword, "ECU_ADDRESS") if address_arg is None else {}
    parents = doc.blocks.parent
    keywords = doc.blocks.keyword
    raw = doc.tokens.raw
    encoding = doc.encoding
    targets = []
    for block in doc.block_indices(keyword):
        parent = int(parents[block])
        if parent < 0 or keywords[parent] != "MODULE":
            continue
        name_token = doc.block_begin[block] + 2
        name = raw(name_token).decode(encoding)
        symbol, offset = name, 0
        link = links.get(block)
        if link is not None:
            symbol = doc.text(link + 1)
            offset_raw = raw(link + 2)
            offset = parse_int(offset_raw) if is_int(offset_raw) else 0
        if address_arg is None:
            option = addresses.get(block)
            address_token = option + 1 if option is not None else None
        else:
            address_token = name_token + address_arg
        targets.append(Target(keyword, block, name, name_token, symbol, offset, address_token,
                              name_token + positional - 1))
    return targets
