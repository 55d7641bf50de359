"""One XCP link to an ECU over pyxcp's transport layer: XCP on CAN (any python-can bus) or XCP on Ethernet.

pyxcp frames the packets (the Ethernet header and counter), runs the receive thread and
queues the responses; this module hides every pyxcp quirk behind four calls
(:meth:`Link.exchange`, :meth:`Link.send`, :meth:`Link.receive`, :meth:`Link.close`):

* ``import pyxcp`` installs rich's traceback and display hooks in the interpreter: they are
  put back as they were;
* pyxcp's application object would parse ``sys.argv``: it is built from a dictionary instead;
* its logger gets a rich console handler: removed, so its records go where the user's
  logging sends them (warnings and up);
* its request path raises its own exception classes and builds long diagnostic texts: the
  master (:mod:`workbench.xcp.master`) sends packets itself and reads the responses.

A late response to a command that timed out would be taken for the answer to the next one;
every exchange therefore drops what is queued before it sends.
"""

from __future__ import annotations

import logging
import socket
import sys
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from workbench.errors import InputError, WorkbenchError
from workbench.xcp_protocol import CAN_ID_EXTENDED_FLAG

log = logging.getLogger(__name__)

__all__ = ["Link", "LinkSettings"]

DtoHandler = Callable[[bytes, int], None]  # (packet, host receive time in ns)
_import_lock = threading.Lock()


@dataclass(frozen=True)
class LinkSettings:
    """How to reach the ECU: ``transport`` "CAN", "UDP" or "TCP".

    CAN: ``bus`` is python-can's ``Bus(**bus)`` keyword arguments (``interface``, ``channel``,
    ``bitrate``, and any backend option such as udp_multicast's ``port`` or Vector's
    ``app_name``); ids without the extended flag, ``*_extended`` says which are 29-bit.
    Ethernet: ``host`` and ``port``.
    """

    transport: str = "CAN"
    bus: dict[str, Any] = field(default_factory=dict)
    can_id_master: int = 0
    can_id_slave: int = 0
    can_id_master_extended: bool = False
    can_id_slave_extended: bool = False
    max_dlc_required: bool = False
    daq_can_ids: tuple[tuple[int, bool], ...] = ()  # extra ids the slave sends DTOs on (DAQ_LIST_CAN_ID)
    host: str | None = None
    port: int | None = None

    def describe(self) -> str:
        if self.transport == "CAN":
            where = " ".join(str(self.bus[k]) for k in ("interface", "channel") if self.bus.get(k) is not None)
            return f"XCP on CAN ({where or 'bus'}, ids 0x{self.can_id_master:X}/0x{self.can_id_slave:X})"
        return f"XCP on {self.transport} ({self.host}:{self.port})"


def _pyxcp():
    """pyxcp's modules, imported without the hooks and console logging its package installs."""
    with _import_lock:
        hooks = sys.excepthook, sys.displayhook
        try:
            import pyxcp.config
            import pyxcp.transport.can
            import pyxcp.transport.eth
            from pyxcp.transport.transport_ext import FrameCategory
        finally:
            sys.excepthook, sys.displayhook = hooks
    return pyxcp.config, pyxcp.transport.can, pyxcp.transport.eth, FrameCategory


def _lighten(transport) -> None:
    """Attach the transport to no master, and skip the diagnostic record pyxcp formats (a hex dump) for
    every frame it receives: at a saturated bus's 8,000 DTOs a second that costs a good share of a core."""
    transport.parent = _Service()
    transport._record_pdu = lambda *args, **kwargs: None


UDP_RECEIVE_BUFFER = 4 << 20  # bytes: a second of a saturated bus as udp_multicast datagrams


def _widen_udp_receive_buffer(bus) -> None:
    """udp_multicast carries each CAN frame as a datagram: with the kernel's default buffer (about 200 kB,
    ~270 frames) a busy interpreter pausing for 30 ms at a saturated bus's 8,000 frames/s loses frames."""
    sock = getattr(getattr(bus, "_multicast", None), "_socket", None)  # python-can keeps it private
    if sock is not None:
        try:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, UDP_RECEIVE_BUFFER)
        except OSError:  # capped by the system (net.core.rmem_max): keep what it gives
            log.debug("could not widen the udp_multicast receive buffer", exc_info=True)


