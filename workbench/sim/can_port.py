"""The simulated ECU on python-can buses: the buses themselves (:class:`CanBuses`) and XCP on CAN
(:class:`CanXcpPort`), with XCP on CAN's own commands (TRANSPORT_LAYER_CMD GET_SLAVE_ID, GET_DAQ_ID, SET_DAQ_ID).

Buses are given by role, ``CAN1`` (XCP on CAN) and ``CAN2`` (the FLCU messages), as python-can
settings (opened here, shut down at close) or as open buses (the caller's). Two roles may share
one bus. Each distinct bus gets one receiver thread and one transmitter, paced by the bus timing
model when a bit rate is given.
"""

from __future__ import annotations

import logging
import struct
import time
from collections.abc import Callable, Mapping
from typing import Any

import can

from workbench.bus_defaults import open_bus
from workbench.logs import logger
from workbench.sim.bus import ECHOING_INTERFACES, EchoFilter, Receiver, Transmitter
from workbench.sim.can_timing import BusClock
from workbench.sim.ecu import EcuState, SimulatedEcu
from workbench.sim.xcp_port import XcpPort
from workbench.xcp_protocol import (
    PID_ERR,
    PID_RES,
    SLAVE_ID_ECHO,
    CanCmd,
    CanId,
    Cmd,
    Err,
    SlaveIdMode,
)

__all__ = ["BusSpec", "CanBuses", "CanXcpPort"]

log = logger(__name__)

MAX_DLC = 8  # classic CAN
MAX_FD_DLC = 64
FD_LENGTHS = (12, 16, 20, 24, 32, 48, 64)  # CAN FD data lengths beyond 8

BusSpec = can.BusABC | Mapping[str, Any]
_TRANSPORT_LAYER_CMD = bytes((Cmd.TRANSPORT_LAYER_CMD,))
_GET_SLAVE_ID = bytes((Cmd.TRANSPORT_LAYER_CMD, CanCmd.GET_SLAVE_ID))


class CanBuses:
    """The buses by role; frames received go to ``on_frame(role, message)`` (the first role of a shared bus)."""

    def __init__(self, specs: Mapping[str, BusSpec | None], bitrate: int | None = None):
        self._specs = {name: spec for name, spec in specs.items() if spec is not None}
        self.bitrate = bitrate
        self._buses: dict[str, can.BusABC] = {}
        self._owned: list[can.BusABC] = []
        self._transmitters: dict[str, Transmitter] = {}
        self._receivers: list[Receiver] = []

    def open(self, on_frame: Callable[[str, can.Message], None]) -> None:
        """Open the buses given as settings and start their threads.

        :raises InputError: an interface python-can does not know (the message names the known ones), or options
            it refuses (a ValueError or TypeError of python-can's).
        :raises WorkbenchError: a bus cannot be opened (the message names the role and the interface).
        """
        for name, spec in self._specs.items():
            self._buses[name] = spec if isinstance(spec, can.BusABC) else self._open(name, spec)
        for name, bus in self._distinct():
            clock = BusClock(self.bitrate) if self.bitrate else None
            echoes = EchoFilter() if self._echoes(name, bus) else None
            self._transmitters[name] = Transmitter(bus, clock, name, echoes)
            self._receivers.append(Receiver(bus, lambda message, role=name: on_frame(role, message), clock, name, echoes))
        for name, bus in self._buses.items():  # a role sharing a bus sends through that bus's transmitter
            if name not in self._transmitters:
                self._transmitters[name] = next(self._transmitters[other] for other, b in self._distinct() if b is bus)

    def _open(self, name: str, spec: Mapping[str, Any]) -> can.BusABC:
        bus = open_bus(spec, name)
        self._owned.append(bus)
        return bus

    def _echoes(self, name: str, bus: can.BusABC) -> bool:
        spec = self._specs[name]
        interface = spec.get("interface") if isinstance(spec, Mapping) else None
        return interface in ECHOING_INTERFACES or type(bus).__name__ == "UdpMulticastBus"

    def _distinct(self) -> list[tuple[str, can.BusABC]]:
        seen: list[tuple[str, can.BusABC]] = []
        for name, bus in self._buses.items():
            if all(bus is not other for _, other in seen):
                seen.append((name, bus))
        return seen

    def shares(self, name: str, other: str) -> bool:
        """Whether roles ``name`` and ``other`` are one bus."""
        bus = self._buses.get(name)
        return bus is not None and bus is self._buses.get(other)

    def transmitter(self, name: str) -> Transmitter | None:
        return self._transmitters.get(name)

    @property
    def buses(self) -> dict[str, can.BusABC]:
        return dict(self._buses)

    def describe(self) -> dict[str, dict[str, Any]]:
        return {name: dict(spec) if isinstance(spec, Mapping) else {"bus": str(spec)} for name, spec in self._specs.items()}

    def close(self) -> None:
        """Stop the threads and shut down the buses opened here (the caller's stay open)."""
        for receiver in self._receivers:
            receiver.stop()
        for transmitter in set(self._transmitters.values()):
            transmitter.close()
        for bus in self._owned:
            bus.shutdown()


