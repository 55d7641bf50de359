"""Read signals by name in physical units, polled ten times a second for a second.

Start the simulated ECU first (``workbench sim --pcm``), or give Session.open your ECU:
``Session.open("my.a2l", interface="socketcan", channel="can0")``.
Usage: python examples/measure.py [UDP_PORT]   (the udp_multicast port ``workbench sim`` serves on)
"""

import sys
import time

from workbench import Session

port = {"port": int(sys.argv[1])} if len(sys.argv) > 1 else {}  # udp_multicast port of a private simulator

with Session.open(bus_kwargs=port) as ecu:  # the demo A2L; its IF_DATA says how to reach the ECU
    print(ecu.epk.describe())
    for _ in range(10):
        values = ecu.read_many(["zsRailPressure", "xsDC", "xsTankCtrlState"])  # one batch of UPLOADs
        print(f"rail {values['zsRailPressure']:6.2f} bar   PRV {values['xsDC']:6.2f} %   {values['xsTankCtrlState']}")
        time.sleep(0.1)
