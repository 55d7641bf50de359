"""Override a signal with its fix calibration (thesis chapter 6), then give it back.

``override`` writes <fix>_VALUE and then <fix>_EN = 1; ``release`` writes <fix>_EN = 0.
Usage: python examples/override.py [UDP_PORT]   (start ``workbench sim --pcm`` first)
"""

import sys
import time

from workbench import Session

port = {"port": int(sys.argv[1])} if len(sys.argv) > 1 else {}

with Session.open(bus_kwargs=port) as ecu:
    for state in ecu.fixes():
        print(f"{state.pair.stem:<26} {'ON ' if state.active else 'off'} {state.signal}")

    ecu.override("zfRAILPRESSURE", 30.0)  # the rail pressure sensor now reads 30 bar
    time.sleep(0.05)
    print(f"rail pressure with the fix: {ecu.read('zsRailPressure'):.2f} bar")
    ecu.release("zfRAILPRESSURE")
    time.sleep(0.05)
    print(f"rail pressure released: {ecu.read('zsRailPressure'):.2f} bar")  # %8.2, its A2L FORMAT
