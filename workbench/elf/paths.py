"""A2L symbol paths (``a.b.c``, ``a[3]``, ``a._3_``, ``a.b[2].c``, ``m[1][2]``) walked through C types.

Member steps find members the way C and C++ do (anonymous structs and unions, base
classes: :meth:`~workbench.elf.ctypes_model.CType.find_member`).
"""

from __future__ import annotations

import re
from typing import NamedTuple

from workbench.elf.ctypes_model import CType, MemberError

__all__ = ["PathError", "Step", "split_path", "walk"]

_STEP = re.compile(r"\.([A-Za-z_][A-Za-z0-9_]*)|\[(\d+)\]")
_OLD_INDEX = re.compile(r"_(\d+)_")


class PathError(ValueError):
    """A path step does not fit the type it is applied to (no such member, index out of range)."""


class Step(NamedTuple):
    member: str | None = None  # ".name" (also "._3_", which may be an index: see index)
    index: int | None = None  # "[3]", or the number in "._3_"


def split_path(path: str) -> tuple[str, list[Step]]:
    """``"a.b[2]._3_"`` -> ``("a", [Step("b"), Step(index=2), Step("_3_", 3)])``.

    Raises :class:`PathError` for a path that is not of this form.
    """
    if "[" not in path and path.isascii() and path.replace(".", "_").isidentifier() \
            and ".." not in path and path[-1] != ".":  # "a.b._3_": much faster than the regex walk
        parts = path.split(".")
        return parts[0], [Step(part, _old_index(part)) for part in parts[1:]]
    match = re.match(r"[A-Za-z_][A-Za-z0-9_]*", path)
    if match is None:
        raise PathError(f"{path!r} is not a C variable path")
    steps: list[Step] = []
    position = match.end()
    while position < len(path):
        step = _STEP.match(path, position)
        if step is None:
            raise PathError(f"{path!r}: unexpected {path[position:]!r}")
        member, index = step.groups()
        if member is not None:
            steps.append(Step(member, _old_index(member)))
        else:
            steps.append(Step(index=int(index)))
        position = step.end()
    return match.group(), steps


def _old_index(member: str) -> int | None:
    """The number in an old-style array index ``_3_``, None for a member name."""
    if member[0] != "_" or member[-1] != "_":
        return None
    old = _OLD_INDEX.fullmatch(member)
    return int(old.group(1)) if old else None


def walk(ctype: CType, steps: list[Step]) -> tuple[int, CType, int | None, int | None]:
    """Apply ``steps`` to a variable of type ``ctype``.

    Returns (byte offset from the variable, type reached, bit size, bit position) -
    the bit fields are set when the last step names a bitfield member.
    Raises :class:`PathError` when a step does not fit.
    """
    offset = 0
    bit_size = bit_position = None
    for step in steps:
        if ctype.kind in ("struct", "union") and step.member is not None:
            try:
                member = ctype.find_member(step.member)
            except MemberError as exc:
                raise PathError(str(exc)) from None
            if member is not None:
                offset += member.offset
                ctype, bit_size, bit_position = member.type, member.bit_size, member.bit_position
                continue
            if ctype.declared_only:
                raise PathError(f"{ctype.display_name} is only declared in the DWARF (no unit defines it)")
        if ctype.kind == "array" and step.index is not None:
            count = ctype.dims[0]
            if count and step.index >= count:
                raise PathError(f"index {step.index} is outside the array of {count}")
            inner = ctype.element if len(ctype.dims) == 1 else CType(
                "array", ctype.size // count if count else 0, element=ctype.element, dims=ctype.dims[1:])
            offset += step.index * inner.size
            ctype, bit_size, bit_position = inner, None, None
            continue
        wanted = f"member {step.member!r}" if step.member is not None else f"index [{step.index}]"
        raise PathError(f"{ctype.display_name} ({ctype.kind}) has no {wanted}")
    return offset, ctype, bit_size, bit_position
