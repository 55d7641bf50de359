"""pyxcp as an independent XCP master for the simulator's tests (built from a config object, quiet), and a DAQ recorder."""

from __future__ import annotations

import logging
import time

from pyxcp.config import create_application_from_config
from pyxcp.daq_stim import DaqOnlinePolicy
from pyxcp.master import Master

from workbench.sim.seedkey import compute_key


def pyxcp_master(interface: str, channel: str, can_id_master: int = 0x7F0, can_id_slave: int = 0x7F1,
                 policy=None, timeout_s: float = 2.0, bus_kwargs: dict | None = None) -> Master:
    """A pyxcp Master on a python-can bus that pads its frames to DLC 8 as the demo A2L's MAX_DLC_REQUIRED asks;
    ``bus_kwargs`` are the interface's own options (udp_multicast's ``port``). Never reads ``sys.argv``."""
    app = create_application_from_config(
        {"Transport": {"CAN": {"interface": interface, "channel": channel, "can_id_master": can_id_master,
                               "can_id_slave": can_id_slave, "max_dlc_required": True}}},
        log_level=logging.CRITICAL,
    )
    backend = getattr(app.transport.can, interface)  # pyxcp keeps each interface's own options apart
    for key, value in (bus_kwargs or {}).items():
        setattr(backend, key, value)
    return _quiet_master("can", app, policy, timeout_s)


def pyxcp_eth_master(host: str, port: int, protocol: str, policy=None, timeout_s: float = 2.0) -> Master:
    """A pyxcp Master on XCP on UDP or TCP (``protocol``), never reading ``sys.argv``."""
    app = create_application_from_config(
        {"Transport": {"Eth": {"host": host, "port": port, "protocol": protocol.upper()}}},
        log_level=logging.CRITICAL,
    )
    return _quiet_master("eth", app, policy, timeout_s)


def _quiet_master(transport: str, app, policy, timeout_s: float) -> Master:
    """Logs only criticals; the seed & key plugin of the demo A2L."""
    app.transport.timeout = timeout_s
    logging.getLogger("pyxcp").setLevel(logging.CRITICAL)
    master = Master(transport, config=app, policy=policy)
    # pyxcp calls the plugin as f(resource, seed); the A2L names compute_key(seed, resource)
    master.seed_n_key_function = lambda resource, seed: compute_key(bytes(seed), resource)
    return master


def connect(master: Master) -> None:
    master.connect()
    if master.slaveProperties.optionalCommMode:
        master.getCommModeInfo()


class Samples(DaqOnlinePolicy):
    """Records every decoded DAQ list sample as ``(timestamp_ns, {measurement name: value})``."""

    def __init__(self, daq_lists):
        # an explicit logger keeps pyxcp from building its global application from sys.argv
        super().__init__(daq_lists, logger=logging.getLogger("pyxcp.daq"))
        self.pid_off = False  # pyxcp 0.29 sets it only when it builds the global application itself
        self.rows: list[tuple[int, dict]] = []

    def on_daq_list(self, daq_list, timestamp0, timestamp1, payload):
        names = [header[0] for header in self.daq_lists[daq_list].headers]  # pyxcp's packing order
        self.rows.append((timestamp1, dict(zip(names, payload))))


def record_50ms_samples(policy: Samples, seconds: float = 1.0) -> list[tuple[int, dict]]:
    """Run the DAQ lists ``policy`` set up for ``seconds``; the samples, checked to be the 50 ms task's:
    at least one every 100 ms, the ECU's timestamps (ns, from 10 us ticks) 50 ms apart or a multiple."""
    policy.start()
    time.sleep(seconds)
    policy.stop()
    rows = list(policy.rows)
    assert len(rows) >= seconds * 10
    ticks = [timestamp for timestamp, _ in rows]
    assert all((b - a) % 50_000_000 == 0 and b > a for a, b in zip(ticks, ticks[1:]))
    return rows
