"""The CAN bus a workbench command or script uses when it is told none, shared by the master and the simulator.

Neutral ground (it imports nothing): the simulator serves where the master looks by default,
so both take the defaults from here.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

__all__ = ["DEFAULT_CHANNELS", "DEFAULT_INTERFACE", "SOFTWARE_INTERFACES", "complete_bus_settings"]

DEFAULT_INTERFACE = "udp_multicast"
DEFAULT_CHANNELS = {"udp_multicast": "239.74.163.2", "virtual": "workbench"}
# python-can interfaces without bit timing of their own: a bit rate given for them is the simulator's timing model
SOFTWARE_INTERFACES = frozenset({"virtual", "udp_multicast"})


def complete_bus_settings(settings: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """python-can ``Bus(**settings)`` keyword arguments with the defaults filled in: ``interface``
    udp_multicast, its ``channel`` 239.74.163.2 (virtual: "workbench"), and on udp_multicast
    ``receive_own_messages`` off. Other keys (``bitrate``, udp_multicast's ``port``, Vector's
    ``app_name`` ...) pass through unchanged."""
    completed = dict(settings or {})
    interface = completed.setdefault("interface", DEFAULT_INTERFACE)
    if completed.get("channel") is None and interface in DEFAULT_CHANNELS:
        completed["channel"] = DEFAULT_CHANNELS[interface]
    if interface == "udp_multicast":
        completed.setdefault("receive_own_messages", False)
    return completed
