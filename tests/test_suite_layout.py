"""Every test module imports the same way whichever directories run together (``pytest tests/xcp tests/session``).

pytest imports each directory's conftest.py under the one name ``conftest`` and puts each test's directory on
sys.path, so ``from conftest import X`` finds whichever conftest came last, and a helper of another directory is
found only when that directory happens to be collected too. Helpers are modules with names of their own: beside
the tests of one directory, or in tests/ itself (pyproject's ``pythonpath``) when several directories use them.
"""

from __future__ import annotations

import ast
from pathlib import Path

TESTS = Path(__file__).parent
MODULES = sorted(TESTS.rglob("*.py"))


def _imported_names(path: Path) -> set[str]:
    """The top-level module names that ``path`` imports absolutely, anywhere in it."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            names.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
    return names


def _helpers() -> dict[str, Path]:
    """Each helper module's name and its directory (every module but the conftests and the tests)."""
    return {path.stem: path.parent for path in MODULES
            if path.stem != "conftest" and not path.stem.startswith("test_")}


def test_no_test_imports_a_conftest():
    importers = [str(path.relative_to(TESTS)) for path in MODULES if "conftest" in _imported_names(path)]
    assert not importers, f"import from a helper module, not from conftest: {importers}"


def test_every_module_of_the_suite_has_a_name_of_its_own():
    seen: dict[str, Path] = {}
    twins = []
    for path in MODULES:
        if path.stem != "conftest" and (other := seen.setdefault(path.stem, path)) != path:
            twins.append(f"{other.relative_to(TESTS)} and {path.relative_to(TESTS)}")
    assert not twins, f"one of each pair shadows the other on sys.path: {twins}"


def test_a_helper_of_several_directories_lives_in_tests():
    helpers = _helpers()
    misplaced = [f"{path.relative_to(TESTS)} imports {name} from {helpers[name].relative_to(TESTS)}/"
                 for path in MODULES for name in _imported_names(path)
                 if name in helpers and helpers[name] not in (path.parent, TESTS)]
    assert not misplaced, f"move these helpers to tests/: {misplaced}"
