"""CDFX: every category and container read, with and without namespaces; malformed files located; the writer's structure."""

from __future__ import annotations

import math

import numpy as np
import pytest
from lxml import etree

from workbench.calib.dataset import load_dataset_string
from workbench.calib.dataset.cdfx_write import losses, write
from workbench.calib.dataset.model import CsFlag, Dataset, HistoryEntry, ObjectInfo
from workbench.calib.values import Axis, CalValue
from workbench.errors import DatasetParseError, InputError


def document(instances: str, tree_extra: str = "", root_attributes: str = "", before: str = "") -> str:
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n{before}<MSRSW{root_attributes}><SHORT-NAME>T</SHORT-NAME>'
            f'<CATEGORY>CDF20</CATEGORY><SW-SYSTEMS><SW-SYSTEM><SHORT-NAME>ECU</SHORT-NAME><SW-INSTANCE-SPEC>'
            f'<SW-INSTANCE-TREE><SHORT-NAME>base</SHORT-NAME><CATEGORY>NO_VCD</CATEGORY>{tree_extra}\n'
            f'{instances}\n</SW-INSTANCE-TREE></SW-INSTANCE-SPEC></SW-SYSTEM></SW-SYSTEMS></MSRSW>\n')


def instance(name: str, category: str, values: str, extra: str = "", axes: str = "", unit: str = "") -> str:
    unit_element = f"<UNIT-DISPLAY-NAME>{unit}</UNIT-DISPLAY-NAME>" if unit else ""
    axes_element = f"<SW-AXIS-CONTS>{axes}</SW-AXIS-CONTS>" if axes else ""
    return (f"<SW-INSTANCE><SHORT-NAME>{name}</SHORT-NAME><CATEGORY>{category}</CATEGORY>{extra}"
            f"<SW-VALUE-CONT>{unit_element}<SW-VALUES-PHYS>{values}</SW-VALUES-PHYS></SW-VALUE-CONT>{axes_element}"
            f"</SW-INSTANCE>")


def axis(category: str, values: str = "", ref: str = "", unit: str = "") -> str:
    parts = [f"<CATEGORY>{category}</CATEGORY>" if category else "", f"<UNIT-DISPLAY-NAME>{unit}</UNIT-DISPLAY-NAME>" if unit else "",
             f"<SW-INSTANCE-REF>{ref}</SW-INSTANCE-REF>" if ref else "", f"<SW-VALUES-PHYS>{values}</SW-VALUES-PHYS>" if values else ""]
    return f"<SW-AXIS-CONT>{''.join(parts)}</SW-AXIS-CONT>"


def read(text: str, path: str = "t.cdfx") -> Dataset:
    return load_dataset_string(text, "cdfx", path)


