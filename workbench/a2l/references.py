"""References between the blocks of a MODULE: every name a block uses must be defined there.

The tables say where names are used: a positional parameter (a MEASUREMENT's COMPU_METHOD, a
TYPEDEF_CHARACTERISTIC's RECORD_LAYOUT, an INSTANCE's typedef ...), an option's parameters
(AXIS_PTS_REF, OVERWRITE CONVERSION ...) or the entries of a name list (REF_MEASUREMENT ...).
An object may also be named as a component of an INSTANCE (``inst.member``, ``inst[2].member``,
as in ASAM MCD-2 MC 1.7), and inside a typedef as ``THIS.member``: a component of every
TYPEDEF_STRUCTURE that uses the typedef.
"""

from __future__ import annotations

import re

from workbench.a2l import grammar
from workbench.a2l.document import A2lDocument, Block
from workbench.a2l.reports import finding_at
from workbench.findings import Report, Severity

__all__ = ["check_references"]

Names = dict[str, dict[str, Block]]  # namespace -> name -> defining block

# (block, positional index (name = 0), what it names, namespace it refers to, values that mean "none")
_POSITIONAL = [
    ("MEASUREMENT", 3, "COMPU_METHOD", "compu method", ("NO_COMPU_METHOD",)),
    ("CHARACTERISTIC", 4, "RECORD_LAYOUT", "record layout", ()),
    ("CHARACTERISTIC", 6, "COMPU_METHOD", "compu method", ("NO_COMPU_METHOD",)),
    ("AXIS_PTS", 3, "input quantity", "object", ("NO_INPUT_QUANTITY",)),
    ("AXIS_PTS", 4, "RECORD_LAYOUT", "record layout", ()),
    ("AXIS_PTS", 6, "COMPU_METHOD", "compu method", ("NO_COMPU_METHOD",)),
    ("AXIS_DESCR", 1, "input quantity", "object", ("NO_INPUT_QUANTITY",)),
    ("AXIS_DESCR", 2, "COMPU_METHOD", "compu method", ("NO_COMPU_METHOD",)),
    ("INSTANCE", 2, "typedef", "typedef", ()),
    ("TYPEDEF_MEASUREMENT", 3, "COMPU_METHOD", "compu method", ("NO_COMPU_METHOD",)),
    ("TYPEDEF_CHARACTERISTIC", 3, "RECORD_LAYOUT", "record layout", ()),
    ("TYPEDEF_CHARACTERISTIC", 5, "COMPU_METHOD", "compu method", ("NO_COMPU_METHOD",)),
    ("TYPEDEF_AXIS", 2, "input quantity", "object", ("NO_INPUT_QUANTITY",)),
    ("TYPEDEF_AXIS", 3, "RECORD_LAYOUT", "record layout", ()),
    ("TYPEDEF_AXIS", 5, "COMPU_METHOD", "compu method", ("NO_COMPU_METHOD",)),
    ("STRUCTURE_COMPONENT", 1, "typedef", "typedef", ()),
    ("TRANSFORMER", 6, "inverse TRANSFORMER", "transformer", ("NO_INVERSE_TRANSFORMER",)),
]
# (block, option keyword, namespace): each parameter of the option names one
_OPTIONS = [
    ("AXIS_DESCR", "AXIS_PTS_REF", "object"), ("AXIS_DESCR", "CURVE_AXIS_REF", "object"),
    ("COMPU_METHOD", "COMPU_TAB_REF", "conversion table"), ("COMPU_METHOD", "REF_UNIT", "unit"),
    ("COMPU_METHOD", "STATUS_STRING_REF", "conversion table"), ("UNIT", "REF_UNIT", "unit"),
    ("CHARACTERISTIC", "COMPARISON_QUANTITY", "object"),
    ("OVERWRITE", "CONVERSION", "compu method"), ("OVERWRITE", "INPUT_QUANTITY", "object"),
    ("MOD_COMMON", "S_REC_LAYOUT", "record layout"), ("FRAME", "FRAME_MEASUREMENT", "object"),
    ("VAR_CRITERION", "VAR_MEASUREMENT", "object"), ("VAR_CRITERION", "VAR_SELECTION_CHARACTERISTIC", "object"),
    *((block, "REF_MEMORY_SEGMENT", "memory segment") for block in ("MEASUREMENT", "CHARACTERISTIC", "AXIS_PTS")),
]
# name-list block -> namespace of its entries (those after the block's positional parameters)
_LISTS = {
    "DEF_CHARACTERISTIC": "object", "REF_CHARACTERISTIC": "object", "IN_MEASUREMENT": "object",
    "OUT_MEASUREMENT": "object", "LOC_MEASUREMENT": "object", "REF_MEASUREMENT": "object",
    "SUB_FUNCTION": "function", "FUNCTION_LIST": "function", "SUB_GROUP": "group", "MAP_LIST": "object",
    "VIRTUAL": "object", "REF_GROUP": "group", "DEPENDENT_CHARACTERISTIC": "object",
    "VIRTUAL_CHARACTERISTIC": "object", "TRANSFORMER_IN_OBJECTS": "object", "TRANSFORMER_OUT_OBJECTS": "object",
}
_INDEX = re.compile(r"\[[^\]]*\]")


