"""The variables of an ELF's DWARF with the scopes C and C++ give them, and lookups in the DIE tree.

Variables come as plain tuples of :class:`~workbench.elf.lookup.Variable`'s fields.

- :meth:`DwarfIndex.global_variables`: one fast pass over every compile unit lists the
  variables at file scope and in namespaces. A definition that points at its declaration
  (DW_AT_specification: ``extern`` in C, a C++ static member) takes name, type and scope
  from it, so ``int Controller::instances = 1;`` is ``app::Controller::instances``.
- :meth:`DwarfIndex.function_statics`: the statics inside functions (their lexical
  blocks, their inlined and abstract instances) - a second pass, which
  :class:`~workbench.elf.debugdata.DebugData` runs only for a name the globals lack.
- :meth:`DwarfIndex.scope_of`: the namespaces, classes and functions around a DIE.
- :meth:`DwarfIndex.definition_of`: the definition of a struct, class or union that a unit
  only declares (clang's default ``-fno-standalone-debug``, opaque C types), by qualified name.
"""

from __future__ import annotations

import gc
from bisect import bisect_right
from contextlib import contextmanager
from pathlib import PurePosixPath, PureWindowsPath

from workbench.elf import dwarf
from workbench.progress import Progress, report

__all__ = ["DwarfIndex"]

_NAMESPACES = frozenset({dwarf.TAG_NAMESPACE})
_VARIABLES = frozenset({dwarf.TAG_VARIABLE})
_FUNCTIONS = frozenset({dwarf.TAG_SUBPROGRAM, dwarf.TAG_INLINED_SUBROUTINE})
_SUBPROGRAMS = frozenset({dwarf.TAG_SUBPROGRAM})
_INSIDE_FUNCTIONS = _NAMESPACES | _FUNCTIONS | {dwarf.TAG_LEXICAL_BLOCK}
_RECORDS = frozenset({dwarf.TAG_STRUCT, dwarf.TAG_CLASS, dwarf.TAG_UNION})
_SCOPES = _NAMESPACES | _RECORDS | {dwarf.TAG_SUBPROGRAM}
_RECORD_ATTRS = frozenset({dwarf.AT_SIBLING, dwarf.AT_NAME, dwarf.AT_DECLARATION, dwarf.AT_SPECIFICATION})
_ANONYMOUS = {dwarf.TAG_NAMESPACE: "(anonymous namespace)"}


