"""Code made for each DIE abbreviation: the hot loops of reading a large ELF's DWARF.

An ELF of 50,000 variables has 50,000 variable DIEs of a handful of abbreviations. Code made for
one abbreviation (Python source generated from its attribute forms, compiled once and shared by
every unit with the same abbreviation) handles a DIE without a loop over its attributes:

- :func:`variable_reader` reads a variable DIE with one ``struct`` call per run of fixed-size
  attributes, about twice as fast as decoding attribute by attribute, into the attributes
  :mod:`workbench.elf.dwarf_index` reads a variable for: a tuple in :data:`VARIABLE_FIELDS`
  order (None where the DIE lacks one, ``external`` False);
- :func:`skipper` steps over a DIE's attributes: the byte count when all have a fixed size,
  else a function of (data, position) that returns the position after them.
"""

from __future__ import annotations

import itertools
import struct
import types
from collections.abc import Callable

from workbench.elf import dwarf

__all__ = ["VARIABLE_FIELDS", "VariableReader", "skipper", "variable_reader"]

VARIABLE_FIELDS = (dwarf.AT_NAME, dwarf.AT_TYPE, dwarf.AT_EXTERNAL, dwarf.AT_LOCATION, dwarf.AT_DECLARATION,
                   dwarf.AT_SPECIFICATION, dwarf.AT_ABSTRACT_ORIGIN, dwarf.AT_SIBLING)
NAME, TYPE, EXTERNAL, LOCATION, DECLARATION, SPECIFICATION, ABSTRACT_ORIGIN, SIBLING = range(len(VARIABLE_FIELDS))

# (data, position, unit) -> (fields, the position after the DIE's attributes)
VariableReader = Callable[[bytes, int, "dwarf.Unit"], tuple[tuple, int]]

_STRUCT_CODES = {1: "B", 2: "H", 4: "I", 8: "Q"}
_REFERENCES = frozenset({0x11, 0x12, 0x13, 0x14})  # ref1-ref8: relative to the unit
_BLOCKS = frozenset({0x18, 0x09})  # exprloc, block: a uleb length, then the bytes
_compiled: dict[tuple, Callable] = {}


def variable_reader(reader: "dwarf.DwarfReader", specs: tuple, steps: tuple) -> VariableReader:
    """The reader of the variable DIEs of one abbreviation: ``specs`` its (attribute, form, implicit
    value) triples, ``steps`` (attribute, form, size in bytes or -1) as the unit lays them out."""
    key = (specs, tuple(size for _, _, size in steps), reader.order)
    compiled = _compiled.get(key)
    if compiled is None:
        compiled = _compiled[key] = _compile(specs, steps, reader.order)
    # the same code, this reader's sections bound as its defaults: no call in between
    return types.FunctionType(compiled.__code__, compiled.__globals__, "read",
                              (reader.strings, reader.line_strings, reader._read_form))


