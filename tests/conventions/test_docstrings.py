"""Documentation conventions of the ccedi libraries, enforced.

In the spirit of python-control's ``control/tests/docstrings_test.py``: every module
of :mod:`ccedi.fea`, :mod:`ccedi.rom`, :mod:`ccedi.design`, :mod:`ccedi.calibrate` and the
shared :mod:`ccedi.errors` (and :mod:`ccedi.models` when it exists) is walked, and for
every public function, class and public method *defined in that module* (names not
starting with ``_``; imported names are skipped) the docstring is checked against the
code:

* a docstring exists;
* a numpydoc ``Parameters`` (or ``Other Parameters``) section lists every argument of
  the signature (``self``/``cls`` excepted; ``*args``/``**kwargs`` under those names) and
  no argument that the signature lacks;
* a function that returns a value (a ``return <expr>`` other than ``return None``) has a
  ``Returns`` or ``Yields`` section, a generator a ``Yields`` or ``Returns`` section;
* a function whose own body raises ``InputError``, ``SolverError`` or ``ValueError``
  has a ``Raises`` section naming each of them;
* a dataclass (or named tuple) documents each of its fields under ``Parameters`` or
  ``Attributes`` of the class docstring, and lists no unknown field under
  ``Parameters``; a plain class with its own ``__init__`` documents the ``__init__``
  arguments in the class (or ``__init__``) docstring;
* properties need a docstring only.

No docstring or comment may cite an issue tracker (``issue 12``, ``PR #3``, ``gh-7``):
the code has to explain itself.

There is one test per module, so a module that does not yet follow the conventions
fails on its own and lists *all* its offenders (``module:name: missing parameter x``)
in one message. ``python tests/conventions/test_docstrings.py`` prints the offender count
of each module.
"""
import ast
import dataclasses
import importlib
import importlib.util
import inspect
import io
import pkgutil
import re
import sys
import textwrap
import tokenize

import pytest

LIBRARIES = ("ccedi.fea", "ccedi.rom", "ccedi.design", "ccedi.calibrate")
SHARED = ("ccedi.errors", "ccedi.models", "ccedi.outputs", "ccedi.distributed", "ccedi.units")
CHECKED_EXCEPTIONS = ("InputError", "SolverError", "ValueError")
ISSUE_CITATION = re.compile(
    r"\b(?:issues?|tickets?|bugs?)\s*(?:no\.?\s*|number\s*)?#?\s*\d+"
    r"|\bPR\s*#?\s*\d+|\bgh-\d+|\bgithub\.com/\S+/(?:issues|pull)/\d+",
    re.IGNORECASE)
SECTION_UNDERLINE = re.compile(r"^\s*-{3,}\s*$")


def library_modules():
    """Names of every module to check: the libraries' modules (the packages' own
    ``__init__`` included) and the shared modules that exist."""
    names = []
    for package in LIBRARIES:
        pkg = importlib.import_module(package)
        names.append(package)
        for info in pkgutil.walk_packages(pkg.__path__, prefix=package + "."):
            names.append(info.name)
    for name in SHARED:
        if importlib.util.find_spec(name) is not None:
            names.append(name)
    return sorted(set(names))


# --- a small numpydoc section parser --------------------------------------------------

def numpydoc_sections(doc):
    """Map section title -> list of lines (dedented to the section's own indentation)."""
    lines = inspect.cleandoc(doc or "").splitlines()
    sections, title = {"": []}, ""
    i = 0
    while i < len(lines):
        line = lines[i]
        if (line.strip() and i + 1 < len(lines) and SECTION_UNDERLINE.match(lines[i + 1])
                and len(lines[i + 1].strip()) >= min(3, len(line.strip()))):
            title = line.strip()
            sections[title] = []
            i += 2
            continue
        sections[title].append(line)
        i += 1
    return {k: textwrap.dedent("\n".join(v)).splitlines() for k, v in sections.items()}


