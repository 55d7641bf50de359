"""What only the simulated ECU can do for a test: plant inputs and faults (:mod:`workbench.sim.inject`).

The bench reaches them through a :class:`SimulatorControl`: :class:`LocalSimulator` for a simulated
ECU in the test's own process, :class:`RemoteSimulator` for ``workbench sim`` in another process (its
control channel, found by the bus options), :class:`NoSimulator` for a real ECU, whose every call raises
:class:`SimulatorUnavailable` saying so. Tests reach them as ``ecu.sim``::

    ecu.sim.sensor_voltage("rail", 4.9)          # 4.9 V on the rail pressure sensor's input
    ecu.sim.actuator_error("OTV1", "OPEN_LOAD")  # the OTV1 driver reports an open load
    ecu.sim.channel_id_error("PCM_TO_FLCU_001")
    ecu.sim.plant(engine_flow_kg_h=30.0)
    ecu.sim.clear()
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from workbench.errors import WorkbenchError

__all__ = ["LocalSimulator", "NoSimulator", "RemoteSimulator", "SimSteps", "SimulatorControl", "SimulatorUnavailable"]


class SimulatorUnavailable(WorkbenchError):
    """A test asked for what only the simulated ECU can do (a plant input, a fault) of a real ECU."""


class SimulatorControl:
    """The simulated ECU's faults and plant inputs, by the names of :class:`~workbench.sim.inject.FlcuFaults`."""

    available = True
    where = ""

    def call(self, operation: str, *args: Any, **kwargs: Any) -> str:
        raise NotImplementedError

    def close(self) -> None:
        """Nothing to free unless a connection is held."""


class LocalSimulator(SimulatorControl):
    """A simulated ECU in this process (the plugin's own, one per test)."""

    def __init__(self, faults):
        self.faults = faults
        self.where = "the simulated ECU in this process"

    def call(self, operation: str, *args: Any, **kwargs: Any) -> str:
        return getattr(self.faults, operation)(*args, **kwargs)


class RemoteSimulator(SimulatorControl):
    """``workbench sim`` in another process, through its control channel (:mod:`workbench.sim.control`)."""

    def __init__(self, client):
        self.client = client
        host, port = client.address
        self.where = f"workbench sim (pid {client.hello.get('pid')}, control {host}:{port})"

    def call(self, operation: str, *args: Any, **kwargs: Any) -> str:
        return self.client.call(operation, *args, **kwargs)

    def close(self) -> None:
        self.client.close()


class NoSimulator(SimulatorControl):
    """A real ECU (or a simulator whose control channel is out of reach): every call says why it cannot be done."""

    available = False

    def __init__(self, reason: str):
        self.where = reason

    def call(self, operation: str, *args: Any, **kwargs: Any) -> str:
        raise SimulatorUnavailable(f"{operation}: plant inputs and faults need the simulated ECU; {self.where}")


class SimSteps:
    """``ecu.sim``: the simulator's controls as logged stimulus steps of a bench."""

    def __init__(self, control: SimulatorControl, begin: Callable[[], None], log_stimulus: Callable[[str, float], None],
                 now: Callable[[], float]):
        self.control = control
        self._begin = begin
        self._log = log_stimulus
        self._now = now
        self.touched = False

    @property
    def available(self) -> bool:
        return self.control.available

    def _do(self, operation: str, *args: Any, **kwargs: Any) -> str:
        if self.control.available:
            self._begin()
        start = self._now()
        done = self.control.call(operation, *args, **kwargs)
        self.touched = True
        self._log(f"sim: {done}", start)
        return done

    def sensor_voltage(self, sensor: str, volts: float | None) -> str:
        """Force a sensor's input voltage (tank1, tank2, manifold, rail); None gives it back to the plant."""
        return self._do("sensor_voltage", sensor, volts)

    def actuator_error(self, actuator: str, status: str | int | None) -> str:
        """The driver of OTV1, OTV2, PRV or LED reports ``status`` (SHORT_TO_GND, SHORT_TO_BAT, OPEN_LOAD ...);
        None repairs it."""
        return self._do("actuator_error", actuator, status)

    def channel_id_error(self, message: str, active: bool = True) -> str:
        """The ECU's CAN2 driver reports a channel id error for an RX message."""
        return self._do("channel_id_error", message, active)

    def pcm_message(self, message: str, *, stopped: bool | None = None, dlc: int | None = None) -> str:
        """The simulator's own PCM (``workbench sim --pcm``) stops a message or sends it with another DLC."""
        return self._do("pcm_message", message, stopped=stopped, dlc=dlc)

    def plant(self, **inputs: float) -> str:
        """Tank/manifold/rail pressures (``tank1_bar`` ...) and ``engine_flow_kg_h`` of the simulated fuel system."""
        return self._do("plant", **inputs)

    def clear(self) -> str:
        """Every fault and override removed."""
        return self._do("clear")
