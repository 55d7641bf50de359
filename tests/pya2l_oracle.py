"""pya2ldb as an independent judge of our output: the file must import without parser errors, and pya2ldb
must read the objects and conversions as we do.

Each distinct file is imported once for the whole run (and kept between runs) by
:mod:`pya2ldb_cache`, which keeps what pya2ldb's C++ parser printed (it logs problems to stdout and
carries on) to be searched for error lines; the questions are asked of the database it left.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from pya2ldb_cache import import_once


def _imported(path: Path, encoding: str = "utf-8", *, strict: bool = True):
    """The import of ``path``; ``strict``: no parser error either (else: the import ran to its end)."""
    imported = import_once(path, encoding)
    problems = imported.errors if strict else [f"exit status {imported.returncode}"] * bool(imported.returncode)
    assert not problems, f"pya2ldb rejected {path}:\n" + "\n".join(problems + list(imported.output[-40:]))
    return imported


def pya2l_import(path: Path, encoding: str = "utf-8") -> dict:
    """Import ``path`` with pya2ldb; returns object counts, raises AssertionError on any parser error."""
    from pya2l import model

    with _imported(path, encoding).session() as session:
        return {
            "MEASUREMENT": session.query(model.Measurement).count(),
            "CHARACTERISTIC": session.query(model.Characteristic).count(),
            "AXIS_PTS": session.query(model.AxisPts).count(),
            "ECU_ADDRESS": sorted([m.name, m.ecu_address.address] for m in session.query(model.Measurement)
                                  if m.ecu_address),
        }


def pya2l_describe(path: Path, request: dict) -> dict:
    """What pya2ldb reads from ``path``: the objects and conversions named in ``request``
    (``{"characteristics": [...], "measurements": [...], "axis_pts": [...], "conversions":
    {method: {"raw": [...], "physical": [...]}}, "layouts": [characteristics]}``), as plain data;
    an object pya2ldb fails on is ``{"error": "..."}``."""
    from pya2l.api import inspect

    out: dict = {"characteristics": {}, "measurements": {}, "axis_pts": {}, "conversions": {}, "addresses": {}}
    with _imported(path, strict=False).session() as session:
        readers = (("characteristics", _characteristic), ("measurements", _measurement), ("axis_pts", _axis_pts))
        for kind, read in readers:
            for name in request.get(kind, []):
                try:
                    out[kind][name] = read(inspect, session, name)
                except Exception as error:  # an object pya2ldb cannot read: say so, the caller decides
                    out[kind][name] = {"error": f"{type(error).__name__}: {error}"}
        for name, samples in request.get("conversions", {}).items():
            method = _get(lambda: inspect.CompuMethod(session, name))
            if method is None:  # TAB_INTP and FORM need scipy/numexpr, which pya2ldb does not install
                continue
            result = {"type": method.conversionType}
            if "raw" in samples:
                result["physical"] = [_number(_get(lambda: method.int_to_physical(v))) for v in samples["raw"]]
            if "physical" in samples:
                result["raw"] = [_number(_get(lambda: method.physical_to_int(v))) for v in samples["physical"]]
            out["conversions"][name] = result
        for name in request.get("layouts", []):
            components = inspect.Characteristic(session, name).record_layout_components
            out["addresses"][name] = {key: getattr(attr, "address", None) for key, attr in components["position"]}
    return out


def _get(read):  # pya2ldb raises on some absent options: absent is None here
    try:
        return read()
    except Exception:
        return None


def _name_of(thing):
    return getattr(thing, "name", None) if thing is not None else None


def _pair(limits):
    return [limits.lowerLimit, limits.upperLimit] if limits is not None and _get(limits.valid) else None


def _number(value):
    return value if value is None or isinstance(value, str) else float(np.asarray(value))


def _characteristic(inspect, session, name: str) -> dict:
    c = inspect.Characteristic(session, name)
    return {
        "type": c.type, "address": c.address, "record_layout": _name_of(c.deposit),
        "conversion": _name_of(c.compuMethod), "limits": [c.lowerLimit, c.upperLimit],
        "bit_mask": _get(lambda: c.bitMask), "byte_order": _get(lambda: c.byteOrder),
        "read_only": bool(_get(lambda: c.readOnly)), "extension": _get(lambda: c.ecuAddressExtension),
        "extended_limits": _pair(_get(lambda: c.extendedLimits)),
        "axes": [[a.attribute, a.maxAxisPoints, _name_of(_get(lambda: a.axisPtsRef)), _name_of(a.compuMethod),
                  a.lowerLimit, a.upperLimit] for a in c.axisDescriptions],
        "functions": sorted(getattr(f, "name", f) for f in (_get(lambda: c.functionList) or [])),
    }


def _measurement(inspect, session, name: str) -> dict:
    m = inspect.Measurement(session, name)
    dims = _get(lambda: m.matrixDim)
    return {
        "datatype": m.datatype, "address": m.ecuAddress, "conversion": _name_of(m.compuMethod),
        "limits": [m.lowerLimit, m.upperLimit], "bit_mask": _get(lambda: m.bitMask),
        "byte_order": _get(lambda: m.byteOrder),
        "matrix_dim": [d for d in (dims.x, dims.y, dims.z) if d is not None] if dims is not None else [],
        "array_size": _get(lambda: m.arraySize), "extension": _get(lambda: m.ecuAddressExtension),
    }


def _axis_pts(inspect, session, name: str) -> dict:
    a = inspect.AxisPts(session, name)
    return {"address": a.address, "record_layout": _name_of(a.depositAttr), "max": a.maxAxisPoints,
            "conversion": _name_of(a.compuMethod), "limits": [a.lowerLimit, a.upperLimit]}