def test_every_category():
    ds = read(document("\n".join([
        instance("v", "VALUE", "<V>0.20000000298023224</V>", unit="bar"),
        instance("b", "BOOLEAN", "<VT>true</VT>"),
        instance("d", "DEPENDENT_VALUE", "<V>0x10</V>"),
        instance("s", "ASCII", "<VT>  two  spaces &amp; &lt;tags&gt; </VT>"),
        instance("blk", "VAL_BLK", "<VG><V>1</V><V>2</V><V>3</V></VG><VG><V>4</V><V>5</V><V>6</V></VG>",
                 extra="", unit=""),
        instance("flat", "VAL_BLK", "<V>1</V><V>2</V><V>3</V><V>4</V>"),
        instance("c", "CURVE", "<V>1</V><V>2</V>", axes=axis("STD_AXIS", "<V>10</V><V>20</V>", unit="rpm")),
        instance("fx", "CURVE", "<VG><V>1</V><V>2</V></VG>", axes=axis("FIX_AXIS", "<V>0</V><V>1</V>")),
        instance("m", "MAP", "<VG><LABEL>100</LABEL><V>1</V><V>2</V><V>3</V></VG><VG><LABEL>200</LABEL><V>4</V><V>5</V><V>6</V></VG>",
                 axes=axis("STD_AXIS", "<V>1</V><V>2</V><V>3</V>") + axis("STD_AXIS", "<V>100</V><V>200</V>")),
        instance("ax", "COM_AXIS", "<V>5</V><V>6</V>", unit="bar"),
        instance("g", "CURVE", "<V>7</V><V>8</V>", axes=axis("", ref="ax")),  # category and points from the reference
        instance("r", "RES_AXIS", "<V>1</V><V>2</V>"),
    ])))
    assert ds["v"] == CalValue("v", "VALUE", 0.20000000298023224, unit="bar")
    assert ds["b"].value == "true" and ds.info["b"].category == "BOOLEAN"
    assert ds["d"].value == 16 and ds.info["d"].category == "DEPENDENT_VALUE"
    assert ds["s"] == CalValue("s", "ASCII", "  two  spaces & <tags> ")
    assert ds["blk"].value.shape == (3, 2) and ds["blk"].value[:, 1].tolist() == [4, 5, 6]  # one VG per y, x along
    assert ds["flat"].value.tolist() == [1, 2, 3, 4]
    assert ds["c"].axes == (Axis(np.array([10, 20]), "STD_AXIS", unit="rpm"),)
    assert ds["fx"].value.tolist() == [1, 2] and ds["fx"].axes[0].kind == "FIX_AXIS"
    assert ds["m"].value.tolist() == [[1, 4], [2, 5], [3, 6]]  # [x, y]
    assert ds["ax"] == CalValue("ax", "AXIS_PTS", np.array([5, 6]), unit="bar")
    assert ds["g"].axes == (Axis(np.array([5, 6]), "COM_AXIS", "ax", "bar"),)
    assert ds["r"].kind == "AXIS_PTS" and ds.info["r"].category == "RES_AXIS"
    assert (ds.title, ds.system, ds.name) == ("T", "ECU", "base")


def test_metadata_history_flags_functions_origin_and_comments():
    extra = ("<SW-FEATURE-REF>PRVCtrl</SW-FEATURE-REF>")
    text = document(
        "<!-- between instances -->\n"
        "<SW-INSTANCE><SHORT-NAME>kp</SHORT-NAME><!-- about kp\n second line --><LONG-NAME>PID gain</LONG-NAME>"
        "<DISPLAY-NAME>KP</DISPLAY-NAME><CATEGORY>VALUE</CATEGORY>" + extra +
        "<SW-VALUE-CONT><SW-VALUES-PHYS><V>5</V></SW-VALUES-PHYS></SW-VALUE-CONT>"
        "<SW-CS-HISTORY><CS-ENTRY><STATE>checked</STATE><DATE>2025-03-01</DATE><CSUS>jm</CSUS><CSPR>P</CSPR>"
        "<REMARK><P>one</P><P>two</P></REMARK></CS-ENTRY><SW-CS-ENTRY><STATE>released</STATE><DATE>d</DATE><CSUS>u</CSUS>"
        "</SW-CS-ENTRY></SW-CS-HISTORY>"
        "<SW-CS-FLAGS><SW-CS-FLAG><CATEGORY>COMPLETE</CATEGORY><FLAG>true</FLAG><CSUS>jm</CSUS></SW-CS-FLAG></SW-CS-FLAGS>"
        "</SW-INSTANCE>",
        tree_extra="<SW-INSTANCE-TREE-ORIGIN><SYMBOLIC-FILE>FLCU.a2l</SYMBOLIC-FILE><DATA-FILE>FLCU.s19</DATA-FILE>"
                   "</SW-INSTANCE-TREE-ORIGIN><SW-CS-COLLECTIONS><SW-CS-COLLECTION><CATEGORY>FEATURE</CATEGORY>"
                   "<SW-FEATURE-REF>PRVCtrl</SW-FEATURE-REF><REVISION>1.2</REVISION></SW-CS-COLLECTION>"
                   "<SW-CS-COLLECTION><CATEGORY>COLLECTION</CATEGORY><SW-COLLECTION-REF>group</SW-COLLECTION-REF>"
                   "</SW-CS-COLLECTION></SW-CS-COLLECTIONS>",
        before="<!-- Created with CANape 21.0 CDF 2.0 Writer -->\n")
    ds = read(text)
    assert ds["kp"].comment == "PID gain"
    assert ds.info["kp"] == ObjectInfo(
        display_name="KP", functions=("PRVCtrl",), comments=("about kp", "second line"),
        history=(HistoryEntry("checked", "2025-03-01", "jm", "one\ntwo", (("CSPR", "P"),)), HistoryEntry("released", "d", "u")),
        flags=(CsFlag("COMPLETE", "true", "jm"),), category="VALUE", line=5, value_line=6, value_runs=((6, 1),))
    assert ds.comments == ["Created with CANape 21.0 CDF 2.0 Writer", "between instances"]
    assert ds.functions["PRVCtrl"].version == "1.2" and (ds.a2l_file, ds.data_file) == ("FLCU.a2l", "FLCU.s19")
    assert [(n.name, n.line) for n in ds.notes] == [("SW-CS-COLLECTION", 3)]
    assert "of category COLLECTION is not kept" in ds.notes[0].message


