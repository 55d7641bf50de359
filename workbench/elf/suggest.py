"""Did-you-mean for the symbols an ELF lacks: "not in app.elf; did you mean 'fooBar_Ctr'?".

A renamed variable is the usual reason an A2L object's symbol is missing from a new build. An update of
65,000 objects pays nothing for this while none is missing (nothing here is imported or built), and little
when a few are (:data:`MOST_SUGGESTED`: the wrong ELF, every symbol missing, must not cost a query for each
of 65,000). The ELF's variable names are indexed by their three-letter pieces (trigrams) when the
first suggestion is asked for, each missing name narrows the 50,000 names to the few dozen that share the
most pieces with it (numpy), and difflib ranks only those (a plain difflib over every name per missing
symbol takes seconds).
"""

from __future__ import annotations

import re
import weakref
from collections.abc import Iterable
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from workbench.elf.debugdata import DebugData

__all__ = ["MOST_SUGGESTED", "NameIndex", "missing_symbol_reason"]

_HEAD = re.compile(r"[A-Za-z_$][A-Za-z0-9_$]*")  # the variable a member/element path starts with
_NARROWED = 40  # names difflib ranks per query: those sharing the most trigrams with it
_CUTOFF = 0.75  # difflib's ratio below which a name is no suggestion (0.6, its default, suggests strangers
# among 50,000 names that share a unit prefix)
MOST_SUGGESTED = 10  # missing symbols a report gives a close name for: a few renamed variables get theirs
_indexes: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # DebugData -> its NameIndex, built on need


class NameIndex:
    """Names indexed by their lower-case trigrams (a name's start and end count as a character, so one of one
    or two letters has trigrams too), for :meth:`closest`."""

    def __init__(self, names: Iterable[str]):
        self.names = list(dict.fromkeys(names))
        folded = ("\n" + "\n".join(self.names) + "\n").lower().encode("utf-8", "replace")  # one call, not 50,000
        data = np.frombuffer(folded, np.uint8)
        inside = np.flatnonzero(data[1:-1] != ord("\n"))  # a trigram whose middle is a separator spans two names
        owners = np.cumsum(data == ord("\n"), dtype=np.int64)[inside]  # the name each middle byte belongs to, + 1
        codes = (data[inside].astype(np.int64) << 48) | (data[inside + 1].astype(np.int64) << 40) \
            | (data[inside + 2].astype(np.int64) << 32)  # the trigram around each byte but the ends
        pairs = np.sort(codes | (owners - 1))  # (trigram, name) by trigram
        first = np.ones(len(pairs), dtype=bool)
        first[1:] = pairs[1:] != pairs[:-1]
        pairs = pairs[first]  # once each (np.unique: 20 times slower, and its first call imports numpy.ma)
        self._trigrams, self._owners = pairs >> 32, pairs & 0xFFFFFFFF
        self._sizes = np.bincount(self._owners, minlength=len(self.names))  # distinct trigrams per name

    def closest(self, name: str, count: int = 1, cutoff: float = _CUTOFF) -> list[str]:
        """Up to ``count`` names most like ``name`` (difflib's ratio ignoring case, at least ``cutoff``), best
        first: a name that differs in case only is the first."""
        if not self.names:
            return []
        query = b"\n" + name.lower().encode("utf-8", "replace") + b"\n"
        wanted = np.array(sorted({(query[i] << 16) | (query[i + 1] << 8) | query[i + 2]
                                  for i in range(len(query) - 2)}))
        starts = np.searchsorted(self._trigrams, wanted)
        ends = np.searchsorted(self._trigrams, wanted, side="right")
        shared = np.bincount(np.concatenate([self._owners[a:b] for a, b in zip(starts.tolist(), ends.tolist())]),
                             minlength=len(self.names))
        sharing = np.flatnonzero(shared)  # often a few hundred of 50,000: the rest need no ranking
        likeness = shared[sharing] / (len(wanted) + self._sizes[sharing])  # Dice's coefficient, halved
        if len(sharing) > _NARROWED:
            sharing = sharing[np.argpartition(-likeness, _NARROWED)[:_NARROWED]]
        import difflib  # here: an update with many symbols missing asks for no suggestion

        matcher = difflib.SequenceMatcher(b=name.lower())
        ranked = []
        for index in sharing.tolist():
            candidate = self.names[index]
            matcher.set_seq1(candidate.lower())
            if matcher.real_quick_ratio() >= cutoff and matcher.quick_ratio() >= cutoff:
                ratio = matcher.ratio()
                if ratio >= cutoff:
                    ranked.append((-ratio, candidate))
        return [candidate for _, candidate in sorted(ranked)[:count]]


def missing_symbol_reason(debug: DebugData, path: str) -> str:
    """Why ``debug`` cannot resolve ``path`` (:meth:`DebugData.resolve_error`); when the ELF lacks the variable the
    path starts with, also the variable most like it: ``not in app.elf; did you mean 'fooBar_Ctr'?`` (with the
    path's members where the suggested variable has them). Scoped and Vector names get no suggestion."""
    why = debug.resolve_error(path)
    head = _HEAD.match(path) if "::" not in path and "{" not in path else None
    if why != f"not in {debug.path.name}" or head is None:
        return why
    index = _indexes.get(debug)
    if index is None:
        index = _indexes[debug] = NameIndex(debug.variable_names())
    close = index.closest(head.group())
    if not close:
        return why
    suffix = path[head.end():]
    suggested = close[0] + suffix if suffix and debug.find(close[0] + suffix) is not None else close[0]
    return f"{why}; did you mean {suggested!r}?"
