"""pya2ldb as an independent judge of our output: the file must import without parser errors.

pya2ldb's C++ parser logs problems to the process's stdout and carries on, so the
import runs in a child process whose output is searched for its error lines.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

_SCRIPT = """
import json, sys
import pya2l
from pya2l import model
session = pya2l.import_a2l(sys.argv[1], in_memory=True, progress_bar=False, loglevel="ERROR", encoding=sys.argv[2])
print("COUNTS " + json.dumps({
    "MEASUREMENT": session.query(model.Measurement).count(),
    "CHARACTERISTIC": session.query(model.Characteristic).count(),
    "AXIS_PTS": session.query(model.AxisPts).count(),
    "ECU_ADDRESS": sorted((m.name, m.ecu_address.address) for m in session.query(model.Measurement) if m.ecu_address),
}))
"""


def pya2l_import(path: Path, encoding: str = "utf-8") -> dict:
    """Import ``path`` with pya2ldb; returns object counts, raises AssertionError on any parser error."""
    run = subprocess.run([sys.executable, "-c", _SCRIPT, str(path), encoding], capture_output=True, text=True,
                         timeout=120)
    output = run.stdout + run.stderr
    errors = [line for line in output.splitlines() if "[error]" in line or "Traceback" in line]
    assert run.returncode == 0 and not errors, f"pya2ldb rejected {path}:\n" + "\n".join(errors or [output[-2000:]])
    counts = next(line for line in run.stdout.splitlines() if line.startswith("COUNTS "))
    return json.loads(counts[len("COUNTS "):])
