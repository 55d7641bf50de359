"""Measure with DAQ for two seconds and write the samples to a CSV file.

Each signal is sampled on its own event (the A2L's DAQ_EVENT), with the ECU's timestamps.
Usage: python examples/daq_to_csv.py OUT.csv [UDP_PORT]   (start ``workbench sim --pcm`` first)
"""

import csv
import sys
import time

from workbench import Session

out = sys.argv[1] if len(sys.argv) > 1 else "daq.csv"
port = {"port": int(sys.argv[2])} if len(sys.argv) > 2 else {}
signals = ["zsRailPressure", "xsPidP", "xsPidI", "xsDC"]

with Session.open(bus_kwargs=port) as ecu, open(out, "w", newline="") as file:
    writer = csv.writer(file)
    writer.writerow(["time_s", "event", "signal", "value"])
    with ecu.measure(signals) as live:
        deadline = time.monotonic() + 2.0
        while time.monotonic() < deadline:
            for batch in live.read(timeout_s=0.1):
                for name, values in batch.values.items():
                    writer.writerows((f"{t:.6f}", batch.event_name, name, v) for t, v in zip(batch.time, values))
    print(f"{live.stats.samples} samples, {live.stats.lost} lost -> {out}")