class CanXcpPort(XcpPort):
    """XCP on CAN on the ``CAN1`` role of ``buses``: commands on CAN_ID_MASTER, responses and DTOs on CAN_ID_SLAVE.

    GET_SLAVE_ID is answered on CAN_ID_BROADCAST (when the parameters name one) and on CAN_ID_MASTER, connected or
    not; a request without the ``XCP`` pattern or with another mode goes unanswered, as a slave's CAN driver does,
    and so does an inverse echo (mode 1) without an echo (mode 0) answered before it (the master identifies by echo,
    then confirms by inverse echo; ETAS's XCP slave answers so).
    GET_DAQ_ID answers in a session: a DAQ list's DTOs go on its id of :attr:`XcpParameters.daq_can_ids`
    (DAQ_LIST_CAN_ID FIXED), a list of :attr:`XcpParameters.variable_daq_can_ids` (VARIABLE) on the id
    SET_DAQ_ID last gave it since power-on (before: the one stated there; RAM, as a real slave's), the others' on
    CAN_ID_SLAVE, fixed. SET_DAQ_ID (implemented where a list is VARIABLE; else ERR_CMD_UNKNOWN) refuses a fixed
    list, an id this slave takes commands on and a frame format's impossible id with ERR_OUT_OF_RANGE, a running list
    with ERR_DAQ_ACTIVE.
    Without TRANSPORT_LAYER_CMD (:attr:`XcpParameters.without`) the slave is silent on the broadcast id.

    With MAX_DLC_REQUIRED the slave pads every frame to MAX_DLC (8; 64 on CAN FD) and ignores master
    frames of another length, as AUTOSAR's CanXcp does. On CAN FD (:attr:`XcpParameters.can_fd`) frames
    carry up to 64 bytes with the bit rate switch; a packet is padded to the next length CAN FD has.
    """

    transport = "CAN"

    def __init__(self, ecu: SimulatedEcu, lock, buses: CanBuses):
        super().__init__(ecu, lock)
        self.buses = buses
        self.master_id = ecu.params.can_id_master
        self.slave_id = ecu.params.can_id_slave
        self.broadcast_id = ecu.params.can_id_broadcast
        self.daq_ids: dict[int, CanId] = {}  # where DTOs go now
        self.variable_lists = frozenset(number for number, _ in ecu.params.variable_daq_can_ids)
        self._echoed = False  # GET_SLAVE_ID's echo answered, its inverse echo not yet
        self._power_on()
        ecu.on_power_on.append(self._power_on)
        self.max_dlc = MAX_FD_DLC if ecu.params.can_fd else MAX_DLC
        self._short_frame_seen = False

    def start(self) -> None:
        """Nothing of its own to open: :class:`CanBuses` opens the bus and hands frames to :meth:`on_frame`."""

    def close(self) -> None:
        super().close()
        if self._power_on in self.ecu.on_power_on:
            self.ecu.on_power_on.remove(self._power_on)

    def _power_on(self) -> None:
        """What the transport layer keeps in RAM, as at power-on: the DAQ lists' ids stated (SET_DAQ_ID's are
        forgotten, as a real slave's), no GET_SLAVE_ID echo."""
        params = self.ecu.params
        self.daq_ids = dict(params.daq_can_ids) | dict(params.variable_daq_can_ids)
        self._echoed = False

    def accepts(self, message: can.Message) -> bool:
        return self.master_id.matches(message) or (self.broadcast_id is not None and self.broadcast_id.matches(message))

    def on_frame(self, message: can.Message) -> None:
        if message.is_remote_frame or (self.ecu.params.max_dlc_required and len(message.data) != self.max_dlc):
            # MAX_DLC_REQUIRED binds the master too: a shorter frame is no XCP packet (AUTOSAR CanXcp ignores it)
            level = logging.DEBUG if self._short_frame_seen else logging.WARNING
            self._short_frame_seen = True
            log.log(level, "XCP frame of %d bytes ignored: the A2L says MAX_DLC_REQUIRED, the master must pad to %d",
                    len(message.data), self.max_dlc)
            return
        cto = bytes(message.data)
        if not self.master_id.matches(message) and cto[:2] != _GET_SLAVE_ID:
            return  # on the broadcast id a slave hears GET_SLAVE_ID only
        self.on_command(cto)

    def _command_answer(self, cto: bytes) -> list[bytes]:
        params = self.ecu.params
        if cto[:1] != _TRANSPORT_LAYER_CMD or Cmd.TRANSPORT_LAYER_CMD not in params.transport_commands("CAN"):
            return self.ecu.handle_cto(cto)
        if self.ecu.state is EcuState.OFF or time.monotonic() < self.ecu.slave.silent_until:
            return []
        if cto[:2] == _GET_SLAVE_ID:
            if cto[2:5] != SLAVE_ID_ECHO or len(cto) < 6 or cto[5] not in tuple(SlaveIdMode):
                return []
            mode = SlaveIdMode(cto[5])
            if mode is SlaveIdMode.INVERSE_ECHO and not self._echoed:
                return []  # confirms only what an echo identified, once (ETAS's slave; the master sends both)
            self._echoed = mode is SlaveIdMode.ECHO
            answer_id = struct.pack(params.byte_order + "I", self.master_id.a2l)
            return [bytes((PID_RES,)) + mode.pattern + answer_id]
        if not self.ecu.slave.connected:
            return []
        if cto[1] not in (CanCmd.GET_DAQ_ID, CanCmd.SET_DAQ_ID) or cto[1] not in params.can_sub_commands:
            return [bytes((PID_ERR, Err.CMD_UNKNOWN))]  # a slave with no VARIABLE list implements no SET_DAQ_ID
        setting = cto[1] == CanCmd.SET_DAQ_ID
        if len(cto) < (8 if setting else 4):
            return [bytes((PID_ERR, Err.CMD_SYNTAX))]
        number = struct.unpack_from(params.byte_order + "H", cto, 2)[0]
        if number >= (len(params.daq.static_lists) or params.daq.max_daq):
            return [bytes((PID_ERR, Err.OUT_OF_RANGE))]
        if setting:
            return [self._set_daq_id(number, struct.unpack_from(params.byte_order + "I", cto, 4)[0])]
        can_id = self.daq_ids.get(number, self.slave_id)
        fixed = number not in self.variable_lists
        return [struct.pack(params.byte_order + "BBHI", PID_RES, fixed, 0, can_id.a2l)]

    def _set_daq_id(self, number: int, a2l_id: int) -> bytes:
        """SET_DAQ_ID's answer; a VARIABLE list's DTOs go on the id from now."""
        try:
            can_id = CanId.from_a2l(a2l_id)
        except ValueError:  # reserved bits set, or above 0x7FF without the extended bit
            return bytes((PID_ERR, Err.OUT_OF_RANGE))
        if number not in self.variable_lists or can_id in (self.master_id, self.broadcast_id):
            return bytes((PID_ERR, Err.OUT_OF_RANGE))
        lists = self.ecu.slave.daq.lists
        if number < len(lists) and lists[number].running:
            return bytes((PID_ERR, Err.DAQ_ACTIVE))
        self.daq_ids[number] = can_id
        return bytes((PID_RES,))

    def _frame(self, packet: bytes, can_id: CanId | None = None) -> can.Message:
        fd = self.ecu.params.can_fd
        if self.ecu.params.max_dlc_required:
            packet = packet.ljust(self.max_dlc, b"\0")
        elif fd and len(packet) > MAX_DLC:
            packet = packet.ljust(next(length for length in FD_LENGTHS if length >= len(packet)), b"\0")
        slave = can_id or self.slave_id
        return can.Message(arbitration_id=slave.id, is_extended_id=slave.extended, data=packet, is_fd=fd,
                           bitrate_switch=fd)

    def _transmit_response(self, packet: bytes) -> None:
        self.buses.transmitter("CAN1").send(self._frame(packet))

    def _transmit_dtos(self, packets: list[bytes]) -> bool:
        if self.daq_ids:  # DAQ_LIST_CAN_ID: a list's DTOs on its own id
            daq = self.ecu.slave.daq
            frames = [self._frame(packet, self.daq_ids.get(daq.list_of(packet))) for packet in packets]
        else:
            frames = [self._frame(packet) for packet in packets]
        return self.buses.transmitter("CAN1").send_dtos(frames)

    def describe(self) -> dict[str, Any]:
        params = self.ecu.params
        broadcast = {"can_id_broadcast": params.can_id_broadcast.a2l} if params.can_id_broadcast is not None else {}
        return {"transport": "CAN", "can_id_master": params.can_id_master.a2l, "can_id_slave": params.can_id_slave.a2l,
                **broadcast, "max_cto": params.max_cto, "max_dto": params.max_dto}
