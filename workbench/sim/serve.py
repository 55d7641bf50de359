"""The demo ECU served in one call, as ``workbench sim`` serves it: :func:`serve_demo`.

```python
from workbench.sim import EthernetEndpoint, serve_demo

with serve_demo({"interface": "virtual", "channel": "bench"}, pcm_target_bar=25.0) as sim:
    ...  # XCP on CAN on the virtual bus "bench", the FLCU messages there too
with serve_demo(ethernet=EthernetEndpoint("127.0.0.1", 5555, "TCP")) as sim:
    ...  # XCP on TCP at 127.0.0.1:5555 (MAX_CTO/MAX_DTO of the A2L's XCP_ON_TCP_IP)
with serve_demo({"interface": "virtual", "channel": "bench"}, profile="segments") as sim:
    ...  # calibrations in XCP segment 1; Session.open(sim.a2l, ...) reads that from the profile's A2L
```
"""

from __future__ import annotations

import random
from collections.abc import Mapping
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from workbench.a2l import read_xcp_config
from workbench.bus_defaults import SOFTWARE_INTERFACES, complete_bus_settings
from workbench.errors import InputError
from workbench.sim.demo_ecu import DemoEcu, DemoFiles, build_demo_ecu
from workbench.sim.faults import FaultPlan
from workbench.sim.profiles import SlaveProfile
from workbench.sim.server import Simulator

if TYPE_CHECKING:
    import can

    from workbench.sim.eth_port import EthernetEndpoint

__all__ = ["serve_demo"]


def serve_demo(
    bus: Mapping[str, Any] | can.BusABC | None = None,
    *,
    ethernet: EthernetEndpoint | None = None,
    can2: Mapping[str, Any] | can.BusABC | None = None,
    files: DemoFiles | None = None,
    demo: DemoEcu | None = None,
    pcm_target_bar: float | None = None,
    time_scale: float | None = 1.0,
    valid_key: bool = True,
    unlocked: bool = False,
    static_daq: bool = False,
    profile: SlaveProfile | str = "demo",
    faults: FaultPlan | None = None,
    rng: random.Random | None = None,
) -> Simulator:
    """Build the FLCU demo ECU and serve it; returns the started :class:`Simulator` (a context manager).

    :param bus: the CAN bus, as python-can settings (completed with the defaults of
        :func:`~workbench.bus_defaults.complete_bus_settings`) or an open bus (it stays the caller's).
        It carries XCP on CAN unless ``ethernet`` is given, and the FLCU's CAN2 messages unless ``can2`` is. On virtual/udp_multicast a ``bitrate`` sets the simulator's bus
        timing model; on other interfaces it goes to the interface (default: the A2L's BAUDRATE).
        Default: udp_multicast on 239.74.163.2 with XCP on CAN, no CAN bus with XCP on Ethernet.
    :param ethernet: serve XCP on UDP/TCP there instead of on CAN, with the packet sizes (and, when
        ``ethernet.port`` is None, the port) of the A2L's XCP_ON_UDP_IP / XCP_ON_TCP_IP.
    :param can2: the FLCU messages on a bus of their own (settings completed as ``bus``'s).
    :param demo: an ECU built by :func:`build_demo_ecu` for the same transport (default: built here
        from ``files`` with ``valid_key``, ``unlocked``, ``static_daq``, ``profile``, ``faults`` and ``rng``).
    :param profile: a slave profile (:mod:`workbench.sim.profiles`, e.g. ``"motorola"``): the demo served
        through another implementation of XCP's options; the simulator's :attr:`~Simulator.a2l` says how.
    :param pcm_target_bar: add a residual-bus PCM sending EnableFLCU = 1 and this TargetRailPressure
        (bar) every 100 ms.
    :param time_scale: simulated seconds per real second; None: only ``Simulator.advance`` moves time.
    :raises InputError: a file, setting or target the demo cannot take (the message names it).
    :raises WorkbenchError: a bus or the Ethernet address cannot be opened.
    """
    if ethernet is not None and bus is not None and can2 is not None:
        raise InputError("with XCP on Ethernet the CAN bus carries only the FLCU messages: give bus or can2, not both")
    if demo is None:
        demo = build_demo_ecu(files, transport=ethernet.protocol if ethernet is not None else "CAN",
                              valid_key=valid_key, unlocked=unlocked, static_daq=static_daq, slave_profile=profile,
                              faults=faults, rng=rng)
    if ethernet is not None and ethernet.port is None:
        block = getattr(read_xcp_config(demo.a2l), ethernet.protocol.lower())
        ethernet = replace(ethernet, port=block.port)
    if ethernet is None:
        bus = complete_bus_settings(bus) if not _is_open_bus(bus) else bus
    elif bus is not None:
        bus, can2 = None, bus  # XCP left the bus: what stays on it is CAN2
    can2 = complete_bus_settings(can2) if can2 is not None and not _is_open_bus(can2) else can2
    baudrate = demo.ecu.params.baudrate
    timing = _timing_bitrate(bus, baudrate) or _timing_bitrate(can2, baudrate)
    pcm = None
    if pcm_target_bar is not None:
        pcm = demo.pcm_node(target_bar=pcm_target_bar)
        try:
            pcm.frames()
        except ValueError as exc:
            raise InputError(f"PCM TargetRailPressure {pcm_target_bar} bar: {exc}") from None
    simulator = Simulator(demo.ecu, bus, can2, ethernet=ethernet, can2_driver=demo.can2, pcm=pcm, bitrate=timing,
                          time_scale=time_scale, a2l=demo.a2l, profile=demo.profile.name)
    return simulator.start()


def _timing_bitrate(settings: object, baudrate: int) -> int | None:
    """A software bus's ``bitrate``, taken out of its settings for the timing model; a hardware
    interface keeps its own (default ``baudrate``, the A2L's)."""
    if not isinstance(settings, dict):
        return None
    if settings["interface"] in SOFTWARE_INTERFACES:
        return settings.pop("bitrate", None)
    settings.setdefault("bitrate", baudrate)
    return None


def _is_open_bus(bus: object) -> bool:
    return bus is not None and not isinstance(bus, Mapping)
