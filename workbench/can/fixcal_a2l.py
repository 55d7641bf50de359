"""The fix calibrations as an A2L fragment, in the form of the demo's ``a2l/modules/*.a2l``.

The fragment is a complete small A2L (PROJECT/MODULE with MOD_COMMON) holding one
CHARACTERISTIC VALUE per calibration at the placeholder address 0x0000 (``workbench a2l
update`` fills it in from the ELF) and the COMPU_METHODs, COMPU_VTABs and RECORD_LAYOUTs
they use, named and worded as the demo ECU's fragments do, so that identical definitions
merge silently:

* ``_EN`` and ``cs…_En``: ``CM_OnOff`` (``VTAB_OnOff``: 0 "OFF", 1 "ON"), limits 0..1;
* ``_VALUE`` with factor 1, offset 0 and DBC value descriptions: a TAB_VERB conversion,
  ``CM_<table>`` when the descriptions are a DBC ``VAL_TABLE_``, else ``CM_CAN_<Signal>``;
* ``_VALUE`` otherwise: LINEAR ``CM_CAN_<factor>[_<offset>][_<unit>]`` (``CM_CAN_0p01_bar``:
  phys = 0.01 · raw + 0), or ``CM_Identity`` for factor 1, offset 0 and no unit;
* record layouts ``Scalar_<datatype>`` (``Scalar_UBYTE``, ``Scalar_UWORD`` ...);
* ``_VALUE`` of a signal whose live MEASUREMENT is known (a sent signal's source variable, a
  received signal's published value): ``COMPARISON_QUANTITY <measurement>`` (ASAM MCD-2MC: the
  measurement a calibration tool shows beside the adjustable object), so a tool that reads the
  A2L finds the signal's live value by the link, not by its name.

Two conversions that would get one name but differ (``µs`` and ``s`` both spell ``_s``;
``Sgn2`` with other value descriptions in another message, under ``--qualified``) must not
share it: the later one is renamed, a verbal one to ``CM_CAN_<Message>_<Signal>``, any
other with a numeric suffix (``CM_CAN_1_s_2``).

The MOD_COMMON (byte order, alignments: a property of the target, not of the DBC) is the
master A2L's, as every demo fragment carries it; without a master the fragment has none.
"""

from __future__ import annotations

import dataclasses
import itertools
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from workbench.a2l.document import A2lDocument
from workbench.can.fixcal import FixCalibration, FixKind, format_number
from workbench.can.model import SignalOfMsg, step_decimals

__all__ = ["A2L_DATATYPES", "a2l_fragment", "mod_common_lines"]

A2L_DATATYPES = {
    "uint8_T": "UBYTE", "int8_T": "SBYTE", "uint16_T": "UWORD", "int16_T": "SWORD",
    "uint32_T": "ULONG", "int32_T": "SLONG", "uint64_T": "A_UINT64", "int64_T": "A_INT64",
    "real32_T": "FLOAT32_IEEE", "real_T": "FLOAT64_IEEE",
}
_ON_OFF = ("CM_OnOff", "VTAB_OnOff")
_UNIT_WORDS = {"%": "Percent", "°": "deg", "µ": "u", "μ": "u", "²": "2", "³": "3", "/": "_per_"}


@dataclass(frozen=True)
class _Conversion:
    """A COMPU_METHOD (and, verbal, its COMPU_VTAB) as the fragment writes it."""

    name: str
    title: str
    kind: str
    """``IDENTICAL``, ``LINEAR`` or ``TAB_VERB``."""
    display_format: str
    unit: str = ""
    coefficients: str = ""
    """``COEFFS_LINEAR`` arguments of a LINEAR conversion."""
    table: str | None = None
    """The COMPU_VTAB of a verbal conversion."""
    table_title: str = ""
    choices: tuple[tuple[int, str], ...] = ()
    alternative: str | None = field(default=None, compare=False)
    """The name to try before a numeric suffix when :attr:`name` is taken (verbal: message-qualified)."""

    def method_text(self) -> str:
        extra = f"COEFFS_LINEAR {self.coefficients}" if self.coefficients else (
            f"COMPU_TAB_REF {self.table}" if self.table else None)
        return _compu_method(self.name, self.title, self.kind, self.display_format, self.unit, extra)

    def table_text(self) -> str:
        entries = "".join(f'      {value} "{_string(text)}"\n' for value, text in self.choices)
        return (f'    /begin COMPU_VTAB {self.table} "{_string(self.table_title)}" TAB_VERB {len(self.choices)}\n'
                f"{entries}    /end COMPU_VTAB\n")

    def renamed(self, stem: str) -> _Conversion:
        """This conversion as ``CM_<stem>`` (verbal: with ``VTAB_<stem>``), without an alternative."""
        table = f"VTAB_{stem}" if self.table else None
        return dataclasses.replace(self, name=f"CM_{stem}", table=table, alternative=None)


