"""``update --types``: the RECORD_LAYOUTs of a document, who uses each, and how to correct them.

A CHARACTERISTIC's or AXIS_PTS's element type is not written in the object: it is the
data type of FNC_VALUES (AXIS_PTS_X for an axis) in its RECORD_LAYOUT, which other
objects may share. When the C type says another element type (or, for a struct that
holds axes and values, other types and point counts), the correction stays local to
the object:

1. another RECORD_LAYOUT exists that is the same but for those data types and counts:
   the object is switched to it (only the object's own deposit token changes);
2. else, when no other object uses the layout: the layout itself is corrected;
3. else (the layout is shared): nothing is changed, the mismatch is reported with the
   users of the layout, as editing it would change every one of them.
"""

from __future__ import annotations

from collections import Counter
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument

__all__ = ["AXES", "Correction", "Layout", "RecordLayouts"]

# the objects that name a RECORD_LAYOUT, and the parameter that does (after the name)
_DEPOSITS = {"CHARACTERISTIC": 4, "AXIS_PTS": 4, "TYPEDEF_CHARACTERISTIC": 3, "TYPEDEF_AXIS": 3}
# the items that place values of an element type (and the data type after their position)
VALUE_ITEMS = ("FNC_VALUES", "AXIS_PTS_X")
AXES = ("X", "Y", "Z", "4", "5")
# the items with a position and a data type whose C counterpart is a struct member (a2ltool's reading)
TYPED_ITEMS = ("FNC_VALUES", *(f"AXIS_PTS_{axis}" for axis in AXES), *(f"NO_AXIS_PTS_{axis}" for axis in AXES))
# items whose presence means the layout holds more than the values (axes, counts ... in one record)
_OTHER_CONTENT = ("AXIS_PTS_Y", "AXIS_PTS_Z", "AXIS_PTS_4", "AXIS_PTS_5", "NO_AXIS_PTS_X", "NO_AXIS_PTS_Y",
                  "NO_AXIS_PTS_Z", "AXIS_RESCALE_X", "NO_RESCALE_X", "SRC_ADDR_X", "SRC_ADDR_Y", "RIP_ADDR_W",
                  "RIP_ADDR_X", "RIP_ADDR_Y", "SHIFT_OP_X", "OFFSET_X", "DIST_OP_X", "IDENTIFICATION", "RESERVED")


class Layout(NamedTuple):
    name: str
    datatypes: dict[str, int]  # value item -> the token of its data type
    index_modes: dict[str, str]  # value item -> its index mode (ROW_DIR, COLUMN_DIR, INDEX_INCR ...)
    values_only: bool  # only FNC_VALUES, or only AXIS_PTS_X: the object's C variable is the values array
    typed: dict[str, tuple[int, int]]  # typed item -> (its position, the token of its data type)
    fixed_counts: dict[str, int]  # axis -> the token of FIX_NO_AXIS_PTS_<axis>'s count
    items: tuple[tuple[str, tuple[int, ...]], ...]  # every item: (keyword, its parameter tokens)


class Correction(NamedTuple):
    """What makes a RECORD_LAYOUT state what the C variable holds (see the module docstring)."""

    changes: dict[int, str]  # token -> its new text, in the layout
    described: list[str]  # the changes as "FNC_VALUES UBYTE -> FLOAT32_IEEE"
    alternative: str | None  # an existing layout that states it already
    users: int  # the objects that refer to the layout


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
        self._by_content: dict[tuple, str] | None = None

    def _read(self, block) -> Layout:
        doc = self.doc
        datatypes, modes, others, typed, fixed, items = {}, {}, False, {}, {}, []
        for keyword, params in block.layout()[1]:
            texts = [doc.text(token) for token in params]
            items.append((keyword, tuple(params)))
            if keyword in TYPED_ITEMS and len(params) > 1 and texts[0].isdigit():
                typed[keyword] = (int(texts[0]), params[1])
            if keyword.startswith("FIX_NO_AXIS_PTS_") and params:
                fixed[keyword[len("FIX_NO_AXIS_PTS_"):]] = params[0]
            if keyword in VALUE_ITEMS and len(params) > 1:
                datatypes[keyword] = params[1]
                modes[keyword] = texts[2] if len(texts) > 2 else ""
            others |= keyword in _OTHER_CONTENT
        return Layout(block.name, datatypes, modes, len(datatypes) == 1 and not others, typed, fixed, tuple(items))

    def correction(self, layout: str, datatypes: dict[str, str], counts: dict[str, int]) -> Correction | None:
        """What makes ``layout`` state these data types of its typed items and these FIX_NO_AXIS_PTS counts
        (by axis); None when it states them already."""
        found = self.layouts[layout]
        text = self.doc.text
        wanted = [(item, found.typed[item][1], datatype) for item, datatype in datatypes.items() if item in found.typed]
        wanted += [(f"FIX_NO_AXIS_PTS_{axis}", found.fixed_counts[axis], str(count)) for axis, count in counts.items()
                   if axis in found.fixed_counts]
        changed = [(item, token, new) for item, token, new in wanted if text(token) != new]
        if not changed:
            return None
        changes = {token: new for _, token, new in changed}
        if self._by_content is None:  # the first layout of each content, in file order
            self._by_content = {}
            for name, other in self.layouts.items():
                self._by_content.setdefault(self._content(other, {}), name)
        alternative = self._by_content.get(self._content(found, changes))
        return Correction(changes, [f"{item} {text(token)} -> {new}" for item, token, new in changed], alternative,
                          self.users[layout])

    def _content(self, layout: Layout, changes: dict[int, str]) -> tuple:
        """A layout's items as text (``changes`` applied), without its name: equal content, equal layout."""
        text = self.doc.text
        return tuple((keyword, *(changes.get(token) or text(token) for token in params))
                     for keyword, params in layout.items)
