"""``check`` of a MODULE's typedef structures (ASAP2 1.7), each finding located.

Errors in the file: a STRUCTURE_COMPONENT that reaches beyond its TYPEDEF_STRUCTURE's size (its offset, plus its
size where the typedef tells it), a structure that contains itself (directly or through others), a component name
given twice in one structure. A typedef that does not exist is a reference finding (:mod:`workbench.a2l.references`).
What the workbench does not support (a pointer, ADDRESS_TYPE) is an info finding, not a failed check: its objects
are left out, the rest works.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.errors import A2lParseError
from workbench.findings import Finding, Report, Severity

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument, Block
    from workbench.a2l.objects import StructureComponent, TypedefStructure

__all__ = ["check_structures"]


def check_structures(doc: A2lDocument, module: Block, report: Report) -> None:
    """Add the findings of ``module``'s TYPEDEF_STRUCTUREs and INSTANCEs to ``report``."""
    from workbench.a2l.instances import component_beyond
    from workbench.a2l.model import A2lModel

    if not {"TYPEDEF_STRUCTURE", "INSTANCE"} & set(doc.blocks.keyword_names):
        return  # nothing to check: no model built (a large file without typedefs)
    model = A2lModel(doc, module.name)
    names = model.names("TYPEDEF_STRUCTURE")
    if not names and not model.names("INSTANCE"):
        return
    sizes = model.typedef_sizes()
    structures = {}
    for name in dict.fromkeys(names):
        try:
            structures[name] = model.typedef(name)
        except A2lParseError:
            continue  # a malformed block: a syntax finding already
    for structure in structures.values():
        seen: set[str] = set()
        for component in structure.components:
            label = f"TYPEDEF_STRUCTURE {structure.name}: STRUCTURE_COMPONENT {component.name}"
            if component.name in seen:
                _add(report, doc, component, "duplicate-component", structure.name,
                     f"{label} is defined twice in the structure", None)
            seen.add(component.name)
            inside = component.typedef in structures and _cycle(structures, component.typedef, structure.name)
            beyond = None if inside else component_beyond(structure, component, sizes)  # a loop: said once below
            if beyond:
                _add(report, doc, component, "component-beyond-structure", structure.name, f"{label}: {beyond}",
                     "offset")
        cycle = _cycle(structures, structure.name, structure.name)
        if cycle and min(cycle) == structure.name:  # each loop once, at its first structure by name
            component = next(c for c in structure.components if c.typedef == cycle[1] and c.address_type in (None,
                                                                                                             "DIRECT"))
            _add(report, doc, component, "recursive-structure", structure.name, f"TYPEDEF_STRUCTURE {structure.name} "
                 f"contains itself: {' -> '.join(cycle)} (STRUCTURE_COMPONENT {component.name})", "typedef")
    for limit in model.instance_limits():
        report.add(Finding("not-supported", limit.instance, limit.reason, limit.path, limit.line, limit.column,
                           "INSTANCE", Severity.INFO))


def _cycle(structures: dict[str, TypedefStructure], start: str, target: str) -> list[str] | None:
    """The chain of structures from ``start`` through components back to ``target``, or None (a pointer to a
    structure, ADDRESS_TYPE, does not contain it: a linked list's ``next``)."""
    stack = [(start, [start])]
    visited: set[str] = set()
    while stack:
        name, chain = stack.pop()
        for component in structures[name].components:
            if component.address_type not in (None, "DIRECT"):
                continue
            if component.typedef == target:
                return chain + [target]
            if component.typedef in structures and component.typedef not in visited:
                visited.add(component.typedef)
                stack.append((component.typedef, chain + [component.typedef]))
    return None


def _add(report: Report, doc: A2lDocument, component: StructureComponent, kind: str, name: str, message: str,
         field: str | None) -> None:
    token = (component.ref_tokens or {}).get(field) if field else None
    file, line, column = doc.token_position(token) if token is not None else (component.location or ("", 0, 0))
    report.add(Finding(kind, name, message, file, line, column, "STRUCTURE_COMPONENT", Severity.ERROR))