def check_references(doc: A2lDocument, module: Block, names: Names, report: Report) -> None:
    """Add an "undefined-reference" error for every name used in ``module`` that ``names`` (the
    module's definitions by namespace) does not define, located at the token that uses it."""
    Resolver(doc, module, names).check(report)


class Resolver:
    """Which names a MODULE defines, including the components of its INSTANCEs."""

    def __init__(self, doc: A2lDocument, module: Block, names: Names):
        self.doc = doc
        self.module = module
        self.names = names
        typedefs = names.get("typedef", {})
        # TYPEDEF_STRUCTURE -> component name -> the component's typedef
        self.components: dict[str, dict[str, str]] = {}
        self.users: dict[str, list[str]] = {}  # typedef -> the structures that have a component of it
        for name, block in typedefs.items():
            if block.keyword != "TYPEDEF_STRUCTURE":
                continue
            members = self.components[name] = {}
            for component in block.children_named("STRUCTURE_COMPONENT"):
                args = component.args
                if len(args) > 1:
                    members[doc.text(args[0])] = doc.text(args[1])
                    self.users.setdefault(doc.text(args[1]), []).append(name)

    def check(self, report: Report) -> None:
        for keyword, index, what, namespace, none in _POSITIONAL:
            for block in self._blocks(keyword):
                args = block.args
                if index < len(args):
                    self._expect(report, args[index], namespace, block, what, none)
        for keyword, option, namespace in _OPTIONS:
            for block in self._blocks(keyword):
                for params in block.options(option):
                    for token in params:
                        self._expect(report, token, namespace, block, option)
        for keyword, namespace in _LISTS.items():
            skip = len(grammar.BLOCKS[keyword].params)
            for block in self._blocks(keyword):
                owner = block.parent or block
                for token in block.args[skip:]:
                    self._expect(report, token, namespace, owner, f"{keyword} entry")

    def _blocks(self, keyword: str) -> list[Block]:
        """The ``keyword`` blocks inside this module (blocks are numbered in document order)."""
        doc, module = self.doc, self.module
        indices = doc.blocks.having_keyword(keyword)
        inside = (indices > module.index) & (doc.blocks.begin[indices] < module.end_token)
        return [Block(doc, index) for index in indices[inside].tolist()]

    def _expect(self, report: Report, token: int, namespace: str, owner: Block, what: str,
                none: tuple[str, ...] = ()) -> None:
        target = self.doc.text(token)
        if target in none or target in self.names.get(namespace, {}):
            return
        problem = "is not defined"
        if namespace == "object":
            if target.startswith("THIS."):
                problem = self._this_problem(target[len("THIS."):], owner)
            elif self.component_typedef(target) is not None:
                return
            if problem is None:
                return
        elif namespace == "typedef":
            from workbench.a2l.model import closest_names

            close = closest_names(target, self.names.get(namespace, {}))
            problem += f" (did you mean {', '.join(close)}?)" if close else ""
        report.add(finding_at(self.doc, token, "undefined-reference", target,
                              f"{_label(owner)}: {what} {target} {problem}", owner.keyword, Severity.ERROR))

    def component_typedef(self, path: str) -> str | None:
        """The typedef of ``path`` when it names an INSTANCE or a component of one (``inst.a.b``,
        array indices allowed), else None."""
        first, *members = path.split(".")
        instance = self.names.get("object", {}).get(_INDEX.sub("", first))
        if instance is None or instance.keyword != "INSTANCE" or len(instance.args) < 3:
            return None
        typedef = self.doc.text(instance.args[2])
        for member in members:
            typedef = self.components.get(typedef, {}).get(_INDEX.sub("", member))
            if typedef is None:
                return None
        return typedef

    def _this_problem(self, member: str, owner: Block) -> str | None:
        """Why ``THIS.member`` used in ``owner`` does not resolve (None: it does): every structure
        using the enclosing typedef must have the component."""
        typedef = _enclosing_typedef(owner)
        if typedef is None:
            return "is not inside a typedef (THIS names a component of the enclosing structure)"
        structures = self.users.get(typedef, [])
        if not structures:
            return f"cannot resolve: no TYPEDEF_STRUCTURE has a component of type {typedef}"
        lacking = [name for name in structures if _INDEX.sub("", member) not in self.components[name]]
        if lacking:
            return f"is not a component of TYPEDEF_STRUCTURE {', '.join(lacking)}"
        return None


def _enclosing_typedef(block: Block) -> str | None:
    found: Block | None = block
    while found is not None and not found.keyword.startswith("TYPEDEF_"):
        found = found.parent
    return found.name if found is not None else None


def _label(block: Block) -> str:
    """``KEYWORD name`` of a block; an unnamed one (AXIS_DESCR) is named after its parent."""
    if block.name:
        return f"{block.keyword} {block.name}"
    parent = block.parent
    if parent is not None and parent.name:
        return f"{parent.keyword} {parent.name} {block.keyword}"
    return block.keyword

