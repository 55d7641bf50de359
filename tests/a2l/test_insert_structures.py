"""insert --structures (a2ltool's -t): a struct variable as one INSTANCE of a TYPEDEF_STRUCTURE. The objects the
INSTANCEs stand for are those the plain insert makes of the same variables (names, addresses, types); the file
passes check and pya2ldb; typedefs are shared by the variables of one C type."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from cli_helpers import run
from pya2l_oracle import pya2l_import

from workbench import demo
from workbench.a2l import load_a2l
from workbench.a2l.check import check_file
from workbench.a2l.insert import Selection, insert_file

TYPES_ELF = Path(__file__).parents[1] / "elf" / "fixtures" / "types_dwarf5.elf"
EMPTY = ('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n    /begin MOD_COMMON "" BYTE_ORDER MSB_LAST '
         '/end MOD_COMMON\n  /end MODULE\n/end PROJECT\n')
# structs (nested, arrays of them, bitfields, a union, a pointer member) and scalars beside them
MEASURED, CALIBRATED = "outer|bits|node|u|zsScalar|state", "zvLut|vector"


def _objects(path: Path) -> dict:
    """Every object of the file (those INSTANCEs stand for too) by name: what must not depend on the form."""
    model = load_a2l(path).model()
    return {obj.name: (obj.kind, obj.address, model.datatype_of(obj), obj.shape, getattr(obj, "bit_mask", None),
                       getattr(obj, "type", None), getattr(obj, "conversion", None)) for obj in model}


def _both(tmp_path: Path, elf: Path, text: str | None, **selections) -> tuple[Path, Path]:
    source = tmp_path / "in.a2l"
    if text is not None:
        source.write_text(text)
    outputs = []
    for structures in (False, True):
        out = tmp_path / f"{'typed' if structures else 'plain'}.a2l"
        insert_file(source if text is not None else demo.a2l(), elf, out, structures=structures, use_cache=False,
                    **selections)
        outputs.append(out)
    return outputs[0], outputs[1]


@pytest.fixture(scope="module")
def types(tmp_path_factory) -> tuple[Path, Path]:
    return _both(tmp_path_factory.mktemp("structures"), TYPES_ELF, EMPTY, measurements=Selection((MEASURED,)),
                 characteristics=Selection((CALIBRATED,)))


def test_the_instances_stand_for_the_objects_the_plain_insert_makes(types):
    plain, typed = types
    assert _objects(typed) == _objects(plain)
    model = load_a2l(typed).model()
    assert model.names("INSTANCE") == ["zvLut", "outer", "bits", "u", "node"]
    assert model.placed("outer.arr[3].d") is not None and model.measurement("outer.arr[3].d").shape == (3,)
    assert model.characteristic("zvLut.Table").type == "VAL_BLK"  # a VALUE typedef with MATRIX_DIM
    assert not any(name.startswith("node.next") for name in model.names())  # a pointer: left out, as plain


def test_typedefs_are_shared_and_named_as_a2ltool_names_them(types):
    text = types[1].read_text()
    assert text.count("/begin TYPEDEF_STRUCTURE Inner") == 1  # outer.b and outer.arr[4]: one struct Inner
    # offsets in decimal, as a2ltool writes them
    assert re.search(r"/begin STRUCTURE_COMPONENT\s+arr Inner\s+8\s+MATRIX_DIM 4\s+SYMBOL_TYPE_LINK", text)
    for name in ("Measurement_ULong_0x7", "Measurement_ULong_0xF8", "Measurement_UByte", "Parameter_Float32",
                 "Measurement_Float64"):
        assert text.count(f"/begin TYPEDEF_{'CHARACTERISTIC' if name[0] == 'P' else 'MEASUREMENT'} {name} ") == 1
    assert re.search(r'/begin INSTANCE outer "instance for symbol outer"\s+tOuter 0x', text)  # a2ltool's text


def test_the_result_passes_check_and_pya2ldb(types):
    typed = types[1]
    report = check_file(typed, TYPES_ELF, use_cache=False)
    assert report.ok, report.findings
    assert pya2l_import(typed)["MEASUREMENT"] == 2  # zsScalar, state: the rest are INSTANCEs
    moved = typed.with_name("moved.a2l")  # an INSTANCE's address against the ELF's, as any object's
    text = typed.read_text()
    address = re.search(r"tOuter (0x[0-9A-F]+)", text)[1]
    moved.write_text(text.replace(f"tOuter {address}", f"tOuter {int(address, 16) + 4:#X}"))
    (mismatch,) = check_file(moved, TYPES_ELF, use_cache=False).findings
    assert (mismatch.kind, mismatch.name) == ("address-mismatch", "outer")


def test_the_demo_arrays_of_structs_one_typedef_and_a_struct_the_file_describes_in_part(tmp_path):
    plain, typed = _both(tmp_path, demo.elf(), None,
                         measurements=Selection((r"API_CAN_.*|CAN.X_.*_Pdu|emptyPdu|PRVCtrl_DW",)))
    assert _objects(typed) == _objects(plain)
    model = load_a2l(typed).model()
    rx = model.instance("API_CAN_RxPdu")
    assert (rx.typedef, rx.matrix_dim) == ("tRxPduInfo", (2,))
    assert model.measurement("API_CAN_RxPdu[1].Data").address == rx.address + 0xD + 1
    assert typed.read_text(encoding="latin-1").count("/begin TYPEDEF_STRUCTURE tRxPduInfo") == 1
    # the demo's A2L describes CANTX_FLCU_TO_PCM_001_Pdu.Dlc: that struct's other members come one by one
    assert "CANTX_FLCU_TO_PCM_001_Pdu" not in model.names("INSTANCE")
    assert model.kind_of("CANTX_FLCU_TO_PCM_001_Pdu.Data") == "MEASUREMENT"
    assert check_file(typed, demo.elf()).ok


def test_structures_need_asap2_1_70(tmp_path, capsys):
    source = tmp_path / "old.a2l"
    source.write_text(EMPTY.replace("1 71", "1 61"))
    code, _, err = run(capsys, "a2l", "insert", source, TYPES_ELF, "-o", tmp_path / "out.a2l", "--structures",
                       "--measurement-regex", "outer", "--no-cache")
    assert code == 2 and "from version 1.70 on" in err and err.count("\n") == 1


ENUMS = """#include <stdint.h>
typedef enum { A0 = 0, A1 = 1 } tMode;
enum Color { RED, GREEN };
typedef struct { tMode mode; enum Color color; enum { X1, X2 } anon; uint8_t arr[2][3]; struct { int16_t q; } in[2]; } tS;
tS s1; tS s2[3];
int main(void) { return s1.arr[0][0] + s2[1].mode; }
"""


@pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc is not installed")
def test_enums_and_anonymous_types_in_structs(tmp_path):
    (tmp_path / "enums.c").write_text(ENUMS)
    elf = tmp_path / "enums.elf"
    subprocess.run([shutil.which("gcc"), "-g", "-O0", "-o", elf, tmp_path / "enums.c"], check=True, timeout=120)
    plain, typed = _both(tmp_path, elf, EMPTY, measurements=Selection(("s1|s2",)))
    model = load_a2l(typed).model()
    # an anonymous enum's COMPU_METHOD is named by the struct's type, once for all its variables (plain: per object)
    rename = {f"{name}.anon_compu_method": "tS.anon_compu_method" for name in ("s1", "s2[0]", "s2[1]", "s2[2]")}
    assert _objects(typed) == {name: (*fields[:-1], rename.get(fields[-1], fields[-1]))
                               for name, fields in _objects(plain).items()}
    assert [model.conversion(model.measurement(f"s2[2].{member}")).to_physical(1)
            for member in ("mode", "color", "anon")] == ["A1", "GREEN", "X2"]
    assert model.typedef("tS_in_type").size == 2 and check_file(typed, elf, use_cache=False).ok


def test_the_summary_counts_an_instance_as_one(tmp_path, capsys):
    out = tmp_path / "new.a2l"
    code, _, err = run(capsys, "a2l", "insert", "--create", demo.elf(), "-o", out, "--structures",
                       "--measurement-regex", "API_CAN_RxPdu|API_DOUT_Value", "--no-cache")
    assert code == 0 and load_a2l(out).model().instance("API_CAN_RxPdu").typedef == "tRxPduInfo"
    assert err == f"wrote {out}: 1 MEASUREMENT, 1 INSTANCE inserted\n"  # was '2 MEASUREMENT inserted'
    code, out, _ = run(capsys, "a2l", "insert", "--create", demo.elf(), "--structures", "--dry-run", "--json",
                       "--measurement-regex", "API_CAN_RxPdu|API_DOUT_Value", "--no-cache")
    inserted = json.loads(out)["inserted"]  # under the block written, as the summary counts them
    assert (code, inserted) == (0, {"MEASUREMENT": ["API_DOUT_Value"], "CHARACTERISTIC": [],
                                    "INSTANCE": ["API_CAN_RxPdu"]})
