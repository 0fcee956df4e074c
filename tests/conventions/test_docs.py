"""The documentation holds together: a short README that opens with the two set-up
commands, a TOML reference that is the schema's, links that lead somewhere, and only
sub-commands that exist."""
import argparse
import importlib.util
import re

import pytest
from conftest import ROOT

from ccedi.study.cli import build_parser

README = ROOT / "README.md"
DOCS = ROOT / "docs"
PAGES = [README, *sorted(DOCS.glob("*.md"))]

OPENING = [                             # the project's contract: byte-identical
    "# ccedi",
    "",
    "```",
    "make demo    # creates .venv, installs ccedi, runs the whole design study -> reports/index.html (and index.pdf)",
    "make test    # same set-up, then runs the test suite (tests/)",
    "```",
    "",
    "Both need only Python 3.11 and pip (`PYTHON=python3.11 make demo` if `python3` is older).",
]

LINK = re.compile(r"(?<!!)\[(?:[^\]\[]|\[[^\]]*\])*\]\(([^()\s]+)\)")
FENCE = re.compile(r"^[ \t]*```.*?^[ \t]*```", re.S | re.M)
INLINE_CODE = re.compile(r"`([^`\n]+)`")
COMMAND = re.compile(r"(?<![\w.-])ccedi\s+([a-z][a-z0-9_-]*)")


def _load_make_reference():
    spec = importlib.util.spec_from_file_location("make_reference", DOCS / "make_reference.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _links(page):
    """(line number, target) of every markdown link of ``page`` outside code."""
    out = []
    text = page.read_text(encoding="utf-8")
    for block in FENCE.finditer(text):          # blank out code blocks, keeping line numbers
        text = text.replace(block.group(0), "\n" * block.group(0).count("\n"), 1)
    for number, line in enumerate(text.splitlines(), 1):
        for match in LINK.finditer(INLINE_CODE.sub("", line)):
            out.append((number, match.group(1)))
    return out


def _slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def _anchors(page):
    text = FENCE.sub("", page.read_text(encoding="utf-8"))
    return {_slug(m.group(1)) for m in re.finditer(r"^#{1,6}\s+(.+?)\s*#*$", text, re.M)}


def test_readme_is_short_and_opens_with_the_two_commands():
    lines = README.read_text(encoding="utf-8").splitlines()
    assert len(lines) < 150, f"README.md has {len(lines)} lines; move detail into docs/"
    assert lines[:len(OPENING)] == OPENING


def test_toml_reference_is_the_schemas():
    expected = _load_make_reference().reference_markdown()
    assert expected == _load_make_reference().reference_markdown(), "reference_markdown() is not deterministic"
    actual = (DOCS / "toml-reference.md").read_text(encoding="utf-8")
    assert actual == expected, "docs/toml-reference.md is stale: run .venv/bin/python docs/make_reference.py"


def test_reference_names_every_schema_key():
    from ccedi.study.config import SCHEMA
    text = _load_make_reference().reference_markdown()
    for section, keys in SCHEMA.items():
        assert f"\n## {section}\n" in text
        for key in keys:
            assert f"| `{key}` |" in text, f"[{section}] {key}"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_lead_to_files_and_headings(page):
    assert page.exists()
    broken = []
    for number, target in _links(page):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target):        # http:, https:, mailto:
            continue
        path, _, anchor = target.partition("#")
        file = (page.parent / path).resolve() if path else page
        if not file.exists():
            broken.append(f"{page.name}:{number}: {target} (no such file)")
        elif anchor and file.suffix == ".md" and anchor not in _anchors(file):
            broken.append(f"{page.name}:{number}: {target} (no heading #{anchor} in {file.name})")
    assert not broken, "\n".join(broken)


def test_link_check_finds_links():
    """The link test reads links (a pattern that matched none would pass anything)."""
    targets = [t for _, t in _links(README)]
    assert "docs/index.md" in targets and "docs/user-guide.md" in targets
    assert _slug("One model interface (`ccedi.models`)") == "one-model-interface-ccedimodels"


def _readme_commands():
    text = README.read_text(encoding="utf-8")
    code = [block.group(0) for block in FENCE.finditer(text)]
    code += INLINE_CODE.findall(FENCE.sub("", text))
    return {m.group(1) for snippet in code for m in COMMAND.finditer(snippet)}


def test_readme_names_only_real_subcommands():
    parser = build_parser()
    (sub,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    named = _readme_commands()
    assert {"init", "study", "design"} <= named, named
    assert named <= set(sub.choices), f"not sub-commands of ccedi: {sorted(named - set(sub.choices))}"


PLACEHOLDERS = {"FILE": "study.toml", "PATH": "out.json", "DIR": "out", "MEASURED.csv": "measured.csv", "L": "4.5",
                "A": "180", "STEP": "finger"}
"""Words the docs' command lines stand in for a value with, and a value of each."""
SYNOPSIS = re.compile(r"[\[\]|]|\.\.\.|: error:")
"""A usage synopsis (optional parts in brackets, choices, repetition) or an error line."""


def _command_lines():
    """(page, line, in a code block) of every ``ccedi SUBCOMMAND ...`` line in the README
    and docs: the lines of code blocks and the inline code spans."""
    found = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        blocks = [line.strip() for block in FENCE.finditer(text) for line in block.group(0).splitlines()]
        spans = INLINE_CODE.findall(FENCE.sub("", text))
        for line, fenced in [(b, True) for b in blocks] + [(s, False) for s in spans]:
            line = line.split(" #")[0].strip()
            if re.match(r"ccedi\s+[a-z][a-z0-9_-]*(\s|$)", line):          # not an output line ("ccedi study: ...")
                found.append((page.name, line, fenced))
    return found


def _subparsers():
    (sub,) = [a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)]
    return sub.choices


def test_every_documented_command_line_parses():
    """Every ``ccedi`` command line of a code block parses with the real command line
    (placeholders such as FILE replaced by a value); every flag a synopsis or an inline
    mention names is one its sub-command has."""
    commands, broken, parsed, checked = _subparsers(), [], 0, 0
    for page, line, fenced in _command_lines():
        words = line.split()
        name = words[1]
        if name not in commands:
            if fenced:
                broken.append(f"{page}: {line!r}: no sub-command {name!r}")
            continue
        options = {o for action in commands[name]._actions for o in action.option_strings}
        flags = [w.strip("[]") for w in words if w.strip("[]").startswith("--")]
        broken += [f"{page}: {line!r}: {name} has no {f}" for f in flags if f.split("=")[0] not in options]
        checked += len(flags)
        if fenced and not SYNOPSIS.search(line):
            try:
                commands[name].parse_args([PLACEHOLDERS.get(w, w) for w in words[2:]])
                parsed += 1
            except SystemExit:
                broken.append(f"{page}: {line!r}: does not parse")
    assert not broken, "\n".join(broken)
    assert parsed >= 3 and checked >= 50, (parsed, checked)     # the check reads the docs' commands


def test_the_command_line_check_catches_a_stale_flag():
    commands = _subparsers()
    with pytest.raises(SystemExit):
        commands["study"].parse_args(["--no-such-flag"])
    assert "--paper" in {o for a in commands["study"]._actions for o in a.option_strings}
