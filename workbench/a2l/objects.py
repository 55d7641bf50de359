"""The A2L's objects as plain, frozen data: what a MEASUREMENT, CHARACTERISTIC, AXIS_PTS ... means.

Built by :class:`workbench.a2l.model.A2lModel` from the reader's tokens on first access; nothing
here refers back to the document. Names of other objects (a COMPU_METHOD, a RECORD_LAYOUT, an
AXIS_PTS) stay names: the model resolves them. Every object keeps its :class:`Location` (the
``/begin`` of its block) and the locations of the names it refers to, so a broken reference is
reported at ``file:line:column``.

Spellings follow the ASAP2 keywords, lower-cased: ``datatype`` ``UBYTE``, ``byte_order``
``MSB_FIRST``/``MSB_LAST`` (Motorola/Intel; ``BIG_ENDIAN``/``LITTLE_ENDIAN`` are read as those),
``conversion`` the COMPU_METHOD name (``NO_COMPU_METHOD`` for none). Limits and coefficients are
floats; addresses, masks and counts ints. Optional fields are ``None`` when the keyword is absent.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Mapping, NamedTuple

from workbench.a2l.display_format import format_parts

__all__ = [
    "Alignments", "AxisDescr", "AxisPts", "Blob", "Characteristic", "CompuMethod", "CompuTab", "CompuVtab",
    "CompuVtabRange", "Function", "Group", "Instance", "LayoutEntry", "Location", "Measurement", "ModCommon",
    "Overwrite", "RecordLayout", "StructureComponent", "TypedefStructure", "Unit", "AXIS_NAMES", "NO_COMPU_METHOD",
]

NO_COMPU_METHOD = "NO_COMPU_METHOD"
AXIS_NAMES = ("X", "Y", "Z", "4", "5")  # the record layout's axis suffixes, in AXIS_DESCR order


class Location(NamedTuple):
    """Where something is written: file name, 1-based line and column."""

    file: str
    line: int
    column: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


def _meta():
    """A field that is data about the text, not part of the object's value (not compared)."""
    return field(default=None, compare=False, repr=False)


@dataclass(frozen=True)
class Alignments:
    """ALIGNMENT_* in bytes per data type size class; the defaults are ASAP2's (natural alignment)."""

    byte: int = 1
    word: int = 2
    long: int = 4
    int64: int = 8
    float16: int = 2
    float32: int = 4
    float64: int = 8

    _BY_DATATYPE = {
        "UBYTE": "byte", "SBYTE": "byte", "UWORD": "word", "SWORD": "word", "ULONG": "long", "SLONG": "long",
        "A_UINT64": "int64", "A_INT64": "int64", "FLOAT16_IEEE": "float16", "FLOAT32_IEEE": "float32",
        "FLOAT64_IEEE": "float64",
    }
    KEYWORDS = {
        "ALIGNMENT_BYTE": "byte", "ALIGNMENT_WORD": "word", "ALIGNMENT_LONG": "long", "ALIGNMENT_INT64": "int64",
        "ALIGNMENT_FLOAT16_IEEE": "float16", "ALIGNMENT_FLOAT32_IEEE": "float32",
        "ALIGNMENT_FLOAT64_IEEE": "float64",
    }

    def of(self, datatype: str) -> int:
        """The alignment of one ASAP2 data type (1 for an unknown one)."""
        slot = self._BY_DATATYPE.get(datatype)
        return getattr(self, slot) if slot else 1


@dataclass(frozen=True)
class ModCommon:
    """MOD_COMMON: the module's defaults for byte order, alignment and axis deposit."""

    comment: str = ""
    byte_order: str = "MSB_FIRST"  # ASAP2's default when MOD_COMMON says nothing
    alignments: Alignments = Alignments()
    deposit: str | None = None  # ABSOLUTE / DIFFERENCE
    data_size: int | None = None  # bits
    s_rec_layout: str | None = None
    location: Location | None = _meta()


