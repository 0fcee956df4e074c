"""The project's import graph, read from the source (every import, at module top or inside
a function): no circle, and the libraries (ccedi's core modules, fea, rom, design,
calibrate) never import the application layer (study)."""
import ast
from functools import lru_cache

import pytest
from conftest import ROOT

TOP = {"ccedi": ROOT / "ccedi", "ccedi.fea": ROOT / "fea", "ccedi.rom": ROOT / "rom", "ccedi.design": ROOT / "design",
       "ccedi.calibrate": ROOT / "calibrate", "ccedi.study": ROOT / "study"}
PACKAGES = {f"{name}{'.' if rel.parts else ''}{'.'.join(rel.parts)}": folder / rel
            for name, folder in TOP.items()
            for rel in [init.parent.relative_to(folder) for init in folder.rglob("__init__.py")]}
"""Every package of the project, its sub-packages (fea.elements, study.commands, ...) included."""
APPLICATION = "ccedi.study"
ENTRY_POINTS = {"ccedi.__main__"}
"""``python -m ccedi`` runs the command line: the one core module that may import it."""


def _modules():
    """{module name: source path} of every project module."""
    return {(package if path.stem == "__init__" else f"{package}.{path.stem}"): path
            for package, folder in PACKAGES.items() for path in folder.glob("*.py")}


def _targets(module, path, modules):
    """The project modules ``module`` imports anywhere in its source."""
    package = module if path.stem == "__init__" else module.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[:len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([node.module] if node.module else []))
            names = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base for alias in node.names]
        else:
            continue
        for name in names:
            while name and name not in modules:
                name = name.rsplit(".", 1)[0] if "." in name else ""
            if name and name != module:
                found.add(name)
    return found


@lru_cache(maxsize=1)
def import_graph():
    """{module: set of project modules it imports}."""
    modules = _modules()
    return {module: _targets(module, path, modules) for module, path in modules.items()}


def circles(graph):
    """The strongly connected components of more than one module (Tarjan's algorithm,
    iterative), each sorted."""
    index, low, stack, on_stack, found, counter = {}, {}, [], set(), [], [0]

    def visit(root):
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = counter[0]
                    counter[0] += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))

    for module in sorted(graph):
        if module not in index:
            visit(module)
    return found


def test_no_import_circle():
    assert circles(import_graph()) == []


def test_the_circle_finder_finds_circles():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": {"e2"}, "e2": set()}
    assert circles(graph) == [["a", "b", "c"]]
    assert circles({"x": {"y"}, "y": {"x"}, "z": set()}) == [["x", "y"]]


@pytest.mark.parametrize("module", sorted(m for m in _modules() if not m.startswith(APPLICATION)))
def test_libraries_do_not_import_the_application(module):
    if module in ENTRY_POINTS:
        return
    upward = sorted(t for t in import_graph()[module] if t.startswith(APPLICATION))
    assert upward == [], f"{module} imports the application layer: {upward}"


PLOT_WRITERS = {"ccedi.outputs"}
"""Library modules allowed to load matplotlib: the writer of a PDF from PNG pages."""


def _imports_matplotlib(path):
    for node in ast.walk(ast.parse(path.read_text())):
        names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                 else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
        if any(name.split(".")[0] == "matplotlib" for name in names):
            return True
    return False


def test_only_the_application_draws():
    """Plotting belongs to the application (study): the libraries return numbers, and no
    library module imports matplotlib (but the PDF writer of ccedi.outputs)."""
    drawing = sorted(m for m, path in _modules().items()
                     if not m.startswith(APPLICATION) and m not in PLOT_WRITERS and _imports_matplotlib(path))
    assert drawing == [], f"library modules that draw: {drawing}"
    assert _imports_matplotlib(_modules()["ccedi.study.figures"])             # the check sees an import


def test_core_modules_import_no_subpackage():
    """ccedi's shared modules (errors, units, quantities, progress, models) sit under the
    libraries: none imports fea, rom, design, calibrate or study."""
    graph = import_graph()
    core = [m for m in graph if m.count(".") == 1 and m.split(".")[1] in {p.stem for p in PACKAGES["ccedi"].glob("*.py")}]
    for module in core:
        if module in ENTRY_POINTS:
            continue
        assert not [t for t in graph[module] if t.split(".")[1] not in {p.stem for p in PACKAGES["ccedi"].glob("*.py")}], module


def test_the_graph_sees_relative_absolute_and_in_function_imports():
    graph = import_graph()
    assert "ccedi.fea.model" in graph["ccedi.fea.solvers.explicit"]                  # from .model import Model
    assert "ccedi.units" in graph["ccedi.quantities"] and "ccedi.units" in graph["ccedi.fea.mesh"]
    assert "ccedi.fea.elements.hex8" in graph["ccedi.fea.model"]                # a sub-package's module
    assert "ccedi.study.config" in graph["ccedi.study.commands.arguments"]    # imported inside load_config


MODULE_REASON = "# Imports inside functions:"
"""A module whose functions import lazily says why once, in a comment line starting so."""


def deferred_imports_without_a_reason(path):
    """The in-function imports of ``path`` (as ``line: text``) that give no reason: no
    comment on the import's first line or on the line above, and no module-level
    :data:`MODULE_REASON` comment."""
    text = path.read_text()
    if any(line.startswith(MODULE_REASON) for line in text.splitlines()):
        return []
    lines = text.splitlines()
    found = []
    for function in ast.walk(ast.parse(text)):
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        for node in ast.walk(function):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                line, above = lines[node.lineno - 1], lines[node.lineno - 2].strip()
                if "#" not in line and not above.startswith("#"):
                    found.append(f"{node.lineno}: {line.strip()}")
    return found


@pytest.mark.parametrize("module", sorted(_modules()))
def test_an_import_inside_a_function_says_why(module):
    """Imports sit at the module top, which shows the graph; one inside a function (a heavy
    library loaded only when needed, a command line that must start fast) says why."""
    assert deferred_imports_without_a_reason(_modules()[module]) == []


def test_the_reason_check_can_fail(tmp_path):
    source = tmp_path / "m.py"
    source.write_text("def f():\n    import json\n    return json\n\n\ndef g():\n    import csv  # why\n    return csv\n")
    assert deferred_imports_without_a_reason(source) == ["2: import json"]
    source.write_text(f"{MODULE_REASON} a reason\n" + source.read_text())
    assert deferred_imports_without_a_reason(source) == []
