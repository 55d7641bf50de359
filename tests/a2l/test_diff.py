"""diff: added, removed and changed objects with the fields that changed."""

from workbench.a2l import load_a2l_string
from workbench.a2l.diff import diff_documents

A = """ASAP2_VERSION 1 71
/begin PROJECT P ""
  /begin MODULE M ""
    /begin MOD_PAR "" EPK "one" /end MOD_PAR
    /begin MEASUREMENT kept "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x10 /end MEASUREMENT
    /begin MEASUREMENT moved "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x20 /end MEASUREMENT
    /begin MEASUREMENT gone "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x30 /end MEASUREMENT
    /begin CHARACTERISTIC c "" CURVE 0x40 RL 0 NO_COMPU_METHOD 0 1
      /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 8 0 1 /end AXIS_DESCR
    /end CHARACTERISTIC
  /end MODULE
/end PROJECT
"""
B = (A.replace("ECU_ADDRESS 0x20", "ECU_ADDRESS 0x000024")
     .replace("ECU_ADDRESS 0x10", "ECU_ADDRESS 16 /* same value */")
     .replace('    /begin MEASUREMENT gone "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x30 /end MEASUREMENT\n',
              '    /begin MEASUREMENT new "" UBYTE NO_COMPU_METHOD 1 0 0 255 /end MEASUREMENT\n')
     .replace("NO_COMPU_METHOD 8 0 1", "NO_COMPU_METHOD 9 0 1 FORMAT \"%4.1\"")
     .replace('EPK "one"', 'EPK "two"'))


def test_object_level_changes():
    entries = {(e.status, e.keyword, e.name): e for e in diff_documents(load_a2l_string(A, "a.a2l"), load_a2l_string(B, "b.a2l"))}
    assert set(entries) == {("changed", "MOD_PAR", "MOD_PAR"), ("changed", "MEASUREMENT", "moved"),
                            ("added", "MEASUREMENT", "new"), ("removed", "MEASUREMENT", "gone"),
                            ("changed", "CHARACTERISTIC", "c")}
    moved = entries[("changed", "MEASUREMENT", "moved")]
    assert [(c.field, c.old, c.new) for c in moved.changes] == [("ECU_ADDRESS", "0x20", "0x000024")]
    assert moved.old_location == "a.a2l:6:5" and moved.new_location == "b.a2l:6:5"
    curve = entries[("changed", "CHARACTERISTIC", "c")]
    assert [(c.field, c.old, c.new) for c in curve.changes] == [
        ("AXIS_DESCR[0].max_axis_points", "8", "9"), ("AXIS_DESCR[0].FORMAT", None, '"%4.1"')]
    assert entries[("removed", "MEASUREMENT", "gone")].old_location == "a.a2l:7:5"
    assert diff_documents(load_a2l_string(A), load_a2l_string(A)) == []


def test_numbers_compare_by_value_nan_included():
    a = A.replace("UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x10", "UBYTE NO_COMPU_METHOD 1 0 NaN 255 ECU_ADDRESS 0x10")
    b = a.replace("NaN 255 ECU_ADDRESS 0x10", "nan 255.0 ECU_ADDRESS 16")
    assert diff_documents(load_a2l_string(a), load_a2l_string(b)) == []
