"""Where gdb puts C/C++ expressions in ELF files: the independent reader the ELF matrix is checked against.

Runs inside gdb (``gdb -batch -nx -x gdb_oracle.py``), nothing of the workbench imported:
reads the request named by $WB_GDB_REQUEST, ``[{"elf": path, "language": "c"|"c++",
"expressions": [...]}]``, and writes to $WB_GDB_RESULT, per ELF, per expression,
``[bit address, bit size or null, byte size]`` (the address in bits: byte address * 8,
plus the bit position for a bitfield, as gdb's own type description counts it), or the
error gdb gave. :func:`locate` is the only logic: gdb parses and places everything.
"""

import json
import os
import re

import gdb  # noqa: F401  (only inside gdb)

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


def locate(expression):
    value = gdb.parse_and_eval(expression)
    member = _MEMBER.match(expression)
    if member:
        parent = gdb.parse_and_eval(member.group(1))
        bits = _field_bits(parent.type, member.group(2))
        if bits is not None and bits[1]:
            return [int(parent.address) * 8 + bits[0], bits[1], value.type.sizeof]
    return [int(value.address) * 8, None, value.type.sizeof]


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
