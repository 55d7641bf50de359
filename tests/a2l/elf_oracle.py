"""Addresses of A2L symbol paths computed with pyelftools alone (not workbench.elf).

Used to prove the committed demo A2L against its ELF without trusting our own DWARF code.
"""

from __future__ import annotations

import re
from pathlib import Path

from elftools.elf.elffile import ELFFile

_QUALIFIERS = {"DW_TAG_typedef", "DW_TAG_const_type", "DW_TAG_volatile_type"}


class PyelftoolsOracle:
    def __init__(self, path: Path):
        self._handle = open(path, "rb")
        self.elf = ELFFile(self._handle)
        self.variables = {}
        for unit in self.elf.get_dwarf_info().iter_CUs():
            for die in unit.get_top_DIE().iter_children():
                location = die.attributes.get("DW_AT_location")
                if die.tag != "DW_TAG_variable" or location is None or location.form != "DW_FORM_exprloc" \
                        or location.value[0] != 0x03:  # DW_OP_addr
                    continue
                declaration = die.get_DIE_from_attribute("DW_AT_specification") \
                    if "DW_AT_specification" in die.attributes else die  # gcc: definition -> extern declaration
                address = int.from_bytes(bytes(location.value[1:]), "little" if self.elf.little_endian else "big")
                self.variables[declaration.attributes["DW_AT_name"].value.decode()] = (address, declaration)

    def close(self) -> None:
        self._handle.close()

    def address(self, path: str) -> int:
        steps = re.findall(r"\.?([A-Za-z_]\w*)|\[(\d+)\]", path)
        name = steps[0][0]
        address, die = self.variables[name]
        ctype = self._strip(die.get_DIE_from_attribute("DW_AT_type"))
        for member, index in steps[1:]:
            old_index = re.fullmatch(r"_(\d+)_", member or "")
            if ctype.tag == "DW_TAG_array_type" and (index or old_index):
                element = self._strip(ctype.get_DIE_from_attribute("DW_AT_type"))
                dims = [c.attributes["DW_AT_upper_bound"].value + 1 for c in ctype.iter_children()
                        if c.tag == "DW_TAG_subrange_type"]
                inner = element.attributes["DW_AT_byte_size"].value
                for dim in dims[1:]:
                    inner *= dim
                address += int(index or old_index.group(1)) * inner
                ctype = element if len(dims) == 1 else ctype  # nested dims are not used by the demo
            else:
                child = next(c for c in ctype.iter_children() if c.attributes.get("DW_AT_name") and
                             c.attributes["DW_AT_name"].value.decode() == member)
                address += child.attributes["DW_AT_data_member_location"].value
                ctype = self._strip(child.get_DIE_from_attribute("DW_AT_type"))
        return address

    def _strip(self, die):
        while die.tag in _QUALIFIERS:
            die = die.get_DIE_from_attribute("DW_AT_type")
        return die
