"""``update --types``: the RECORD_LAYOUTs of a document, who uses each, and how to correct an element type.

A CHARACTERISTIC's or AXIS_PTS's element type is not written in the object: it is the
data type of FNC_VALUES (AXIS_PTS_X for an axis) in its RECORD_LAYOUT, which other
objects may share. When the C type says another element type, the correction stays
local to the object:

1. another RECORD_LAYOUT exists that is the same but for that data type: the object
   is switched to it (only the object's own deposit token changes);
2. else, when no other object uses the layout: the layout's data type is corrected;
3. else (the layout is shared): nothing is changed, the mismatch is reported with the
   users of the layout, as editing it would change every one of them.
"""

from __future__ import annotations

from collections import Counter
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument

# the objects that name a RECORD_LAYOUT, and the parameter that does (after the name)
_DEPOSITS = {"CHARACTERISTIC": 4, "AXIS_PTS": 4, "TYPEDEF_CHARACTERISTIC": 3, "TYPEDEF_AXIS": 3}
# the items that place values of an element type (and the data type after their position)
VALUE_ITEMS = ("FNC_VALUES", "AXIS_PTS_X")
# items whose presence means the layout holds more than the values (axes, counts ... in one record)
_OTHER_CONTENT = ("AXIS_PTS_Y", "AXIS_PTS_Z", "AXIS_PTS_4", "AXIS_PTS_5", "NO_AXIS_PTS_X", "NO_AXIS_PTS_Y",
                  "NO_AXIS_PTS_Z", "AXIS_RESCALE_X", "NO_RESCALE_X", "SRC_ADDR_X", "SRC_ADDR_Y", "RIP_ADDR_W",
                  "RIP_ADDR_X", "RIP_ADDR_Y", "SHIFT_OP_X", "OFFSET_X", "DIST_OP_X", "IDENTIFICATION", "RESERVED")


class Layout(NamedTuple):
    name: str
    datatypes: dict[str, int]  # value item -> the token of its data type
    index_modes: dict[str, str]  # value item -> its index mode (ROW_DIR, COLUMN_DIR, INDEX_INCR ...)
    shape: tuple  # the layout's items as text, with the value items' data types left out
    values_only: bool  # only FNC_VALUES, or only AXIS_PTS_X: the object's C variable is the values array


class RecordLayouts:
    """The RECORD_LAYOUTs of ``doc`` by name, with how many objects refer to each."""

    def __init__(self, doc: "A2lDocument"):
        self.doc = doc
        self.layouts: dict[str, Layout] = {}
        for block in doc.blocks_named("RECORD_LAYOUT"):
            if block.name is not None and block.name not in self.layouts:
                self.layouts[block.name] = self._read(block)
        self.users: Counter[str] = Counter()
        for keyword, index in _DEPOSITS.items():
            for block in doc.blocks_named(keyword):
                args = block.args
                if len(args) > index:
                    self.users[doc.text(args[index])] += 1
        self._by_shape: dict[tuple, list[str]] = {}
        for name, layout in self.layouts.items():
            self._by_shape.setdefault(layout.shape, []).append(name)

    def _read(self, block) -> Layout:
        doc = self.doc
        datatypes, modes, shape, others = {}, {}, [], False
        for keyword, params in block.layout()[1]:
            texts = [doc.text(token) for token in params]
            if keyword in VALUE_ITEMS and len(params) > 1:
                datatypes[keyword] = params[1]
                modes[keyword] = texts[2] if len(texts) > 2 else ""
                texts[1] = "*"
            others |= keyword in _OTHER_CONTENT
            shape.append((keyword, *texts))
        return Layout(block.name, datatypes, modes, tuple(shape), len(datatypes) == 1 and not others)

    def datatype(self, layout: str, item: str) -> str | None:
        found = self.layouts.get(layout)
        token = found.datatypes.get(item) if found else None
        return self.doc.text(token) if token is not None else None

    def alternative(self, layout: str, item: str, datatype: str) -> str | None:
        """A RECORD_LAYOUT like ``layout`` whose ``item`` holds ``datatype`` instead (the first in the file)."""
        found = self.layouts.get(layout)
        if found is None:
            return None
        for name in self._by_shape.get(found.shape, []):
            if name != layout and self.datatype(name, item) == datatype:
                return name
        return None
