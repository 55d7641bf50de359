"""Well-formed A2L text for any block of the keyword table, built from the table itself, so a test can
cover every block and every option (and stays right when the table grows)."""

from __future__ import annotations

from collections import deque

from workbench.a2l import grammar

HEAD = 'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n'
TAIL = "  /end MODULE\n/end PROJECT\n"
_PLAIN = {"ident": "a_name", "str": '"text"', "int": "3", "float": "0.5", "int*": "2 3", "ident*": "m_one m_two"}


def sample(kind: str) -> str:
    """A valid parameter of ``kind`` (an enumeration: its first word)."""
    enumeration = grammar.ENUMS.get(kind)
    return enumeration.words[0] if enumeration is not None else _PLAIN[kind]


def parameters(keyword: str, replace: dict[int, str] | None = None) -> list[str]:
    """The positional parameters of block ``keyword`` (with one repeated group and one list item),
    ``replace`` putting other text at some indices."""
    spec = grammar.BLOCKS[keyword]
    words = [sample(kind) for kind in spec.params]
    if spec.repeat:
        words[-1] = "1"
        words += [sample(kind) for kind in spec.repeat]
    if spec.items:
        words.append(sample(spec.items))
    for index, text in (replace or {}).items():
        words[index] = text
    return words


def option_text(option: str, replace: dict[int, str] | None = None) -> str:
    words = [sample(kind) for kind in grammar.OPTIONS[option]]
    for index, text in (replace or {}).items():
        words[index] = text
    return " ".join([option, *words])


def block_text(keyword: str, inner: list[str] = (), replace: dict[int, str] | None = None) -> str:
    """``/begin KEYWORD parameters inner... /end KEYWORD`` on one line."""
    return " ".join(["/begin", keyword, *parameters(keyword, replace), *inner, "/end", keyword])


def path_to(keyword: str) -> list[str]:
    """The blocks from MODULE down to (not including) ``keyword``, the shortest way the table allows."""
    queue = deque([["MODULE"]])
    seen = {"MODULE"}
    while queue:
        path = queue.popleft()
        spec = grammar.BLOCKS[path[-1]]
        if keyword in spec.blocks:
            return path
        for child in sorted(spec.blocks - seen):
            if not grammar.BLOCKS[child].free:
                seen.add(child)
                queue.append(path + [child])
    raise LookupError(f"{keyword} cannot be reached from MODULE")


def document(keyword: str, text: str) -> str:
    """A whole file with ``text`` (a ``keyword`` block) on line 5, inside the blocks it must stand in."""
    for outer in reversed(path_to(keyword)[1:]):
        text = block_text(outer, [text])
    return HEAD + "\n" + text + "\n" + TAIL


def child_of(keyword: str) -> str | None:
    """A well-formed child block for ``keyword`` (IF_DATA where it may stand), None when it has none."""
    spec = grammar.BLOCKS[keyword]
    if "IF_DATA" in spec.blocks:
        return "/begin IF_DATA XCP LINK 1 /end IF_DATA"
    for child in sorted(spec.blocks):
        if not grammar.BLOCKS[child].free:
            return block_text(child)
    return None


def reachable_blocks() -> list[str]:
    """Every block keyword a MODULE can contain (directly or deeper), not free-form ones."""
    found = []
    for keyword, spec in sorted(grammar.BLOCKS.items()):
        if spec.free or keyword in ("PROJECT", "MODULE", "HEADER"):
            continue
        try:
            path_to(keyword)
        except LookupError:
            continue
        found.append(keyword)
    return found


def in_block(keyword: str, message: str) -> str:
    """``message`` as the grammar check gives it for a ``keyword`` block of :func:`block_text`: a block with a
    name says which object it is (``MEASUREMENT a_name: ...``, its keyword's own ``MEASUREMENT: `` dropped)."""
    if grammar.BLOCKS[keyword].params[:1] != ("ident",):
        return message
    return f"{keyword} {sample('ident')}: {message.removeprefix(keyword + ': ')}"

