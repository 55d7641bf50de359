"""The ASAP2 (ASAM MCD-2 MC 1.5-1.7) keyword table the reader validates against.

Each block keyword has its positional parameters, the keyword options allowed inside
it and the blocks allowed inside it. Options have the same parameters wherever they
appear, so they live in one table. ``IF_DATA`` and ``A2ML`` are free-form (their
grammar is the A2ML inside the file) and are never validated here. Options may stand
in any order among a block's own tokens, before or after its child blocks.

Parameter kinds: ``ident`` (a name), ``str`` ("..."), ``int``, ``float`` (any number),
``int*`` (one or more ints, MATRIX_DIM), ``ident*`` (one or more names), or the name of
an enumeration in :data:`ENUMS` (a word from a fixed list: ``datatype``, ``indexmode`` ...).
"""

from __future__ import annotations

from typing import NamedTuple

from workbench.a2l.datatypes import DATATYPES

__all__ = ["ADDRESSED_OBJECTS", "BLOCKS", "ENUMS", "MAX_ADDRESS", "NAMESPACES", "OPTIONS", "REPEATABLE_OPTIONS",
           "TOP_LEVEL_BLOCKS", "TOP_LEVEL_OPTIONS", "BlockSpec", "Enumeration"]


class BlockSpec(NamedTuple):
    params: tuple[str, ...] = ()
    options: frozenset[str] = frozenset()
    blocks: frozenset[str] = frozenset()
    repeat: tuple[str, ...] = ()  # after params: the last int param counts groups of these kinds
    items: str = ""  # "" or the kind every remaining token must have (list blocks)
    free: bool = False  # content not validated (IF_DATA, A2ML)


class Enumeration(NamedTuple):
    """The words ASAP2 allows for one enumerated parameter; ``what`` names it in messages."""

    what: str
    words: tuple[str, ...]


# Enumerated parameter kinds -> the words allowed (ASAM MCD-2 MC 1.7.1, with the words of 1.5/1.6
# that later versions dropped, such as BYTE_ORDER LITTLE_ENDIAN, still accepted).
ENUMS: dict[str, Enumeration] = {
    "datatype": Enumeration("a data type", tuple(DATATYPES)),
    "datasize": Enumeration("a data size", ("BYTE", "WORD", "LONG")),
    "addrtype": Enumeration("an address type", ("PBYTE", "PWORD", "PLONG", "PLONGLONG", "DIRECT")),
    "indexorder": Enumeration("an index order", ("INDEX_INCR", "INDEX_DECR")),
    "indexmode": Enumeration("an index mode", (
        "ROW_DIR", "COLUMN_DIR", "ALTERNATE_CURVES", "ALTERNATE_WITH_X", "ALTERNATE_WITH_Y")),
    "layout": Enumeration("a layout", ("ROW_DIR", "COLUMN_DIR")),
    "characteristic_type": Enumeration("a CHARACTERISTIC type", (
        "VALUE", "CURVE", "MAP", "CUBOID", "CUBE_4", "CUBE_5", "VAL_BLK", "ASCII")),
    "axis_attribute": Enumeration("an axis attribute", ("STD_AXIS", "FIX_AXIS", "COM_AXIS", "RES_AXIS", "CURVE_AXIS")),
    "conversion_type": Enumeration("a conversion type", (
        "IDENTICAL", "LINEAR", "RAT_FUNC", "FORM", "TAB_INTP", "TAB_NOINTP", "TAB_VERB")),
    "table_conversion": Enumeration("a table conversion type", ("TAB_INTP", "TAB_NOINTP")),
    "verbal_conversion": Enumeration("a verbal table conversion type", ("TAB_VERB",)),
    "byte_order": Enumeration("a byte order", (
        "MSB_LAST", "MSB_FIRST", "MSB_FIRST_MSW_LAST", "MSB_LAST_MSW_FIRST", "LITTLE_ENDIAN", "BIG_ENDIAN")),
    "calibration_access": Enumeration("a calibration access", (
        "CALIBRATION", "NO_CALIBRATION", "NOT_IN_MCD_SYSTEM", "OFFLINE_CALIBRATION")),
    "deposit": Enumeration("a deposit mode", ("ABSOLUTE", "DIFFERENCE")),
    "monotony": Enumeration("a monotony", (
        "MON_INCREASE", "MON_DECREASE", "STRICT_INCREASE", "STRICT_DECREASE", "MONOTONOUS", "STRICT_MON", "NOT_MON")),
    "encoding": Enumeration("a character encoding", ("UTF8", "UTF16", "UTF32")),
    "prg_type": Enumeration("a segment type", (
        "CALIBRATION_VARIABLES", "CODE", "DATA", "EXCLUDE_FROM_FLASH", "OFFLINE_DATA", "RESERVED", "SERAM",
        "VARIABLES")),
    "memory_type": Enumeration("a memory type", ("EEPROM", "EPROM", "FLASH", "RAM", "ROM", "REGISTER", "NOT_IN_ECU")),
    "memory_attribute": Enumeration("a memory attribute", ("INTERN", "EXTERN")),
    "prog_type": Enumeration("a memory layout type", ("PRG_CODE", "PRG_DATA", "PRG_RESERVED")),
    "unit_type": Enumeration("a unit type", ("DERIVED", "EXTENDED_SI")),
    "trigger": Enumeration("a transformer trigger", ("ON_USER_REQUEST", "ON_CHANGE")),
    "var_naming": Enumeration("a variant naming", ("NUMERIC",)),
}


