"""A2L COMPU_METHODs as MDF4 conversions: a recording keeps the raw values, readers show physical ones.

CANape records a signal as the ECU holds it and attaches the conversion; asammdf, CANape and
the MDF validators then show physical values (or texts) and the raw values stay exact. The
mapping, as asammdf's conversion dictionaries (:func:`asammdf.blocks.conversion_utils.from_dict`):

===========================  ==================================================================
IDENTICAL, NO_COMPU_METHOD   no conversion: the raw value is physical
LINEAR                       linear (a = factor, b = offset)
RAT_FUNC                     rational; ASAP2 gives raw = f(phys), MDF phys = g(raw): g is f
                             inverted (possible without quadratic terms, as the session reads it)
TAB_INTP / TAB_NOINTP        value to value with / without interpolation
TAB_VERB (COMPU_VTAB)        value to text; DEFAULT_VALUE as default text, else the raw number
                             (a nested identity conversion), as the session shows it
TAB_VERB (COMPU_VTAB_RANGE)  value range to text (a float range's upper bound nudged up one ulp:
                             MDF reads float ranges as [lower, upper), ASAP2 as [lower, upper])
FORM                         algebraic, when the formula uses only what both ASAP2 and MDF
                             spell alike (X1, numbers, + - * / and sin cos tan sinh cosh tanh
                             exp sqrt abs); anything else (C operators, log, pow, sysc) is not
===========================  ==================================================================

A mapping is used only when asammdf computes the same physical values as the workbench
(:mod:`workbench.a2l.compu`) for probe raw values: every value of an 8- or 16-bit type, else the
table's keys and their neighbours and a spread of ordinary numbers. Where it does not map, the
channel holds physical float64 values instead (:attr:`MdfEncoding.physical`) and its comment says
why; a conversion that cannot be read at all (quadratic RAT_FUNC) leaves the raw values, also said.

Tables are probed where ASAP2 defines them: MDF has no default for value-to-value tables (outside
an interpolated table it holds the end values, between the keys of a table without interpolation
it takes the nearest key), so a DEFAULT_VALUE_NUMERIC is noted in the comment, not mapped.
"""

from __future__ import annotations

import copy
import re
from dataclasses import dataclass

import numpy as np

from workbench.a2l.compu import Conversion
from workbench.errors import ConversionError

__all__ = ["MdfEncoding", "mdf_encoding"]

# relative: the same formula in another evaluator differs in the last bits; numexpr computes float32 raw values
# in float32 (their own precision), the workbench in float64
_TOLERANCE = {2: 1e-2, 4: 1e-6}
_TOLERANCE_DEFAULT = 1e-9
_ORDINARY = np.array([0.0, 1.0, -1.0, 2.0, 0.5, -0.5, 3.25, 10.0, 100.0, 255.0, 1000.0, 12345.0, -12345.0, 1e6, -1e6])
_FORMULA_TOKEN = re.compile(r"\s*(?:(?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|(?P<name>[A-Za-z_]\w*)|(?P<op>[-+*/()]))")
_SHARED_FUNCTIONS = frozenset({"sin", "cos", "tan", "sinh", "cosh", "tanh", "exp", "sqrt", "abs"})


@dataclass(frozen=True)
class MdfEncoding:
    """How a channel's values are stored.

    ``physical`` False: the raw values, with ``conversion`` (an asammdf conversion dictionary;
    None: none needed, or none possible). True: physical float64 values, no conversion.
    ``note``: what a reader should know (why physical values, or a table's default), for the comment.
    """

    conversion: dict | None
    physical: bool = False
    note: str = ""


def mdf_encoding(conversion: Conversion, raw_dtype: np.dtype) -> MdfEncoding:
    """The MDF form of ``conversion`` for raw values of ``raw_dtype`` (see the module docstring)."""
    kind = conversion.conversion_type
    if kind == "IDENTICAL":
        return MdfEncoding(None)
    try:
        probes = _probes(raw_dtype, conversion)
        conversion.to_physical(probes)
    except ConversionError as exc:
        return MdfEncoding(None, note=f"raw values: {exc}")
    candidate, note = _candidate(conversion, raw_dtype)
    if candidate is not None and _agrees(conversion, candidate, probes):
        return MdfEncoding(candidate, note=note)
    if conversion.verbal:  # texts cannot be stored as numbers; the raw values keep what the ECU sent
        return MdfEncoding(None, note=f"raw values: {conversion.name} (TAB_VERB) has no MDF form asammdf reads alike")
    return MdfEncoding(None, physical=True,
                       note=f"physical values: {conversion.name} ({kind}) has no MDF conversion asammdf computes alike")


