"""COMPU_METHODs applied both ways: raw ECU values to physical values and back.

``model.conversion(obj)`` gives the :class:`Conversion` of an object's COMPU_METHOD;
``to_physical(raw)`` and ``to_raw(physical)`` take a number or a numpy array (any shape) and
return the same: a Python number for a scalar, a float64 array for an array (a verbal table gives
``str`` and an ``object`` array). ``to_raw`` does not round: the codec, which knows the data type,
rounds (half away from zero for integer types) and checks the range.

=============  =====================================================================================
IDENTICAL      raw = physical (NO_COMPU_METHOD too); integers stay integers
LINEAR         phys = a * raw + b (COEFFS_LINEAR a b)
RAT_FUNC       ASAP2 defines raw = f(phys) = (a p^2 + b p + c) / (d p^2 + e p + f) (COEFFS a..f);
               to_physical inverts it: p = (c - f r) / (e r - b) when a = d = 0 (linear and
               reciprocal forms); a quadratic one cannot be inverted and is refused when read
TAB_INTP       COMPU_TAB pairs, linear interpolation; outside the table DEFAULT_VALUE_NUMERIC if
               given, else the end values. Back by interpolation when the physical column is
               strictly monotonic; a value outside its range is refused
TAB_NOINTP     COMPU_TAB pairs, exact raw values; any other raw value gives DEFAULT_VALUE_NUMERIC
               (NaN without one). Back: only the table's physical values
TAB_VERB       COMPU_VTAB (raw -> text) or COMPU_VTAB_RANGE (raw in [lower, upper] -> text; ranges
               should not overlap: where they do, the one with the highest lower bound wins). A raw value in no entry gives DEFAULT_VALUE, else the
               number itself. Back: a listed text, or a number (taken as the raw value); any other
               text is refused naming the allowed ones. A range gives its lowest integer value.
FORM           FORMULA in X1 (:mod:`workbench.a2l.formula`, never ``eval``); back with
               FORMULA_INV, else found numerically: for integer data types by bisection when the
               formula is monotonic over the data type's range, for float types when it is affine
=============  =====================================================================================
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from workbench.a2l.datatypes import DATATYPES, datatype_range
from workbench.a2l.display_format import format_parts
from workbench.a2l.formula import Formula, compile_formula
from workbench.a2l.objects import CompuMethod, CompuTab, CompuVtab, CompuVtabRange
from workbench.errors import A2lParseError, ConversionError

__all__ = ["Conversion", "conversion_for"]

_SHOWN = 12  # allowed values named in an error


class Conversion:
    """One COMPU_METHOD in both directions (see the module docstring for the rules)."""

    verbal = False  # True: physical values are texts (TAB_VERB)

    def __init__(self, method: CompuMethod | None):
        self.method = method
        self.name = method.name if method else "NO_COMPU_METHOD"
        self.conversion_type = method.conversion_type if method else "IDENTICAL"
        self.unit = method.unit if method else ""
        self.format = method.format if method else None

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name}>"

    @property
    def decimals(self) -> int | None:
        """Decimal places to show (from the FORMAT ``%8.3`` -> 3)."""
        return format_parts(self.format)[1]

    def to_physical(self, raw: Any) -> Any:
        """Raw value(s) -> physical; :raises ConversionError: the method cannot be read this way."""
        scalar = np.ndim(raw) == 0
        result = self._physical(self._numbers(raw, "raw"))
        return _shaped(result, scalar)

    def to_raw(self, physical: Any, datatype: str | None = None) -> Any:
        """Physical value(s) -> raw, unrounded. ``datatype``: the object's ASAP2 data type, which a
        formula without FORMULA_INV needs to be inverted numerically.

        :raises ConversionError: a value this conversion cannot take back (a text for a numeric
            method, a value outside a table, a non-invertible method).
        """
        scalar = np.ndim(physical) == 0
        result = self._raw(self._numbers(physical, "physical"), datatype)
        return _shaped(result, scalar)

    # -- overridden ------------------------------------------------------------------------------------
    def _physical(self, raw: np.ndarray) -> np.ndarray:
        return raw

    def _raw(self, physical: np.ndarray, datatype: str | None) -> np.ndarray:
        return physical

    def _numbers(self, value: Any, what: str) -> np.ndarray:
        array = np.asarray(value)
        if array.dtype.kind in "biuf":
            return array if self.conversion_type == "IDENTICAL" else array.astype(np.float64)
        try:
            return array.astype(np.float64)
        except (TypeError, ValueError):
            bad = next((v for v in array.ravel().tolist() if isinstance(v, str)), array.ravel()[0])
            raise ConversionError(f"{self.name}: {bad!r} is not a number ({self.conversion_type} conversion of "
                                  f"{what} values)") from None


def _shaped(result: np.ndarray, scalar: bool) -> Any:
    if not scalar:
        return result
    item = np.asarray(result).reshape(()).item() if np.ndim(result) == 0 else result
    return item


class _Identity(Conversion):
    """IDENTICAL and NO_COMPU_METHOD."""


class _Linear(Conversion):
    def __init__(self, method: CompuMethod):
        super().__init__(method)
        self.a, self.b = method.coeffs_linear

    def _physical(self, raw):
        return self.a * raw + self.b

    def _raw(self, physical, datatype):
        if self.a == 0:
            raise ConversionError(f"{self.name}: LINEAR with factor 0 maps every raw value to {self.b}; "
                                  "it cannot be inverted")
        return (physical - self.b) / self.a


class _RationalFunction(Conversion):
    def __init__(self, method: CompuMethod):
        super().__init__(method)
        self.a, self.b, self.c, self.d, self.e, self.f = method.coeffs

    def _raw(self, p, datatype):
        a, b, c, d, e, f = self.a, self.b, self.c, self.d, self.e, self.f
        with np.errstate(all="ignore"):
            return (a * p * p + b * p + c) / (d * p * p + e * p + f)

    def _physical(self, r):
        a, b, c, d, e, f = self.a, self.b, self.c, self.d, self.e, self.f
        if a != 0 or d != 0:
            raise ConversionError(f"{self.name}: RAT_FUNC with quadratic terms (COEFFS {self.a:g} {self.b:g} "
                                  f"{self.c:g} {self.d:g} {self.e:g} {self.f:g}) cannot be inverted to read "
                                  "physical values")
        if b * f - c * e == 0:
            raise ConversionError(f"{self.name}: RAT_FUNC COEFFS 0 {b:g} {c:g} 0 {e:g} {f:g} is constant; it "
                                  "cannot be inverted to read physical values")
        with np.errstate(all="ignore"):
            return (c - f * r) / (e * r - b)


class _Table(Conversion):
    """TAB_INTP and TAB_NOINTP over a COMPU_TAB."""

    def __init__(self, method: CompuMethod, table: CompuTab):
        super().__init__(method)
        pairs = np.array(table.pairs, dtype=np.float64).reshape(-1, 2)
        order = np.argsort(pairs[:, 0], kind="stable")
        self.raws, self.physicals = pairs[order, 0], pairs[order, 1]
        self.default = table.default_value_numeric
        self.interpolate = method.conversion_type == "TAB_INTP"
        if not len(self.raws):
            raise ConversionError(f"{self.name}: COMPU_TAB {table.name} is empty")

    def _physical(self, raw):
        if self.interpolate:
            result = np.interp(raw, self.raws, self.physicals)
            if self.default is not None:
                result = np.where((raw < self.raws[0]) | (raw > self.raws[-1]), self.default, result)
            return result
        slot = np.clip(np.searchsorted(self.raws, raw), 0, len(self.raws) - 1)
        found = self.raws[slot] == raw
        fallback = np.nan if self.default is None else self.default
        return np.where(found, self.physicals[slot], fallback)

    def _raw(self, physical, datatype):
        if not self.interpolate:
            matches = physical[..., None] == self.physicals
            if not matches.any(axis=-1).all():
                bad = physical[~matches.any(axis=-1)].ravel()[0]
                allowed = ", ".join(f"{v:g}" for v in self.physicals[:_SHOWN])
                raise ConversionError(f"{self.name}: {bad:g} is not a value of its table (TAB_NOINTP; allowed: "
                                      f"{allowed}{' ...' if len(self.physicals) > _SHOWN else ''})")
            return self.raws[np.argmax(matches, axis=-1)]
        steps = np.diff(self.physicals)
        if len(steps) and (steps > 0).all():
            xs, ys = self.physicals, self.raws
        elif len(steps) and (steps < 0).all():
            xs, ys = self.physicals[::-1], self.raws[::-1]
        else:
            raise ConversionError(f"{self.name}: the physical values of its TAB_INTP table are not strictly "
                                  "monotonic, so a physical value has no single raw value")
        outside = (physical < xs[0]) | (physical > xs[-1])
        if outside.any():
            bad = physical[outside].ravel()[0]
            raise ConversionError(f"{self.name}: {bad:g} is outside its table's physical range "
                                  f"[{xs[0]:g}, {xs[-1]:g}]")
        return np.interp(physical, xs, ys)


class _Verbal(Conversion):
    """TAB_VERB over a COMPU_VTAB or COMPU_VTAB_RANGE."""

    verbal = True

    def __init__(self, method: CompuMethod, table: CompuVtab | CompuVtabRange):
        super().__init__(method)
        if isinstance(table, CompuVtab):
            triples = [(raw, raw, text) for raw, text in table.pairs]
        else:
            triples = list(table.triples)
        self.lowers = np.array([t[0] for t in triples], dtype=np.float64)
        self.uppers = np.array([t[1] for t in triples], dtype=np.float64)
        self.texts = [t[2] for t in triples]
        if not triples:
            raise ConversionError(f"{self.name}: {table.name} has no entries")
        self._by_lower = np.argsort(self.lowers, kind="stable")
        self._sorted_lowers = self.lowers[self._by_lower]
        self._text_array = np.array(self.texts + [None], dtype=object)[:-1]
        self.default = table.default_value
        self.raw_of: dict[str, float] = {}
        for lower, upper, text in triples:
            first = np.ceil(lower) if np.ceil(lower) <= upper else lower
            self.raw_of.setdefault(text, float(first))
        self._by_folded: dict[str, list[str]] = {}  # casefolded text -> the table's texts
        for text in self.raw_of:
            self._by_folded.setdefault(text.strip().casefold(), []).append(text)

    @property
    def allowed(self) -> list[str]:
        """The texts, in table order."""
        return list(self.raw_of)

    @property
    def allowed_shown(self) -> str:
        """The texts as a refusal lists them: the first few, "..." for the rest."""
        allowed = self.allowed
        return ", ".join(allowed[:_SHOWN]) + (" ..." if len(allowed) > _SHOWN else "")

    def to_physical(self, raw: Any) -> Any:
        scalar = np.ndim(raw) == 0
        values = self._numbers(raw, "raw").astype(np.float64)
        flat = values.ravel()
        # the entry with the highest lower bound <= value (vectorized); misses look at every entry
        slot = np.clip(np.searchsorted(self._sorted_lowers, flat, side="right") - 1, 0, len(self.texts) - 1)
        entry = self._by_lower[slot]
        hit = (flat >= self.lowers[entry]) & (flat <= self.uppers[entry])
        out = self._text_array[entry]
        for i in np.flatnonzero(~hit).tolist():
            number = flat[i]
            holders = np.flatnonzero((number >= self.lowers) & (number <= self.uppers))
            if len(holders):
                out[i] = self.texts[holders[0]]
            elif self.default is not None:
                out[i] = self.default
            else:
                out[i] = int(number) if float(number).is_integer() else float(number)
        return out[0] if scalar else out.reshape(values.shape)

    def text_of(self, value: str) -> str | None:
        """The table's text that ``value`` names: itself, itself without end blanks, or the one text that
        differs from it only in case (``low`` for ``Low``); None when it names none.

        :raises ConversionError: several texts differ from ``value`` only in case.
        """
        for text in (value, value.strip()):
            if text in self.raw_of:
                return text
        texts = self._by_folded.get(value.strip().casefold(), [])
        if len(texts) > 1:
            raise ConversionError(f"{self.name}: {value!r} matches {', '.join(map(repr, texts))}, which differ only "
                                  "in case: write one exactly")
        return texts[0] if texts else None

    def to_raw(self, physical: Any, datatype: str | None = None) -> Any:
        scalar = np.ndim(physical) == 0
        values = np.asarray(physical, dtype=object)
        flat = values.ravel()
        out = np.empty(len(flat), dtype=np.float64)
        for i, value in enumerate(flat.tolist()):
            if isinstance(value, str):
                text = self.text_of(value)
                if text is None:
                    raise ConversionError(f"{self.name}: {value!r} is not one of its texts (allowed: "
                                          f"{self.allowed_shown})")
                out[i] = self.raw_of[text]
            else:
                try:
                    out[i] = float(value)
                except (TypeError, ValueError):
                    raise ConversionError(f"{self.name}: {value!r} is neither a text of the table nor a raw "
                                          "number") from None
        return out[0].item() if scalar else out.reshape(values.shape)


class _Form(Conversion):
    """FORM: FORMULA in X1, FORMULA_INV or a numeric inverse."""

    def __init__(self, method: CompuMethod, constants: Mapping[str, str]):
        super().__init__(method)
        self.formula: Formula = compile_formula(method.formula, constants)
        self.inverse: Formula | None = compile_formula(method.formula_inv, constants) if method.formula_inv else None

    def _physical(self, raw):
        return self.formula(raw)

    def _raw(self, physical, datatype):
        if self.inverse is not None:
            return self.inverse(physical)
        if datatype is None or datatype not in DATATYPES:
            raise ConversionError(f"{self.name}: FORM without FORMULA_INV can only be inverted numerically for "
                                  "a known data type")
        limits = datatype_range(datatype)
        if limits is None:
            return self._affine_inverse(physical)
        return self._bisect(physical, *limits)

    def _affine_inverse(self, physical):
        probes = np.array([-1000.0, -1.0, 0.0, 1.0, 2.0, 10.0, 12345.5])
        values = self.formula(probes)
        slope = (values[4] - values[3])
        predicted = values[2] + slope * probes
        if slope == 0 or not np.allclose(values, predicted, rtol=1e-12, atol=1e-12 * max(1.0, abs(values[2]))):
            raise ConversionError(f"{self.name}: FORM {self.formula.text!r} has no FORMULA_INV and is not linear, "
                                  "so a physical value cannot be written to a float")
        return (physical - values[2]) / slope

    def _bisect(self, physical, lowest: int, highest: int):
        lowest, highest = max(lowest, -(2**53)), min(highest, 2**53)  # where float64 counts every integer
        grid = np.unique(np.round(np.linspace(lowest, highest, min(highest - lowest + 1, 65537))))
        values = self.formula(grid)
        steps = np.diff(values)
        if (steps > 0).all():
            sign = 1.0
        elif (steps < 0).all():
            sign = -1.0
        else:
            raise ConversionError(f"{self.name}: FORM {self.formula.text!r} has no FORMULA_INV and is not "
                                  f"monotonic over the raw range [{lowest}, {highest}], so it cannot be inverted")
        target = sign * physical
        low_value, high_value = sign * values[0], sign * values[-1]
        outside = (target < low_value) | (target > high_value)
        if outside.any():
            bad = physical[outside].ravel()[0]
            raise ConversionError(f"{self.name}: {bad:g} is beyond what FORM {self.formula.text!r} reaches over "
                                  f"the raw range [{lowest}, {highest}]")
        low = np.full(np.shape(target), float(lowest))
        high = np.full(np.shape(target), float(highest))
        while np.any(high - low > 1):  # f(low) <= target <= f(high), in integers
            middle = np.floor((low + high) / 2)
            above = sign * self.formula(middle) >= target
            high = np.where(above, middle, high)
            low = np.where(above, low, middle)
        nearer_low = np.abs(sign * self.formula(low) - target) <= np.abs(sign * self.formula(high) - target)
        return np.where(nearer_low, low, high)


def conversion_for(method: CompuMethod | None, table: CompuTab | CompuVtab | CompuVtabRange | None,
                   system_constants: Mapping[str, str] | None = None) -> Conversion:
    """The :class:`Conversion` of a COMPU_METHOD (None: NO_COMPU_METHOD) and its conversion table.

    :raises A2lParseError: at the COMPU_METHOD when it lacks what its type needs (coefficients,
        a table of the right kind, a formula) or its formula does not parse.
    """
    if method is None:
        return _Identity(None)
    kind = method.conversion_type
    try:
        if kind == "IDENTICAL":
            return _Identity(method)
        if kind == "LINEAR" and method.coeffs_linear is not None:
            return _Linear(method)
        if kind == "RAT_FUNC" and method.coeffs is not None:
            return _RationalFunction(method)
        if kind in ("TAB_INTP", "TAB_NOINTP") and isinstance(table, CompuTab):
            return _Table(method, table)
        if kind == "TAB_VERB" and isinstance(table, (CompuVtab, CompuVtabRange)):
            return _Verbal(method, table)
        if kind == "FORM" and method.formula is not None:
            return _Form(method, system_constants or {})
    except ConversionError as error:
        raise _located(method, str(error)) from None
    needs = {"LINEAR": "COEFFS_LINEAR", "RAT_FUNC": "COEFFS", "TAB_INTP": "a COMPU_TAB_REF to a COMPU_TAB",
             "TAB_NOINTP": "a COMPU_TAB_REF to a COMPU_TAB", "FORM": "a FORMULA",
             "TAB_VERB": "a COMPU_TAB_REF to a COMPU_VTAB or COMPU_VTAB_RANGE"}
    if kind in needs:
        raise _located(method, f"COMPU_METHOD {method.name}: {kind} needs {needs[kind]}")
    raise _located(method, f"COMPU_METHOD {method.name}: unknown conversion type {kind}")


def _located(method: CompuMethod, message: str) -> A2lParseError:
    location = method.location
    return A2lParseError(message, *(location if location else ("<string>", 0, 0)))
