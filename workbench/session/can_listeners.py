"""The CAN frames a session's tools listen to (a recorder, the window's CAN monitor, ``measure``'s CAN2 view),
through one python-can :class:`~can.Notifier` a bus, never a second bus object on the same channel.

On the session's own XCP on CAN bus the listeners join the link's Notifier (the link keeps it running, and lets
every frame through, while they listen); another bus (CAN2 on a channel of its own, XCP on Ethernet) is opened
once for all its listeners, with one Notifier, and closed when the last one leaves or the session closes::

    listening = ecu.listen_can(lambda frame: print(frame))            # the XCP bus
    listening = ecu.listen_can(recorder_queue, BusSpec("virtual", "can2"))  # another bus, shared
    listening.close()
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from workbench.bus_defaults import BusSpec
from workbench.errors import InputError, WorkbenchError
from workbench.logs import logger

if TYPE_CHECKING:
    import can

    from workbench.xcp.link import Link

log = logger(__name__)

__all__ = ["CanListeners", "Listening"]

Listener = Callable[["can.Message"], Any]  # a python-can Listener, or any callable taking a Message
_POLL_S = 0.1  # how long the Notifier of a bus of its own waits before it looks whether it should stop


class Listening:
    """One listener on one bus; :meth:`close` takes it off (the bus closes with its last listener)."""

    def __init__(self, owner: CanListeners, tap: _Tap, listener: Listener):
        self._owner, self._tap, self.listener = owner, tap, listener
        self.closed = False

    @property
    def bus(self) -> can.BusABC:
        """The python-can bus listened to."""
        return self._tap.bus

    def describe(self) -> str:
        """``udp_multicast 239.74.163.2 port 43200``: the bus, for people and file headers."""
        return self._tap.describe()

    @property
    def fd(self) -> bool:
        return self._tap.fd

    def close(self) -> None:
        if not self.closed:
            self.closed = True
            self._owner._remove(self._tap, self.listener)

    def __enter__(self) -> Listening:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()


class _Tap:
    """A bus and its listeners."""

    bus: Any

    def add(self, listener: Listener) -> None:
        raise NotImplementedError

    def remove(self, listener: Listener) -> bool:
        """Take ``listener`` off; whether listeners are left."""
        raise NotImplementedError

    def describe(self) -> str:
        raise NotImplementedError

    fd = False

    def close(self) -> None:
        raise NotImplementedError


class _LinkTap(_Tap):
    """The session's XCP on CAN bus: the listeners join the link's Notifier."""

    def __init__(self, link: Link):
        self.link = link
        self.bus = link.can_bus
        self.fd = link.settings.fd or bool(link.settings.bus is not None and link.settings.bus.fd)
        self._listeners: list[Listener] = []

    def add(self, listener: Listener) -> None:
        self.link.add_listener(listener)
        self._listeners.append(listener)

    def remove(self, listener: Listener) -> bool:
        self._listeners.remove(listener)
        self.link.remove_listener(listener)
        return bool(self._listeners)

    def describe(self) -> str:
        spec = self.link.settings.bus
        return spec.describe() if spec is not None else str(self.bus.channel_info)

    def close(self) -> None:
        for listener in list(self._listeners):
            self.remove(listener)


class _BusTap(_Tap):
    """A bus of its own (``spec`` opened here, or a bus the caller opened) with one Notifier for its listeners."""

    def __init__(self, spec: BusSpec | None, bus: can.BusABC | None = None):
        import can

        from workbench.xcp.transport.can import open_bus, widen_udp_receive_buffer

        self.spec = spec
        self.fd = spec.fd if spec is not None else "FD" in str(getattr(bus, "protocol", ""))
        self._owned = bus is None
        self.bus = open_bus(spec.kwargs(), "CAN2") if bus is None else bus
        if self._owned:
            widen_udp_receive_buffer(self.bus)  # raw logging of a saturated bus: ride out the listeners' pauses
        self._notifier = can.Notifier(self.bus, [], timeout=_POLL_S)

    def add(self, listener: Listener) -> None:
        self._notifier.add_listener(listener)

    def remove(self, listener: Listener) -> bool:
        self._notifier.remove_listener(listener)
        return bool(self._notifier.listeners)

    def describe(self) -> str:
        return self.spec.describe() if self.spec is not None else str(self.bus.channel_info)

    def close(self) -> None:
        self._notifier.stop(timeout=2 * _POLL_S + 1.0)
        if self._owned:
            self.bus.shutdown()


class CanListeners:
    """A session's CAN listeners, one tap (bus + Notifier) per bus."""

    def __init__(self, link: Link):
        self.link = link
        self._taps: dict[Any, _Tap] = {}
        self._lock = threading.Lock()

    def add(self, listener: Listener, bus: BusSpec | can.BusABC | None = None) -> Listening:
        """Hand every frame of ``bus`` to ``listener`` (a python-can Listener or a callable) from the bus's one
        receive thread; ``bus`` None (or the session's own bus spec): the XCP bus.

        :raises InputError: ``bus`` None on a session whose XCP does not run on CAN (name the bus then).
        :raises WorkbenchError: the bus cannot be opened.
        """
        with self._lock:
            key, make = self._tap_for(bus)
            tap = self._taps.get(key)
            if tap is None:
                tap = self._taps[key] = make()
            try:
                tap.add(listener)
            except BaseException:
                self._drop_if_unused(key, tap)
                raise
        return Listening(self, tap, listener)

    def _tap_for(self, bus: BusSpec | can.BusABC | None) -> tuple[Any, Callable[[], _Tap]]:
        link = self.link
        own = link.settings.bus
        if bus is None or (own is not None and bus == own) or (link.is_can and bus is link.can_bus):
            if not link.is_can:
                raise InputError(f"the session runs {link.describe()}: name the CAN2 bus "
                                 "(--can2-interface/--can2-channel, a BusSpec)")
            return "xcp", lambda: _LinkTap(link)
        if isinstance(bus, BusSpec):
            return ("spec", tuple(sorted(map(str, bus.kwargs().items())))), lambda: _BusTap(bus)
        return ("bus", id(bus)), lambda: _BusTap(None, bus)

    def _remove(self, tap: _Tap, listener: Listener) -> None:
        with self._lock:
            try:
                left = tap.remove(listener)
            except (ValueError, WorkbenchError):  # gone already (the session closed first)
                left = True
            if not left:
                key = next((key for key, known in self._taps.items() if known is tap), None)
                if key is not None:
                    self._drop_if_unused(key, tap)

    def _drop_if_unused(self, key: Any, tap: _Tap) -> None:
        del self._taps[key]
        try:
            tap.close()
        except Exception:  # closing must not fail the caller who leaves
            log.debug("closing a CAN listener's bus failed", exc_info=True)

    def close(self) -> None:
        """Stop every listener and close the buses opened for them (before the link closes)."""
        with self._lock:
            taps, self._taps = list(self._taps.values()), {}
        for tap in taps:
            try:
                tap.close()
            except Exception:
                log.debug("closing a CAN listener's bus failed", exc_info=True)