@dataclass(frozen=True)
class CompuMethod:
    """COMPU_METHOD: how a raw value becomes physical (see :mod:`workbench.a2l.compu` to apply it).

    ``format`` is the display format (``"%8.3"``: width 8, 3 decimals), ``unit`` the physical unit
    (or the REF_UNIT's display text when ``unit`` is empty).
    """

    name: str
    long_identifier: str
    conversion_type: str  # IDENTICAL, LINEAR, RAT_FUNC, TAB_INTP, TAB_NOINTP, TAB_VERB, FORM
    format: str
    unit: str
    coeffs: tuple[float, float, float, float, float, float] | None = None  # RAT_FUNC a..f
    coeffs_linear: tuple[float, float] | None = None  # LINEAR: phys = a * raw + b
    compu_tab_ref: str | None = None
    formula: str | None = None  # FORM: phys = f(X1)
    formula_inv: str | None = None  # FORM: raw = g(X1 = phys)
    ref_unit: str | None = None
    status_string_ref: str | None = None
    location: Location | None = _meta()
    ref_tokens: Mapping[str, int] | None = _meta()  # field -> token of the name, in the model's document

    @property
    def decimals(self) -> int | None:
        """Decimal places of :attr:`format` (``"%8.3"`` -> 3), None when it has none."""
        return format_parts(self.format)[1]


@dataclass(frozen=True)
class CompuTab:
    """COMPU_TAB (TAB_INTP / TAB_NOINTP): (raw, physical) pairs in file order."""

    name: str
    long_identifier: str
    conversion_type: str
    pairs: tuple[tuple[float, float], ...]
    default_value: str | None = None
    default_value_numeric: float | None = None
    location: Location | None = _meta()


@dataclass(frozen=True)
class CompuVtab:
    """COMPU_VTAB (TAB_VERB): raw value -> text."""

    name: str
    long_identifier: str
    pairs: tuple[tuple[float, str], ...]
    default_value: str | None = None
    location: Location | None = _meta()


@dataclass(frozen=True)
class CompuVtabRange:
    """COMPU_VTAB_RANGE: raw range [lower, upper] -> text."""

    name: str
    long_identifier: str
    triples: tuple[tuple[float, float, str], ...]
    default_value: str | None = None
    location: Location | None = _meta()


@dataclass(frozen=True)
class Unit:
    """UNIT: a physical unit and its relation to a reference unit."""

    name: str
    long_identifier: str
    display: str
    type: str  # DERIVED / EXTENDED_SI
    ref_unit: str | None = None
    si_exponents: tuple[int, ...] | None = None
    unit_conversion: tuple[float, float] | None = None  # gradient, offset
    location: Location | None = _meta()


@dataclass(frozen=True)
class LayoutEntry:
    """One item of a RECORD_LAYOUT: ``FNC_VALUES 1 FLOAT32_IEEE COLUMN_DIR DIRECT`` is keyword
    ``FNC_VALUES``, position 1, datatype FLOAT32_IEEE, mode COLUMN_DIR, addressing DIRECT.

    ``axis`` is the axis letter of per-axis items (``AXIS_PTS_X`` -> ``"X"``). ``count`` holds the
    number of FIX_NO_AXIS_PTS_* and the maximum number of rescale pairs of AXIS_RESCALE_*; RESERVED's
    ``datatype`` is its size keyword (BYTE, WORD, LONG).
    """

    keyword: str  # FNC_VALUES, AXIS_PTS, NO_AXIS_PTS, FIX_NO_AXIS_PTS, SRC_ADDR, RIP_ADDR, SHIFT_OP ...
    axis: str | None
    position: int | None
    datatype: str | None = None
    mode: str | None = None  # FNC_VALUES: index mode; AXIS_PTS/AXIS_RESCALE: INDEX_INCR/INDEX_DECR
    addressing: str | None = None  # DIRECT, PBYTE, PWORD, PLONG, PLONGLONG
    count: int | None = None

    @property
    def spelled(self) -> str:
        """The keyword as the file writes it (``AXIS_PTS_X``)."""
        return f"{self.keyword}_{self.axis}" if self.axis else self.keyword