def test_namespaces_default_or_prefixed():
    plain = document(instance("v", "VALUE", "<V>1</V>"))
    default = plain.replace("<MSRSW>", '<MSRSW xmlns="http://www.asam.net/xml/CDF">')
    root = etree.fromstring(plain.encode())
    for element in root.iter():
        element.tag = "{urn:cdf}" + element.tag
    prefixed = etree.tostring(etree.ElementTree(etree.fromstring(
        etree.tostring(root).replace(b"ns0:", b"cdf:").replace(b"xmlns:ns0", b"xmlns:cdf"))))
    for text in (default, prefixed):
        assert read(text)["v"].value == 1


def test_a_single_variant_without_criteria_is_the_value_as_inca_writes_it():
    text = document("<SW-INSTANCE><SHORT-NAME>v</SHORT-NAME><CATEGORY>VALUE</CATEGORY><SW-INSTANCE-PROPS-VARIANTS>"
                    "<SW-INSTANCE-PROPS-VARIANT><SW-VALUE-CONT><SW-VALUES-PHYS><V>17.0000000000000000</V></SW-VALUES-PHYS>"
                    "</SW-VALUE-CONT></SW-INSTANCE-PROPS-VARIANT></SW-INSTANCE-PROPS-VARIANTS></SW-INSTANCE>")
    assert read(text)["v"].value == 17.0