def _spec(params: str = "", options: str = "", blocks: str = "", repeat: str = "", items: str = "", free: bool = False) -> BlockSpec:
    return BlockSpec(tuple(params.split()), frozenset(options.split()), frozenset(blocks.split()),
                     tuple(repeat.split()), items, free)


# Option keyword -> parameter kinds.
OPTIONS: dict[str, tuple[str, ...]] = {
    key: tuple(kinds.split()) for key, kinds in {
        "ADDRESS_TYPE": "addrtype", "ADDR_EPK": "int", "ANNOTATION_LABEL": "str", "ANNOTATION_ORIGIN": "str", "ALIGNMENT_BYTE": "int", "ALIGNMENT_FLOAT16_IEEE": "int",
        "ALIGNMENT_FLOAT32_IEEE": "int", "ALIGNMENT_FLOAT64_IEEE": "int", "ALIGNMENT_INT64": "int",
        "ALIGNMENT_LONG": "int", "ALIGNMENT_WORD": "int", "ARRAY_SIZE": "int", "AXIS_PTS_REF": "ident",
        "BIT_MASK": "int", "BYTE_ORDER": "byte_order", "CALIBRATION_ACCESS": "calibration_access", "CALIBRATION_HANDLE_TEXT": "str", "COEFFS": "float " * 6,
        "COEFFS_LINEAR": "float float", "COMPARISON_QUANTITY": "ident", "COMPU_TAB_REF": "ident",
        "CONSISTENT_EXCHANGE": "", "CONVERSION": "ident", "CPU_TYPE": "str", "CURVE_AXIS_REF": "ident",
        "CUSTOMER": "str", "CUSTOMER_NO": "str", "DATA_SIZE": "int", "DEFAULT_VALUE": "str",
        "DEFAULT_VALUE_NUMERIC": "float", "DEPOSIT": "deposit", "DISCRETE": "", "DISPLAY_IDENTIFIER": "ident",
        "ECU": "str", "ECU_ADDRESS": "int", "ECU_ADDRESS_EXTENSION": "int", "ECU_CALIBRATION_OFFSET": "int",
        "ENCODING": "encoding", "EPK": "str", "ERROR_MASK": "int", "EXTENDED_LIMITS": "float float",
        "FIX_AXIS_PAR": "float float int", "FIX_AXIS_PAR_DIST": "float float int", "FORMAT": "str",
        "FORMULA_INV": "str", "FRAME_MEASUREMENT": "ident*", "FUNCTION_VERSION": "str", "GUARD_RAILS": "",
        "INPUT_QUANTITY": "ident", "LAYOUT": "layout", "LIMITS": "float float", "MATRIX_DIM": "int*",
        "MAX_GRAD": "float", "MAX_REFRESH": "int int", "MODEL_LINK": "str", "MONOTONY": "monotony",
        "NO_OF_INTERFACES": "int", "NUMBER": "int", "PHONE_NO": "str", "PHYS_UNIT": "str",
        "PROJECT_NO": "ident", "READ_ONLY": "", "READ_WRITE": "", "REF_MEMORY_SEGMENT": "ident",
        "REF_UNIT": "ident", "ROOT": "", "SI_EXPONENTS": "int " * 7, "STATIC_ADDRESS_OFFSETS": "",
        "STATIC_RECORD_LAYOUT": "", "STATUS_STRING_REF": "ident", "STEP_SIZE": "float",
        "SUPPLIER": "str", "SYMBOL_LINK": "str int", "SYMBOL_TYPE_LINK": "str", "SYSTEM_CONSTANT": "str str",
        "S_REC_LAYOUT": "ident", "UNIT": "ident", "UNIT_CONVERSION": "float float", "USER": "str",
        "VAR_NAMING": "var_naming", "VAR_SEPARATOR": "str", "VERSION": "str",
        # RECORD_LAYOUT entries: position, data type, then mode/addressing identifiers
        "FNC_VALUES": "int datatype indexmode addrtype", "IDENTIFICATION": "int datatype", "RESERVED": "int datasize",
    }.items()
}
for _axis in ("X", "Y", "Z", "4", "5"):
    OPTIONS.update({
        f"AXIS_PTS_{_axis}": ("int", "datatype", "indexorder", "addrtype"),
        f"AXIS_RESCALE_{_axis}": ("int", "datatype", "int", "indexorder", "addrtype"),
        f"DIST_OP_{_axis}": ("int", "datatype"), f"FIX_NO_AXIS_PTS_{_axis}": ("int",),
        f"NO_AXIS_PTS_{_axis}": ("int", "datatype"), f"NO_RESCALE_{_axis}": ("int", "datatype"),
        f"OFFSET_{_axis}": ("int", "datatype"), f"RIP_ADDR_{_axis}": ("int", "datatype"),
        f"SHIFT_OP_{_axis}": ("int", "datatype"), f"SRC_ADDR_{_axis}": ("int", "datatype"),
    })
