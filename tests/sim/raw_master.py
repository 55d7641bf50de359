"""A raw XCP master on a python-can bus: sends CTOs to 0x7F0, collects what 0x7F1 answers."""

from __future__ import annotations

import can

MASTER_ID, SLAVE_ID = 0x7F0, 0x7F1


class RawMaster:
    """CTOs are padded to DLC 8 (the demo A2L's MAX_DLC_REQUIRED) unless ``pad=False``."""

    def __init__(self, channel: str, interface: str = "virtual"):
        self.bus = can.Bus(interface=interface, channel=channel)

    def send(self, cto: bytes, pad: bool = True) -> None:
        self.bus.send(can.Message(arbitration_id=MASTER_ID, is_extended_id=False, data=cto.ljust(8, b"\0") if pad else cto))

    def responses(self, timeout_s: float = 0.15) -> list[bytes]:
        """Every response frame until the bus stays quiet for ``timeout_s``."""
        out = []
        while (message := self.bus.recv(timeout_s)) is not None:
            if message.arbitration_id == SLAVE_ID:
                out.append(bytes(message.data))
        return out

    def request(self, cto: bytes, pad: bool = True) -> list[bytes]:
        self.send(cto, pad)
        return self.responses()

    def close(self) -> None:
        self.bus.shutdown()

    def __enter__(self) -> RawMaster:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()
