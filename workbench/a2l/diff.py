"""``diff``: what changed between two A2L files, object by object and field by field.

Objects are matched by (namespace, name); MOD_PAR, MOD_COMMON, the module's IF_DATA
and the A2ML are compared as single objects. A field is a positional parameter
(named after the ASAP2 spec for the common blocks), an option keyword, or a child
block; numbers compare by value, so ``0x10`` and ``16`` are equal.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from workbench.a2l.document import A2lDocument, Block, load_a2l
from workbench.a2l.grammar import NAMESPACES
from workbench.a2l.values import is_number, parse_number

__all__ = ["DiffEntry", "FieldChange", "diff", "diff_files"]

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


@dataclass
class _Object:
    block: Block
    fields: dict[str, tuple] = field(default_factory=dict)  # field -> (values to compare, text to show)


def diff_files(a: str | Path, b: str | Path) -> list[DiffEntry]:
    return diff_documents(load_a2l(a), load_a2l(b))


def diff_documents(a: A2lDocument, b: A2lDocument) -> list[DiffEntry]:
    """Object-level differences from ``a`` to ``b``, in the order of ``b`` (removals last)."""
    old, new = _objects(a), _objects(b)
    entries = []
    for key, item in new.items():
        before = old.get(key)
        if before is None:
            entries.append(DiffEntry("added", item.block.keyword, key[1], new_location=_where(item.block)))
            continue
        changes = _changes(_fields(before), _fields(item))
        if changes:
            entries.append(DiffEntry("changed", item.block.keyword, key[1], tuple(changes),
                                     _where(before.block), _where(item.block)))
    for key, item in old.items():
        if key not in new:
            entries.append(DiffEntry("removed", item.block.keyword, key[1], old_location=_where(item.block)))
    return entries


def _objects(doc: A2lDocument) -> dict[tuple[str, str], _Object]:
    found: dict[tuple[str, str], _Object] = {}
    for module in doc.modules:
        for block in module.children:
            if block.keyword in NAMESPACES and block.name:
                found.setdefault((NAMESPACES[block.keyword], block.name), _Object(block))
            elif block.keyword in _SINGLE_BLOCKS:
                found.setdefault((block.keyword, block.keyword), _Object(block))
            elif block.keyword == "IF_DATA":
                found.setdefault(("IF_DATA", f"IF_DATA {block.name}"), _Object(block))
    return found


def _fields(item: _Object) -> dict[str, tuple]:
    if not item.fields:
        item.fields = _block_fields(item.block, "")
    return item.fields


def _block_fields(block: Block, prefix: str) -> dict[str, tuple]:
    doc = block.doc
    if block.keyword in ("IF_DATA", "A2ML"):  # free-form: compared as one token sequence
        return {prefix + "content": _field(doc, range(block.keyword_token + 1, block.end_token))}
    args, options = block.layout()
    names = PARAM_NAMES.get(block.keyword, "").split()
    fields = {}
    for index, token in enumerate(args):
        fields[prefix + (names[index] if index < len(names) else f"param{index + 1}")] = _field(doc, [token])
    seen: dict[str, int] = {}
    for keyword, params in options:
        count = seen[keyword] = seen.get(keyword, 0) + 1
        label = keyword if count == 1 else f"{keyword}[{count - 1}]"
        fields[prefix + label] = _field(doc, params)
    seen.clear()
    for child in block.children:
        count = seen[child.keyword] = seen.get(child.keyword, 0) + 1
        label = child.keyword if child.keyword != "IF_DATA" else f"IF_DATA {child.name}"
        fields.update(_block_fields(child, f"{prefix}{label}[{count - 1}]."))
    return fields


def _field(doc: A2lDocument, tokens) -> tuple:
    """(values compared: numbers by value, the rest as written; the text shown)."""
    raws = [doc.raw(t) for t in tokens]
    key = tuple(_comparable(raw) for raw in raws)
    return key, b" ".join(raws).decode(doc.encoding)


def _comparable(raw: bytes):
    """A number by value (NaN as a word: it equals no number, not even itself), anything else as written."""
    if raw[:1] == b'"' or not is_number(raw):
        return raw
    value = parse_number(raw)
    return value if value == value else b"NaN"


def _changes(old: dict[str, tuple], new: dict[str, tuple]) -> list[FieldChange]:
    changes = [FieldChange(name, old[name][1] if name in old else None, value[1])
               for name, value in new.items() if name not in old or old[name][0] != value[0]]
    changes += [FieldChange(name, value[1], None) for name, value in old.items() if name not in new]
    return changes


def _where(block: Block) -> str:
    file, line, column = block.position
    return f"{file}:{line}:{column}"
