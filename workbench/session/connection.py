"""How a session reaches the ECU: the A2L's IF_DATA XCP, overridden by what the caller says.

XCP on CAN takes one :class:`~workbench.bus_defaults.BusSpec` (python-can's ``interface``, ``channel``,
``bitrate`` and any backend keyword: udp_multicast's ``port``, Vector's ``app_name`` ...). XCP on Ethernet
takes ``host``, ``port`` and ``protocol`` ("udp"/"tcp"). Without any of them, the A2L decides: its
XCP_ON_CAN ids on the default bus (udp_multicast on 239.74.163.2, where ``workbench sim`` serves), or its
XCP_ON_UDP_IP/TCP_IP address when it has no XCP on CAN. The A2L completes the bus: its BAUDRATE for a
hardware interface given none, CAN FD with its data bit rate where it has a CAN_FD block. DAQ lists its
DAQ_LIST_CAN_ID calls VARIABLE are moved to the ids the caller gives (``daq_can_ids``), else to CAN_ID_SLAVE.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from workbench.a2l.xcp import XcpConfig, XcpOnCan
from workbench.bus_defaults import BusSpec
from workbench.errors import InputError
from workbench.xcp.link import LinkSettings
from workbench.xcp.master import Timeouts
from workbench.xcp_protocol import CanId

__all__ = ["Connection", "assigned_daq_can_ids", "daq_can_ids_of", "link_settings", "parse_daq_can_ids", "timeouts_of"]


@dataclass(frozen=True)
class Connection:
    """The caller's overrides; None means "as the A2L says" (or the default bus)."""

    bus: BusSpec | None = None
    host: str | None = None
    port: int | None = None
    protocol: str | None = None  # "udp" or "tcp"
    open_bus: bool = False  # XCP on CAN goes on a python-can bus the caller opened (``bus`` is None then)
    daq_can_ids: tuple[tuple[int, CanId], ...] = ()  # (DAQ list, CAN id) the master sets with SET_DAQ_ID

    @property
    def wants_ethernet(self) -> bool:
        return bool(self.host or self.port or self.protocol)


def link_settings(config: XcpConfig, connection: Connection) -> tuple[LinkSettings, XcpConfig]:
    """The link settings and the XCP configuration of the transport chosen (its own PROTOCOL_LAYER/DAQ/PGM).

    :raises InputError: the A2L describes no transport that fits the request.
    """
    if (connection.bus is not None or connection.open_bus) and connection.wants_ethernet:
        if connection.port is not None and not connection.host:  # udp_multicast's own port, meant
            raise InputError(f"port={connection.port} (--port) is XCP on Ethernet's, beside host= (--host); the port "
                             f"of a udp_multicast CAN bus goes in bus_kwargs={{'port': {connection.port}}} "
                             f"(--bus-kwargs port={connection.port})")
        raise InputError("give either CAN options (--interface/--channel) or Ethernet ones (--host/--port/--protocol)")
    ethernet = connection.wants_ethernet or (config.can is None and (config.udp or config.tcp) is not None
                                             and connection.bus is None and not connection.open_bus)
    if ethernet and connection.daq_can_ids:
        raise InputError("DAQ lists' CAN ids (daq_can_ids, --daq-can-id) are XCP on CAN's; this is XCP on Ethernet")
    if ethernet:
        return _ethernet(config, connection)
    return _can(config, connection)


def _can(config: XcpConfig, connection: Connection) -> tuple[LinkSettings, XcpConfig]:
    can = config.can
    if can is None:
        raise InputError("the A2L has no XCP_ON_CAN block and names no Ethernet address: connect by XCP on Ethernet "
                         "with the ECU's host and port (--host/--port; in the window: ECU > Connection…)")
    fd = (can.max_dlc or 8) > 8  # the A2L's CAN_FD block: frames of up to MAX_DLC bytes
    bus = None if connection.open_bus else _completed(connection.bus or BusSpec(), can, fd)
    settings = LinkSettings("CAN", bus, can.can_id_master, can.can_id_slave, can.max_dlc_required,
                            tuple(item.can_id for item in can.daq_list_can_ids if item.can_id is not None),
                            fd=fd, max_dlc=can.max_dlc if fd else 8,
                            assigned_daq_can_ids=assigned_daq_can_ids(can, dict(connection.daq_can_ids)))
    return settings, _for_transport(config, "CAN")


