"""Faults and plant inputs of the simulated FLCU by name: what a test bench does to the wiring harness.

::

    faults = FlcuFaults(demo, simulator.lock, simulator.pcm)
    faults.sensor_voltage("rail", 4.9)            # the rail sensor reads 4.9 V (out of range)
    faults.actuator_error("OTV1", "OPEN_LOAD")    # the OTV1 driver reports an open load
    faults.channel_id_error("PCM_TO_FLCU_001")    # the driver says the frame came on another channel
    faults.pcm_message("PCM_TO_FLCU_002", stopped=True)   # the simulator's PCM stops sending it
    faults.clear()                                # everything injected removed

Sensors are ``tank1``, ``tank2``, ``manifold``, ``rail`` (the analog inputs ANIN_CH_ID_000..003),
actuators ``OTV1``, ``OTV2``, ``PRV``, ``LED`` (their output drivers), statuses the names of
``Std_eDiagStatusT`` (SHORT_TO_GND, SHORT_TO_BAT, OPEN_LOAD, ...). Every call takes the simulator's
lock, so it lands between two steps of the application, and returns one line saying what it did.
:meth:`FlcuFaults.apply` takes the same as text (``workbench sim --fault rail=4.9V``).

A wrong DLC or a stopped message from the test bench itself needs no simulator: the bench sends
(or stops sending) the PCM's frames on CAN2, as it would to a real ECU. What only the simulator
can do is here.
"""

from __future__ import annotations

import re
import threading
from contextlib import nullcontext
from typing import TYPE_CHECKING

from workbench.errors import InputError
from workbench.sim.flcu.hardware import (
    ANIN_MANIFOLD,
    ANIN_RAIL,
    ANIN_TANK1,
    ANIN_TANK2,
    DOUT_LED,
    DOUT_OTV1,
    DOUT_OTV2,
    PWMOUT_PRV,
    DiagStatus,
)
from workbench.sim.pcm import MESSAGES as PCM_MESSAGES

if TYPE_CHECKING:
    from workbench.sim.demo_ecu import DemoEcu
    from workbench.sim.pcm import PcmNode

__all__ = ["ACTUATORS", "FAULT_SYNTAX", "SENSORS", "FlcuFaults"]

SENSORS = {"tank1": ANIN_TANK1, "tank2": ANIN_TANK2, "manifold": ANIN_MANIFOLD, "rail": ANIN_RAIL}
ACTUATORS = {"OTV1": DOUT_OTV1, "OTV2": DOUT_OTV2, "PRV": PWMOUT_PRV, "LED": DOUT_LED}
FAULT_SYNTAX = ("SENSOR=VOLTS (tank1, tank2, manifold, rail; e.g. rail=4.9), ACTUATOR=STATUS (OTV1, OTV2, PRV, LED; "
                "SHORT_TO_GND, SHORT_TO_BAT, OPEN_LOAD, OUT_OF_RANGE, IMPLAUSIBLE), chid:MESSAGE (a channel id "
                "error on an RX message), pcm-stop:MESSAGE, pcm-dlc:MESSAGE=N (the simulator's PCM)")


