"""Name patterns as a2ltool reads them (``insert --measurement-regex``, ``remove --regex``)."""

from __future__ import annotations

import re

__all__ = ["as_typed", "selection_pattern"]

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
