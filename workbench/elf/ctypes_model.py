"""C and C++ types as the A2L tool chain needs them: sizes, members, base classes, arrays, bitfields.

:class:`~workbench.elf.type_resolver.TypeResolver` makes them from DWARF; this module holds the model
alone (a cached index's types unpickle without the DWARF decoder).

:meth:`CType.find_member` looks a name up the way C and C++ do: a member of the type,
of an anonymous struct or union in it (C11 ``reg.Value``), then of its base classes
(a derived member hides a base member of the same name; one found in two bases is
ambiguous). A base class can also be named as a step (a2ltool's ``obj.Base.member``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

__all__ = ["VOID", "CMember", "CType", "MemberError"]


class MemberError(ValueError):
    """A member name that a type does not have, or has twice through two base classes."""


@dataclass(frozen=True)
class CMember:
    name: str  # "" for an anonymous struct/union member; a base class: the class name
    offset: int | None  # bytes from the start of the struct (the storage unit of a bitfield); None: a virtual base
    type: "CType"
    bit_size: int | None = None  # bitfields only
    bit_position: int | None = None  # bitfields: lowest bit inside the storage unit (0 = LSB), outside it
    # (negative, or beyond its bits) for a field no unit of its type's size holds (a packed struct's)


@dataclass(frozen=True)
class CType:
    kind: str  # base, enum, struct, union, array, pointer, function, void
    size: int  # bytes
    name: str | None = None  # the C name (struct tag, base type name), None when anonymous
    encoding: str | None = None  # base and enum: signed, unsigned, float, bool, address
    members: tuple[CMember, ...] = ()
    element: "CType | None" = None  # arrays
    dims: tuple[int, ...] = ()  # arrays: element counts, outermost first
    typedef: str | None = field(default=None, compare=False)  # e.g. real32_T
    bases: tuple[CMember, ...] = ()  # C++ base classes, in declaration order
    declared_only: bool = False  # a struct the DWARF only declares (no unit defines it)
    enumerators: tuple[tuple[str, int], ...] = ()  # enums: (name, value) in declaration order

    def member(self, name: str) -> CMember | None:
        """The member declared in this type itself with this name."""
        for member in self.members:
            if member.name == name:
                return member
        return None

    def find_member(self, name: str) -> CMember | None:
        """The member ``name`` reaches, its offset from the start of this type (see the module
        docstring); None when there is none. Raises :class:`MemberError` when two base classes
        have it, or when it lies in a virtual base (whose offset only the running program knows)."""
        own = self.member(name)
        if own is not None and name:
            return own
        for anonymous in self.members:
            if not anonymous.name and anonymous.type.kind in ("struct", "union"):
                inner = anonymous.type.find_member(name)
                if inner is not None:
                    return _moved(inner, anonymous.offset)
        for base in self.bases:
            if base.name == name:
                return _through_base(base, replace(base, offset=0), name)
        found = [(base, member) for base in self.bases if (member := base.type.find_member(name)) is not None]
        if not found:
            return None
        if len(found) > 1:
            raise MemberError(f"{name!r} is in more than one base class of {self.display_name} "
                              f"({', '.join(base.name for base, _ in found)}): name the base, e.g. "
                              f"{found[0][0].name}.{name}")
        base, member = found[0]
        return _through_base(base, member, name)

    @property
    def display_name(self) -> str:
        return self.typedef or self.name or self.kind


VOID = CType("void", 0)


def _moved(member: CMember, by: int | None) -> CMember:
    if by is None or member.offset is None:
        return replace(member, offset=None)
    return replace(member, offset=member.offset + by) if by else member


def _through_base(base: CMember, member: CMember, name: str) -> CMember:
    if base.offset is None:
        raise MemberError(f"{name!r} lies in the virtual base {base.name}: its offset is known at run time only")
    return _moved(member, base.offset)
