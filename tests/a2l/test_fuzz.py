"""Random mutations of real A2L files: the reader parses them or raises A2lParseError, and update, merge,
diff, check and the XCP reader fail with our errors only."""

import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from workbench import demo
from workbench.a2l.check import check_document
from workbench.a2l.document import A2lDocument
from workbench.a2l.source import SourceMap, decode_source
from workbench.a2l.tokens import _OPAQUE, _simple_opaque_spans, tokenize
from workbench.a2l.diff import diff_documents
from workbench.a2l.merge import merge_documents
from workbench.a2l.reports import ConflictPolicy
from workbench.a2l.update import update_document
from workbench.a2l.xcp import read_xcp_config
from workbench.elf.debugdata import DebugData
from workbench.errors import A2lParseError, WorkbenchError

CORPUS = Path(__file__).parents[1] / "corpus" / "a2l"
FILES = [demo.master_a2l(), *demo.fragment_a2ls()[:3], Path(__file__).parent / "fixtures" / "xcp_ecu.a2l",
         Path(__file__).parent / "fixtures" / "types.a2l", CORPUS / "a2ltool" / "update_test2.a2l",
         CORPUS / "a2ltool" / "update_typedef_test4.a2l", CORPUS / "domohuhn-a2l" / "example-ecu.a2l"]
DEBUG = DebugData(Path(__file__).parents[1] / "elf" / "fixtures" / "types_dwarf5.elf", use_cache=False)
MASTER = A2lDocument.from_source(decode_source(demo.master_a2l().read_bytes(), demo.master_a2l()))
SNIPPETS = [b"/begin", b"/end", b"/include", b'"', b"/*", b"*/", b"//", b"\n", b"0x", b"0x1G", b"-", b".", b"1e",
            b"MEASUREMENT", b"ECU_ADDRESS", b"IF_DATA", b"\xef\xbb\xbf", b"\xff\xfe", b"\xc3", b"\x00", b"\\",
            b"/begin MODULE", b"/end MODULE", b"ASAP2_VERSION"]

mutation = st.one_of(
    st.tuples(st.just("delete"), st.floats(0, 1), st.integers(1, 200)),
    st.tuples(st.just("insert"), st.floats(0, 1), st.one_of(st.sampled_from(SNIPPETS), st.binary(min_size=1, max_size=8))),
    st.tuples(st.just("duplicate"), st.floats(0, 1), st.integers(1, 400)),
    st.tuples(st.just("truncate"), st.floats(0, 1), st.just(0)),
)


def mutate(data: bytes, operations) -> bytes:
    for kind, where, argument in operations:
        position = int(where * len(data))
        if kind == "delete":
            data = data[:position] + data[position + argument:]
        elif kind == "insert":
            data = data[:position] + argument + data[position:]
        elif kind == "duplicate":
            data = data[:position] + data[position:position + argument] + data[position:]
        else:
            data = data[:position]
    return data


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(index=st.integers(0, len(FILES) - 1), operations=st.lists(mutation, min_size=1, max_size=4))
def test_mutated_files_parse_or_raise_a2l_parse_error(index, operations):
    data = mutate(FILES[index].read_bytes(), operations)
    try:
        doc = A2lDocument.from_source(decode_source(data, FILES[index]))
    except A2lParseError as error:
        assert error.line >= 1 and error.column >= 1 and str(error).startswith(str(FILES[index]))
        return
    # a document that parsed can be used: every operation fails with our errors or not at all
    original = A2lDocument.from_source(decode_source(FILES[index].read_bytes(), FILES[index]))
    for action in (lambda: check_document(doc), lambda: read_xcp_config(doc), lambda: update_document(doc, DEBUG, types=True),
                   lambda: merge_documents(MASTER, [doc], policy=ConflictPolicy.RENAME), lambda: diff_documents(original, doc)):
        try:
            action()
        except WorkbenchError:
            pass


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_unmutated_files_parse(path):
    A2lDocument.from_source(decode_source(path.read_bytes(), path))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(index=st.integers(0, len(FILES) - 1), operations=st.lists(mutation, min_size=0, max_size=4))
def test_numpy_string_and_comment_finder_agrees_with_the_regex(index, operations):
    data = mutate(FILES[index].read_bytes(), operations)
    simple = _simple_opaque_spans(data, np.frombuffer(data, np.uint8))
    if simple is not None:  # None: the file is not simple, and the regex decides alone
        assert simple.tolist() == [list(match.span()) for match in _OPAQUE.finditer(data)]


def _reference_tokens(data: bytes) -> list[tuple[int, int]]:
    """Tokens read plainly: strings and comments as the regex finds them (comments dropped), the text
    between them split at blanks (every byte up to 0x20)."""
    tokens, position = [], 0
    for match in _OPAQUE.finditer(data):
        tokens += [(position + m.start(), position + m.end())
                   for m in re.finditer(rb"[^\x00-\x20]+", data[position : match.start()])]
        if data[match.start()] == ord('"'):
            tokens.append(match.span())
        position = match.end()
    return tokens + [(position + m.start(), position + m.end()) for m in re.finditer(rb"[^\x00-\x20]+", data[position:])]


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(index=st.integers(0, len(FILES) - 1), operations=st.lists(mutation, min_size=0, max_size=4),
       soup=st.lists(st.sampled_from([b" ", b"\n", b'"', b'""', b"\\", b"/*", b"*/", b"//", b"a", b"x y", b"0x1",
                                      b"ECU_ADDRESS", b"/begin", b"KEYWORD_LONGER_THAN_24_BYTES"]), max_size=30))
def test_tokens_keys_and_matching_agree_with_a_plain_reading(index, operations, soup):
    data = mutate(FILES[index].read_bytes(), operations)[:4000] + b"".join(soup)
    try:
        source = decode_source(data, None)
        tokens = tokenize(source.data, SourceMap.single(source))
    except A2lParseError:
        return
    data = source.data
    assert list(zip(tokens.starts.tolist(), tokens.ends.tolist())) == _reference_tokens(data)
    raws = [tokens.raw(i) for i in range(len(tokens))]
    keys, exact = tokens.keys(np.arange(len(tokens)))
    # equal keys exactly for equal bytes: as many distinct keys as distinct texts, each key one text
    keyed = {}
    for i, raw in enumerate(raws):
        if exact[i]:
            assert keyed.setdefault(tuple(keys[:, i].tolist()), raw) == raw
    assert len(keyed) == len({raw for i, raw in enumerate(raws) if exact[i]})
    for word in set(raws[:40]) | {b"ECU_ADDRESS", b"/end"}:
        assert tokens.matching(word).tolist() == [i for i, raw in enumerate(raws) if raw == word]


def test_block_keywords_are_numbered_alike_when_their_hashes_collide(monkeypatch):
    """Keywords are grouped by one hash of their keys; were every hash the same, the grouping falls back
    to the keys themselves and numbers them as before."""
    from workbench.a2l import tree

    expected = (MASTER.blocks.keyword_id.tolist(), MASTER.blocks.keyword_names)
    monkeypatch.setattr(tree, "_hashes", lambda keys: np.zeros(keys.shape[1], np.uint64))
    again = A2lDocument.from_source(decode_source(demo.master_a2l().read_bytes(), demo.master_a2l()))
    assert (again.blocks.keyword_id.tolist(), again.blocks.keyword_names) == expected
    assert again.blocks.keyword == MASTER.blocks.keyword
