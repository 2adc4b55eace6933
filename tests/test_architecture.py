"""The library's structure stays as docs/architecture.md draws it (issue 31's rules).

Read from the source with ``ast`` (nothing is imported): no import cycle among
the modules of uniform2d and the surface layer, imports inside functions
included; no module takes another module's private names (the kernel's modules
among themselves aside); no module over 500 lines and no function over 80 lines
of code; and the surface layer builds on uniform2d, never the other way.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("uniform2d", "surface")
MAX_MODULE_LINES = 500
MAX_FUNCTION_CODE_LINES = 80


def _modules() -> dict[str, tuple[Path, bool]]:
    """name -> (path, is a package's __init__) of every module of the packages."""
    out = {}
    for path in sorted(p for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py")):
        parts = list(path.relative_to(ROOT).with_suffix("").parts)
        package = parts[-1] == "__init__"
        out[".".join(parts[:-1] if package else parts)] = (path, package)
    return out


MODULES = _modules()


def _owner(name: str) -> str:
    """The module that defines ``name`` (a module, or a name in one)."""
    while name not in MODULES and "." in name:
        name = name.rsplit(".", 1)[0]
    return name


def _imports(module: str):
    """(imported module, name taken or None, local name, line) of every import
    of the packages in ``module``, at any depth."""
    path, package = MODULES[module]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] in PACKAGES:
                    yield _owner(a.name), None, a.asname, node.lineno
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = module.split(".")[: None if package else -1]
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] not in PACKAGES:
                continue
            for a in node.names:
                full = f"{target}.{a.name}"
                if full in MODULES:
                    yield full, None, a.asname or a.name, node.lineno
                else:
                    yield _owner(target), a.name, a.asname or a.name, node.lineno


def _kernel(module: str) -> bool:
    return module.startswith("uniform2d._kernel")


def test_no_import_cycle():
    graph = {m: {t for t, _, _, _ in _imports(m) if t != m} for m in MODULES}
    state: dict[str, int] = {}  # 1: on the path, 2: done
    path: list[str] = []

    def visit(m):
        state[m] = 1
        path.append(m)
        for t in sorted(graph[m]):
            if state.get(t) == 1:
                cycle = path[path.index(t):] + [t]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if t not in state:
                visit(t)
        path.pop()
        state[m] = 2

    for m in sorted(MODULES):
        if m not in state:
            visit(m)


def test_no_private_name_taken_from_another_module():
    taken = []
    for m, (path, _) in MODULES.items():
        aliases = {}  # local name -> imported module
        for t, name, local, line in _imports(m):
            if name is None:
                if local:
                    aliases[local] = t
            elif name.startswith("_") and not name.startswith("__") and t != m \
                    and not (_kernel(m) and _kernel(t)):
                taken.append(f"{m}:{line} takes {name} from {t}")
        for node in ast.walk(ast.parse(path.read_text())):  # module._private
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id in aliases and node.attr.startswith("_")
                    and not node.attr.startswith("__")):
                t = aliases[node.value.id]
                if t != m and not (_kernel(m) and _kernel(t)):
                    taken.append(f"{m}:{node.lineno} uses {t}.{node.attr}")
    assert not taken, "\n".join(taken)


def test_no_module_over_500_lines():
    big = {m: n for m, (p, _) in MODULES.items()
           if (n := len(p.read_text().splitlines())) > MAX_MODULE_LINES}
    assert not big, big


def _code_lines(lines: list[str], node) -> int:
    body = node.body
    doc = set()
    if isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
            and isinstance(body[0].value.value, str):
        doc = set(range(body[0].lineno, body[0].end_lineno + 1))
    return sum(1 for k in range(node.lineno, node.end_lineno + 1)
               if k not in doc and lines[k - 1].strip() and not lines[k - 1].strip().startswith("#"))


def test_no_function_over_80_lines_of_code():
    long = []
    for m, (path, _) in MODULES.items():
        text = path.read_text()
        lines = text.splitlines()
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = _code_lines(lines, node)
                if n > MAX_FUNCTION_CODE_LINES:
                    long.append(f"{m}.{node.name}: {n}")
    assert not long, long


def test_surface_builds_on_uniform2d_never_back():
    back = [f"{m}:{line} imports {t}" for m in MODULES if m.split(".")[0] == "uniform2d"
            for t, _, _, line in _imports(m) if t.split(".")[0] == "surface"]
    assert not back