class DwarfIndex:
    """Variables and scopes of the DWARF that ``reader`` decodes."""

    def __init__(self, reader: dwarf.DwarfReader):
        self.reader = reader
        self._declared: dict[int, tuple[str, ...]] = {}  # a declaration DIE met at file scope -> its scope
        self._layouts: dict[int, tuple[list[int], list[int]]] = {}  # unit -> starts and ends of its top DIEs
        self._functions: dict[int, tuple[str, ...]] = {}  # subprogram DIE -> its qualified name
        self._definitions: dict[tuple[int, tuple[str, ...]], int] | None = None
        # unit -> the functions (DIE offset, the scope around it) met by global_variables
        self._function_dies: dict[int, list[tuple[int, tuple[str, ...]]]] = {}
        self._byte_order = "little" if reader.order == "<" else "big"

    # -- variables ---------------------------------------------------------------------------
    def global_variables(self, progress: Progress | None = None) -> list[tuple]:
        """Every named variable at file scope or in a namespace, as :class:`Variable` fields (reports
        progress in bytes of DWARF)."""
        with _no_cyclic_gc():  # tens of thousands of tuples that live on: no collections while they are made
            return self._global_variables(progress)

    def _global_variables(self, progress: Progress | None) -> list[tuple]:
        found: list[tuple] = []
        total = len(self.reader.info)
        for unit in self.reader.units:
            report(progress, unit.offset, total, "reading DWARF")
            if unit.type_signature is not None:
                continue
            unit_name, scope, stack = self.unit_name(unit), (), []
            direct, order = 1 + unit.address_size, self._byte_order  # DW_OP_addr a: most variables' location
            functions = self._function_dies[unit.offset] = []  # where function statics can be: their scopes
            for event, offset, tag, attrs in self.reader.scan(unit, _NAMESPACES, _VARIABLES, dwarf.VARIABLE_ATTRS,
                                                               note=_SUBPROGRAMS):
                if event == "item":
                    name, type_offset, external, location, _, specification, origin, _ = attrs
                    if specification is None and origin is None and name.__class__ is str \
                            and location.__class__ is bytes and len(location) == direct and location[0] == dwarf.OP_ADDR:
                        found.append((name, int.from_bytes(location[1:], order),
                                      type_offset if type_offset.__class__ is int else None, scope, unit_name,
                                      bool(external), False))  # what _variable makes of it, without the call
                        continue
                    variable = self._variable(attrs, unit, offset, scope, unit_name)
                    if variable is not None:
                        found.append(variable)
                elif event == "enter":
                    stack.append(scope)
                    scope = scope + (_scope_name(tag, attrs),)
                elif event == "note":
                    functions.append((offset, scope))
                else:
                    scope = stack.pop()
        report(progress, total, total, "reading DWARF")
        return found

    def function_statics(self) -> list[tuple]:
        """Every variable with a static address inside a function (``static`` in a function body), as
        :class:`Variable` fields."""
        found: list[tuple] = []
        for unit in self.reader.units:
            if unit.type_signature is not None:
                continue
            unit_name = self.unit_name(unit)
            # the functions the pass over the globals met (with the scope around each), else the whole unit:
            # the variables at file scope and in namespaces are stepped over, not decoded
            for start, scope in self._function_dies.get(unit.offset, [(None, ())]):
                frames: list[tuple[str, ...]] = []  # the scope around each open DIE
                for event, offset, tag, attrs in self.reader.scan(unit, _INSIDE_FUNCTIONS, _VARIABLES,
                                                                   dwarf.VARIABLE_ATTRS, within=_FUNCTIONS, start=start):
                    if event == "enter":
                        frames.append(scope)
                        if tag in _FUNCTIONS:
                            scope = self._function_name(attrs, scope)
                        elif tag == dwarf.TAG_NAMESPACE:
                            scope = scope + (_scope_name(tag, attrs),)
                    elif event == "leave":
                        scope = frames.pop()
                    else:
                        variable = self._variable(attrs, unit, offset, scope, unit_name, function=True)
                        if variable is not None and variable[1] is not None:
                            found.append(variable)
        return found

    def _variable(self, fields: tuple, unit: dwarf.Unit, offset: int, scope: tuple[str, ...], unit_name: str,
                  function: bool = False) -> tuple | None:
        """The :class:`Variable` fields of a variable DIE (its attributes in VARIABLE_FIELDS order), as a plain
        tuple (50,000 of them are made and cached on every read of a large ELF); None for a declaration or a
        DIE without a name."""
        name, type_offset, external, location, declaration, specification, origin, _ = fields
        origin = specification or origin
        if origin is not None:
            declared = self.reader.die(origin)
            if declared is not None:
                name = name or declared.attrs.get(dwarf.AT_NAME)
                type_offset = type_offset or declared.attrs.get(dwarf.AT_TYPE)
                external = external or declared.attrs.get(dwarf.AT_EXTERNAL, False)
            if specification is not None and not function:
                known = self._declared.get(specification)
                scope = known if known is not None else self.scope_of(specification)
        if location is None:
            address = None
        elif location.__class__ is bytes and len(location) == 1 + unit.address_size and location[0] == dwarf.OP_ADDR:
            address = int.from_bytes(location[1:], self._byte_order)  # most: DW_OP_addr a
        else:
            address = self.reader.static_address(location, unit)
        if address is None and declaration:
            self._declared[offset] = scope
            return None
        if name.__class__ is not str:
            return None
        return (name, address, type_offset if type_offset.__class__ is int else None, scope, unit_name,
                bool(external) and not function, function)

    def _function_name(self, attrs: dict, scope: tuple[str, ...]) -> tuple[str, ...]:
        """The qualified name of a function DIE: its own, or its declaration's (a member function
        defined outside its class, an inlined or out-of-line instance of an abstract one)."""
        origin = attrs.get(dwarf.AT_SPECIFICATION) or attrs.get(dwarf.AT_ABSTRACT_ORIGIN)
        if isinstance(origin, int):
            known = self._functions.get(origin)
            if known is None:
                declaration = self.reader.die(origin)
                if declaration is None:
                    return scope + ("(unknown function)",)
                known = self._function_name(declaration.attrs, self.scope_of(origin))
                self._functions[origin] = known
            return known
        name = attrs.get(dwarf.AT_NAME)
        return scope + (name if isinstance(name, str) else "(unknown function)",)

    def unit_name(self, unit: dwarf.Unit) -> str:
        """The compile unit's file name with "." -> "_" (``src/wild.c`` -> ``wild_c``), "" without one."""
        root = self.reader.die(unit.first_die, unit)
        name = root.attrs.get(dwarf.AT_NAME) if root is not None else None
        if not isinstance(name, str):
            return ""
        path = PureWindowsPath(name) if "\\" in name else PurePosixPath(name)
        return path.name.replace(".", "_")

    # -- scopes -------------------------------------------------------------------------------
    def scope_of(self, offset: int) -> tuple[str, ...]:
        """The names of the namespaces, classes and functions that enclose the DIE at ``offset``,
        outermost first (anonymous ones as ``(anonymous namespace)``/``(anonymous)``)."""
        unit = self.reader.unit_of(offset)
        starts, ends = self._layout(unit)
        index = bisect_right(starts, offset) - 1
        if index < 0 or starts[index] == offset or ends[index] <= offset:
            return ()
        names: list[str] = []
        parent = self.reader.die(starts[index], unit)
        while parent is not None and parent.offset != offset:
            if parent.tag == dwarf.TAG_SUBPROGRAM:
                names.append(self._function_name(parent.attrs, tuple(names))[-1])
            elif parent.tag in _SCOPES:
                names.append(_scope_name(parent.tag, self._signed(parent).attrs))
            inner = None
            for child in self.reader.children(parent):
                if child.offset == offset:
                    return tuple(names)
                if child.offset < offset < self.reader.after(child):
                    inner = child
                    break
            parent = inner
        return tuple(names)

    def _signed(self, die: dwarf.Die) -> dwarf.Die:
        """The DIE a type unit holds for a declaration that carries only its signature (clang's
        -fdebug-types-section leaves the name there), else ``die`` itself."""
        signed = die.attrs.get(dwarf.AT_SIGNATURE)
        if isinstance(signed, int) and dwarf.AT_NAME not in die.attrs:
            return self.reader.die(signed) or die
        return die

    def _layout(self, unit: dwarf.Unit) -> tuple[list[int], list[int]]:
        layout = self._layouts.get(unit.offset)
        if layout is None:
            root = self.reader.die(unit.first_die, unit)
            children = self.reader.children(root) if root is not None else []
            layout = ([child.offset for child in children], [self.reader.after(child) for child in children])
            self._layouts[unit.offset] = layout
        return layout

    # -- declarations -------------------------------------------------------------------------
    def definition_of(self, declaration: dwarf.Die) -> int | None:
        """The DIE offset of the definition of the struct/class/union ``declaration`` declares
        (DW_AT_declaration), found by kind and qualified name in any unit; None when no unit has one."""
        name = declaration.attrs.get(dwarf.AT_NAME)
        if not isinstance(name, str):
            return None
        if self._definitions is None:
            self._definitions = self._read_definitions()
        key = (_record_kind(declaration.tag), self.scope_of(declaration.offset) + (name,))
        return self._definitions.get(key)

    def _read_definitions(self) -> dict[tuple[int, tuple[str, ...]], int]:
        definitions: dict[tuple[int, tuple[str, ...]], int] = {}
        for unit in self.reader.units:
            scope, stack = (), []
            for event, offset, tag, attrs in self.reader.scan(unit, _NAMESPACES, _RECORDS, _RECORD_ATTRS):
                if event == "enter":
                    stack.append(scope)
                    scope = scope + (_scope_name(tag, attrs),)
                elif event == "leave":
                    scope = stack.pop()
                elif isinstance(attrs.get(dwarf.AT_NAME), str) and not attrs.get(dwarf.AT_DECLARATION):
                    # gcc's type units define a class at their top, pointing at its declaration in its namespace
                    specification = attrs.get(dwarf.AT_SPECIFICATION)
                    where = self.scope_of(specification) if isinstance(specification, int) else scope
                    definitions.setdefault((_record_kind(tag), where + (attrs[dwarf.AT_NAME],)), offset)
        return definitions


@contextmanager
def _no_cyclic_gc():
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _record_kind(tag: int) -> int:
    """struct and class are one kind: a declaration may say ``struct`` for a ``class`` (and back)."""
    return dwarf.TAG_STRUCT if tag == dwarf.TAG_CLASS else tag


def _scope_name(tag: int, attrs: dict) -> str:
    name = attrs.get(dwarf.AT_NAME)
    return name if isinstance(name, str) else _ANONYMOUS.get(tag, "(anonymous)")