def section_entries(lines):
    """Names of the entries of a Parameters-like section: the unindented lines
    ``name : type`` (or ``name``), several names separated by commas."""
    names = []
    for line in lines:
        if not line.strip() or line[0].isspace():
            continue
        head = line.split(" :", 1)[0] if " :" in line else line.split(":", 1)[0]
        for name in head.split(","):
            name = name.strip().replace("\\", "").strip("`")
            if name:
                names.append(name)
    return names


def documented_parameters(doc):
    """Names listed under ``Parameters`` and ``Other Parameters``."""
    sections = numpydoc_sections(doc)
    return (section_entries(sections.get("Parameters", []))
            + section_entries(sections.get("Other Parameters", [])))


# --- what the code does ----------------------------------------------------------------

def _own_nodes(func_node):
    """AST nodes of a function's own body, not descending into nested defs/lambdas/classes."""
    nested = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)
    stack = [n for n in func_node.body if not isinstance(n, nested)]
    while stack:
        node = stack.pop()
        yield node
        for child in ast.iter_child_nodes(node):
            if not isinstance(child, nested):
                stack.append(child)


def body_facts(func):
    """(returns a value, is a generator, set of checked exceptions raised directly)."""
    try:
        source = textwrap.dedent(inspect.getsource(func))
        tree = ast.parse(source)
    except (OSError, TypeError, SyntaxError):
        return False, False, set()
    node = next(n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)))
    returns, generator, raised = False, False, set()
    for n in _own_nodes(node):
        if isinstance(n, ast.Return) and n.value is not None and not (
                isinstance(n.value, ast.Constant) and n.value.value is None):
            returns = True
        elif isinstance(n, (ast.Yield, ast.YieldFrom)):
            generator = True
        elif isinstance(n, ast.Raise) and n.exc is not None:
            exc = n.exc.func if isinstance(n.exc, ast.Call) else n.exc
            name = exc.attr if isinstance(exc, ast.Attribute) else getattr(exc, "id", None)
            if name in CHECKED_EXCEPTIONS:
                raised.add(name)
    return returns, generator, raised


def signature_names(func, drop_first=False):
    """Documentable argument names: ``*args``/``**kwargs`` keep their stars."""
    try:
        params = list(inspect.signature(func).parameters.values())
    except (TypeError, ValueError):
        return []
    if drop_first and params and params[0].name in ("self", "cls"):
        params = params[1:]
    names = []
    for p in params:
        if p.kind is p.VAR_POSITIONAL:
            names.append("*" + p.name)
        elif p.kind is p.VAR_KEYWORD:
            names.append("**" + p.name)
        else:
            names.append(p.name)
    return names


def _unwrap(obj):
    """The Python function behind numba dispatchers and functools.wraps decorators."""
    obj = getattr(obj, "py_func", obj)
    return inspect.unwrap(obj) if callable(obj) else obj


def check_function(label, func, drop_first=False, doc=None, where=None):
    """Offender lines of one function or method; ``doc`` overrides its own docstring."""
    func = _unwrap(func)
    doc = inspect.getdoc(func) if doc is None else doc
    if not doc:
        return [f"{label}: no docstring"]
    problems = []
    where = where or label
    names = signature_names(func, drop_first)
    documented = documented_parameters(doc)
    for name in names:
        if name not in documented:
            problems.append(f"{where}: missing parameter {name}")
    for name in documented:
        if name not in names:
            problems.append(f"{where}: documented parameter {name} not in the signature")
    returns, generator, raised = body_facts(func)
    sections = numpydoc_sections(doc)
    if (returns or generator) and "Returns" not in sections and "Yields" not in sections:
        problems.append(f"{where}: returns a value but has no Returns/Yields section")
    if raised:
        if "Raises" not in sections:
            problems.append(f"{where}: raises {', '.join(sorted(raised))} but has no Raises section")
        else:
            listed = set(section_entries(sections["Raises"]))
            for exc in sorted(raised - listed):
                problems.append(f"{where}: Raises section does not name {exc}")
    return problems