@pytest.mark.parametrize("text, line, message", [
    ("<MSRSW><CATEGORY>CDF20</CATEGORY>\n<SW-SYSTEMS>", 2, "not well-formed XML"),
    ("<?xml version='1.0'?>\n<DCM/>", 2, "the root element is <DCM>, expected <MSRSW>"),
    (document(instance("v", "VALUE", "<V>1</V>").replace("<CATEGORY>", "<DESC>x</DESC><CATEGORY>")), 3,
     "unexpected <DESC> in <SW-INSTANCE>"),
    (document(instance("v", "VALUE", "<V>1,5</V>")), 3, "decimal comma"),
    (document(instance("v", "VALUE", "<V></V>")), 3, "<V> without a number"),
    (document(instance("v", "VALUE", "<V>1</V><V>2</V>")), 3, "v: a VALUE holds one value, found 2"),
    (document(instance("v", "ASCII", "<V>1</V>")), 3, "v: an ASCII holds its text in <VT>"),
    (document(instance("c", "CURVE", "<V>1</V>", axes=axis("STD_AXIS", "<V>1</V><V>2</V>"))), 3, "c: 1 values for the shape 2"),
    (document(instance("c", "CURVE", "<V>1</V>")), 3, "c: a CURVE has 1 SW-AXIS-CONT, found 0"),
    (document(instance("c", "CURVE", "<V>1</V>", axes=axis("SOME_AXIS", "<V>1</V>"))), 3, "axis CATEGORY 'SOME_AXIS'"),
    (document(instance("m", "MAP", "<VG><V>1</V><V>2</V></VG><VG><V>3</V><V>4</V></VG><VG><V>5</V><V>6</V></VG>",
                       axes=axis("STD_AXIS", "<V>1</V><V>2</V><V>3</V>") + axis("STD_AXIS", "<V>1</V><V>2</V>"))), 3,
     "its VG groups do not make 3 x 2 values (one VG per Y point holding the values along X)"),
    (document(instance("m", "MAP", "<VG><V>1</V><V>2</V></VG><VG><V>3</V></VG><VG><V>5</V><V>6</V></VG>",
                       axes=axis("STD_AXIS", "<V>1</V><V>2</V>") + axis("STD_AXIS", "<V>1</V><V>2</V><V>3</V>"))), 3,
     "m: 5 values for the shape 2 x 3 (VG 2 of 3 holds 1 values, the others 2)"),
    (document(instance("v", "VALUE", "<V>1</V>") + "\n" + instance("v", "VALUE", "<V>2</V>")), 4,
     "v is defined twice (first at line 3)"),
    (document("<SW-INSTANCE><CATEGORY>STRUCTURE</CATEGORY></SW-INSTANCE>"), 3,
     "SW-INSTANCE without a SHORT-NAME or SW-ARRAY-INDEX"),
    (document(instance("c", "CUBOID", "<V>1</V>", axes=axis("STD_AXIS", "<V>1</V>") * 2)), 3,
     "c: a CUBOID has 3 SW-AXIS-CONT, found 2"),
    (document(instance("b", "VAL_BLK", "<VG><V>1</V></VG><VG><V>1</V><V>2</V></VG>")), 3,
     "VG groups of different lengths and no SW-ARRAYSIZE"),
    (document("", tree_extra="<SW-INSTANCE-TREE-ORIGIN><HEX>x</HEX></SW-INSTANCE-TREE-ORIGIN>"), 2,
     "unexpected <HEX> in <SW-INSTANCE-TREE-ORIGIN>"),
])
def test_a_malformed_file_names_its_line_and_what_was_expected(text, line, message):
    with pytest.raises(DatasetParseError) as caught:
        read(text, "bad.cdfx")
    error = str(caught.value)
    assert error.startswith(f"bad.cdfx:{line}:") and message in error, error
    assert "\n" not in error


def test_no_dtd_or_entity_is_fetched():
    text = ('<?xml version="1.0"?>\n<!DOCTYPE MSRSW SYSTEM "http://127.0.0.1:9/cdf.dtd" [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
            + document(instance("s", "ASCII", "<VT>&x;</VT>")).split("\n", 1)[1])
    with pytest.raises(DatasetParseError, match=r"^t.cdfx:4: the entity reference &x; is not resolved"):
        read(text)  # neither the file's content nor a silently empty text