OPTIONS["RIP_ADDR_W"] = ("int", "datatype")

_RECORD_LAYOUT_OPTIONS = " ".join(
    key for key in OPTIONS
    if key.startswith(("AXIS_PTS_", "AXIS_RESCALE_", "DIST_OP_", "FIX_NO_AXIS_PTS_", "NO_AXIS_PTS_",
                       "NO_RESCALE_", "OFFSET_", "RIP_ADDR_", "SHIFT_OP_", "SRC_ADDR_", "ALIGNMENT_"))
) + " FNC_VALUES IDENTIFICATION RESERVED STATIC_RECORD_LAYOUT STATIC_ADDRESS_OFFSETS"

_NAME_LIST = _spec(items="ident")
_FREE = _spec(free=True)

BLOCKS: dict[str, BlockSpec] = {
    "PROJECT": _spec("ident str", blocks="HEADER MODULE"),
    "HEADER": _spec("str", "VERSION PROJECT_NO"),
    "MODULE": _spec("ident str", blocks=(
        "A2ML AXIS_PTS BLOB CHARACTERISTIC COMPU_METHOD COMPU_TAB COMPU_VTAB COMPU_VTAB_RANGE FRAME FUNCTION "
        "GROUP IF_DATA INSTANCE MEASUREMENT MOD_COMMON MOD_PAR RECORD_LAYOUT TRANSFORMER TYPEDEF_AXIS "
        "TYPEDEF_BLOB TYPEDEF_CHARACTERISTIC TYPEDEF_MEASUREMENT TYPEDEF_STRUCTURE UNIT USER_RIGHTS "
        "VARIANT_CODING")),
    "A2ML": _FREE,
    "IF_DATA": _FREE,
    "MOD_PAR": _spec("str", (
        "ADDR_EPK CPU_TYPE CUSTOMER CUSTOMER_NO ECU ECU_CALIBRATION_OFFSET EPK NO_OF_INTERFACES PHONE_NO "
        "SUPPLIER SYSTEM_CONSTANT USER VERSION"), "CALIBRATION_METHOD MEMORY_LAYOUT MEMORY_SEGMENT"),
    "MEMORY_SEGMENT": _spec("ident str prg_type memory_type memory_attribute int int int int int int int", blocks="IF_DATA"),
    "MEMORY_LAYOUT": _spec("prog_type int int int int int int int", blocks="IF_DATA"),
    "CALIBRATION_METHOD": _spec("str int", blocks="CALIBRATION_HANDLE"),
    "CALIBRATION_HANDLE": _spec(options="CALIBRATION_HANDLE_TEXT", items="int"),
    "MOD_COMMON": _spec("str", (
        "ALIGNMENT_BYTE ALIGNMENT_WORD ALIGNMENT_LONG ALIGNMENT_INT64 ALIGNMENT_FLOAT16_IEEE "
        "ALIGNMENT_FLOAT32_IEEE ALIGNMENT_FLOAT64_IEEE BYTE_ORDER DATA_SIZE DEPOSIT S_REC_LAYOUT")),
    "MEASUREMENT": _spec("ident str datatype ident int float float float", (
        "ADDRESS_TYPE ARRAY_SIZE BIT_MASK BYTE_ORDER DISCRETE DISPLAY_IDENTIFIER ECU_ADDRESS "
        "ECU_ADDRESS_EXTENSION ERROR_MASK FORMAT LAYOUT MATRIX_DIM MAX_REFRESH MODEL_LINK PHYS_UNIT "
        "READ_WRITE REF_MEMORY_SEGMENT SYMBOL_LINK"),
        "ANNOTATION BIT_OPERATION FUNCTION_LIST IF_DATA VIRTUAL"),
    "CHARACTERISTIC": _spec("ident str characteristic_type int ident float ident float float", (
        "BIT_MASK BYTE_ORDER CALIBRATION_ACCESS COMPARISON_QUANTITY DISCRETE DISPLAY_IDENTIFIER "
        "ECU_ADDRESS_EXTENSION ENCODING EXTENDED_LIMITS FORMAT GUARD_RAILS MATRIX_DIM MAX_REFRESH MODEL_LINK "
        "NUMBER PHYS_UNIT READ_ONLY REF_MEMORY_SEGMENT STEP_SIZE SYMBOL_LINK"),
        "ANNOTATION AXIS_DESCR DEPENDENT_CHARACTERISTIC FUNCTION_LIST IF_DATA MAP_LIST VIRTUAL_CHARACTERISTIC"),
    "AXIS_DESCR": _spec("axis_attribute ident ident int float float", (
        "AXIS_PTS_REF BYTE_ORDER CURVE_AXIS_REF DEPOSIT EXTENDED_LIMITS FIX_AXIS_PAR FIX_AXIS_PAR_DIST FORMAT "
        "MAX_GRAD MONOTONY PHYS_UNIT READ_ONLY STEP_SIZE"), "ANNOTATION FIX_AXIS_PAR_LIST"),
    "AXIS_PTS": _spec("ident str int ident ident float ident int float float", (
        "BYTE_ORDER CALIBRATION_ACCESS DEPOSIT DISPLAY_IDENTIFIER ECU_ADDRESS_EXTENSION EXTENDED_LIMITS FORMAT "
        "GUARD_RAILS MAX_REFRESH MODEL_LINK MONOTONY PHYS_UNIT READ_ONLY REF_MEMORY_SEGMENT STEP_SIZE SYMBOL_LINK"),
        "ANNOTATION FUNCTION_LIST IF_DATA"),
    "BLOB": _spec("ident str int int", (
        "ADDRESS_TYPE CALIBRATION_ACCESS DISPLAY_IDENTIFIER ECU_ADDRESS_EXTENSION MAX_REFRESH MODEL_LINK "
        "SYMBOL_LINK"), "ANNOTATION IF_DATA"),
    "INSTANCE": _spec("ident str ident int", (
        "ADDRESS_TYPE CALIBRATION_ACCESS DISPLAY_IDENTIFIER ECU_ADDRESS_EXTENSION LAYOUT MATRIX_DIM MAX_REFRESH "
        "MODEL_LINK READ_WRITE SYMBOL_LINK"), "ANNOTATION IF_DATA OVERWRITE"),
    "OVERWRITE": _spec("ident int", (
        "CONVERSION EXTENDED_LIMITS FORMAT INPUT_QUANTITY LIMITS MONOTONY PHYS_UNIT")),
    "COMPU_METHOD": _spec("ident str conversion_type str str", (
        "COEFFS COEFFS_LINEAR COMPU_TAB_REF REF_UNIT STATUS_STRING_REF"), "FORMULA"),
    "FORMULA": _spec("str", "FORMULA_INV"),
    "COMPU_TAB": _spec("ident str table_conversion int", "DEFAULT_VALUE DEFAULT_VALUE_NUMERIC", repeat="float float"),
    "COMPU_VTAB": _spec("ident str verbal_conversion int", "DEFAULT_VALUE", repeat="float str"),
    "COMPU_VTAB_RANGE": _spec("ident str int", "DEFAULT_VALUE", repeat="float float str"),
    "RECORD_LAYOUT": _spec("ident", _RECORD_LAYOUT_OPTIONS),
    "UNIT": _spec("ident str str unit_type", "REF_UNIT SI_EXPONENTS UNIT_CONVERSION"),
    "FUNCTION": _spec("ident str", "FUNCTION_VERSION", (
        "ANNOTATION AR_COMPONENT DEF_CHARACTERISTIC IF_DATA IN_MEASUREMENT LOC_MEASUREMENT OUT_MEASUREMENT "
        "REF_CHARACTERISTIC SUB_FUNCTION")),
    "GROUP": _spec("ident str", "ROOT", (
        "ANNOTATION FUNCTION_LIST IF_DATA REF_CHARACTERISTIC REF_MEASUREMENT SUB_GROUP")),
    "FRAME": _spec("ident str int int", "FRAME_MEASUREMENT", "IF_DATA"),
    "AR_COMPONENT": _spec("str", "AR_PROTOTYPE_OF"),
    "ANNOTATION": _spec(options="ANNOTATION_LABEL ANNOTATION_ORIGIN", blocks="ANNOTATION_TEXT"),
    "ANNOTATION_TEXT": _spec(items="str"),
    "BIT_OPERATION": _spec(blocks="LEFT_SHIFT RIGHT_SHIFT SIGN_EXTEND"),
    "LEFT_SHIFT": _spec("int"),
    "RIGHT_SHIFT": _spec("int"),
    "SIGN_EXTEND": _spec(),
    "DEPENDENT_CHARACTERISTIC": _spec("str", items="ident"),
    "VIRTUAL_CHARACTERISTIC": _spec("str", items="ident"),
    "FIX_AXIS_PAR_LIST": _spec(items="float"),
    "USER_RIGHTS": _spec("ident", "READ_ONLY", "REF_GROUP"),
    "TYPEDEF_MEASUREMENT": _spec("ident str datatype ident int float float float", (
        "ADDRESS_TYPE BIT_MASK BYTE_ORDER DISCRETE ERROR_MASK FORMAT LAYOUT MATRIX_DIM PHYS_UNIT"),
        "BIT_OPERATION"),
    "TYPEDEF_CHARACTERISTIC": _spec("ident str characteristic_type ident float ident float float", (
        "BIT_MASK BYTE_ORDER DISCRETE ENCODING EXTENDED_LIMITS FORMAT MATRIX_DIM NUMBER PHYS_UNIT STEP_SIZE"),
        "AXIS_DESCR"),
    "TYPEDEF_AXIS": _spec("ident str ident ident float ident int float float", (
        "BYTE_ORDER DEPOSIT EXTENDED_LIMITS FORMAT MONOTONY PHYS_UNIT STEP_SIZE")),
    "TYPEDEF_BLOB": _spec("ident str int", "ADDRESS_TYPE"),
    "TYPEDEF_STRUCTURE": _spec("ident str int", "ADDRESS_TYPE CONSISTENT_EXCHANGE SYMBOL_TYPE_LINK",
                               "STRUCTURE_COMPONENT"),
    "STRUCTURE_COMPONENT": _spec("ident ident int", "ADDRESS_TYPE LAYOUT MATRIX_DIM SYMBOL_TYPE_LINK"),
    "VARIANT_CODING": _spec(options="VAR_NAMING VAR_SEPARATOR", blocks="VAR_CHARACTERISTIC VAR_CRITERION VAR_FORBIDDEN_COMB"),
    "VAR_CHARACTERISTIC": _spec("ident", items="ident", blocks="VAR_ADDRESS"),
    "VAR_ADDRESS": _spec(items="int"),
    "VAR_CRITERION": _spec("ident str", "VAR_MEASUREMENT VAR_SELECTION_CHARACTERISTIC", items="ident"),
    "VAR_FORBIDDEN_COMB": _spec(items="ident"),
    "TRANSFORMER": _spec("ident str str str int trigger ident", blocks="TRANSFORMER_IN_OBJECTS TRANSFORMER_OUT_OBJECTS"),
}
for _name in ("DEF_CHARACTERISTIC", "FUNCTION_LIST", "IN_MEASUREMENT", "LOC_MEASUREMENT", "MAP_LIST",
              "OUT_MEASUREMENT", "REF_CHARACTERISTIC", "REF_GROUP", "REF_MEASUREMENT", "SUB_FUNCTION",
              "SUB_GROUP", "VIRTUAL", "TRANSFORMER_IN_OBJECTS", "TRANSFORMER_OUT_OBJECTS"):
    BLOCKS[_name] = _NAME_LIST
