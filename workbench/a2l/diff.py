"""``diff``: what changed between two A2L files, object by object and field by field.

Objects are matched by (namespace, name); MOD_PAR, MOD_COMMON, the module's IF_DATA
and the A2ML are compared as single objects. A field is a positional parameter
(named after the ASAP2 spec for the common blocks), an option keyword, or a child
block; numbers compare by value, so ``0x10`` and ``16`` are equal.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from workbench.a2l.document import A2lDocument, Block, load_a2l
from workbench.a2l.grammar import NAMESPACES
from workbench.a2l.values import is_number, parse_number

__all__ = ["DiffEntry", "FieldChange", "diff_documents", "diff_files"]

PARAM_NAMES = {
    "MEASUREMENT": "name long_identifier datatype conversion resolution accuracy lower_limit upper_limit",
    "CHARACTERISTIC": "name long_identifier type address deposit max_diff conversion lower_limit upper_limit",
    "AXIS_PTS": "name long_identifier address input_quantity deposit max_diff conversion max_axis_points "
                "lower_limit upper_limit",
    "AXIS_DESCR": "attribute input_quantity conversion max_axis_points lower_limit upper_limit",
    "BLOB": "name long_identifier address size",
    "INSTANCE": "name long_identifier typedef address",
    "COMPU_METHOD": "name long_identifier conversion_type format unit",
    "UNIT": "name long_identifier display type",
    "MEMORY_SEGMENT": "name long_identifier prg_type memory_type attribute address size",
    "MOD_PAR": "comment", "MOD_COMMON": "comment",
}
_SINGLE_BLOCKS = ("MOD_PAR", "MOD_COMMON", "A2ML")


@dataclass(frozen=True)
class FieldChange:
    field: str  # e.g. "ECU_ADDRESS", "upper_limit", "AXIS_DESCR[0].max_axis_points"
    old: str | None  # None: the field is new
    new: str | None  # None: the field was removed


@dataclass(frozen=True)
class DiffEntry:
    status: str  # added, removed, changed
    keyword: str
    name: str
    changes: tuple[FieldChange, ...] = ()
    old_location: str = ""  # file:line:column in A
    new_location: str = ""  # file:line:column in B

    def to_dict(self) -> dict:
        return {"status": self.status, "keyword": self.keyword, "name": self.name,
                "old_location": self.old_location, "new_location": self.new_location,
                "changes": [{"field": c.field, "old": c.old, "new": c.new} for c in self.changes]}


def diff_files(a: str | Path, b: str | Path) -> list[DiffEntry]:
    return diff_documents(load_a2l(a), load_a2l(b))


def diff_documents(a: A2lDocument, b: A2lDocument) -> list[DiffEntry]:
    """Object-level differences from ``a`` to ``b``, in the order of ``b`` (removals last).

    An object whose text is the same in both is skipped unread; of the others, only the fields whose tokens
    differ are compared by value (an update's diff of 65,000 objects: one changed address each).
    """
    old, new = _objects(a), _objects(b)
    found: list[tuple[str, Block | None, Block | None, str, list[FieldChange]]] = []
    for key, block in new.items():
        before = old.get(key)
        if before is None:
            found.append(("added", None, block, key[1], []))
        elif before.doc.data[slice(*before.span)] != block.doc.data[slice(*block.span)]:
            changes = _changes(before, block)
            if changes:
                found.append(("changed", before, block, key[1], changes))
    found += [("removed", block, None, key[1], []) for key, block in old.items() if key not in new]
    old_where = _locations(a, [before for _, before, _, _, _ in found if before is not None])
    new_where = _locations(b, [after for _, _, after, _, _ in found if after is not None])
    return [DiffEntry(status, (after or before).keyword, name, tuple(changes),
                      old_where[before.index] if before is not None else "",
                      new_where[after.index] if after is not None else "")
            for status, before, after, name, changes in found]


def _objects(doc: A2lDocument) -> dict[tuple[str, str], Block]:
    found: dict[tuple[str, str], Block] = {}
    for module in doc.modules:
        for block in module.children:
            if block.keyword in NAMESPACES and block.name:
                found.setdefault((NAMESPACES[block.keyword], block.name), block)
            elif block.keyword in _SINGLE_BLOCKS:
                found.setdefault((block.keyword, block.keyword), block)
            elif block.keyword == "IF_DATA":
                found.setdefault(("IF_DATA", f"IF_DATA {block.name}"), block)
    return found


def _block_fields(block: Block, prefix: str = "") -> dict[str, list[int]]:
    """Field name -> its tokens."""
    if block.keyword in ("IF_DATA", "A2ML"):  # free-form: compared as one token sequence
        return {prefix + "content": list(range(block.keyword_token + 1, block.end_token))}
    args, options = block.layout()
    names = PARAM_NAMES.get(block.keyword, "").split()
    fields = {}
    for index, token in enumerate(args):
        fields[prefix + (names[index] if index < len(names) else f"param{index + 1}")] = [token]
    seen: dict[str, int] = {}
    for keyword, params in options:
        count = seen[keyword] = seen.get(keyword, 0) + 1
        label = keyword if count == 1 else f"{keyword}[{count - 1}]"
        fields[prefix + label] = params
    seen.clear()
    for child in block.children:
        count = seen[child.keyword] = seen.get(child.keyword, 0) + 1
        label = child.keyword if child.keyword != "IF_DATA" else f"IF_DATA {child.name}"
        fields.update(_block_fields(child, f"{prefix}{label}[{count - 1}]."))
    return fields


def _changes(old: Block, new: Block) -> list[FieldChange]:
    a, b = old.doc, new.doc
    old_raw, new_raw = a.tokens.raw, b.tokens.raw
    old_fields, new_fields = _block_fields(old), _block_fields(new)
    changes = []
    for name, tokens in new_fields.items():
        raws = list(map(new_raw, tokens))
        if name not in old_fields:
            changes.append(FieldChange(name, None, _shown(b, raws)))
            continue
        before = list(map(old_raw, old_fields[name]))
        if before != raws and list(map(_comparable, before)) != list(map(_comparable, raws)):
            changes.append(FieldChange(name, _shown(a, before), _shown(b, raws)))
    changes += [FieldChange(name, _shown(a, list(map(old_raw, tokens))), None)
                for name, tokens in old_fields.items() if name not in new_fields]
    return changes


def _shown(doc: A2lDocument, raws: list[bytes]) -> str:
    return b" ".join(raws).decode(doc.encoding)


def _comparable(raw: bytes):
    """A number by value (NaN as a word: it equals no number, not even itself), anything else as written."""
    if raw[:1] == b'"' or not is_number(raw):
        return raw
    value = parse_number(raw)
    return value if value == value else b"NaN"


def _locations(doc: A2lDocument, blocks: list[Block]) -> dict[int, str]:
    """Block index -> ``file:line:column`` of its ``/begin``, found for all at once."""
    offsets = [doc.tokens.span(block.begin_token)[0] for block in blocks]
    return {block.index: f"{file}:{line}:{column}"
            for block, (file, line, column) in zip(blocks, doc.source_map.positions(offsets))}
