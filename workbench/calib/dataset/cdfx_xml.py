"""The XML side of CDFX files: parsing with positions, names without namespaces, text content.

CDF 2.0 files come with or without an XML namespace, with a DOCTYPE naming the ASAM DTD (never
loaded: no file or network access while reading), with XML comments anywhere.
"""

from __future__ import annotations

from collections.abc import Iterator

from lxml import etree

from workbench.errors import DatasetParseError

__all__ = ["DOCTYPE", "DOCTYPE_21", "children", "comments_in", "content", "file_comments", "local_name", "parse"]

DOCTYPE = ('<!DOCTYPE MSRSW PUBLIC "-//ASAM//DTD CALIBRATION DATA FORMAT:V2.0.0:LAI:IAI:XML:CDF200.XSD//EN" '
           '"cdf_v2.0.0.sl.dtd">')
DOCTYPE_21 = '<!DOCTYPE MSRSW PUBLIC "-//ASAM//DTD CALIBRATION DATA FORMAT:V2.1:LAI:IAI:XML //EN" "cdf_v2.1.0.sl.dtd">'


def parse(data: bytes, path: str) -> etree._Element:
    """The root element of ``data``; no DTD is loaded, no declared entity resolved.

    :raises DatasetParseError: not well-formed XML, located at its line and column; a reference to
        a declared entity (its text would be missing).
    """
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, remove_comments=False,
                             huge_tree=False)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:
        line, column = exc.position if exc.position else (0, 0)
        raise DatasetParseError(f"not well-formed XML: {exc.msg}", path, line or 1, column) from None
    for entity in root.iter(etree.Entity):
        raise DatasetParseError(f"the entity reference {entity.text} is not resolved (declared entities are not "
                                f"supported; use the character itself or &#...;)", path, entity.sourceline or 0)
    return root


def local_name(element) -> str | None:
    """The element's name without namespace; None for comments and processing instructions."""
    if not isinstance(element.tag, str):
        return None
    return etree.QName(element).localname


def children(element) -> Iterator[tuple[str, etree._Element]]:
    """The child elements as (local name, element), comments and processing instructions left out."""
    for child in element:
        name = local_name(child)
        if name is not None:
            yield name, child


def comments_in(element) -> list[str]:
    """The lines of the XML comments below ``element`` (an SW-INSTANCE), in document order, stripped;
    those inside an SW-INSTANCE nested in it belong to that one."""
    return [line for node in element.iter(etree.Comment) if _instance_of(node) is element for line in _lines(node)]


def _instance_of(node):
    return next((a for a in node.iterancestors() if local_name(a) == "SW-INSTANCE"), None)


def file_comments(root) -> list[str]:
    """The comment lines of the document outside every SW-INSTANCE (those belong to their instance)."""
    lines: list[str] = []
    nodes = [*reversed(list(root.itersiblings(preceding=True))), *root.iter(etree.Comment), *root.itersiblings()]
    for node in nodes:
        if isinstance(node, etree._Comment) and not any(local_name(a) == "SW-INSTANCE" for a in node.iterancestors()):
            lines += _lines(node)
    return lines


def _lines(comment) -> list[str]:
    return [line.strip() for line in (comment.text or "").strip().splitlines()] or [""]


def content(element) -> str:
    """The text of ``element`` and its descendants, without the text of comments inside it."""
    parts = [element.text or ""]
    for child in element:
        if local_name(child) is not None:
            parts.append(content(child))
        parts.append(child.tail or "")
    return "".join(parts)