def _candidate(conversion: Conversion, raw_dtype: np.dtype) -> tuple[dict | None, str]:
    """(asammdf conversion dictionary or None, note) for ``conversion``; not yet checked."""
    kind = conversion.conversion_type
    if kind == "LINEAR":
        return {"a": float(conversion.a), "b": float(conversion.b)}, ""
    if kind == "RAT_FUNC":
        a, b, c, d, e, f = conversion.a, conversion.b, conversion.c, conversion.d, conversion.e, conversion.f
        if a or d:
            return None, ""
        return {"P1": 0.0, "P2": float(-f), "P3": float(c), "P4": 0.0, "P5": float(e), "P6": float(-b)}, ""
    if kind in ("TAB_INTP", "TAB_NOINTP"):
        table = {"interpolation": conversion.interpolate}
        for i, (raw, physical) in enumerate(zip(conversion.raws.tolist(), conversion.physicals.tolist())):
            table[f"raw_{i}"], table[f"phys_{i}"] = raw, physical
        return table, _table_note(conversion)
    if kind == "TAB_VERB":
        return _verbal(conversion, raw_dtype), ""
    if kind == "FORM":
        formula = _mdf_formula(conversion.method.formula)
        return ({"formula": formula} if formula else None), ""
    return None, ""


def _table_note(conversion: Conversion) -> str:
    if conversion.interpolate:
        if conversion.default is None:
            return ""
        return (f"outside [{conversion.raws[0]:g}, {conversion.raws[-1]:g}] the A2L gives {conversion.default:g} "
                "(DEFAULT_VALUE_NUMERIC), MDF the end values")
    default = "NaN" if conversion.default is None else f"{conversion.default:g} (DEFAULT_VALUE_NUMERIC)"
    return f"a raw value not in the table: the A2L gives {default}, MDF the nearest entry's value"


def _verbal(conversion: Conversion, raw_dtype: np.dtype) -> dict:
    table: dict = {}
    ranges = bool(np.any(conversion.lowers != conversion.uppers))
    for i, (lower, upper, text) in enumerate(zip(conversion.lowers.tolist(), conversion.uppers.tolist(), conversion.texts)):
        if ranges:
            table[f"lower_{i}"] = lower
            table[f"upper_{i}"] = float(np.nextafter(upper, np.inf)) if raw_dtype.kind == "f" else upper
        else:
            table[f"val_{i}"] = lower
        table[f"text_{i}"] = text
    table["default_addr"] = conversion.default if conversion.default is not None else {"a": 1.0, "b": 0.0}
    return table


def _mdf_formula(text: str | None) -> str | None:
    """``text`` in MDF's algebraic syntax (X for X1), or None when it uses anything beyond the shared subset."""
    if not text:
        return None
    out, position = [], 0
    text = text.strip()
    while position < len(text):
        token = _FORMULA_TOKEN.match(text, position)
        if token is None or token.end() == position:
            return None
        position = token.end()
        name = token.group("name")
        if name is not None:
            if name.upper() in ("X", "X1"):
                name = "X"
            elif name.lower() in _SHARED_FUNCTIONS:
                name = name.lower()
            else:
                return None
            out.append(name)
        else:
            out.append(token.group("number") or token.group("op"))
    return "".join(out)


def _probes(raw_dtype: np.dtype, conversion: Conversion) -> np.ndarray:
    """Raw values to compare both evaluations on, of ``raw_dtype``."""
    kind = conversion.conversion_type
    if kind == "TAB_NOINTP":
        return conversion.raws.astype(raw_dtype)  # MDF and ASAP2 agree on the keys only (see _table_note)
    if raw_dtype.kind in "iu" and raw_dtype.itemsize <= 2:
        info = np.iinfo(raw_dtype)
        values = np.arange(info.min, info.max + 1)
    else:
        keys = _keys(conversion)
        values = np.concatenate((_ORDINARY, keys, keys - 1, keys + 1, keys + 0.5, keys - 0.5))
        if raw_dtype.kind in "iu":
            info = np.iinfo(raw_dtype)
            values = np.concatenate((np.clip(np.round(values), float(info.min), float(info.max)), [info.min, info.max]))
    if kind == "TAB_INTP" and conversion.default is not None:
        values = values[(values >= conversion.raws[0]) & (values <= conversion.raws[-1])]
    return np.unique(values.astype(raw_dtype))


def _keys(conversion: Conversion) -> np.ndarray:
    if conversion.conversion_type in ("TAB_INTP", "TAB_NOINTP"):
        return conversion.raws
    if conversion.verbal:
        return np.concatenate((conversion.lowers, conversion.uppers))
    return np.zeros(0)


def _agrees(conversion: Conversion, candidate: dict, probes: np.ndarray) -> bool:
    from asammdf.blocks.conversion_utils import from_dict

    ours = np.asarray(conversion.to_physical(probes))
    try:
        theirs = np.asarray(from_dict(copy.deepcopy(candidate)).convert(probes, as_object=True))
    except Exception:  # asammdf cannot evaluate it (numexpr refuses a formula ...): then it does not map
        return False
    if conversion.verbal:
        return [_comparable(v) for v in ours.ravel().tolist()] == [_comparable(v) for v in theirs.ravel().tolist()]
    try:
        theirs = theirs.astype(np.float64)
    except (TypeError, ValueError):
        return False
    tolerance = _TOLERANCE.get(probes.dtype.itemsize, _TOLERANCE_DEFAULT) if probes.dtype.kind == "f" else _TOLERANCE_DEFAULT
    return bool(np.allclose(ours.astype(np.float64), theirs, rtol=tolerance, atol=0.0, equal_nan=True))


def _comparable(value) -> str | float:
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    return value if isinstance(value, str) else float(value)