OPTIONS.update({"VAR_MEASUREMENT": ("ident",), "VAR_SELECTION_CHARACTERISTIC": ("ident",), "AR_PROTOTYPE_OF": ("ident",)})

# Options a block may have more than once (ASAM MCD-2 MC 1.7.1); every other option stands at most once in a block.
REPEATABLE_OPTIONS: dict[str, frozenset[str]] = {
    "MOD_PAR": frozenset({"ADDR_EPK", "SYSTEM_CONSTANT"}),
    "RECORD_LAYOUT": frozenset({"RESERVED"}),
}

# Top-level keywords outside any block.
TOP_LEVEL_OPTIONS = {"ASAP2_VERSION": ("int", "int"), "A2ML_VERSION": ("int", "int")}
TOP_LEVEL_BLOCKS = frozenset({"PROJECT"})

MAX_ADDRESS = 0xFFFFFFFF  # addresses are ULONG: 32 bits

# Objects with an address in the ECU, and the index (among the block's own tokens,
# the name being 0) of the address parameter; None: the address is ECU_ADDRESS.
ADDRESSED_OBJECTS: dict[str, int | None] = {
    "MEASUREMENT": None,
    "CHARACTERISTIC": 3,
    "AXIS_PTS": 2,
    "BLOB": 2,
    "INSTANCE": 3,
}