def mod_common_lines(master: A2lDocument) -> tuple[str, ...]:
    """The options of the A2L's MOD_COMMON, one line each as written (``BYTE_ORDER MSB_LAST``); empty
    when it has none."""
    block = master.mod_common()
    if block is None:
        return ()
    return tuple(" ".join([keyword, *(master.raw(token).decode(master.encoding) for token in params)])
                 for keyword, params in block.layout()[1])


def a2l_fragment(calibrations: Sequence[FixCalibration], module: str, title: str,
                 mod_common: Sequence[str] = (), comparison: Mapping[str, str] | None = None) -> str:
    """The A2L text: PROJECT/MODULE ``module`` (an identifier) described by ``title``.

    :param mod_common: the MOD_COMMON keyword lines (:func:`mod_common_lines` of the master).
    :param comparison: calibration name -> the MEASUREMENT its COMPARISON_QUANTITY names (a ``_VALUE``'s
        live signal); the measurement is defined elsewhere (the module that computes or publishes it).
    """
    comparison = comparison or {}
    conversions: dict[str, _Conversion] = {}
    layouts: set[str] = set()
    characteristics = []
    for calibration in calibrations:
        conversion = _unique(_conversion(calibration), conversions)
        conversions[conversion.name] = conversion
        layout = f"Scalar_{A2L_DATATYPES[calibration.c_type]}"
        layouts.add(layout)
        characteristics.append(_characteristic(calibration, layout, conversion.name,
                                               comparison.get(calibration.name)))
    tables = sorted((c.table, c.table_text()) for c in conversions.values() if c.table)
    parts = [
        (f"/* ASAP2 fragment: {title}.\n"
        "   Generated by `workbench dbc fixcal`: every address is a placeholder 0x0000 that\n"
        "   `workbench a2l update` fills in from the ELF. */\n"),
        "ASAP2_VERSION 1 71\n",
        f'/begin PROJECT {module} "{_string(title)}"\n',
        f'  /begin HEADER "{_string(title)}"\n    VERSION "1.0.0"\n  /end HEADER\n',
        f'  /begin MODULE {module} "{_string(title)}"\n',
    ]
    if mod_common:
        parts += ['    /begin MOD_COMMON ""\n', *(f"      {line}\n" for line in mod_common), "    /end MOD_COMMON\n"]
    parts += [
        "\n", *characteristics,
        "\n", *(conversions[name].method_text() for name in sorted(conversions)),
    ]
    if tables:
        parts += ["\n", *(text for _, text in tables)]
    parts += ["\n", *(_record_layout(layout) for layout in sorted(layouts))]
    parts.append("  /end MODULE\n/end PROJECT\n")
    return "".join(parts)


def _characteristic(calibration: FixCalibration, layout: str, conversion: str, comparison: str | None) -> str:
    name = calibration.name
    link = f"      COMPARISON_QUANTITY {comparison}\n" if comparison else ""
    return (
        "    /begin CHARACTERISTIC\n"
        f"      /* Name                   */ {name}\n"
        f'      /* Long Identifier        */ "{_string(calibration.description)}"\n'
        "      /* Type                   */ VALUE\n"
        f"      /* ECU Address            */ 0x0000 /* @ECU_Address@{name}@ */\n"
        f"      /* Record Layout          */ {layout}\n"
        "      /* Maximum Difference     */ 0\n"
        f"      /* Conversion Method      */ {conversion}\n"
        f"      /* Lower Limit            */ {format_number(calibration.lower)}\n"
        f"      /* Upper Limit            */ {format_number(calibration.upper)}\n"
        f"{link}"
        "    /end CHARACTERISTIC\n"
    )


