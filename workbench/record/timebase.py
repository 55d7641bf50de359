"""The recording's time axis: seconds since the MDF header's start time, on the ECU's clock.

* The start time (:attr:`RecordingClock.origin`, s since the epoch) is the host time of the ECU's
  first DAQ sample, so a DAQ group's ``time`` is exactly the measurement's ECU time (0 at the
  first sample; the DAQ clock unwraps the slave's counter, see :mod:`workbench.xcp.daq.clock`).
* CAN frames carry the host's receive time (python-can's ``timestamp``, s since the epoch). It is
  mapped onto the ECU clock with the DAQ clock's current offset between the two (host time −
  ECU time of the latest DAQ samples, which follows the drift of the ECU's crystal), so frames and
  samples line up within the bus latency, also after an hour.
* An ECU that sends no DAQ timestamps (or a plan that left them no room on classic CAN): the DAQ "ECU
  time" is the master's receive time, so the whole axis is the host's; the file's header says so
  (``time_axis``, ``daq_time_source``).
* Without DAQ samples (CAN only, or none yet after ``wait_s``), the start time is the host time
  at which the recording started and CAN times are host times from there; DAQ samples that come
  later keep the ECU clock's steps, shifted by a constant onto that axis.
"""

from __future__ import annotations

import numpy as np

__all__ = ["RecordingClock"]


class RecordingClock:
    """Maps DAQ and host times onto the recording's axis; :attr:`origin` None until fixed."""

    def __init__(self) -> None:
        self.origin: float | None = None
        self._shift: float | None = None  # recording time - ECU time, fixed at the first DAQ samples
        self._ecu_epoch: float | None = None  # host time of ECU time 0, as the latest DAQ samples give it

    def fix(self, origin: float) -> None:
        """Start the axis at ``origin`` (s since the epoch) when no DAQ sample fixed it."""
        if self.origin is None:
            self.origin = origin

    def daq(self, time: np.ndarray, host_time: np.ndarray) -> np.ndarray:
        """Recording times of DAQ samples: ``time`` the ECU's (s since the first sample), ``host_time`` the
        same instants on the host's clock (s since the epoch)."""
        if not len(time):
            return np.asarray(time, dtype=np.float64)
        epoch = float(host_time[-1] - time[-1])
        if self.origin is None:
            self.origin = float(host_time[0] - time[0])
        if self._shift is None:
            self._shift = float(host_time[0] - time[0]) - self.origin
        self._ecu_epoch = epoch
        return np.asarray(time, dtype=np.float64) + self._shift

    def host(self, epoch_s: np.ndarray) -> np.ndarray:
        """Recording times of host timestamps (s since the epoch). :raises ValueError: the axis has no origin."""
        if self.origin is None:
            raise ValueError("the recording's time axis has no origin yet")
        epoch_s = np.asarray(epoch_s, dtype=np.float64)
        if self._ecu_epoch is None:
            return epoch_s - self.origin
        return epoch_s - self._ecu_epoch + self._shift
