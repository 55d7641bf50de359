"""Calibrate by name: a scalar, a map cell, then back to the flashed values.

Writes go to the working page (CAL RAM): limits are checked before anything is sent, the value
is read back. ``copy_reference_to_working`` restores what is in flash (CAL ROM).
Usage: python examples/calibrate.py [UDP_PORT]   (start ``workbench sim`` first)
"""

import sys

from workbench import LimitsError, Session

port = {"port": int(sys.argv[1])} if len(sys.argv) > 1 else {}

with Session.open(bus_kwargs=port) as ecu:
    print("switch threshold:", ecu.read("xsSWITCH_TANK_THR"), "bar")
    written = ecu.write("xsSWITCH_TANK_THR", 25.0)  # returns what the ECU holds afterwards
    print("now:", written.value, written.unit)

    try:
        ecu.write("xsSWITCH_TANK_THR", 2500.0)  # beyond the A2L's limits: refused, nothing sent
    except LimitsError as error:
        print("refused:", error)

    feed_forward = ecu.read_value("xvPRV_DC_FF")  # a MAP: values [target, manifold] and both axes
    target, manifold = feed_forward.axes
    print("PRV feed-forward at", target.values[2], "bar target,", manifold.values[3], "bar manifold:",
          feed_forward.value[2, 3], feed_forward.unit)
    table = feed_forward.value.copy()
    table[2, 3] += 5.0
    ecu.write("xvPRV_DC_FF", table)
    print("changed to", ecu.read("xvPRV_DC_FF")[2, 3])

    ecu.copy_reference_to_working()  # undo: the working page starts over from flash
    print("restored:", ecu.read("xsSWITCH_TANK_THR"), "bar,", ecu.read("xvPRV_DC_FF")[2, 3], "%")