def parse_daq_can_ids(text: str) -> dict[int, int]:
    """``1=0x7F6 2=0x80012345`` (spaces or commas between) -> {1: 0x7F6, 2: 0x80012345}: DAQ list numbers and CAN ids
    as the A2L writes them (bit 31: extended), as ``--daq-can-id`` and the window's connection take them.

    :raises InputError: an item that is not LIST=ID.
    """
    pairs = {}
    for item in text.replace(",", " ").split():
        number, separator, can_id = item.partition("=")
        try:
            if not separator:
                raise ValueError
            pairs[int(number, 0)] = int(can_id, 0)
        except ValueError:
            raise InputError(f"DAQ list CAN id {item!r}: give LIST=ID, e.g. 1=0x7F6") from None
    return pairs


def daq_can_ids_of(given: Mapping[int, int | CanId]) -> tuple[tuple[int, CanId], ...]:
    """(DAQ list, CAN id) pairs from a mapping of list numbers to ids: :class:`CanId` or numbers as the A2L writes
    them (bit 31: extended).

    :raises InputError: a list number or an id out of range.
    """
    pairs = []
    for number, can_id in given.items():
        if not 0 <= int(number) <= 0xFFFF:
            raise InputError(f"DAQ list {number}: list numbers are 0..65535")
        try:
            pairs.append((int(number), can_id if isinstance(can_id, CanId) else CanId.from_a2l(int(can_id))))
        except ValueError as exc:
            raise InputError(f"DAQ list {number}'s CAN id: {exc}") from None
    return tuple(sorted(pairs))


def assigned_daq_can_ids(can: XcpOnCan, given: Mapping[int, CanId]) -> tuple[tuple[int, CanId], ...]:
    """The DAQ lists the master moves with SET_DAQ_ID, and where: each list the A2L's DAQ_LIST_CAN_ID calls VARIABLE
    to the id ``given`` for it, else to CAN_ID_SLAVE (where the slave's other DTOs and responses come: no id of
    another node is taken); a list ``given`` an id the A2L does not mention, there too.

    :raises InputError: an id ``given`` for a list whose DAQ_LIST_CAN_ID is FIXED on another id.
    """
    stated = {item.daq_list: item.can_id for item in can.daq_list_can_ids}
    for number, can_id in given.items():
        fixed = stated.get(number)
        if fixed is not None and fixed != can_id:
            raise InputError(f"DAQ list {number} sends on CAN id {fixed} (the A2L's DAQ_LIST_CAN_ID {number} FIXED): "
                             f"it cannot be moved to {can_id}")
    assigned = {number: given.get(number, can.can_id_slave) for number, can_id in stated.items() if can_id is None}
    assigned.update((number, can_id) for number, can_id in given.items() if number not in stated)
    return tuple(sorted(assigned.items()))


def _completed(bus: BusSpec, can: XcpOnCan, fd: bool) -> BusSpec:
    """The bus as the A2L completes it: its BAUDRATE for a hardware interface given none, CAN FD."""
    if bus.bitrate is None and not bus.software:
        bus = bus.with_bitrate(can.baudrate)
    if fd:
        data_bitrate = can.fd_data_baudrate if not bus.software else None
        bus = bus.with_options(fd=True, **({"data_bitrate": data_bitrate} if data_bitrate else {}))
    return bus


def _ethernet(config: XcpConfig, connection: Connection) -> tuple[LinkSettings, XcpConfig]:
    protocol = (connection.protocol or "").upper()
    if protocol and protocol not in ("UDP", "TCP"):
        raise InputError(f"--protocol must be udp or tcp, not {connection.protocol!r}")
    described = {"UDP": config.udp, "TCP": config.tcp}
    if not protocol:
        protocol = "UDP" if config.udp is not None or config.tcp is None else "TCP"
    block = described[protocol]
    host = connection.host or (block.host if block is not None else None)
    port = connection.port or (block.port if block is not None else None)
    if not host or not port:
        raise InputError(f"XCP on {protocol}: the A2L has no XCP_ON_{protocol}_IP address; give --host and --port")
    config = _for_transport(config, protocol) if block is not None else config
    return LinkSettings(protocol, host=host, port=port), config


def _for_transport(config: XcpConfig, transport: str) -> XcpConfig:
    try:
        return config.for_transport(transport)
    except KeyError:
        return config


def timeouts_of(config: XcpConfig) -> Timeouts:
    """The A2L's T1-T7 (seconds), as the master takes them."""
    t = config.timeouts
    return Timeouts(t.t1, t.t2, t.t3, t.t4, t.t5, t.t6, t.t7)
