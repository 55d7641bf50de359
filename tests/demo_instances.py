"""A variant of the demo A2L in which a few of its calibrations and measurements are described again as INSTANCEs of
TYPEDEF_STRUCTUREs at the same addresses (for the tests of the objects INSTANCEs stand for: CLI, window)."""

from __future__ import annotations

from pathlib import Path

from workbench import demo

# xsEMPTY_TANK_THR 0x400000D8, xsSWITCH_TANK_THR 0x400000E0, xsPRV_KP 0x400000E4 (FLOAT32, Scalar_FLOAT32_IEEE);
# zvTankPConv 0x4000001C and zvRailPConv 0x40000064 (CURVEs of 9, 0x48 bytes: one array of two); zsSensVolt[4] 0x4002001C and zsRailPressure 0x4002004C (FLOAT32)
TYPEDEFS = '''
/begin TYPEDEF_CHARACTERISTIC T_THR "tank threshold" VALUE Scalar_FLOAT32_IEEE 0 CM_bar 0 800 /end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_CHARACTERISTIC T_KP "gain" VALUE Scalar_FLOAT32_IEEE 0 CM_PRV_KP 0 100 /end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_CHARACTERISTIC T_CONV "volts -> bar" CURVE Lookup1D_Struct_FLOAT32_IEEE 0 CM_bar 0 800
  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY CM_V 9 0 5 /end AXIS_DESCR
/end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_MEASUREMENT T_VOLT "volts" FLOAT32_IEEE CM_V 0 0 0 5 /end TYPEDEF_MEASUREMENT
/begin TYPEDEF_MEASUREMENT T_BAR "bar" FLOAT32_IEEE CM_bar 0 0 0 50 /end TYPEDEF_MEASUREMENT
/begin TYPEDEF_STRUCTURE Tank_T "" 0x10
  /begin STRUCTURE_COMPONENT empty T_THR 0x0 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT switch T_THR 0x8 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT kp T_KP 0xC /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin TYPEDEF_STRUCTURE Conv_T "" 0x48
  /begin STRUCTURE_COMPONENT tank T_CONV 0x0 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin TYPEDEF_STRUCTURE Convs_T "" 0x90
  /begin STRUCTURE_COMPONENT curves T_CONV 0x0 MATRIX_DIM 2 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin TYPEDEF_STRUCTURE Sens_T "" 0x34
  /begin STRUCTURE_COMPONENT volt T_VOLT 0x0 MATRIX_DIM 4 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT rail T_BAR 0x30 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin INSTANCE tank "" Tank_T 0x400000D8 /end INSTANCE
/begin INSTANCE conv "" Conv_T 0x4000001C /end INSTANCE
/begin INSTANCE convs "" T_CONV 0x4000001C MATRIX_DIM 2 /end INSTANCE
/begin INSTANCE pconv "" Convs_T 0x4000001C /end INSTANCE
/begin INSTANCE sens "" Sens_T 0x4002001C
  /begin IF_DATA XCP /begin DAQ_EVENT VARIABLE /begin DEFAULT_EVENT_LIST EVENT 0x0000 /end DEFAULT_EVENT_LIST
  /end DAQ_EVENT /end IF_DATA
/end INSTANCE
'''


def write_demo_instances_a2l(folder: Path) -> Path:
    """The demo A2L with the typedefs and INSTANCEs added to its MODULE, written into ``folder``."""
    text = demo.a2l().read_text(encoding="latin-1")
    cut = text.rindex("/end MODULE")
    path = folder / "FLCU_instances.a2l"
    path.write_text(text[:cut] + TYPEDEFS + text[cut:], encoding="latin-1")
    return path
