"""Typed access to the application's variables in ECU memory, by ELF symbol name.

Every read and write goes through ``memory.read``/``memory.write`` at the symbol's address,
so calibrations come from the active page and what XCP reads is the application's state.
Values are little-endian (the demo ELF is i386); ``real32_T`` values are ``numpy.float32``
so arithmetic on them rounds as the C code's single-precision arithmetic does.
"""

from __future__ import annotations

import struct
from collections.abc import Mapping
from typing import Protocol

import numpy as np

from workbench.errors import UnknownSymbolError

__all__ = ["Memory", "Variables"]

_F32 = struct.Struct("<f")
_U16 = struct.Struct("<H")


class Memory(Protocol):
    def read(self, address: int, size: int) -> bytes: ...

    def write(self, address: int, data: bytes) -> None: ...


class Variables:
    """Reads and writes C variables (``real32_T``, ``uint8_T``, ``uint16_T``, arrays, raw bytes).

    ``symbols`` maps a name to an address (``int``) or to an object with ``.address``
    (:class:`workbench.elf.Symbol`). An unknown name raises :class:`UnknownSymbolError`.
    """

    def __init__(self, memory: Memory, symbols: Mapping[str, object]):
        self._memory = memory
        self._symbols = symbols
        self._addresses: dict[str, int] = {}

    def address(self, name: str, offset: int = 0) -> int:
        """Address of ``name`` plus ``offset`` bytes; raises :class:`UnknownSymbolError`."""
        try:
            return self._addresses[name] + offset
        except KeyError:
            pass
        try:
            entry = self._symbols[name]
        except KeyError:
            raise UnknownSymbolError(name, "the FLCU application's symbols") from None
        self._addresses[name] = int(getattr(entry, "address", entry))
        return self._addresses[name] + offset

    def f32(self, name: str, offset: int = 0) -> np.float32:
        return np.float32(_F32.unpack(self._memory.read(self.address(name, offset), 4))[0])

    def set_f32(self, name: str, value: np.float32 | float, offset: int = 0) -> None:
        self._memory.write(self.address(name, offset), _F32.pack(value))

    def f32_array(self, name: str, count: int, offset: int = 0) -> np.ndarray:
        data = self._memory.read(self.address(name, offset), 4 * count)
        return np.frombuffer(data, dtype="<f4").astype(np.float32)

    def u8(self, name: str, offset: int = 0) -> int:
        return self._memory.read(self.address(name, offset), 1)[0]

    def set_u8(self, name: str, value: int, offset: int = 0) -> None:
        self._memory.write(self.address(name, offset), bytes([int(value) & 0xFF]))

    def u16(self, name: str, offset: int = 0) -> int:
        return _U16.unpack(self._memory.read(self.address(name, offset), 2))[0]

    def set_u16(self, name: str, value: int, offset: int = 0) -> None:
        self._memory.write(self.address(name, offset), _U16.pack(int(value) & 0xFFFF))

    def raw(self, name: str, size: int, offset: int = 0) -> bytes:
        return self._memory.read(self.address(name, offset), size)

    def set_raw(self, name: str, data: bytes, offset: int = 0) -> None:
        self._memory.write(self.address(name, offset), bytes(data))
