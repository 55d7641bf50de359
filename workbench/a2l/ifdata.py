"""IF_DATA content as a generic tree of blocks, words, numbers and strings.

IF_DATA follows the A2ML grammar inside the file, so instead of hard-coding one
file's layout, a block becomes an :class:`IfDataNode`: its values in order (numbers,
strings, and :class:`Word`\\ s for enum values and tags) and its child blocks.
Interpreters (:mod:`workbench.a2l.xcp`) then ask for "the value after tag X" or
"the n-th leading number", which holds for every A2ML that orders the spec's fields.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Iterator, Union

from workbench.a2l.values import is_number, parse_number

if TYPE_CHECKING:
    from workbench.a2l.document import Block

__all__ = ["IfDataNode", "Word", "read_if_data"]


class Word(str):
    """A bare identifier (enum value or tag), as opposed to a quoted string."""

    __slots__ = ()


Value = Union[int, float, str, Word]


@dataclass(frozen=True)
class IfDataNode:
    """One ``/begin NAME ... /end NAME`` block inside IF_DATA (or the IF_DATA block itself)."""

    name: str
    values: tuple[Value, ...]
    children: tuple["IfDataNode", ...] = ()
    location: tuple[str, int, int] = field(default=("<string>", 0, 0), compare=False)  # file, line, column

    def blocks(self, name: str) -> list["IfDataNode"]:
        return [child for child in self.children if child.name == name]

    def block(self, name: str) -> "IfDataNode | None":
        found = self.blocks(name)
        return found[0] if found else None

    def walk(self) -> Iterator["IfDataNode"]:
        """This node and all nodes below it, depth first."""
        yield self
        for child in self.children:
            yield from child.walk()

    def leading_numbers(self) -> list[int | float]:
        """The numbers before the first word or string (a struct's leading numeric fields)."""
        numbers: list[int | float] = []
        for value in self.values:
            if isinstance(value, str):
                break
            numbers.append(value)
        return numbers

    def has(self, word: str) -> bool:
        return any(isinstance(value, Word) and value == word for value in self.values)

    def word_with_prefix(self, prefix: str) -> Word | None:
        """The first word that starts with ``prefix`` (an enum such as ``BYTE_ORDER_...``)."""
        for value in self.values:
            if isinstance(value, Word) and value.startswith(prefix):
                return value
        return None

    def word_among(self, choices) -> Word | None:
        for value in self.values:
            if isinstance(value, Word) and value in choices:
                return value
        return None

    def after(self, tag: str, count: int = 1) -> tuple[Value, ...] | None:
        """The ``count`` values after the first ``tag`` word, or None without that tag."""
        found = self.all_after(tag, count)
        return found[0] if found else None

    def all_after(self, tag: str, count: int = 1) -> list[tuple[Value, ...]]:
        """The ``count`` values after every occurrence of the ``tag`` word (repeated tags)."""
        return [
            tuple(self.values[i + 1 : i + 1 + count])
            for i, value in enumerate(self.values)
            if isinstance(value, Word) and value == tag
        ]

    def number_after(self, tag: str) -> int | float | None:
        found = self.after(tag)
        if found and not isinstance(found[0], str):
            return found[0]
        return None

    def numbers_after(self, word: str) -> list[int | float]:
        """The run of numbers right after ``word``."""
        for i, value in enumerate(self.values):
            if isinstance(value, Word) and value == word:
                run = []
                for following in self.values[i + 1 :]:
                    if isinstance(following, str):
                        break
                    run.append(following)
                return run
        return []


def read_if_data(block: "Block") -> IfDataNode:
    """The tree of an IF_DATA block (or any block), values parsed."""
    doc = block.doc
    values: list[Value] = []
    for token in block.own_tokens:
        raw = doc.raw(token)
        if raw[:1] == b'"':
            values.append(doc.text(token))
        elif is_number(raw):
            values.append(parse_number(raw))
        else:
            values.append(Word(raw.decode(doc.encoding)))
    children = tuple(read_if_data(child) for child in block.children)
    return IfDataNode(block.keyword, tuple(values), children, block.position)
