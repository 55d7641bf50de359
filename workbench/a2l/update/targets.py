"""The objects an update touches: one row per MEASUREMENT, CHARACTERISTIC, AXIS_PTS, BLOB, INSTANCE.

Collected with the document's vectorized keyword search (``option_tokens``), so a
file with 50,000 objects costs a few microseconds per object.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from workbench.a2l import grammar
from workbench.a2l.values import is_int, parse_int

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument


class Target(NamedTuple):
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
    limits = _parameter_limits(doc)
    parents = doc.blocks.parent.tolist()
    keywords = doc.blocks.keyword
    data, starts, ends = doc.data, doc.tokens.starts_list, doc.tokens.ends_list
    encoding = doc.encoding
    begins = doc.block_begin
    targets = []
    for block in doc.block_indices(keyword):
        parent = parents[block]
        if parent < 0 or keywords[parent] != "MODULE":
            continue
        name_token = begins[block] + 2
        name = data[starts[name_token] : ends[name_token]].decode(encoding)
        if name_token + positional > limits[block]:  # the address would be read from the wrong token
            raise doc.error(f"{keyword} {name}: missing parameter(s), {positional} expected", begins[block] + 1)
        symbol, offset = name, 0
        link = links.get(block)
        if link is not None:
            if link + 2 >= limits[block] or doc.raw(link + 1)[:1] != b'"' or not is_int(doc.raw(link + 2)):
                raise doc.error(f"{keyword} {name}: SYMBOL_LINK needs a string and an integer offset", link)
            symbol = doc.text(link + 1)
            offset = parse_int(doc.raw(link + 2))
        if address_arg is None:
            option = addresses.get(block)
            address_token = option + 1 if option is not None else None
        else:
            address_token = name_token + address_arg
        targets.append(Target(keyword, block, name, name_token, symbol, offset, address_token,
                              name_token + positional - 1))
    return targets


def _parameter_limits(doc: "A2lDocument") -> list[int]:
    """Per block: the first token that cannot be one of its parameters (its first child or its /end)."""
    limits = doc.blocks.end.copy()
    parents = doc.blocks.parent
    has_parent = parents >= 0
    # blocks are in document order, so the first block naming a parent is its first child
    owners, first = np.unique(parents[has_parent], return_index=True)
    children_begin = doc.blocks.begin[has_parent][first]
    limits[owners] = np.minimum(limits[owners], children_begin)
    return limits.tolist()
