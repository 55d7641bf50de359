"""The keyword table, block by block: options in any order around child blocks, and every enumerated
parameter checked against the words ASAP2 allows there (the cases are generated from the table)."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from grammar_samples import block_text, child_of, document, in_block, option_text, reachable_blocks
from workbench.a2l import grammar, load_a2l_string
from workbench.errors import A2lParseError

BLOCKS_WITH_OPTIONS_AND_CHILDREN = [k for k in reachable_blocks() if grammar.BLOCKS[k].options and child_of(k)]
ENUM_PARAMETERS = [(keyword, index, kind) for keyword in reachable_blocks()
                   for index, kind in enumerate(grammar.BLOCKS[keyword].params) if kind in grammar.ENUMS]
ENUM_OPTIONS = sorted({(option, index, kind) for keyword in reachable_blocks()
                       for option in grammar.BLOCKS[keyword].options
                       for index, kind in enumerate(grammar.OPTIONS[option]) if kind in grammar.ENUMS})


def _host(option: str) -> str:
    """A block that allows ``option``."""
    return next(keyword for keyword in reachable_blocks() if option in grammar.BLOCKS[keyword].options)


def _the_block(doc, keyword):
    (block,) = doc.blocks_named(keyword)[-1:]
    return block


def test_the_generated_cases_cover_the_table():
    assert len(BLOCKS_WITH_OPTIONS_AND_CHILDREN) >= 15 and {"CHARACTERISTIC", "MEASUREMENT", "AXIS_PTS", "BLOB",
                                                            "INSTANCE", "MOD_PAR", "AXIS_DESCR"} <= set(
        BLOCKS_WITH_OPTIONS_AND_CHILDREN)
    assert {kind for _, _, kind in ENUM_PARAMETERS + ENUM_OPTIONS} == set(grammar.ENUMS)


@pytest.mark.parametrize("keyword", BLOCKS_WITH_OPTIONS_AND_CHILDREN)
def test_every_option_may_follow_the_child_blocks(keyword):
    """a2ltool writes SYMBOL_LINK after AXIS_DESCR and IF_DATA; any option may stand anywhere."""
    options = sorted(grammar.BLOCKS[keyword].options)
    child = child_of(keyword)
    for before, after in ((options[::2], options[1::2]), (options[1::2], options[::2])):
        text = document(keyword, block_text(keyword, [*map(option_text, before), child, *map(option_text, after),
                                                      child]))
        block = _the_block(load_a2l_string(text, "order.a2l"), keyword)
        for option in options:
            params = block.option(option)
            assert params is not None, option
            expected = option_text(option).split()[1:]
            assert [block.doc.raw(token).decode() for token in params] == expected, option


@settings(max_examples=60, deadline=None)
@given(data=st.data())
def test_options_and_children_in_any_order(data):
    keyword = data.draw(st.sampled_from(BLOCKS_WITH_OPTIONS_AND_CHILDREN))
    parts = [option_text(option) for option in sorted(grammar.BLOCKS[keyword].options)] + [child_of(keyword)] * 2
    text = document(keyword, block_text(keyword, data.draw(st.permutations(parts))))
    block = _the_block(load_a2l_string(text, "order.a2l"), keyword)
    assert {name for name, _ in block.layout()[1]} == grammar.BLOCKS[keyword].options


@pytest.mark.parametrize("keyword, index, kind", ENUM_PARAMETERS, ids=lambda value: str(value))
def test_an_enumerated_parameter_allows_its_words_only(keyword, index, kind):
    words = grammar.ENUMS[kind].words
    for word in words:
        load_a2l_string(document(keyword, block_text(keyword, replace={index: word})))
    text = document(keyword, block_text(keyword, replace={index: "NOT_A_WORD"}))
    with pytest.raises(A2lParseError) as info:
        load_a2l_string(text, "enum.a2l")
    _assert_located(info.value, text, "NOT_A_WORD", in_block(keyword, f"{keyword}: 'NOT_A_WORD' is not "
                    f"{grammar.ENUMS[kind].what} (allowed: {', '.join(words)})"))


@pytest.mark.parametrize("option, index, kind", ENUM_OPTIONS, ids=lambda value: str(value))
def test_an_enumerated_option_parameter_allows_its_words_only(option, index, kind):
    keyword = _host(option)
    words = grammar.ENUMS[kind].words
    for word in words:
        load_a2l_string(document(keyword, block_text(keyword, [option_text(option, {index: word})])))
    text = document(keyword, block_text(keyword, [option_text(option, {index: "NOT_A_WORD"})]))
    with pytest.raises(A2lParseError) as info:
        load_a2l_string(text, "enum.a2l")
    _assert_located(info.value, text, "NOT_A_WORD", in_block(keyword, f"{option}: 'NOT_A_WORD' is not "
                    f"{grammar.ENUMS[kind].what} (allowed: {', '.join(words)})"))


def test_a_string_where_a_word_belongs_names_the_allowed_words():
    text = document("MEASUREMENT", block_text("MEASUREMENT", replace={2: '"UBYTE"'}))
    with pytest.raises(A2lParseError, match=r"MEASUREMENT a_name: a data type expected, found a string \(allowed: "):
        load_a2l_string(text)


def test_frame_measurement_is_a_list_of_names():
    text = document("FRAME", block_text("FRAME", ["FRAME_MEASUREMENT a b c", "/begin IF_DATA X /end IF_DATA"]))
    block = _the_block(load_a2l_string(text), "FRAME")
    assert [block.doc.text(token) for token in block.option("FRAME_MEASUREMENT")] == ["a", "b", "c"]
    with pytest.raises(A2lParseError, match="FRAME_MEASUREMENT: at least one name expected"):
        load_a2l_string(document("FRAME", block_text("FRAME", ["FRAME_MEASUREMENT 12"])))


def _assert_located(error: A2lParseError, text: str, word: str, message: str) -> None:
    offset = text.index(word)
    line = text.count("\n", 0, offset) + 1
    column = offset - text.rfind("\n", 0, offset)
    assert (error.path, error.line, error.column, error.reason) == ("enum.a2l", line, column, message)