@dataclass(frozen=True)
class RecordLayout:
    """RECORD_LAYOUT: the items of an object in memory, ordered by their position numbers."""

    name: str
    entries: tuple[LayoutEntry, ...]
    alignments: tuple[tuple[str, int], ...] = ()  # this layout's own ALIGNMENT_*: (slot, bytes), slot as in Alignments
    static_record_layout: bool = False
    static_address_offsets: bool = False
    location: Location | None = _meta()

    def entry(self, keyword: str, axis: str | None = None) -> LayoutEntry | None:
        for entry in self.entries:
            if entry.keyword == keyword and entry.axis == axis:
                return entry
        return None

    @property
    def fnc_values(self) -> LayoutEntry | None:
        return self.entry("FNC_VALUES")

    def alignments_over(self, module: Alignments) -> Alignments:
        """The alignments that apply: this layout's own, else the module's."""
        return replace(module, **dict(self.alignments)) if self.alignments else module


@dataclass(frozen=True)
class AxisDescr:
    """AXIS_DESCR of a CURVE, MAP ...: the first is the X axis, then Y, Z, 4, 5."""

    attribute: str  # STD_AXIS, FIX_AXIS, COM_AXIS, RES_AXIS, CURVE_AXIS
    input_quantity: str | None  # None for NO_INPUT_QUANTITY
    conversion: str
    max_axis_points: int
    lower_limit: float
    upper_limit: float
    axis: str = "X"  # X, Y, Z, 4, 5
    axis_pts_ref: str | None = None
    curve_axis_ref: str | None = None
    fix_axis_par: tuple[float, int, int] | None = None  # offset, shift, number: x_i = offset + i * 2**shift
    fix_axis_par_dist: tuple[float, float, int] | None = None  # offset, distance, number
    fix_axis_par_list: tuple[float, ...] | None = None
    deposit: str | None = None  # ABSOLUTE / DIFFERENCE (None: the MOD_COMMON default)
    monotony: str | None = None
    extended_limits: tuple[float, float] | None = None
    format: str | None = None
    phys_unit: str | None = None
    read_only: bool = False
    byte_order: str | None = None  # the axis' own BYTE_ORDER, if it has one
    max_grad: float | None = None
    step_size: float | None = None
    location: Location | None = _meta()
    ref_tokens: Mapping[str, int] | None = _meta()  # field -> token of the name, in the model's document

    @property
    def fix_axis_points(self) -> tuple[float, ...] | None:
        """The raw points of a fixed axis described in the A2L (FIX_AXIS_PAR, _DIST, _LIST), else None."""
        if self.fix_axis_par_list is not None:
            return self.fix_axis_par_list
        if self.fix_axis_par is not None:
            offset, shift, number = self.fix_axis_par
            return tuple(offset + i * 2**shift for i in range(number))
        if self.fix_axis_par_dist is not None:
            offset, distance, number = self.fix_axis_par_dist
            return tuple(offset + i * distance for i in range(number))
        return None


@dataclass(frozen=True)
class _Addressed:
    """What every object with an ECU address has (AXIS_PTS, CHARACTERISTIC, MEASUREMENT, BLOB)."""

    name: str
    long_identifier: str
    address: int | None
    address_extension: int = 0
    display_identifier: str | None = None
    symbol_link: tuple[str, int] | None = None
    functions: tuple[str, ...] = ()  # FUNCTIONs that name the object (their lists, its FUNCTION_LIST)
    groups: tuple[str, ...] = ()  # GROUPs that name it
    location: Location | None = _meta()
    ref_tokens: Mapping[str, int] | None = _meta()  # field -> token of the name, in the model's document