def _conversion(calibration: FixCalibration) -> _Conversion:
    signal = calibration.signal
    if calibration.kind is not FixKind.FIX_VALUE:
        return _verbal(*_ON_OFF, "Switch state", ((0, "OFF"), (1, "ON")))
    if signal.factor == 1 and signal.offset == 0 and signal.choices:
        if signal.value_table:
            table = signal.value_table
            return _verbal(f"CM_{table}", f"VTAB_{table}", table, signal.choices)
        where = f"DBC value table of {calibration.message.name}.{signal.name}"
        return dataclasses.replace(
            _verbal(f"CM_CAN_{signal.name}", f"VTAB_CAN_{signal.name}", where, signal.choices),
            alternative=f"CAN_{calibration.message.name}_{signal.name}",
        )
    if signal.factor == 1 and signal.offset == 0 and not signal.unit:
        return _Conversion("CM_Identity", "Identity", "IDENTICAL", '"%9.3"')
    return _linear(signal)


def _unique(conversion: _Conversion, known: dict[str, _Conversion]) -> _Conversion:
    """``conversion``, renamed when another conversion already has its name (see the module doc)."""
    stem = conversion.name.removeprefix("CM_")
    alternatives = [conversion.alternative] if conversion.alternative else []
    candidates = itertools.chain(
        [conversion], (conversion.renamed(name) for name in alternatives),
        (conversion.renamed(f"{stem}_{number}") for number in itertools.count(2)),
    )
    return next(candidate for candidate in candidates if known.get(candidate.name, candidate) == candidate)


def _verbal(name: str, table: str, title: str, choices: Sequence[tuple[int, str]]) -> _Conversion:
    return _Conversion(name, f"Enumeration {title}", "TAB_VERB", '"%3.0"', table=table, table_title=title,
                       choices=tuple(choices))


def _linear(signal: SignalOfMsg) -> _Conversion:
    factor, offset = format_number(signal.factor), format_number(signal.offset)
    parts = [_name_number(factor)]
    if signal.offset:
        parts.append(_name_number(offset))
    if signal.unit:
        parts.append(_unit_word(signal.unit))
    name = "CM_CAN_" + "_".join(p for p in parts if p)
    unit = f" [{signal.unit}]" if signal.unit else ""
    display = f'"%8.{step_decimals(signal.factor, signal.offset)}"'
    return _Conversion(name, f"phys = {factor} * raw + {offset}{unit}", "LINEAR", display, signal.unit,
                       coefficients=f"{factor} {offset}")


def _compu_method(name: str, title: str, kind: str, display_format: str, unit: str, extra: str | None) -> str:
    return (
        "    /begin COMPU_METHOD\n"
        f"      /* Name of CompuMethod    */ {name}\n"
        f'      /* Long identifier        */ "{_string(title)}"\n'
        f"      /* Conversion Type        */ {kind}\n"
        f"      /* Format                 */ {display_format}\n"
        f'      /* Units                  */ "{_string(unit)}"\n'
        + (f"      {extra}\n" if extra else "")
        + "    /end COMPU_METHOD\n"
    )


def _record_layout(layout: str) -> str:
    datatype = layout.removeprefix("Scalar_")
    return f"    /begin RECORD_LAYOUT {layout}\n      FNC_VALUES 1 {datatype} ROW_DIR DIRECT\n    /end RECORD_LAYOUT\n"


def _name_number(text: str) -> str:
    return text.replace(".", "p").replace("-", "m").replace("+", "")


def _unit_word(unit: str) -> str:
    for symbol, word in _UNIT_WORDS.items():
        unit = unit.replace(symbol, word)
    return re.sub(r"[^A-Za-z0-9_]+", "_", unit).strip("_")


def _string(text: str) -> str:
    """An A2L string literal's content: quotes and backslashes escaped, one line."""
    return " ".join(text.replace("\\", "\\\\").replace('"', '\\"').split())
