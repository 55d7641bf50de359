"""The XCP driver's constant strings, laid out in the boot ROM so masters can UPLOAD them.

GET_ID, GET_DAQ_EVENT_INFO and GET_SECTOR_INFO (mode 2) answer with a length and point
the MTA at the text; the texts live here, NUL-separated, in a read-only area.
"""

from __future__ import annotations

from dataclasses import dataclass

from workbench.sim.memory_map import MemoryMap
from workbench.sim.xcp.parameters import XcpParameters
from workbench.xcp_protocol import IdType

__all__ = ["InfoRom"]

MAX_TEXT = 0xFF


@dataclass(frozen=True)
class InfoRom:
    start: int
    data: bytes
    index: dict[str, tuple[int, int]]  # key -> (address, length)

    @classmethod
    def build(cls, params: XcpParameters, memory_map: MemoryMap) -> InfoRom:
        texts = {f"id:{IdType.ASCII:d}": params.ecu_text, f"id:{IdType.ASAM_MC2_NAME:d}": params.asam_mc2_name}
        texts.update({f"event:{e.number}": e.name for e in params.events})
        texts.update({f"sector:{n}": sector.name for n, sector in enumerate(memory_map.sectors)})
        data = bytearray()
        index = {}
        align = params.address_granularity  # every text starts on an element: UPLOAD reads whole ones from there
        for key, text in texts.items():
            encoded = text.encode("ascii", "replace")[:MAX_TEXT]  # XCP texts are ASCII, their lengths a byte
            index[key] = (memory_map.info_rom_start + len(data), len(encoded))
            data += encoded + b"\0"
            data += bytes(-len(data) % align)
        return cls(memory_map.info_rom_start, bytes(data), index)

