"""The demo ECU's seed & key algorithm, as a plugin for XCP masters.

The A2L names it ``workbench.sim.seedkey:compute_key`` (SEED_AND_KEY_EXTERNAL_FUNCTION);
a master loads the function by that name instead of a vendor DLL. The simulated ECU
uses the same function to check the key of an UNLOCK.

Algorithm (a demonstration, not a security measure): the seed is 4 bytes (a longer one is taken 4
bytes at a time, the last ones padded with zeros, and the key is as long as the seed), read as a
big-endian 32-bit word ``s``;
``r`` is the resource bit (CAL/PAG 0x01, DAQ 0x04, STIM 0x08, PGM 0x10) repeated in all four
bytes (``r * 0x01010101``)::

    key = rotate_left_32(s XOR 0x464C4355 XOR r, 5)    # 0x464C4355 is "FLCU" in ASCII

sent as 4 big-endian bytes. Example: seed ``01 02 03 04``, resource DAQ (0x04) gives
key ``69 48 8A A8``.
"""

from __future__ import annotations

__all__ = ["SEED_LENGTH", "compute_key"]

SEED_LENGTH = 4
_MAGIC = 0x464C4355  # "FLCU"
_RESOURCES = (0x01, 0x04, 0x08, 0x10)


def compute_key(seed: bytes, resource: int) -> bytes:
    """The key that unlocks ``resource`` for ``seed``.

    :param seed: the seed bytes of GET_SEED: 4 (the demo's), or more.
    :param resource: one resource bit (0x01 CAL/PAG, 0x04 DAQ, 0x08 STIM, 0x10 PGM).
    :returns: the key bytes for UNLOCK, as many as the seed's.
    :raises ValueError: the seed is shorter than 4 bytes or the resource is not a single resource bit.
    """
    if len(seed) < SEED_LENGTH:
        raise ValueError(f"seed must be at least {SEED_LENGTH} bytes, got {len(seed)}")
    if resource not in _RESOURCES:
        raise ValueError(f"resource must be one of {', '.join(f'0x{r:02X}' for r in _RESOURCES)}, got 0x{resource:X}")
    key = bytearray()
    for start in range(0, len(seed), SEED_LENGTH):
        word = int.from_bytes(seed[start:start + SEED_LENGTH].ljust(SEED_LENGTH, b"\0"), "big")
        word ^= _MAGIC ^ (resource * 0x01010101)
        key += (((word << 5) | (word >> 27)) & 0xFFFFFFFF).to_bytes(4, "big")
    return bytes(key[:len(seed)])
