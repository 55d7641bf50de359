"""The FLCU application (thesis chapter 7) as the simulated ECU runs it: the twin of
``assets/ecu/api.c``'s OS tasks over the modules of ``assets/ecu``.

Every task reads the calibrations it needs from memory at their ELF addresses (so the active
calibration page counts) and writes every measurement and state back to memory, so what XCP
reads and writes is the application's real state. A test runs the compiled C application
beside this one and compares every measurement bit for bit.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from workbench.sim.flcu import actuator_commands, can_rx, can_tx, fuel_level, press_sens, prv_ctrl, tank_ctrl, utils
from workbench.sim.flcu.actuator_commands import ActuatorCommands
from workbench.sim.flcu.can_rx import CanRx
from workbench.sim.flcu.can_tx import CanTx
from workbench.sim.flcu.fuel_level import FuelLevel
from workbench.sim.flcu.hardware import Hardware
from workbench.sim.flcu.press_sens import PressSens
from workbench.sim.flcu.prv_ctrl import PRVCtrl
from workbench.sim.flcu.tank_ctrl import TankCtrl
from workbench.sim.flcu.utils import Utils
from workbench.sim.flcu.variables import Memory, Variables

__all__ = ["FlcuApplication"]


class FlcuApplication:
    """``API_OS_Init`` and the three OS tasks of the FLCU over ``memory`` and ``hardware``.

    :param memory: the application's view of ECU memory (``read(address, size)``, ``write``).
    :param symbols: ELF symbol name -> address (an ``int`` or a :class:`workbench.elf.Symbol`).
    :param hardware: the BSW services (:class:`~workbench.sim.flcu.hardware.Hardware`).
    :raises UnknownSymbolError: (from a task) a variable the application needs is not in ``symbols``.
    """

    # period [s], method, XCP DAQ event number; tasks due at the same instant run in this order
    TASKS = ((0.004, "task_4ms", 0), (0.050, "task_50ms", 1), (0.100, "task_100ms", 2))
    # every measurement and state the application writes, module by module
    MEASUREMENTS = (
        *press_sens.MEASUREMENTS,
        *utils.MEASUREMENTS,
        *fuel_level.MEASUREMENTS,
        *tank_ctrl.MEASUREMENTS,
        *prv_ctrl.MEASUREMENTS,
        *actuator_commands.MEASUREMENTS,
        *can_rx.MEASUREMENTS,
        *can_tx.MEASUREMENTS,
    )

    def __init__(self, memory: Memory, symbols: Mapping[str, object], hardware: Hardware):
        variables = Variables(memory, symbols)
        self.variables = variables
        self._press_sens = PressSens(variables, hardware)
        self._utils = Utils(variables, hardware)
        self._fuel_level = FuelLevel(variables)
        self._tank_ctrl = TankCtrl(variables)
        self._prv_ctrl = PRVCtrl(variables)
        self._actuator_commands = ActuatorCommands(variables, hardware)
        self._can_rx = CanRx(variables, hardware)
        self._can_tx = CanTx(variables, hardware)
        self._task_4ms = (self._press_sens,)
        self._task_50ms = (self._utils, self._fuel_level, self._tank_ctrl, self._prv_ctrl, self._actuator_commands)
        self._task_100ms = (self._can_rx, self._can_tx)

    @staticmethod
    def _run(modules) -> None:
        # float32 overflow/NaN are silent in C; keep numpy as quiet
        with np.errstate(all="ignore"):
            for module in modules:
                module.step()

    def initialize(self) -> None:
        """``API_OS_Init``: every ``<Model>_initialize()`` (measurements and states to 0)."""
        for module in (*self._task_4ms, *self._task_50ms, *self._task_100ms):
            module.initialize()

    def task_4ms(self) -> None:
        """``API_OS_Task4ms``: PressSens."""
        self._run(self._task_4ms)

    def task_50ms(self) -> None:
        """``API_OS_Task50ms``: Utils, FuelLevel, TankCtrl, PRVCtrl, ActuatorCommands."""
        self._run(self._task_50ms)

    def task_100ms(self) -> None:
        """``API_OS_Task100ms``: CANRX, CANTX."""
        self._run(self._task_100ms)
