"""What insert reads from a name pattern before it walks the ELF's variables: the literal starts of its matches,
the text each match holds, and whether it can match past a variable's own name (into ``.member``, ``[2]``)."""

import re

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from workbench.a2l.patterns import literal_prefixes, required_text, selection_pattern, stops_before


@pytest.mark.parametrize("text, prefixes, required, stops", [
    ("u0[0-9]_var00[0-9][0-9]", ("u0",), "_var00", True),
    ("^zs", ("zs",), "zs", True),  # searched as written: matches "zsScalar.x" in its name
    (r"a(?=b)\w+|c\d", ("a", "c"), "", True),
    (r"(a)\1", ("a",), "a", True),
    ("^u0.*", ("u0",), "u0", False),  # . consumes "."
    (r"x\..*", ("x.",), "x.", False),
    (r".*(ab)+cd(?i:ef)", ("",), "cd", False),
    (r"a[^x]|a\W|a\D|a[Z-a]|a[.]", ("a", "a", "a", "a", "a."), "a", False),
    (r"a(?!x)", ("a",), "a", False),  # a negative lookahead sees the tail: not followed
    ("(?i)ab", None, "", True),  # any case: no literal start
    ("ab$", None, "ab", False),  # not anchored at the start: may match in a member's name
])
def test_what_a_pattern_says_about_its_matches(text, prefixes, required, stops):
    pattern = selection_pattern(text)
    assert literal_prefixes(pattern) == prefixes
    assert required_text(pattern) == required
    assert stops_before(pattern, ".[") is stops


# mostly what cannot consume "." or "[" (the patterns this must tell right), some that can
_ATOMS = st.sampled_from(["a", "_", r"\w", "[a_]", "$", r"\b", r"\B", ".", r"\.", "[^a]", r"\W"])


def _pieces(inner):
    return st.one_of(
        st.tuples(inner, st.sampled_from(["", "*", "+", "?", "{0,2}", "*?"])).map("".join),
        st.lists(inner, min_size=1, max_size=3).map(lambda parts: f"(?:{'|'.join(parts)})"),
        st.tuples(st.sampled_from(["(?=", "(", "(?!"]), inner).map(lambda pair: f"{pair[0]}{pair[1]})"),
    )


_PATTERNS = st.lists(st.recursive(_ATOMS, _pieces, max_leaves=6), min_size=1, max_size=4).map("".join)


_HEADS = ["a", "_", "aa", "a_", "_a", "__", "aaa"]  # variable names: never empty
_TAILS = [".", "[", ".a", ".a_", "[0]", "[0].a", ".a[0]"]


@settings(max_examples=500, deadline=None)
@given(body=_PATTERNS, anchored=st.booleans())
def test_what_insert_reads_from_a_pattern_holds_for_every_path_it_matches(body, anchored):
    """A variable none of whose paths hold the required text, or whose name a pattern that stops before a member
    does not match, is left out: had the pattern matched one of its paths, it would be missing."""
    try:
        pattern = re.compile(("^" if anchored else "") + body)
    except re.error:  # "$*": nothing to repeat
        assume(False)
    required, stops = required_text(pattern), stops_before(pattern, ".[")
    for head in _HEADS:
        matched = [head + tail for tail in ["", *_TAILS] if pattern.search(head + tail)]
        assert all(required in path for path in matched), required
        assert pattern.search(head) or not stops or not matched, head