def _fields(cls):
    """Field names of a dataclass or named tuple, else None."""
    if dataclasses.is_dataclass(cls):
        return [f.name for f in dataclasses.fields(cls)]
    if issubclass(cls, tuple) and hasattr(cls, "_fields"):
        return list(cls._fields)
    return None


def check_class(label, cls):
    """Offender lines of a class and its public methods."""
    problems = []
    doc = cls.__doc__ if "__doc__" in cls.__dict__ else None
    if dataclasses.is_dataclass(cls) and doc and doc.startswith(cls.__name__ + "("):
        doc = None                                    # the docstring dataclass generates
    if not doc:
        problems.append(f"{label}: no docstring")
    fields = _fields(cls)
    if fields is not None:
        if doc:
            sections = numpydoc_sections(doc)
            params = section_entries(sections.get("Parameters", []))
            documented = set(params) | set(section_entries(sections.get("Attributes", [])))
            for name in fields:
                if name not in documented:
                    problems.append(f"{label}: field {name} not documented under Parameters/Attributes")
            for name in params:
                if name not in fields:
                    problems.append(f"{label}: documented parameter {name} is not a field")
    elif ("__init__" in cls.__dict__ and inspect.isfunction(cls.__dict__["__init__"])
          and cls.__dict__["__init__"].__module__ != "typing"):   # typing.Protocol's stand-in, not the class's own
        init = cls.__dict__["__init__"]
        init_doc = doc if documented_parameters(doc) or not inspect.getdoc(init) else inspect.getdoc(init)
        if doc or inspect.getdoc(init):
            problems += check_function(f"{label}.__init__", init, drop_first=True,
                                       doc=init_doc or "", where=f"{label}.__init__")
    for name, attr in cls.__dict__.items():
        if name.startswith("_"):
            continue
        if isinstance(attr, property):
            if not (attr.fget and attr.fget.__doc__):
                problems.append(f"{label}.{name}: property has no docstring")
        elif isinstance(attr, (staticmethod, classmethod)):
            problems += check_function(f"{label}.{name}", attr.__func__,
                                       drop_first=isinstance(attr, classmethod))
        elif inspect.isfunction(attr):
            problems += check_function(f"{label}.{name}", attr, drop_first=True)
    return problems


def public_members(module):
    """(name, object) of the public functions and classes defined in ``module``."""
    for name, obj in vars(module).items():
        if name.startswith("_"):
            continue
        target = _unwrap(obj)
        if not (inspect.isfunction(target) or inspect.isclass(target)):
            continue
        if getattr(target, "__module__", None) != module.__name__:
            continue                                  # imported, documented where defined
        yield name, obj


def issue_citations(module):
    """Offender lines for docstrings or comments that cite an issue tracker."""
    try:
        source = inspect.getsource(module)
    except (OSError, TypeError):
        return []
    problems = []
    label = module.__name__
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT and ISSUE_CITATION.search(tok.string):
            problems.append(f"{label}:{tok.start[0]}: comment cites an issue: {tok.string.strip()!r}")
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            text = ast.get_docstring(node, clean=False)
            if text:
                m = ISSUE_CITATION.search(text)
                if m:
                    where = getattr(node, "name", "<module>")
                    problems.append(f"{label}:{where}: docstring cites an issue: {m.group(0)!r}")
    return problems


def module_offenders(module):
    """Every offender line of one module."""
    problems = []
    for name, obj in public_members(module):
        label = f"{module.__name__}:{name}"
        target = _unwrap(obj)
        if inspect.isclass(target):
            problems += check_class(label, target)
        else:
            problems += check_function(label, target)
    return problems + issue_citations(module)


# --- the tests -------------------------------------------------------------------------

@pytest.mark.parametrize("module_name", library_modules())
def test_docstrings(module_name):
    module = importlib.import_module(module_name)
    problems = module_offenders(module)
    assert not problems, (f"{len(problems)} documentation offenders in {module_name}:\n"
                          + "\n".join(problems))


