"""Name patterns as a2ltool reads them (``insert --measurement-regex``, ``remove --regex``)."""

from __future__ import annotations

import re

__all__ = ["as_typed", "literal_prefixes", "required_text", "selection_pattern", "stops_before"]

_GLOBAL_FLAGS = re.compile(r"(?:\(\?[aiLmsux]+\))+")


def selection_pattern(text: str) -> re.Pattern:
    """A regular expression that selects by the whole name (a2ltool's rule: one that starts with ``^`` or ends
    with ``$`` is searched as written). Raises ``re.error``."""
    if text.startswith("^") or text.endswith("$"):
        return re.compile(text)
    flags = _GLOBAL_FLAGS.match(text)  # (?i) stays in front: Python takes global flags there only
    head = flags.group() if flags else ""
    return re.compile(f"{head}^(?:{text[len(head):]})$")


def as_typed(text: str) -> str:
    """A pattern as a shell takes it, to copy back: ``'tank\\.kp'`` (``repr`` would double the backslash)."""
    if "'" not in text:
        return f"'{text}'"
    import shlex  # here: a quote in a pattern is rare

    return shlex.quote(text)


def literal_prefixes(pattern: re.Pattern) -> tuple[str, ...] | None:
    """The texts one of which starts every string ``pattern`` matches (``^(?:u0[0-9]_a|b)$``: "u0", "b"), from
    Python's own parse of it; None when it does not say (no ``^`` in front, ``(?i)``, a class first)."""
    items = _anchored_items(pattern)
    if items is None or pattern.flags & re.IGNORECASE:
        return None
    return _prefixes_of(items)


def stops_before(pattern: re.Pattern, chars: str) -> bool:
    """Whether ``pattern`` matches from a text's start and never consumes one of ``chars`` (no letter, no newline),
    so that it matches ``head`` whenever it matches ``head + tail`` and ``tail`` starts with one of them:
    ``^(?:u0[0-9]_x)$`` stops before "." and "[", ``^u0.*`` and ``x\\..*`` do not. False when it cannot tell (a
    negative lookaround, an atomic group)."""
    items = _anchored_items(pattern)
    return items is not None and not _may_consume(items, chars)


def required_text(pattern: re.Pattern) -> str:
    """The longest text that every match of ``pattern`` holds as written (``.*var01.*``: "var01"), from Python's
    parse of it; "" when it does not say (``(?i)``, alternatives only)."""
    if pattern.flags & re.IGNORECASE:
        return ""
    try:
        items = list(_parser().parse(pattern.pattern, pattern.flags))
    except Exception:  # noqa: BLE001 - another Python's parser: it does not tell
        return ""
    return max(_literal_runs(items), key=len)


def _literal_runs(items: list) -> list[str]:
    """The runs of literals in a parsed sequence, and in the groups it always matches."""
    runs, text = [], ""
    for op, argument in items:
        kind = str(op)
        if kind == "LITERAL":
            text += chr(argument)
            continue
        runs.append(text)
        text = ""
        if kind == "SUBPATTERN" and not argument[1] & re.IGNORECASE:  # (?i:...) holds its text in any case
            runs += _literal_runs(list(argument[-1]))
    return [*runs, text]


def _parser():
    try:
        from re import _parser as parser  # Python 3.11+
    except ImportError:  # pragma: no cover - Python 3.10
        import sre_parse as parser
    return parser


def _anchored_items(pattern: re.Pattern) -> list | None:
    """Python's own parse of a pattern that starts with ``^``, without it; None for others."""
    try:
        items = list(_parser().parse(pattern.pattern, pattern.flags))
    except Exception:  # noqa: BLE001 - another Python's parser: it does not tell
        return None
    if not items or str(items[0][0]) != "AT" or str(items[0][1]) != "AT_BEGINNING":
        return None
    return items[1:]


def _prefixes_of(items: list) -> tuple[str, ...]:
    """The literal starts of a parsed sequence (ending at the first item that is not a literal, a group or an
    alternation)."""
    text = ""
    for op, argument in items:
        kind = str(op)
        if kind == "LITERAL":
            text += chr(argument)
            continue
        if kind == "SUBPATTERN":
            if argument[1] & re.IGNORECASE:  # (?i:...)
                break
            return tuple(text + inner for inner in _prefixes_of(list(argument[-1])))
        if kind == "BRANCH":
            return tuple(text + inner for branch in argument[1] for inner in _prefixes_of(list(branch)))
        break
    return (text,)


def _may_consume(items: list, chars: str) -> bool:
    """Whether a parsed sequence may consume one of ``chars``; True for what this does not follow."""
    for op, argument in items:
        kind = str(op)
        if kind == "LITERAL":
            found = chr(argument) in chars
        elif kind == "IN":
            found = any(_in_class(argument, char) for char in chars)
        elif kind in ("AT", "GROUPREF"):  # a backreference consumes what its group did
            found = False
        elif kind in ("SUBPATTERN", "MAX_REPEAT", "MIN_REPEAT", "ASSERT"):  # the sequence comes last
            found = _may_consume(list(argument[-1]), chars)
        elif kind == "BRANCH":
            found = any(_may_consume(list(branch), chars) for branch in argument[1])
        elif kind == "GROUPREF_EXISTS":
            found = any(_may_consume(list(branch), chars) for branch in argument[1:] if branch is not None)
        else:  # ANY, NOT_LITERAL; and what may stop a match at a text's end but not before a tail: ASSERT_NOT ...
            found = True
        if found:
            return True
    return False


def _in_class(items: list, char: str) -> bool:
    """Whether a parsed ``[...]`` matches ``char`` (no letter: the case does not matter)."""
    negate = found = False
    for op, argument in items:
        kind = str(op)
        if kind == "NEGATE":
            negate = True
        elif kind == "LITERAL":
            found = found or chr(argument) == char
        elif kind == "RANGE":
            found = found or argument[0] <= ord(char) <= argument[1]
        elif kind == "CATEGORY":  # \W \S \D match punctuation, \w \s \d do not
            found = found or "NOT" in str(argument)
        else:
            return True
    return found != negate