def _compile(specs: tuple, steps: tuple, order: str) -> Callable:
    slots = {attr: slot for slot, attr in enumerate(VARIABLE_FIELDS)}
    values = ["None"] * len(VARIABLE_FIELDS)
    values[EXTERNAL] = "False"
    namespace: dict[str, object] = {}
    numbers = itertools.count()
    lines = ["def read(data, position, unit, strings, line_strings, read_form):"]
    run: list[str] = []  # struct codes of the current run of fixed-size attributes
    run_values: list[tuple[int, int, str]] = []  # (slot, form, local) of the wanted ones among them

    def flush() -> None:
        if not run:
            return
        layout = struct.Struct(order + "".join(run))
        name = f"S{len(namespace)}"
        namespace[name] = layout
        if run_values:
            lines.append(f"    {', '.join(v for _, _, v in run_values)}, = {name}.unpack_from(data, position)")
        lines.append(f"    position += {layout.size}")
        for slot, form, variable in run_values:
            values[slot] = _converted(form, variable)
        run.clear()
        run_values.clear()

    for (attr, form, implicit), (_, _, size) in zip(specs, steps):
        slot = slots.get(attr)
        if size == 0:  # flag_present, implicit_const: the value is in the abbreviation
            if slot is not None:
                constant = f"C{len(namespace)}"
                namespace[constant] = True if form == 0x19 else implicit
                values[slot] = constant
        elif size in _STRUCT_CODES and form not in dwarf.DECODED_FORMS:
            if slot is None:
                run.append(f"{size}x")
            else:
                variable = f"v{next(numbers)}"
                run.append(_STRUCT_CODES[size])
                run_values.append((slot, form, variable))
        else:
            flush()
            variable = f"v{next(numbers)}"
            if form in _BLOCKS:  # most locations: a length byte and a few bytes
                lines += [f"    if data[position] < 0x80:",
                          f"        {variable} = data[position + 1 : position + 1 + data[position]]",
                          f"        position += 1 + data[position]",
                          f"    else:",
                          f"        {variable}, position = read_form({form}, position, unit, None)"]
            elif form == 0x08:  # an inline string
                lines += [f"    end = data.index(b'\\0', position)",
                          f"    {variable} = data[position:end].decode('utf-8', 'replace')",
                          f"    position = end + 1"]
            else:
                namespace[f"C{len(namespace)}"] = implicit
                lines.append(f"    {variable}, position = read_form({form}, position, unit, C{len(namespace) - 1})")
            if slot is not None:
                values[slot] = variable
    flush()
    lines.append(f"    return ({', '.join(values)},), position")
    exec(compile("\n".join(lines), "<variable reader>", "exec"), namespace)
    return namespace["read"]


def _converted(form: int, variable: str) -> str:
    """The expression that turns a struct-read value of ``form`` into the attribute's value."""
    if form in (0x0E, 0x1F):  # strp, line_strp: a NUL-terminated string in .debug_str / .debug_line_str
        section = "strings" if form == 0x0E else "line_strings"
        return f"{section}[{variable} : {section}.index(b'\\0', {variable})].decode('utf-8', 'replace')"
    if form in _REFERENCES:
        return f"({variable} + unit.offset)"
    return variable


_LEBS = frozenset({0x0F, 0x0D, 0x15, 0x1A, 0x1B, 0x22, 0x23, 0x1F01, 0x1F02})  # forms that are one LEB128
_skippers: dict[tuple, Callable] = {}


def skipper(steps: tuple) -> int | Callable[[bytes, int], int] | None:
    """How to step over the attributes of a DIE of this abbreviation (``steps``: (attribute, form, size in
    bytes or -1)): their byte count when every form has a fixed size, else a function (data, position) ->
    the position after them; None for a form only the generic decoder steps over (DW_FORM_indirect)."""
    key = tuple((form, size) for _, form, size in steps)
    if all(size >= 0 for _, size in key):
        return sum(size for _, size in key)
    if key in _skippers:
        return _skippers[key]
    lines, fixed = ["def skip(data, position):"], 0
    for form, size in key:
        if size >= 0:
            fixed += size
            continue
        if fixed:
            lines.append(f"    position += {fixed}")
            fixed = 0
        if form in _BLOCKS:
            lines += ["    if data[position] < 0x80:",
                      "        position += 1 + data[position]",
                      "    else:",
                      "        length, position = uleb(data, position)",
                      "        position += length"]
        elif form == 0x08:
            lines.append("    position = data.index(b'\\0', position) + 1")
        elif form == 0x0A:  # block1
            lines.append("    position += 1 + data[position]")
        elif form in _LEBS:
            lines += ["    while data[position] >= 0x80:", "        position += 1", "    position += 1"]
        else:
            _skippers[key] = None
            return None
    lines.append(f"    return position + {fixed}")
    namespace = {"uleb": dwarf.uleb}
    exec(compile("\n".join(lines), "<die skipper>", "exec"), namespace)
    _skippers[key] = namespace["skip"]
    return namespace["skip"]
