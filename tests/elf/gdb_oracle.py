"""Where gdb puts C/C++ expressions in ELF files: the independent reader the ELF matrix is checked against.

Runs inside gdb (``gdb -batch -nx -x gdb_oracle.py``), nothing of the workbench imported:
reads the request named by $WB_GDB_REQUEST, ``[{"elf": path, "language": "c"|"c++",
"expressions": [...]}]``, and writes to $WB_GDB_RESULT, per ELF, per expression,
``[bit address, bit size or null, byte size, element]`` (the address in bits: byte address * 8,
plus the bit position for a bitfield, as gdb's own type description counts it: from the most
significant bit of the first byte on big-endian targets; the element: the scalar an array is
made of as "float"/"signed"/"unsigned"/"pointer" and its size, "unsigned4"), or the error
gdb gave. :func:`locate` is the only logic: gdb parses and places everything.
"""

import json
import os
import re

import gdb  # only inside gdb

_MEMBER = re.compile(r"^(.*)\.([A-Za-z_]\w*)$")


def _field_bits(gdb_type, name):
    """(bit position, bit size) of the member ``name`` of ``gdb_type``, looking into anonymous
    members and base classes as C and C++ do; None when there is none."""
    for field in gdb_type.strip_typedefs().fields():
        if field.name == name and not field.is_base_class:
            return field.bitpos, field.bitsize
    for field in gdb_type.strip_typedefs().fields():
        if field.is_base_class or not field.name:
            inner = _field_bits(field.type, name)
            if inner is not None:
                return field.bitpos + inner[0], inner[1]
    return None


def _element(gdb_type):
    """The scalar of a type (an array's element) as kind and size: "signed2", "float8", "pointer4"."""
    scalar = gdb_type.strip_typedefs()
    while scalar.code == gdb.TYPE_CODE_ARRAY:
        scalar = scalar.target().strip_typedefs()
    if scalar.code == gdb.TYPE_CODE_FLT:
        kind = "float"
    elif scalar.code == gdb.TYPE_CODE_PTR:
        kind = "pointer"
    elif scalar.code in (gdb.TYPE_CODE_INT, gdb.TYPE_CODE_ENUM, gdb.TYPE_CODE_BOOL, gdb.TYPE_CODE_CHAR):
        kind = "signed" if scalar.is_signed else "unsigned"
    else:
        kind = "other"
    return f"{kind}{scalar.sizeof}"


def locate(expression):
    value = gdb.parse_and_eval(expression)
    member = _MEMBER.match(expression)
    if member:
        parent = gdb.parse_and_eval(member.group(1))
        bits = _field_bits(parent.type, member.group(2))
        if bits is not None and bits[1]:
            return [int(parent.address) * 8 + bits[0], bits[1], value.type.sizeof, _element(value.type)]
    return [int(value.address) * 8, None, value.type.sizeof, _element(value.type)]


def main():
    with open(os.environ["WB_GDB_REQUEST"]) as handle:
        request = json.load(handle)
    results = []
    for entry in request:
        gdb.execute(f"file {entry['elf']}", to_string=True)
        gdb.execute(f"set language {entry['language']}", to_string=True)
        found = {}
        for expression in entry["expressions"]:
            try:
                found[expression] = locate(expression)
            except gdb.error as exc:
                found[expression] = str(exc)
        results.append(found)
    with open(os.environ["WB_GDB_RESULT"], "w") as handle:
        json.dump(results, handle)


main()
