"""Which XCP slaves answer on a CAN bus, and on which identifiers (:func:`detect_slaves`), for the ``scan`` command
and scripts: the broadcast identifier and bus from the A2L or the caller, the detection of
:mod:`workbench.xcp.detect`, and the A2L's XCP_ON_CAN identifiers held against what the slaves said.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from workbench.a2l import A2lDocument
from workbench.a2l.includes import load_a2l_to_work
from workbench.a2l.xcp import read_xcp_config
from workbench.bus_defaults import BusSpec, open_bus
from workbench.errors import A2lParseError, InputError
from workbench.session.connection import Connection, link_settings
from workbench.session.session import _bus_spec
from workbench.xcp.detect import (
    DEFAULT_WAIT_S,
    DetectedSlave,
    SlaveDetection,
    SlaveIdentity,
    detect_can_slaves,
    identify_slave,
)
from workbench.xcp_protocol import CanId

__all__ = ["Detection", "detect_slaves"]

# the CLI's words (the window's scan always gives the broadcast id, with no A2L to read)
_WITHOUT_A2L = "; to scan without it, give --broadcast-id ID instead of --a2l"


@dataclass(frozen=True)
class Detection:
    """A detection (:attr:`found`), each slave's short session when asked for (:attr:`identities`), and the A2L's
    CAN_ID_MASTER/CAN_ID_SLAVE when an A2L was read (:attr:`a2l_ids`)."""

    found: SlaveDetection
    identities: tuple[SlaveIdentity, ...] = ()
    a2l_ids: tuple[CanId, CanId] | None = None

    @property
    def slaves(self) -> tuple[DetectedSlave, ...]:
        return self.found.slaves

    @property
    def a2l_slave(self) -> DetectedSlave | None:
        """The slave that answered on the A2L's identifiers (None: none did, or no A2L)."""
        return next((slave for slave in self.slaves if (slave.command_id, slave.response_id) == self.a2l_ids), None)

    def to_dict(self) -> dict[str, Any]:
        a2l = None
        if self.a2l_ids is not None:
            a2l = {"can_id_master": self.a2l_ids[0].a2l, "can_id_slave": self.a2l_ids[1].a2l,
                   "answered": self.a2l_slave is not None}
        identities = {identity.slave: identity.to_dict() for identity in self.identities}
        return {**self.found.to_dict(), "slaves": [identities.get(slave, slave.to_dict()) for slave in self.slaves],
                "a2l": a2l}


def detect_slaves(a2l: str | Path | A2lDocument | None = None, *, interface: str | None = None,
                  channel: str | int | None = None, bitrate: int | None = None,
                  bus_kwargs: dict[str, Any] | None = None, bus=None, broadcast_id: CanId | int | None = None,
                  wait_s: float = DEFAULT_WAIT_S, identify: bool = False, byte_order: str | None = None,
                  module: str | None = None) -> Detection:
    """The XCP on CAN slaves that answer GET_SLAVE_ID on the broadcast identifier, as CANape's "detect devices".

    :param a2l: the A2L whose XCP_ON_CAN gives the broadcast id (CAN_ID_BROADCAST) and the bit rate, whose
        PROTOCOL_LAYER gives XCP's byte order, and whose CAN_ID_MASTER/SLAVE are held against the answers;
        default: the demo ECU's when no ``broadcast_id`` is given, else none.
    :param interface, channel, bitrate, bus_kwargs: python-can's bus options; or ``bus``: a
        :class:`~workbench.bus_defaults.BusSpec` or an open python-can bus (it stays the caller's). Default: the
        bus ``workbench sim`` serves on.
    :param broadcast_id: the broadcast identifier (an A2L number: bit 31 for extended), instead of the A2L's.
    :param wait_s: how long each of the two requests collects answers.
    :param identify: also CONNECT to each slave that confirmed its ids, read GET_ID (text, EPK) and GET_DAQ_ID,
        DISCONNECT.
    :param byte_order: "<" (Intel) or ">" (Motorola) for the identifier in the answers; default: the A2L's
        PROTOCOL_LAYER BYTE_ORDER, Intel without an A2L.
    :raises InputError: no broadcast id known, bad bus options. :raises WorkbenchError: the bus cannot be used.
    """
    doc = _document(a2l, broadcast_id)
    given = _bus_spec(bus, {"interface": interface, "channel": channel, "bitrate": bitrate, **(bus_kwargs or {})})
    opened = bus if bus is not None and not isinstance(bus, BusSpec) else None
    spec, a2l_ids, fd = given, None, bool(given and given.fd)  # CAN FD requests on a bus opened for CAN FD
    if doc is not None:
        try:
            config = read_xcp_config(doc, module)
        except A2lParseError as exc:  # no IF_DATA XCP (or a malformed one): a bus is scanned without any A2L too
            raise A2lParseError(f"{exc.reason}{_WITHOUT_A2L}", exc.path, exc.line, exc.column) from None
        if config.can is None:
            raise InputError(f"{doc.path or 'the A2L'}: IF_DATA XCP has no XCP_ON_CAN block; slaves are detected "
                             f"on CAN only{_WITHOUT_A2L}")
        settings, on_can = link_settings(config, Connection(given, open_bus=opened is not None))
        spec, fd, a2l_ids = settings.bus, settings.fd, (settings.can_id_master, settings.can_id_slave)
        broadcast_id = broadcast_id if broadcast_id is not None else config.can.can_id_broadcast
        byte_order = byte_order or (">" if on_can.byte_order.startswith("MSB_FIRST") else "<")
    if broadcast_id is None:
        raise InputError(f"{doc.path if doc is not None and doc.path else 'the A2L'}: XCP_ON_CAN has no "
                         "CAN_ID_BROADCAST; give the broadcast identifier: --broadcast-id ID")
    if not isinstance(broadcast_id, CanId):
        broadcast_id = CanId.from_a2l(broadcast_id)
    spec = spec or BusSpec()
    can_bus = opened or open_bus(spec.kwargs())
    try:
        found = detect_can_slaves(can_bus, broadcast_id, wait_s=wait_s, byte_order=byte_order or "<", fd=fd,
                                  describe=spec.describe() if opened is None else None)
        # CONNECT only where a slave confirmed its ids (the inverse echo): never on an id a stray frame named
        identities = tuple(identify_slave(can_bus, slave, fd=fd) for slave in found.slaves
                           if identify and slave.confirmed)
    finally:
        if opened is None:
            can_bus.shutdown()
    return Detection(found, identities, a2l_ids)


def _document(a2l: str | Path | A2lDocument | None, broadcast_id: CanId | int | None) -> A2lDocument | None:
    if isinstance(a2l, A2lDocument):
        return a2l
    if a2l is None and broadcast_id is not None:
        return None  # a bus of unknown slaves: no A2L claims anything
    from workbench import demo

    return load_a2l_to_work(a2l or demo.a2l())

