"""The simulated ECU's CAN2 driver: RX mailboxes with their status, TX of what the application hands over.

Messages, DLCs and RX timeouts come from the DBC (``GenMsgTimeoutTime``, 300 ms for the
FLCU), seen from the ECU's node. The RX status semantics are the C driver's
(docs/demo-ecu.md, CANRX): ``dlc``/``data`` hold the last frame with the configured DLC;
``dlc_error`` says the last frame had another DLC; ``timeout`` that no good frame came
for the timeout since power-on or the last good one; ``new_data_received`` that a good
frame arrived since the previous read (the read clears it); ``channel_id_error`` is set
only by :meth:`Can2Driver.inject_channel_id_error`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import can

from workbench.can.dbc_file import DbcFile
from workbench.can.model import Message, Role, messages_of
from workbench.errors import UnknownSymbolError
from workbench.sim.flcu.hardware import RxPduInfo

__all__ = ["Can2Driver"]

NETWORK = "CAN2"


@dataclass
class _RxMailbox:
    message: Message
    dlc: int = 0
    data: bytes = bytes(8)
    dlc_error: bool = False
    last_good_s: float = 0.0
    new_data: bool = False
    channel_id_error: bool = False


class Can2Driver:
    """RX/TX of one node's CAN2 messages; ``clock()`` is the ECU's time in seconds.

    Assign :attr:`transmit` to put frames on the bus (the simulator does).
    """

    def __init__(self, dbc: DbcFile, node: str, clock: Callable[[], float]):
        self._clock = clock
        messages = messages_of(dbc, NETWORK, node)
        self._rx = {m.name: _RxMailbox(m) for m in messages if m.role is Role.RX}
        self._tx = {m.name: m for m in messages if m.role is Role.TX}
        self._rx_by_id = {(m.message.frame_id, m.message.extended): m for m in self._rx.values()}
        self.transmit: Callable[[can.Message], None] = lambda message: None
        self.reset()

    @property
    def rx_messages(self) -> list[Message]:
        return [box.message for box in self._rx.values()]

    @property
    def tx_messages(self) -> list[Message]:
        return list(self._tx.values())

    def reset(self) -> None:
        """Power-on: empty mailboxes, the RX timeouts start counting now."""
        now = self._clock()
        for name, box in self._rx.items():
            self._rx[name] = _RxMailbox(box.message, last_good_s=now)
        self._rx_by_id = {(m.message.frame_id, m.message.extended): m for m in self._rx.values()}

    def receive(self, frame: can.Message) -> bool:
        """Take a frame from the bus; returns False when it is not one of the node's RX messages."""
        box = self._rx_by_id.get((frame.arbitration_id, frame.is_extended_id))
        if box is None or frame.is_remote_frame or frame.is_error_frame:
            return False
        if frame.dlc != box.message.dlc:
            box.dlc_error = True
            return True
        box.dlc, box.data = frame.dlc, bytes(frame.data).ljust(8, b"\0")
        box.dlc_error = False
        box.last_good_s = self._clock()
        box.new_data = True
        return True

    def inject_channel_id_error(self, message_name: str, active: bool = True) -> None:
        """Make the driver report ``channel_id_error`` for a message (the frame came on another channel)."""
        self._mailbox(message_name).channel_id_error = active

    def _mailbox(self, name: str) -> _RxMailbox:
        try:
            return self._rx[name]
        except KeyError:
            raise UnknownSymbolError(name, f"{NETWORK} RX messages") from None

    # --- the BSW API the application calls ----------------------------------------------------

    def can_get_rx_pdu(self, message_name: str) -> RxPduInfo:
        box = self._mailbox(message_name)
        timeout_s = (box.message.timeout_ms or 0) / 1000
        info = RxPduInfo(
            dlc=box.dlc,
            data=box.data,
            dlc_error=box.dlc_error,
            timeout=bool(timeout_s) and self._clock() - box.last_good_s > timeout_s,
            new_data_received=box.new_data,
            channel_id_error=box.channel_id_error,
        )
        box.new_data = False
        return info

    def can_set_tx_pdu(self, message_name: str, dlc: int, data: bytes) -> None:
        try:
            message = self._tx[message_name]
        except KeyError:
            raise UnknownSymbolError(message_name, f"{NETWORK} TX messages") from None
        self.transmit(can.Message(
            arbitration_id=message.frame_id, is_extended_id=message.extended, dlc=dlc, data=bytes(data[:dlc]),
        ))