@dataclass(frozen=True)
class Measurement(_Addressed):
    """MEASUREMENT: a signal in ECU memory. ``shape`` is its MATRIX_DIM (or legacy ARRAY_SIZE)
    without the dimensions of 1; ``()`` for a scalar."""

    kind = "MEASUREMENT"
    datatype: str = "UBYTE"
    conversion: str = NO_COMPU_METHOD
    resolution: float = 0.0
    accuracy: float = 0.0
    lower_limit: float = 0.0
    upper_limit: float = 0.0
    byte_order: str = "MSB_FIRST"  # the object's BYTE_ORDER, else MOD_COMMON's
    bit_mask: int | None = None
    bit_operation: tuple[int, int, bool] | None = None  # LEFT_SHIFT, RIGHT_SHIFT, SIGN_EXTEND
    matrix_dim: tuple[int, ...] = ()
    array_size: int | None = None
    layout: str | None = None  # ROW_DIR / COLUMN_DIR of a multi-dimensional array
    read_write: bool = False
    discrete: bool = False
    format: str | None = None
    phys_unit: str | None = None
    error_mask: int | None = None
    address_type: str | None = None
    ref_memory_segment: str | None = None
    max_refresh: tuple[int, int] | None = None  # scaling unit, rate
    virtual: tuple[str, ...] = ()  # VIRTUAL: the measurements a virtual one is computed from

    @property
    def shape(self) -> tuple[int, ...]:
        dims = self.matrix_dim or ((self.array_size,) if self.array_size else ())
        return tuple(d for d in dims if d != 1)


@dataclass(frozen=True)
class Characteristic(_Addressed):
    """CHARACTERISTIC: a calibration object. ``record_layout`` is its deposit (the RECORD_LAYOUT
    name); ``axes`` its AXIS_DESCRs (X first)."""

    kind = "CHARACTERISTIC"
    type: str = "VALUE"  # VALUE, CURVE, MAP, CUBOID, CUBE_4, CUBE_5, VAL_BLK, ASCII
    record_layout: str = ""
    max_diff: float = 0.0
    conversion: str = NO_COMPU_METHOD
    lower_limit: float = 0.0
    upper_limit: float = 0.0
    byte_order: str = "MSB_FIRST"
    bit_mask: int | None = None
    calibration_access: str | None = None  # CALIBRATION, NO_CALIBRATION, NOT_IN_MCD_SYSTEM, OFFLINE_CALIBRATION
    read_only: bool = False
    extended_limits: tuple[float, float] | None = None
    format: str | None = None
    phys_unit: str | None = None
    matrix_dim: tuple[int, ...] = ()
    number: int | None = None  # legacy size of ASCII / VAL_BLK
    axes: tuple[AxisDescr, ...] = ()
    discrete: bool = False
    step_size: float | None = None
    comparison_quantity: str | None = None
    encoding: str | None = None  # ASCII: UTF8, UTF16, UTF32
    ref_memory_segment: str | None = None
    model_link: str | None = None
    dependent_characteristic: tuple[str, tuple[str, ...]] | None = None  # formula, the characteristics
    virtual_characteristic: tuple[str, tuple[str, ...]] | None = None

    @property
    def writable(self) -> bool:
        """False when READ_ONLY or CALIBRATION_ACCESS forbids calibrating it."""
        return not self.read_only and self.calibration_access not in ("NO_CALIBRATION", "NOT_IN_MCD_SYSTEM")

    @property
    def shape(self) -> tuple[int, ...]:
        """VAL_BLK/ASCII: MATRIX_DIM (or NUMBER) without dimensions of 1; others: the axes' maximum point counts."""
        if self.type in ("VAL_BLK", "ASCII"):
            dims = self.matrix_dim or ((self.number,) if self.number else ())
            return tuple(d for d in dims if d != 1)
        return tuple(axis.max_axis_points for axis in self.axes)


