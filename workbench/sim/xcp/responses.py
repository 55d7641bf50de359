"""What the slave's command handlers share: negative responses, the length check, block writes.

The protocol's names (command and error codes, resources) are :mod:`workbench.xcp_protocol`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from workbench.sim.memory import AccessFault, MemoryAccessError
from workbench.xcp_protocol import PID_ERR, Err

__all__ = ["PowerLost", "Writer", "XcpNegative", "memory_error", "need"]


class XcpNegative(Exception):
    """A command handler's refusal: becomes the negative response ``FE code *extra``."""

    def __init__(self, code: Err, extra: bytes = b""):
        super().__init__(f"{Err(code).name}")
        self.code = Err(code)
        self.extra = extra

    def packet(self) -> bytes:
        return bytes([PID_ERR, self.code]) + self.extra


def need(req: bytes, length: int) -> None:
    """Refuse a command shorter than ``length`` bytes (command byte included) with ERR_CMD_SYNTAX."""
    if len(req) < length:
        raise XcpNegative(Err.CMD_SYNTAX)


def memory_error(exc: MemoryAccessError) -> XcpNegative:
    """The negative response for a refused memory access."""
    code = {
        AccessFault.READ_ONLY: Err.WRITE_PROTECTED,
        AccessFault.NOT_ERASED: Err.ACCESS_DENIED,
    }.get(exc.fault, Err.OUT_OF_RANGE)
    return XcpNegative(code)


class PowerLost(Exception):
    """Raised inside a handler when an injected power loss strikes: the frame gets no answer."""


@dataclass
class Writer:
    """How a block transfer checks its whole destination, then writes each frame's bytes."""

    check: Callable[[int, int], None]
    write: Callable[[int, bytes], None]