class FlcuFaults:
    """Fault injection into one demo ECU (its plant, CAN2 driver and residual-bus PCM).

    :param lock: the simulator's lock (None: the caller serialises, e.g. a test that advances time itself).
    :param pcm: the simulator's PCM node, if it has one (for :meth:`pcm_message`).
    """

    def __init__(self, demo: DemoEcu, lock: threading.RLock | None = None, pcm: PcmNode | None = None):
        self.demo = demo
        self.pcm = pcm
        self._lock = lock or nullcontext()
        self._rx_messages = {message.name for message in demo.can2.rx_messages}
        self._channel_id_errors: set[str] = set()
        self._engine_flow = demo.plant.engine_flow_kg_h

    # --- the plant's inputs -------------------------------------------------------------------

    def sensor_voltage(self, sensor: str, volts: float | None) -> str:
        """Force a sensor's voltage (e.g. 4.9 V: above its 0.5-4.5 V span); None gives the sensor back."""
        channel = SENSORS[_known(sensor.lower(), SENSORS, "sensor")]
        with self._lock:
            self.demo.plant.override_voltage(channel, volts)
        return f"{sensor} sensor ({channel}) " + ("released" if volts is None else f"at {float(volts):g} V")

    def plant(self, *, tank1_bar: float | None = None, tank2_bar: float | None = None,
              manifold_bar: float | None = None, rail_bar: float | None = None,
              engine_flow_kg_h: float | None = None) -> str:
        """Put the fuel system into a state (pressures in bar; the sensors follow with their response time)
        and set what the engine draws from the rail (kg/h; :meth:`clear` restores it, not the pressures)."""
        pressures = {"tank1_bar": tank1_bar, "tank2_bar": tank2_bar, "manifold_bar": manifold_bar, "rail_bar": rail_bar}
        with self._lock:
            self.demo.plant.set_pressures(**pressures)
            if engine_flow_kg_h is not None:
                self.demo.plant.engine_flow_kg_h = float(engine_flow_kg_h)
        parts = [f"{name.removesuffix('_bar')} {value:g} bar" for name, value in pressures.items() if value is not None]
        if engine_flow_kg_h is not None:
            parts.append(f"engine flow {engine_flow_kg_h:g} kg/h")
        return "plant: " + (", ".join(parts) or "unchanged")

    # --- faults ---------------------------------------------------------------------------------

    def actuator_error(self, actuator: str, status: str | int | None) -> str:
        """The output driver of ``actuator`` reports ``status`` (a faulty output does not actuate);
        None or NO_ERROR repairs it."""
        channel = ACTUATORS[_known(actuator.upper(), ACTUATORS, "actuator")]
        diag = _diag_status(status)
        with self._lock:
            self.demo.plant.set_output_error(channel, diag)
        return f"{actuator} driver ({channel}) reports {diag.name}"

    def channel_id_error(self, message: str, active: bool = True) -> str:
        """The CAN2 driver reports a channel id error for an RX message (the frame came on another channel)."""
        _known(message, self._rx_messages, "CAN2 RX message")
        with self._lock:
            self.demo.can2.inject_channel_id_error(message, active)
        (self._channel_id_errors.add if active else self._channel_id_errors.discard)(message)
        return f"{message}: channel id error {'on' if active else 'off'}"

    def pcm_message(self, message: str, *, stopped: bool | None = None, dlc: int | None = None) -> str:
        """The simulator's own PCM stops sending ``message`` (``stopped``) or sends it with another DLC
        (``dlc``; 0 or the DBC's own DLC sends it right again).

        :raises InputError: the simulator runs no PCM (``workbench sim --pcm``).
        """
        if self.pcm is None:
            raise InputError("the simulator runs no PCM (workbench sim --pcm): send the PCM's frames yourself")
        _known(message, PCM_MESSAGES, "PCM message")
        done = []
        with self._lock:
            if stopped is not None:
                (self.pcm.stopped.add if stopped else self.pcm.stopped.discard)(message)
                done.append("stopped" if stopped else "sent again")
            if dlc is not None:
                if not 0 <= dlc <= 8:
                    raise InputError(f"a classic CAN frame has a DLC of 0..8, not {dlc}")
                right = self.demo.dbc.database.get_message_by_name(message).length
                if dlc in (0, right):
                    self.pcm.wrong_dlc.pop(message, None)
                    done.append(f"DLC {right} again")
                else:
                    self.pcm.wrong_dlc[message] = dlc
                    done.append(f"sent with DLC {dlc}")
        return f"PCM {message}: " + (", ".join(done) or "unchanged")

    def clear(self) -> str:
        """Remove every override and fault injected here (plant pressures stay where the physics took them)."""
        plant = self.demo.plant
        with self._lock:
            for channel in SENSORS.values():
                plant.override_voltage(channel, None)
            for channel in ACTUATORS.values():
                plant.set_output_error(channel, DiagStatus.NO_ERROR)
            for message in self._channel_id_errors:
                self.demo.can2.inject_channel_id_error(message, False)
            plant.engine_flow_kg_h = self._engine_flow
            if self.pcm is not None:
                self.pcm.stopped.clear()
                self.pcm.wrong_dlc.clear()
        self._channel_id_errors.clear()
        return "every fault and override cleared"

    # --- as text --------------------------------------------------------------------------------

    def apply(self, spec: str) -> str:
        """One fault as text (see :data:`FAULT_SYNTAX`); :raises InputError: it does not parse."""
        text = spec.strip()
        if match := re.fullmatch(r"chid:(\w+)", text, re.IGNORECASE):
            return self.channel_id_error(match[1])
        if match := re.fullmatch(r"pcm-stop:(\w+)", text, re.IGNORECASE):
            return self.pcm_message(match[1], stopped=True)
        if match := re.fullmatch(r"pcm-dlc:(\w+)=(\d+)", text, re.IGNORECASE):
            return self.pcm_message(match[1], dlc=int(match[2]))
        if match := re.fullmatch(r"(\w+)=(.+)", text):
            name, value = match[1], match[2].strip()
            if name.lower() in SENSORS:
                try:
                    volts = float(value.removesuffix("V").removesuffix("v"))
                except ValueError:
                    raise InputError(f"fault {spec!r}: a sensor takes a voltage, e.g. {name}=4.9") from None
                return self.sensor_voltage(name, volts)
            if name.upper() in ACTUATORS:
                return self.actuator_error(name, value)
        raise InputError(f"fault {spec!r}: expected {FAULT_SYNTAX}")


def _known(name: str, known, what: str) -> str:
    if name not in known:
        raise InputError(f"no {what} {name!r}; the FLCU has {', '.join(sorted(known))}")
    return name


def _diag_status(status: str | int | None) -> DiagStatus:
    if status is None:
        return DiagStatus.NO_ERROR
    try:
        return DiagStatus[status.upper()] if isinstance(status, str) else DiagStatus(int(status))
    except (KeyError, ValueError):
        raise InputError(f"no diagnostic status {status!r}; Std_eDiagStatusT has "
                         f"{', '.join(s.name for s in DiagStatus)}") from None
