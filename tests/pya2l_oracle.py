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


_DESCRIBE = """
import json, sys
import numpy as np
import pya2l
from pya2l.api import inspect
request = json.loads(sys.argv[2])
session = pya2l.import_a2l(sys.argv[1], in_memory=True, progress_bar=False, loglevel="ERROR", encoding="utf-8")

def get(read):  # pya2ldb raises on some absent options: absent is None here
    try:
        return read()
    except Exception:
        return None

def name_of(thing):
    return getattr(thing, "name", None) if thing is not None else None

def pair(limits):
    return [limits.lowerLimit, limits.upperLimit] if limits is not None and get(limits.valid) else None

def number(value):
    return value if value is None or isinstance(value, str) else float(np.asarray(value))

out = {"characteristics": {}, "measurements": {}, "axis_pts": {}, "conversions": {}, "addresses": {}}
def characteristic(name):
    c = inspect.Characteristic(session, name)
    return {
        "type": c.type, "address": c.address, "record_layout": name_of(c.deposit),
        "conversion": name_of(c.compuMethod), "limits": [c.lowerLimit, c.upperLimit], "bit_mask": get(lambda: c.bitMask),
        "byte_order": get(lambda: c.byteOrder), "read_only": bool(get(lambda: c.readOnly)),
        "extension": get(lambda: c.ecuAddressExtension), "extended_limits": pair(get(lambda: c.extendedLimits)),
        "axes": [[a.attribute, a.maxAxisPoints, name_of(get(lambda: a.axisPtsRef)), name_of(a.compuMethod),
                  a.lowerLimit, a.upperLimit] for a in c.axisDescriptions],
        "functions": sorted(getattr(f, "name", f) for f in (get(lambda: c.functionList) or [])),
    }

def measurement(name):
    m = inspect.Measurement(session, name)
    dims = get(lambda: m.matrixDim)
    return {
        "datatype": m.datatype, "address": m.ecuAddress, "conversion": name_of(m.compuMethod),
        "limits": [m.lowerLimit, m.upperLimit], "bit_mask": get(lambda: m.bitMask), "byte_order": get(lambda: m.byteOrder),
        "matrix_dim": [d for d in (dims.x, dims.y, dims.z) if d is not None] if dims is not None else [],
        "array_size": get(lambda: m.arraySize), "extension": get(lambda: m.ecuAddressExtension),
    }

def axis_pts(name):
    a = inspect.AxisPts(session, name)
    return {"address": a.address, "record_layout": name_of(a.depositAttr), "max": a.maxAxisPoints,
            "conversion": name_of(a.compuMethod), "limits": [a.lowerLimit, a.upperLimit]}

for kind, read in (("characteristics", characteristic), ("measurements", measurement), ("axis_pts", axis_pts)):
    for name in request.get(kind, []):
        try:
            out[kind][name] = read(name)
        except Exception as error:  # an object pya2ldb cannot read: say so, the caller decides
            out[kind][name] = {"error": f"{type(error).__name__}: {error}"}
for name, samples in request.get("conversions", {}).items():
    method = get(lambda: inspect.CompuMethod(session, name))
    if method is None:  # TAB_INTP and FORM need scipy/numexpr, which pya2ldb does not install
        continue
    result = {"type": method.conversionType}
    if "raw" in samples:
        result["physical"] = [number(get(lambda: method.int_to_physical(v))) for v in samples["raw"]]
    if "physical" in samples:
        result["raw"] = [number(get(lambda: method.physical_to_int(v))) for v in samples["physical"]]
    out["conversions"][name] = result
for name in request.get("layouts", []):
    components = inspect.Characteristic(session, name).record_layout_components
    out["addresses"][name] = {key: getattr(attr, "address", None) for key, attr in components["position"]}
print("DESCRIBE " + json.dumps(out))
"""


def pya2l_describe(path: Path, request: dict) -> dict:
    """What pya2ldb reads from ``path``: the objects and conversions named in ``request``
    (``{"characteristics": [...], "measurements": [...], "axis_pts": [...], "conversions":
    {method: {"raw": [...], "physical": [...]}}, "layouts": [characteristics]}``), as plain JSON data;
    an object pya2ldb fails on is ``{"error": "..."}``."""
    run = subprocess.run([sys.executable, "-c", _DESCRIBE, str(path), json.dumps(request)], capture_output=True,
                         text=True, timeout=300)
    line = next((line for line in run.stdout.splitlines() if line.startswith("DESCRIBE ")), None)
    assert run.returncode == 0 and line, f"pya2ldb failed on {path}:\n{(run.stdout + run.stderr)[-3000:]}"
    return json.loads(line[len("DESCRIBE "):])