# MODULE-level blocks whose first parameter is a name in the module's namespace.
NAMED_MODULE_BLOCKS = frozenset({
    "AXIS_PTS", "BLOB", "CHARACTERISTIC", "COMPU_METHOD", "COMPU_TAB", "COMPU_VTAB", "COMPU_VTAB_RANGE",
    "FRAME", "FUNCTION", "GROUP", "INSTANCE", "MEASUREMENT", "RECORD_LAYOUT", "TRANSFORMER", "TYPEDEF_AXIS",
    "TYPEDEF_BLOB", "TYPEDEF_CHARACTERISTIC", "TYPEDEF_MEASUREMENT", "TYPEDEF_STRUCTURE", "UNIT",
    "USER_RIGHTS",
})

# Blocks whose names share one namespace in a MODULE (a name may be defined once per namespace).
NAMESPACES: dict[str, str] = {
    **dict.fromkeys(("AXIS_PTS", "BLOB", "CHARACTERISTIC", "INSTANCE", "MEASUREMENT"), "object"),
    **dict.fromkeys(("COMPU_TAB", "COMPU_VTAB", "COMPU_VTAB_RANGE"), "conversion table"),
    **dict.fromkeys(("TYPEDEF_AXIS", "TYPEDEF_BLOB", "TYPEDEF_CHARACTERISTIC", "TYPEDEF_MEASUREMENT",
                     "TYPEDEF_STRUCTURE"), "typedef"),
    **{keyword: keyword.lower().replace("_", " ") for keyword in (
        "COMPU_METHOD", "RECORD_LAYOUT", "UNIT", "FUNCTION", "GROUP", "FRAME", "TRANSFORMER", "USER_RIGHTS")},
}