def _quiet_pyxcp_logging() -> None:
    logger = logging.getLogger("pyxcp")
    for handler in list(logger.handlers):
        logger.removeHandler(handler)
    logger.setLevel(logging.WARNING)
    logger.propagate = True


class _Policy:
    """pyxcp's frame sink: passes DTOs on, drops everything else (pyxcp calls ``feed`` from Python)."""

    def __init__(self, daq_category):
        self._daq = daq_category
        self.handler: DtoHandler | None = None

    def feed(self, category, counter, timestamp, payload) -> None:
        handler = self.handler
        if handler is not None and category == self._daq:
            handler(payload, timestamp)

    def finalize(self, *args) -> None:
        pass


class _Service:
    """What pyxcp's transport expects of its parent master."""

    def _setService(self, service) -> None:  # noqa: N802 (pyxcp's name)
        pass


class Link:
    """An open XCP link. ``bus`` (CAN only) is a python-can bus the caller owns and keeps open."""

    def __init__(self, settings: LinkSettings, bus=None):
        self.settings = settings
        self._bus = bus
        self._owned_bus = None
        self._transport = None
        self._policy = None
        self._lock = threading.Lock()
        self.closed = False
        self.open()

    @property
    def is_can(self) -> bool:
        return self.settings.transport == "CAN"

    def open(self) -> None:
        config_module, can_module, eth_module, frame_category = _pyxcp()
        self._policy = _Policy(frame_category.DAQ)
        try:
            if self.is_can:
                self._transport = self._open_can(config_module, can_module)
            else:
                self._transport = self._open_ethernet(config_module, eth_module)
        except BaseException:
            self.close()
            raise
        finally:
            _quiet_pyxcp_logging()

    def _application(self, config_module, transport: dict[str, dict]):
        app = config_module.create_application_from_config({"Transport": transport}, log_level=logging.WARNING)
        _quiet_pyxcp_logging()
        app.transport.create_daq_timestamps = True  # host receive time of every DTO, for the clock mapping
        return app

    def _open_can(self, config_module, can_module):
        settings = self.settings
        if self._bus is None:
            self._owned_bus = self._bus = open_bus(settings.bus)
            _widen_udp_receive_buffer(self._bus)
        flag = CAN_ID_EXTENDED_FLAG
        app = self._application(config_module, {"CAN": {
            "can_id_master": settings.can_id_master | (flag if settings.can_id_master_extended else 0),
            "can_id_slave": settings.can_id_slave | (flag if settings.can_id_slave_extended else 0),
            "max_dlc_required": settings.max_dlc_required,
            "padding_value": 0,
        }})
        transport = can_module.Can(app.transport, policy=self._policy, transport_layer_interface=self._bus)
        _lighten(transport)
        transport.connect()
        if settings.daq_can_ids:  # accept DTOs on their own ids; pyxcp's daq_identifier would prepend a PID
            ids = [can_module.Identifier(ident | (flag if extended else 0)) for ident, extended in settings.daq_can_ids]
            transport.can_interface.update_daq_filters(ids)
        return transport

    def _open_ethernet(self, config_module, eth_module):
        settings = self.settings
        if not settings.host or not settings.port:
            raise InputError(f"XCP on {settings.transport} needs a host and a port")
        app = self._application(config_module, {"Eth": {
            "host": settings.host, "port": settings.port, "protocol": settings.transport, "tcp_nodelay": True,
        }})
        try:
            transport = eth_module.Eth(app.transport, policy=self._policy)
            _lighten(transport)
            transport.connect()
        except OSError as exc:
            raise WorkbenchError(f"cannot reach the ECU at {settings.host}:{settings.port} "
                                 f"({settings.transport}): {exc.strerror or exc}") from None
        except Exception as exc:  # pyxcp raises a bare Exception when the address does not resolve
            raise WorkbenchError(f"cannot reach the ECU at {settings.host}:{settings.port}: {exc}") from None
        return transport

    # --- packets ------------------------------------------------------------------------------

    @property
    def dto_handler(self) -> DtoHandler | None:
        return self._policy.handler if self._policy is not None else None

    @dto_handler.setter
    def dto_handler(self, handler: DtoHandler | None) -> None:
        self._policy.handler = handler

    def exchange(self, packet: bytes, timeout_s: float, *, drop_queued: bool = True) -> bytes | None:
        """Send a command packet (PID first) and return the next response or error packet, None on timeout.

        ``drop_queued``: forget responses that came late before sending (False for the last frame of a
        master block, whose early error response must not be lost).
        """
        with self._lock:
            if self._transport is None or self.closed:
                raise WorkbenchError("the XCP link is closed")
            if drop_queued:
                self._drop_queued()
            self._send(packet)
            return self._receive(timeout_s)

    def send(self, packet: bytes) -> None:
        """Send a packet that gets no response (the leading frames of a master block)."""
        with self._lock:
            self._send(packet)

    def receive(self, timeout_s: float) -> bytes | None:
        """The next response packet (slave block mode, a response that came late), None on timeout."""
        with self._lock:
            return self._receive(timeout_s)

    def _send(self, packet: bytes) -> None:
        transport = self._transport
        if transport is None or self.closed:
            raise WorkbenchError("the XCP link is closed")
        frame = transport.framing.prepare_request(packet[0], bytes(packet[1:]))
        try:
            transport.send(frame)
        except OSError as exc:
            raise WorkbenchError(f"cannot send to the ECU ({self.settings.describe()}): {exc}") from None
        except Exception as exc:  # python-can's CanOperationError and friends
            raise WorkbenchError(f"cannot send to the ECU ({self.settings.describe()}): {exc}") from None

    def _receive(self, timeout_s: float) -> bytes | None:
        transport = self._transport
        condition, queue = transport.resQueue_condition, transport.resQueue
        with condition:
            if not queue and (timeout_s <= 0 or not condition.wait_for(lambda: bool(queue), timeout_s)):
                return None
            return bytes(queue.popleft())

    def _drop_queued(self) -> None:
        transport = self._transport
        with transport.resQueue_condition:
            if transport.resQueue:
                log.debug("dropping %d late response(s)", len(transport.resQueue))
                transport.resQueue.clear()

    def close(self) -> None:
        """Stop the receive thread and close what this link opened; safe to call twice."""
        if self.closed:
            return
        self.closed = True
        if self._policy is not None:
            self._policy.handler = None
        transport, self._transport = self._transport, None
        if transport is not None:
            try:
                transport.close()
                # pyxcp does not wait for its receive thread: a bus shut under it logs a bad file descriptor
                if transport.listener.is_alive():
                    transport.listener.join(timeout=1.0)
            except Exception:  # closing must not fail a session that is going away
                log.debug("closing the pyxcp transport failed", exc_info=True)
        if self._owned_bus is not None:
            self._owned_bus.shutdown()

    def __enter__(self) -> Link:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()


def open_bus(config: dict[str, Any]):
    """A python-can bus from ``Bus(**config)`` keyword arguments, errors as one line.

    :raises InputError: an unknown interface (naming the known ones).
    :raises WorkbenchError: the bus cannot be opened (driver missing, device busy ...).
    """
    import can

    interface = config.get("interface")
    if interface not in can.interfaces.VALID_INTERFACES:
        raise InputError(f"unknown python-can interface {interface!r} "
                         f"(known: {', '.join(sorted(can.interfaces.VALID_INTERFACES))})")
    try:
        return can.Bus(**config)
    except (can.CanError, OSError, ValueError, ImportError, TypeError) as exc:
        where = f"{interface} {config.get('channel', '')}".strip()
        raise WorkbenchError(f"cannot open the CAN bus ({where}): {exc}") from None
