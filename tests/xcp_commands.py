"""What a master sends on a virtual CAN bus, command by command: a second python-can bus on the channel hears it.

::

    with CommandLog(channel) as log:
        ...                       # anything that talks XCP on the channel
        assert log.take() == ["SET_MTA", "DOWNLOAD", "SHORT_UPLOAD"]

python-can's virtual bus hands every frame to the other buses of its channel while it is sent, so
:meth:`take` sees all that was sent before it is called, with no thread and no wait.
"""

from __future__ import annotations

import can

from workbench import demo
from workbench.a2l import load_a2l, read_xcp_config
from workbench.xcp_protocol import Cmd

__all__ = ["CommandLog"]


class CommandLog:
    """The XCP commands (and _NEXT frames of a block) on ``channel``, as the standard names them."""

    def __init__(self, channel: str, a2l=None):
        config = read_xcp_config(load_a2l(a2l or demo.a2l()))
        self.master_id = config.can.can_id_master
        self.bus = can.Bus(interface="virtual", channel=channel)
        self.frames: list[can.Message] = []  # the master's frames of the last take()

    def take(self) -> list[str]:
        """The commands sent since the last take (or since the log was opened)."""
        self.frames = []
        while (message := self.bus.recv(0)) is not None:
            if self.master_id.matches(message):
                self.frames.append(message)
        return [_name(message.data[0]) for message in self.frames]

    def close(self) -> None:
        self.bus.shutdown()

    def __enter__(self) -> CommandLog:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()


def _name(pid: int) -> str:
    try:
        return Cmd(pid).name
    except ValueError:
        return f"0x{pid:02X}"