@dataclass(frozen=True)
class AxisPts(_Addressed):
    """AXIS_PTS: an axis of its own, shared by the curves and maps whose COM_AXIS names it."""

    kind = "AXIS_PTS"
    input_quantity: str | None = None
    record_layout: str = ""
    max_diff: float = 0.0
    conversion: str = NO_COMPU_METHOD
    max_axis_points: int = 0
    lower_limit: float = 0.0
    upper_limit: float = 0.0
    byte_order: str = "MSB_FIRST"
    calibration_access: str | None = None
    read_only: bool = False
    deposit: str | None = None
    extended_limits: tuple[float, float] | None = None
    format: str | None = None
    phys_unit: str | None = None
    monotony: str | None = None
    step_size: float | None = None
    ref_memory_segment: str | None = None

    @property
    def writable(self) -> bool:
        return not self.read_only and self.calibration_access not in ("NO_CALIBRATION", "NOT_IN_MCD_SYSTEM")

    @property
    def shape(self) -> tuple[int, ...]:
        return (self.max_axis_points,)


@dataclass(frozen=True)
class Blob(_Addressed):
    """BLOB: bytes without a meaning the A2L describes."""

    kind = "BLOB"
    size: int = 0
    calibration_access: str | None = None
    address_type: str | None = None


@dataclass(frozen=True)
class Function:
    """FUNCTION: a software function and the objects it defines, references and measures."""

    name: str
    long_identifier: str
    version: str | None = None
    def_characteristics: tuple[str, ...] = ()
    ref_characteristics: tuple[str, ...] = ()
    in_measurements: tuple[str, ...] = ()
    out_measurements: tuple[str, ...] = ()
    loc_measurements: tuple[str, ...] = ()
    sub_functions: tuple[str, ...] = ()
    location: Location | None = _meta()


@dataclass(frozen=True)
class Group:
    """GROUP: a user's selection of calibrations and measurements."""

    name: str
    long_identifier: str
    root: bool = False
    ref_characteristics: tuple[str, ...] = ()
    ref_measurements: tuple[str, ...] = ()
    sub_groups: tuple[str, ...] = ()
    functions: tuple[str, ...] = ()  # FUNCTION_LIST
    location: Location | None = _meta()


@dataclass(frozen=True)
class Overwrite:
    """OVERWRITE in an INSTANCE: what one component of this instance has instead of its typedef's.
    ``name`` is the component's path inside the instance (``"lookup.values"``; the instance's own name may
    lead it); ``axis_number`` 0 is the object itself, 1 its X axis, 2 its Y axis ..."""

    name: str
    axis_number: int
    conversion: str | None = None
    extended_limits: tuple[float, float] | None = None
    format: str | None = None
    input_quantity: str | None = None
    limits: tuple[float, float] | None = None
    monotony: str | None = None
    phys_unit: str | None = None
    location: Location | None = _meta()


@dataclass(frozen=True)
class StructureComponent:
    """STRUCTURE_COMPONENT: a member of a TYPEDEF_STRUCTURE, ``offset`` bytes from the structure's start."""

    name: str
    typedef: str
    offset: int
    matrix_dim: tuple[int, ...] = ()
    address_type: str | None = None
    layout: str | None = None
    symbol_type_link: str | None = None
    location: Location | None = _meta()
    ref_tokens: Mapping[str, int] | None = _meta()  # typedef, offset -> their tokens


@dataclass(frozen=True)
class TypedefStructure:
    """TYPEDEF_STRUCTURE: a C struct of ``size`` bytes whose members are typedefs (or structures) themselves."""

    name: str
    long_identifier: str
    size: int
    components: tuple[StructureComponent, ...] = ()
    address_type: str | None = None
    symbol_type_link: str | None = None
    location: Location | None = _meta()


@dataclass(frozen=True)
class Instance(_Addressed):
    """INSTANCE: an object (or an array of them, MATRIX_DIM) of a typedef at ``address``. The model lists the
    objects it stands for by their ASAP2 names (``inst.member``, ``inst[2].member``)."""

    kind = "INSTANCE"
    typedef: str = ""
    matrix_dim: tuple[int, ...] = ()
    address_type: str | None = None
    calibration_access: str | None = None
    read_write: bool = False
    layout: str | None = None
    max_refresh: tuple[int, int] | None = None
    model_link: str | None = None
    overwrites: tuple[Overwrite, ...] = ()