BAD_MODULE = '''
"""A module that breaks every rule once."""
from dataclasses import dataclass
from math import sqrt                          # imported: not checked here

class InputError(ValueError):
    """Bad input."""

def undocumented(x):
    return x

def missing_parameter(a, b, *args, **kwargs):
    """Add.

    Parameters
    ----------
    a : float
        First.
    c : float
        Not in the signature.

    Returns
    -------
    float
    """
    return a + b

def no_returns(a):
    """Square.

    Parameters
    ----------
    a : float
        Value.
    """
    return a * a

def no_raises(a):
    """Check.

    Parameters
    ----------
    a : float
        Value.
    """
    if a < 0:
        raise InputError("a must be >= 0")

def raises_other(a):
    """Check.

    Parameters
    ----------
    a : float
        Value.

    Raises
    ------
    TypeError
        Never, in fact.
    """
    if a < 0:
        raise ValueError("a must be >= 0")

def good(a, *args, **kwargs):
    """Fine.

    Parameters
    ----------
    a : float
        Value [m].
    *args
        Ignored.
    **kwargs
        Ignored.

    Returns
    -------
    float
        ``a`` [m].

    Raises
    ------
    InputError
        If ``a`` < 0.
    """
    def inner():
        raise ValueError("nested functions are not this function's body")
    if a < 0:
        raise InputError("a")
    return a

@dataclass
class Record:
    """A record.

    Parameters
    ----------
    length_m : float
        Length [m].
    """
    length_m: float
    mass_kg: float

class Thing:
    def method(self, y):
        """Nothing documented."""
        return y

    @property
    def size(self):
        return 1

def cites(a):
    """Work around issue 42.

    Parameters
    ----------
    a : float
        Value.
    """
    # see PR #7
'''


def test_checker_catches_offenders(tmp_path, monkeypatch):
    """The checker must be able to fail: a deliberately bad module is caught on every count."""
    path = tmp_path / "ccedi_docstring_selftest.py"
    path.write_text(BAD_MODULE)
    spec = importlib.util.spec_from_file_location("ccedi_docstring_selftest", path)
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, spec.name, module)
    spec.loader.exec_module(module)
    report = "\n".join(module_offenders(module))
    name = spec.name
    expected = [
        f"{name}:undocumented: no docstring",
        f"{name}:missing_parameter: missing parameter b",
        f"{name}:missing_parameter: missing parameter *args",
        f"{name}:missing_parameter: missing parameter **kwargs",
        f"{name}:missing_parameter: documented parameter c not in the signature",
        f"{name}:no_returns: returns a value but has no Returns/Yields section",
        f"{name}:no_raises: raises InputError but has no Raises section",
        f"{name}:raises_other: Raises section does not name ValueError",
        f"{name}:Record: field mass_kg not documented under Parameters/Attributes",
        f"{name}:Thing: no docstring",
        f"{name}:Thing.method: missing parameter y",
        f"{name}:Thing.method: returns a value but has no Returns/Yields section",
        f"{name}:Thing.size: property has no docstring",
        f"{name}:cites: docstring cites an issue",
        "comment cites an issue: '# see PR #7'",
    ]
    for line in expected:
        assert line in report, f"not caught: {line}\nreport:\n{report}"
    assert f"{name}:good" not in report
    assert "sqrt" not in report and f"{name}:InputError" not in report
    assert f"{name}:undocumented: no docstring" in report.splitlines()[0]


def test_parser_reads_numpydoc_sections():
    doc = """Summary.

    Parameters
    ----------
    x, y : float
        Coordinates [m].
    \\*\\*options : dict
        Passed on.

    Returns
    -------
    float
    """
    assert documented_parameters(doc) == ["x", "y", "**options"]
    assert set(numpydoc_sections(doc)) == {"", "Parameters", "Returns"}


if __name__ == "__main__":
    failing = 0
    for name in library_modules():
        count = len(module_offenders(importlib.import_module(name)))
        failing += count > 0
        print(f"{count:5d}  {name}")
    print(f"{failing} modules with offenders")
