"""The master's XCP transports, one module per kind: XCP on CAN (:mod:`~workbench.xcp.transport.can`, any
python-can bus, CAN FD included) and XCP on Ethernet (:mod:`~workbench.xcp.transport.ethernet`, UDP and TCP),
behind the interface of :mod:`~workbench.xcp.transport.base`. :class:`~workbench.xcp.link.Link` opens one
with :func:`open_transport` and decides which thread reads it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.errors import InputError
from workbench.xcp.transport.base import LinkBroken, Transport

if TYPE_CHECKING:
    import can

    from workbench.xcp.link import LinkSettings

__all__ = ["KINDS", "LinkBroken", "Transport", "open_transport"]

KINDS = ("CAN", "UDP", "TCP")


def open_transport(settings: LinkSettings, bus: can.BusABC | None = None) -> Transport:
    """The transport ``settings.transport`` names, open (a CAN bus on ``bus`` when given).

    :raises InputError: an unknown transport or interface, an Ethernet link without host and port.
    :raises WorkbenchError: the bus cannot be opened, the ECU's address cannot be reached.
    """
    kind = settings.transport.upper()
    if kind == "CAN":
        from workbench.xcp.transport.can import CanTransport

        return CanTransport(settings, bus)
    if kind in ("UDP", "TCP"):
        from workbench.xcp.transport.ethernet import EthernetTransport

        if not settings.host or not settings.port:
            raise InputError(f"XCP on {kind} needs a host and a port")
        return EthernetTransport(kind, settings.host, settings.port)
    raise InputError(f"unknown XCP transport {settings.transport!r} (known: {', '.join(KINDS)})")
