"""The commands read a DBC's content without building cantools' database: that reading must be cantools'.

For every file, the content :func:`load_dbc` reads (``workbench.can.dbc_read``) equals the content
taken from cantools' database (``workbench.can.dbc_database``), down to the JSON of ``dbc table``
(``1`` and ``1.0`` differ there), or both refuse the file with the same error: the corpus, the demo's
DBCs, the benchmark's generated DBC, every DBC the other tests of this folder write with ``write_dbc``,
and random DBCs that mix what cantools reads, refuses and reads in its own way.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest
from agreement import assert_reads_as_cantools, outcome
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from workbench import demo
from workbench.can.dbc_file import load_dbc

ROOT = Path(__file__).resolve().parents[2]
CORPUS = ROOT / "tests" / "corpus" / "dbc"
FILES = sorted(CORPUS.rglob("*.dbc")) + sorted(Path(demo.path("dbc")).glob("*.dbc"))


@pytest.mark.parametrize("path", FILES, ids=lambda path: path.name)
def test_every_corpus_and_demo_file_reads_as_cantools_reads_it(path):
    assert_reads_as_cantools(path)


@pytest.mark.parametrize("defects", [False, True], ids=["clean", "defects"])
def test_the_benchmark_dbc_reads_as_cantools_reads_it(defects, tmp_path):
    spec = importlib.util.spec_from_file_location("dbc_generate", ROOT / "benchmarks" / "dbc_generate.py")
    generator = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(generator)
    path = tmp_path / "generated.dbc"
    path.write_text(generator.generate(24, defects=defects))
    read = outcome(path)
    assert read[0] == "read" and len(read[1].messages) > 10
    assert read == outcome(path, by_cantools=True)


_MESSAGE = 'BO_ 1 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] "" A\n'


@pytest.mark.parametrize("text", [
    'VERSION ""\nNS_ :\n\tCM_\n\tBA_\n',  # the NS_ list runs to the end
    f'BU_: A\n{_MESSAGE}// a comment without its newline',
    f'BU_: A\n{_MESSAGE}CM_ BO_ 1 "a comment";\xa0\n',  # space cantools does not skip
    f'BU_: A\n{_MESSAGE}CM_ BO_ 1 "a\xa0comment";\n',  # ... in a string, where it may
    f'BU_: A FILTER\n{_MESSAGE}',  # a keyword as a name
    f'BU_: A\n{_MESSAGE}BA_DEF_ BO_ "GenMsgCycleTime" INT 0;\n',  # one limit of two
    f'BU_: A\n{_MESSAGE}BA_DEF_ BO_ "GenMsgCycleTime" INT 0 9;\nBA_DEF_DEF_ "GenMsgCycleTime" "x";\n',
    f'BU_: A\n{_MESSAGE}BA_DEF_ BO_ "VFrameFormat" INT 0 15;\nBA_DEF_DEF_ "VFrameFormat" 16;\n',
    'BU_: A\nBO_ 1 M: 010 A\n SG_ S : 0|8@1+ (1,0) [0|0] "" A\n',  # cantools reads the DLC with int(x, 0)
    'BU_: A\nBO_ 1 M: 8 A\n SG_ S M : 0|8@1+ (1,0) [0|0] "" A\n SG_ T mX : 8|8@1+ (1,0) [0|0] "" A\n',
])
def test_odd_files_read_as_cantools_reads_them(text, tmp_path):
    path = tmp_path / "odd.dbc"
    path.write_text(text, encoding="utf-8")
    assert_reads_as_cantools(path)


def test_extended_multiplexing_and_long_names_read_as_cantools_reads_them(write_dbc):
    path = write_dbc(
        'BO_ 16 M: 8 ECU\n SG_ MUX M : 0|8@1+ (1,0) [0|0] "" PEER\n SG_ A m1 : 8|8@1+ (1,0) [0|0] "" PEER\n'
        ' SG_ SHORT : 16|8@1+ (1,0) [0|0] "" PEER\n',
        'SG_MUL_VAL_ 16 A MUX 1-3, 7-7;\nBA_DEF_ SG_ "SystemSignalLongSymbol" STRING ;\n'
        'BA_DEF_ BU_ "SystemNodeLongSymbol" STRING ;\nBA_ "SystemSignalLongSymbol" SG_ 16 SHORT "A_Rather_Long_Name";\n'
        'BA_ "SystemNodeLongSymbol" BU_ PEER "The_Peer_Of_The_ECU";\n')
    dbc = load_dbc(path)
    (message,) = dbc.content.messages
    assert [(s.name, s.multiplexer_ids, s.receivers) for s in message.signals] == [
        ("MUX", None, ("The_Peer_Of_The_ECU",)), ("A", (1, 2, 3, 7), ("The_Peer_Of_The_ECU",)),
        ("A_Rather_Long_Name", None, ("The_Peer_Of_The_ECU",))]
    assert dbc.content.nodes == ("ECU", "The_Peer_Of_The_ECU")
    assert "database" not in vars(dbc)  # read without building cantools' database (the fixture compares)


def test_the_table_of_a_file_the_reader_reads_loads_no_cantools():
    code = ("import sys; from workbench.cli import main; code = main(['dbc', 'table', sys.argv[1], '--json']); "
            "sys.exit(code or 3 * ('cantools' in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code, str(demo.path("dbc", "FLCU_CAN2.dbc"))], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    assert '"Name": "FLCU_TO_PCM_003"' in done.stdout


def test_space_at_the_end_and_unterminated_strings_are_read_at_once(tmp_path):
    # the tokenizer once tried every split of such runs: minutes for 30 blank lines or a 40-character string
    blank = tmp_path / "blank.dbc"
    blank.write_text('VERSION ""\nBU_: A\nBO_ 1 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] "" A\n' + "\n" * 60)
    assert [m.name for m in load_dbc(blank).content.messages] == ["M"]
    unterminated = tmp_path / "unterminated.dbc"
    unterminated.write_text('VERSION ""\nBU_: A\nBO_ 1 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] "" A\n'
                            'CM_ "' + "a comment that never ends " * 4 + "\n")
    assert [(w.kind, w.line) for w in load_dbc(unterminated).warnings] == [("comment-syntax", 5)]


# -- random DBCs ------------------------------------------------------------------------------------

_NODES = ("A", "B", "ECU")
_ATTRIBUTES = {  # name: (object kind, the types it may be defined with)
    "GenMsgCycleTime": ("BO_ ", ("INT 0 65535", "FLOAT 0 100", "STRING", "INT 0", "HEX 0 10")),
    "GenMsgTimeoutTime": ("BO_ ", ("INT 0 65535", "STRING", 'ENUM "a","b"')),
    "VFrameFormat": ("BO_ ", ('ENUM "StandardCAN","ExtendedCAN"', "INT 0 15", "STRING", "ENUM", "HEX 0 3")),
    "GenMsgSendType": ("BO_ ", ('ENUM "Cyclic","Event"', "STRING", "INT 0 9")),
    "GenSigStartValue": ("SG_ ", ("INT 0 100", "FLOAT 0 1", "STRING")),
    "SPN": ("SG_ ", ("INT 0 100", "FLOAT 0 1")),
    "DBName": ("", ("STRING", "INT 0 9")),
    "Baudrate": ("", ("INT 0 1000000", "STRING")),
    "Owner": ("BU_ ", ("STRING",)),
    "SystemMessageLongSymbol": ("BO_ ", ("STRING", "INT 0 9")),
    "SystemSignalLongSymbol": ("SG_ ", ("STRING",)),
    "SystemNodeLongSymbol": ("BU_ ", ("STRING",)),
}
_UNITS = ('""', '"km/h"', '"a\\"b"')
_COMMENTS = ("text", 'with \\"quotes\\"', "")
_NUMBERS = ("0", "1", "2", "20", "100", "1.5")
_VALUES = ("0", "1", "2", "20", "100", "-1", "1.5", "1e3", '"x"', '"100"', '"Cyclic"', '""')


@st.composite
def _dbc_texts(draw) -> str:
    def one(options):
        return draw(st.sampled_from(options))

    def rare(usual, odd):  # what cantools refuses, or reads as something else, now and then
        return one(odd) if draw(st.integers(0, 39)) == 0 else one(usual)

    nodes = draw(st.lists(st.sampled_from(_NODES), max_size=3, unique=True))
    lines = ['VERSION ""', "", "NS_ :", "\tCM_", "\tBA_", "", "BS_:", "", "BU_: " + " ".join(nodes), ""]
    lines += [f'VAL_TABLE_ {name} 1 "on" 0 "off" ;' for name in one(((), ("VT",), ("VT", "VT2")))]
    signals: list[tuple[str, str]] = []
    for _ in range(draw(st.integers(1, 3))):
        frame_id = rare(("1", "16", "2047", "2048", "2147483664", "3221225472", "16"), ("0x10", "1.0", "-1"))
        name, dlc = rare(("M1", "M2", "M1"), ("2M", "FILTER")), rare(("8", "0", "64", "4"), ("08", "8.0"))
        lines.append(f"BO_ {frame_id} {name}: {dlc} {one((*nodes, 'Vector__XXX'))}")
        for _ in range(draw(st.integers(0, 4))):
            name = rare(("S1", "S2", "S3", "MUX", "S1"), ("3S", "VERSION"))
            signals.append((frame_id, name))
            lines.append(
                f" SG_ {name}{one(('', '', ' M', ' m0', ' m1', ' m12', ' m1M', ' x', ' mX'))} : "
                f"{draw(st.integers(0, 70))}|{rare(('1', '8', '16', '32', '64', '70'), ('0',))}@{one('01')}{one('+-')} "
                f"({rare(('1', '1.0', '0.5', '2', '2.0', '-1', '1e2'), ('.5',))},"
                f"{one(('0', '0.0', '-40', '1.5', '-0'))}) "
                f"[{one(('0|0', '0|0.0', '-1|1', '0|255', '1e3|2.5'))}] {one(_UNITS)} "
                f"{rare(('Vector__XXX', 'A', 'A,B', 'Vector__XXX,A'), ('A B', 'FILTER'))}")
        lines.append("")
    for name in draw(st.lists(st.sampled_from(sorted(_ATTRIBUTES)), max_size=5, unique=True)):
        kind, types = _ATTRIBUTES[name]
        lines.append(f'BA_DEF_ {kind}"{name}" {rare(types[:1], types[1:] or types)};')
        if draw(st.booleans()):
            lines.append(f'BA_DEF_DEF_ "{name}" {rare(_NUMBERS, _VALUES)};')
    targets = [f"BO_ {frame_id}" for frame_id, _ in signals] + [f"SG_ {frame_id} {name}" for frame_id, name in signals]
    targets += [f"BU_ {node}" for node in nodes] + ["", "BO_ 99"]
    for _ in range(draw(st.integers(0, 6))):
        lines.append(f'BA_ "{one(sorted(_ATTRIBUTES))}" {one(targets)} {one(_VALUES)};')
    for _ in range(draw(st.integers(0, 4))):
        lines.append(f'CM_ {one(targets)} "{one(_COMMENTS)}";')
    for _ in range(draw(st.integers(0, 3))):
        frame_id, name = one(signals or [("16", "S1")])
        multiplexer = one([signal for message_id, signal in signals if message_id == frame_id] or ["MUX"])
        lines.append(rare((f'VAL_ {frame_id} {name} 1 "on" 0 "off" ;', f'VAL_ {frame_id} {name} ;',
                           f'VAL_ {frame_id} {name} 1 ;', f"SIG_VALTYPE_ {frame_id} {name} : {one('012')};",
                           f"BO_TX_BU_ {frame_id} : A,B;",
                           f"SG_MUL_VAL_ {frame_id} {name} {multiplexer} {one(('0-0', '1-3', '1-3, 5-5', '2-1'))};"),
                          (f'VAL_ {frame_id} {name} 1.5 "half" ;',
                           f"SG_MUL_VAL_ {frame_id} {name} {multiplexer} 0 3;")))
    return "\n".join(lines) + "\n"


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=_dbc_texts())
def test_random_dbcs_read_as_cantools_reads_them(text, tmp_path):
    path = tmp_path / "random.dbc"
    path.write_text(text)
    assert outcome(path) == outcome(path, by_cantools=True)