def test_the_writer_follows_the_dtd_order_and_writes_x_fastest():
    ds = Dataset(comments=["file -- comment"], a2l_file="FLCU.a2l")
    axes = (Axis(np.array([1.0, 2.0, 3.0]), "COM_AXIS", "xa", "bar"), Axis(np.array([10, 20]), unit="rpm"))
    ds.add(CalValue("m", "MAP", np.array([[1, 4], [2, 5], [3, 6]]), axes=axes, unit="%", comment="a map"),
           ObjectInfo(display_name="M", functions=("F",), comments=("note",),
                      history=(HistoryEntry("checked", "2025", "me", "why", (("CSWP", "wp"), ("CSPR", "pr"))),),
                      flags=(CsFlag("C", "1"),)))
    root = etree.fromstring(write(ds))
    inst = root.find(".//SW-INSTANCE")
    assert [c.tag for c in inst if isinstance(c.tag, str)] == [
        "SHORT-NAME", "LONG-NAME", "DISPLAY-NAME", "CATEGORY", "SW-FEATURE-REF", "SW-VALUE-CONT", "SW-AXIS-CONTS",
        "SW-CS-HISTORY", "SW-CS-FLAGS"]
    groups = inst.findall("SW-VALUE-CONT/SW-VALUES-PHYS/VG")
    assert [[v.text for v in g] for g in groups] == [["1", "2", "3"], ["4", "5", "6"]]
    first_axis = inst.find("SW-AXIS-CONTS/SW-AXIS-CONT")
    assert [c.tag for c in first_axis] == ["CATEGORY", "UNIT-DISPLAY-NAME", "SW-INSTANCE-REF", "SW-VALUES-PHYS"]
    entry = inst.find("SW-CS-HISTORY/CS-ENTRY")
    assert [c.tag for c in entry] == ["STATE", "DATE", "CSUS", "CSPR", "CSWP", "REMARK"]
    assert root.getprevious().text == " file - - comment "
    back = read(write(ds))
    assert back["m"] == ds["m"] and back.info["m"] == ds.info["m"].__class__(**{**ds.info["m"].__dict__, "line": back.info["m"].line,
                                                                              "value_line": back.info["m"].value_line,
                                                                              "value_runs": back.info["m"].value_runs,
                                                                              "category": "MAP", "history": (
        HistoryEntry("checked", "2025", "me", "why", (("CSPR", "pr"), ("CSWP", "wp"))),)})


def test_special_floats_and_extreme_integers_survive():
    ds = Dataset()
    ds.add(CalValue("f", "VAL_BLK", np.array([math.nan, math.inf, -math.inf, -0.0, 5e-324, 1.7976931348623157e308])))
    ds.add(CalValue("i", "VAL_BLK", np.array([2**64 - 1, 0], dtype=np.uint64)))
    text = write(ds).decode()
    assert "<V>NaN</V>" in text and "<V>INF</V>" in text and "<V>-INF</V>" in text
    back = read(text)
    assert back["f"] == ds["f"] and math.copysign(1, back["f"].value[3]) == -1
    assert back["i"].value.dtype == np.uint64 and back["i"] == ds["i"]


def test_what_cdf_cannot_hold_is_listed_and_left_out():
    ds = Dataset(module_header=[("P", "x")], variant_criteria={"E": ("a",)})
    ds.add(CalValue("v", "VALUE", 1), ObjectInfo(functions=("A", "B"), variants=(("E", "a"),)))
    messages = [f.message for f in losses(ds)]
    assert "v: only the first of its functions (A) is written (one SW-FEATURE-REF)" in messages
    assert "v: its variant dependency (VAR) is not written" in messages
    assert len(messages) == 4
    bad = Dataset()
    bad.add(CalValue("t", "ASCII", "bell\x07"))
    bad.add(CalValue("u", "ASCII", "fine"))
    assert [f.message for f in losses(bad)] == [
        "t: a text holds a control character XML cannot hold; left out of the file"]
    assert list(read(write(bad))) == ["u"]


def test_a_file_of_the_other_format_is_named_so(tmp_path):
    """A CDFX saved as .dcm (or the other way round) said "unknown keyword '<?xml'" or "not well-formed XML"."""
    from workbench.calib.dataset import load_dataset

    (tmp_path / "set.dcm").write_bytes(b"\xef\xbb\xbf<?xml version='1.0'?>\n<MSRSW/>\n")
    (tmp_path / "set.cdfx").write_text("KONSERVIERUNG_FORMAT 2.0\n\nFESTWERT x\n  WERT 1.0\nEND\n")
    with pytest.raises(InputError, match=r"set.dcm: XML, not a DCM \(a CDFX file named .dcm\? name it .cdfx\)"):
        load_dataset(tmp_path / "set.dcm")
    with pytest.raises(InputError, match=r"set.cdfx: not XML, so not a CDFX \(a DCM file named .cdfx\? name it .dcm\)"):
        load_dataset(tmp_path / "set.cdfx")
