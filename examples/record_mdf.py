"""Record two seconds to MDF4: DAQ signals, the CAN2 messages decoded with the DBC, and the raw bus; read it back.

Usage: python examples/record_mdf.py OUT.mf4 [UDP_PORT]   (start ``workbench sim --pcm`` first)
"""

import sys

from asammdf import MDF

from workbench import Session, demo
from workbench.record import record

out = sys.argv[1] if len(sys.argv) > 1 else "run.mf4"
port = {"port": int(sys.argv[2])} if len(sys.argv) > 2 else {}

with Session.open(bus_kwargs=port) as ecu:
    stats = record(ecu, out, ["zsRailPressure", "zsSensVolt", "xsTankCtrlState", "xsDC"],
                   can2=demo.dbc_can2(), raw_can=True, duration=2.0, overwrite=True)  # a second run replaces it
print(f"recorded {stats.describe()}")

with MDF(out) as mdf:
    rail = mdf.get("zsRailPressure")
    state = mdf.get("xsTankCtrlState")  # raw values with the A2L's texts as a value-to-text conversion
    print(f"zsRailPressure: {len(rail)} samples, last {rail.samples[-1]:.2f} {rail.unit} at {rail.timestamps[-1]:.3f} s")
    print(f"xsTankCtrlState: {state.samples[-1].decode()}")
    decoded = mdf.extract_bus_logging({"CAN": [(str(demo.dbc_can2()), 0)]})  # the raw bus log, decoded again
    print(f"TargetRailPressure from the raw bus log: {decoded.get('TargetRailPressure').samples[-1]:.2f} bar")
    decoded.close()
