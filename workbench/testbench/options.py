"""The plugin's ECU options (the names ``workbench`` commands take) turned into an :class:`~workbench.testbench.target.EcuTarget`."""

from __future__ import annotations

from argparse import Namespace
from pathlib import Path
from typing import Any

from workbench.errors import InputError
from workbench.testbench.target import EcuTarget

__all__ = ["target_from_options"]


def target_from_options(option: Namespace) -> EcuTarget:
    """:raises InputError: options that do not fit together or do not parse (named)."""
    from workbench.bus_defaults import BusSpec, bus_beside, complete_bus_settings

    bus_kwargs = _bus_kwargs(option.bus_kwargs or [], "--bus-kwargs")
    can_given = option.interface or option.channel or option.bitrate or bus_kwargs
    ethernet_given = option.host or option.port or option.protocol
    if can_given and ethernet_given:
        raise InputError("give either CAN options (--interface/--channel ...) or Ethernet ones (--host/--port/--protocol)")
    if (option.port or option.protocol) and not option.host:
        raise InputError("--port and --protocol are for XCP on Ethernet: give --host too")
    bus = None
    if can_given:
        given = {"interface": option.interface, "channel": option.channel, "bitrate": option.bitrate, **bus_kwargs}
        bus = complete_bus_settings({key: value for key, value in given.items() if value is not None})
    ethernet = {"host": option.host, "port": option.port, "protocol": option.protocol or "udp"} if option.host else None
    can2 = bus_beside(BusSpec.from_kwargs(bus) if bus else None, option.can2_interface, option.can2_channel,
                      _bus_kwargs(option.can2_bus_kwargs or [], "--can2-bus-kwargs"))
    can2_bus = can2.kwargs() if can2 is not None else None
    if option.sim_s19 and (bus or ethernet):
        raise InputError("--sim-s19 is for the simulated ECU the tests start without bus options; "
                         "give workbench sim --s19 for one served elsewhere")
    for path in (option.a2l, option.dbc, option.sim_s19):
        if path and not Path(path).is_file():
            raise InputError(f"{path}: no such file")
    return EcuTarget(a2l=_path(option.a2l), bus=bus, ethernet=ethernet, can2_bus=can2_bus, dbc=_path(option.dbc),
                     key_function=option.key_function,
                     accept_epk_mismatch=option.accept_epk_mismatch, sim_s19=_path(option.sim_s19), sim_control=option.sim_control)


def _path(text: str | None) -> Path | None:
    return Path(text) if text else None


def _bus_kwargs(pairs: list[str], option: str) -> dict[str, Any]:
    from workbench.bus_defaults import parse_bus_kwargs

    try:
        return parse_bus_kwargs(pairs)
    except ValueError as exc:
        raise InputError(f"{option} {exc}") from None
