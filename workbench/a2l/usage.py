"""Who uses what in a MODULE: every reference to a name, as columns (for ``remove`` and ``cleanup``).

The references are those :mod:`workbench.a2l.references` checks (positional parameters, option parameters,
name-list entries), found with vectorized searches over the token and block tables: a file of 65,000
objects is indexed in a few tens of milliseconds. Each reference knows the MODULE's block that holds it
(its *owner*: the CHARACTERISTIC of an AXIS_DESCR, the GROUP of a REF_MEASUREMENT) and the block it names,
resolved as the checker resolves it (an INSTANCE component ``inst.member`` or ``inst[2].member`` names
the INSTANCE).
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

import numpy as np

from workbench.a2l import grammar
from workbench.a2l.references import _LISTS, _OPTIONS, _POSITIONAL

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument, Block

__all__ = ["ENTRY", "OPTION", "POSITIONAL", "Usage"]

ENTRY, OPTION, POSITIONAL = 0, 1, 2  # a reference is a name list's entry, an option's parameter or a positional one
_INDEX = re.compile(r"\[[^\]]*\]")
_NONE_WORDS = frozenset(none for *_, nones in _POSITIONAL for none in nones)  # NO_COMPU_METHOD, NO_INPUT_QUANTITY ...


class Usage:
    """The references inside one MODULE, one row each in document order of their kind.

    Columns: ``tokens`` (the name's token), ``kinds`` (:data:`ENTRY`, :data:`OPTION`, :data:`POSITIONAL`),
    ``holders`` (the block the token stands in: the list block, the block of the option or parameter),
    ``owners`` (the MODULE's child that holds it), ``targets`` (the MODULE's child it names; -1: none);
    lists ``names``, ``namespaces`` and ``wheres`` (the list or option keyword, or ``KEYWORD#index``).
    ``defined`` maps (namespace, name) to the defining block of the MODULE's children (the first of a name defined
    twice), ``defined_once`` holds the blocks whose name no other block of their namespace has.
    """

    def __init__(self, doc: "A2lDocument", module: "Block", namespaces: frozenset[str] | None = None):
        self.doc, self.module = doc, module
        children = doc.blocks.children(module.index)
        self.children = children
        self.child_begins = doc.blocks.begin[children]
        self.child_ends = doc.blocks.end[children]
        names = doc.block_names(children)
        keywords = doc.blocks.keyword_names
        self.defined: dict[tuple[str, str], int] = {}
        twice: set[tuple[str, str]] = set()
        for block, name, number in zip(children.tolist(), names, doc.blocks.keyword_id[children].tolist()):
            namespace = grammar.NAMESPACES.get(keywords[number])
            if namespace is not None and name is not None:
                if self.defined.setdefault((namespace, name), block) != block:
                    twice.add((namespace, name))
        self.defined_once = {block for key, block in self.defined.items() if key not in twice}  # blocks
        self._components: dict[str, dict[str, str]] | None = None
        parts: list[tuple] = []  # (tokens, holders, kind, namespace, where)
        limits = doc.parameter_limits()
        for keyword, index, _, namespace, _ in (*_POSITIONAL, ("VAR_CHARACTERISTIC", 0, "", "object", ())):
            if namespaces is None or namespace in namespaces:
                blocks = self._inside(keyword)
                tokens = doc.blocks.begin[blocks] + 2 + index
                keep = tokens < limits[blocks]
                parts.append((tokens[keep], blocks[keep], POSITIONAL, namespace, f"{keyword}#{index}"))
        for keyword, option, namespace in (*_OPTIONS, ("FRAME", "FRAME_MEASUREMENT", "object")):
            if namespaces is None or namespace in namespaces:
                parts.extend(self._option(keyword, option, namespace))
        for keyword, namespace in _LISTS.items():
            if namespaces is None or namespace in namespaces:
                parts.append(self._entries(keyword, namespace, limits))
        parts = [part for part in parts if len(part[0])]
        self.tokens = np.concatenate([p[0] for p in parts]) if parts else np.zeros(0, np.int64)
        self.holders = np.concatenate([p[1] for p in parts]) if parts else np.zeros(0, np.int64)
        self.kinds = np.concatenate([np.full(len(p[0]), p[2]) for p in parts]) if parts else np.zeros(0, np.int64)
        self.namespaces: list[str] = [p[3] for p in parts for _ in range(len(p[0]))]
        self.wheres: list[str] = [p[4] for p in parts for _ in range(len(p[0]))]
        self.names: list[str] = doc.texts(self.tokens)
        slot = np.searchsorted(self.child_begins, self.tokens, side="right") - 1
        self.owners = children[np.maximum(slot, 0)] if len(children) else self.tokens * 0 - 1
        self.targets = np.array([self.resolve(namespace, name) for namespace, name in zip(self.namespaces, self.names)],
                                dtype=np.int64)

    def __len__(self) -> int:
        return len(self.tokens)

    def resolve(self, namespace: str, name: str) -> int:
        """The MODULE's block ``name`` names in ``namespace`` (-1: none, or a "none" word such as NO_COMPU_METHOD;
        -2: ``THIS.member`` inside a typedef, which names no block of its own)."""
        found = self.defined.get((namespace, name))
        if found is not None:
            return found
        if name in _NONE_WORDS:
            return -1
        if namespace == "object":
            if name.startswith("THIS."):
                return -2
            if "." in name or "[" in name:
                return self._instance_of(name)
        return -1

    def _instance_of(self, path: str) -> int:
        """The INSTANCE a component path ``inst.a[2].b`` lies in, when the path names a component (-1: not)."""
        first, *members = path.split(".")
        instance = self.defined.get(("object", _INDEX.sub("", first)))
        if instance is None or self.doc.blocks.keyword_of(instance) != "INSTANCE":
            return -1
        doc = self.doc
        if self._components is None:
            self._components = {}
            for namespace_name, block in self.defined.items():
                if namespace_name[0] == "typedef" and doc.blocks.keyword_of(block) == "TYPEDEF_STRUCTURE":
                    self._components[namespace_name[1]] = {
                        doc.text(component.args[0]): doc.text(component.args[1])
                        for component in doc.block(block).children_named("STRUCTURE_COMPONENT")
                        if len(component.args) > 1}
        typedef = doc.text(doc.block_begin[instance] + 4)
        for member in members:
            typedef = self._components.get(typedef, {}).get(_INDEX.sub("", member))
            if typedef is None:
                return -1
        return instance

    def _inside(self, keyword: str) -> np.ndarray:
        """The ``keyword`` blocks inside the MODULE."""
        doc, module = self.doc, self.module
        blocks = doc.blocks.having_keyword(keyword)
        return blocks[(blocks > module.index) & (doc.blocks.begin[blocks] < module.end_token)]

    def _option(self, keyword: str, option: str, namespace: str) -> list[tuple]:
        doc = self.doc
        owners, tokens = doc.option_occurrences(keyword, option)
        inside = (owners > self.module.index) & (doc.blocks.begin[np.maximum(owners, 0)] < self.module.end_token)
        owners, tokens = owners[inside], tokens[inside]
        if grammar.OPTIONS.get(option) != ("ident*",):
            keep = tokens + 1 < doc.blocks.end[owners]
            return [(tokens[keep] + 1, owners[keep], OPTION, namespace, option)]
        rows = [(owner, token) for owner, token in zip(owners.tolist(), tokens.tolist())
                for token in self._option_list(owner, token)]
        return [(np.array([r[1] for r in rows], np.int64), np.array([r[0] for r in rows], np.int64), OPTION,
                 namespace, option)]

    def _option_list(self, block: int, keyword_token: int) -> list[int]:
        """The names after an ``ident*`` option: up to the next keyword, child block or the block's end."""
        doc, found = self.doc, []
        token = keyword_token + 1
        while token < doc.block_end[block] and doc.raw(token)[:1] != b"/" and \
                doc.raw(token).decode("latin-1") not in grammar.OPTIONS:
            found.append(token)
            token += 1
        return found

    def _entries(self, keyword: str, namespace: str, limits: np.ndarray) -> tuple:
        """The entries of every ``keyword`` name list in the MODULE (VAR_CRITERION's stop at its options)."""
        doc = self.doc
        blocks = self._inside(keyword)
        spec = grammar.BLOCKS[keyword]
        if spec.options:  # entries, then options: read block by block (a rare block)
            rows = [(block, token) for block in blocks.tolist() for token in doc.block(block).args[len(spec.params):]]
            return (np.array([r[1] for r in rows], np.int64), np.array([r[0] for r in rows], np.int64), ENTRY,
                    namespace, keyword)
        firsts = doc.blocks.begin[blocks] + 2 + len(spec.params)
        counts = np.maximum(limits[blocks] - firsts, 0)
        holders = np.repeat(blocks, counts)
        tokens = np.repeat(firsts - np.cumsum(counts) + counts, counts) + np.arange(int(counts.sum()))
        return tokens, holders, ENTRY, namespace, keyword
