"""Every sub-command's ``--help`` has a description, and every option a help text and its
default (or says it is required, a switch, or has none)."""
import argparse

import pytest

from ccedi.study.cli import build_parser


def _commands():
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices


@pytest.mark.parametrize("name", sorted(_commands()))
def test_sub_command_help_describes_every_option(name, capsys):
    parser = _commands()[name]
    assert parser.description and len(parser.description) > 20
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction):
            continue
        where = f"ccedi {name} {'/'.join(action.option_strings) or action.dest}"
        assert action.help and len(action.help) > 8, f"{where}: no help text"
    with pytest.raises(SystemExit):
        parser.parse_args(["--help"])
    text = "".join(capsys.readouterr().out.split())       # wrapping moves spaces, not words
    assert "".join(parser.description.split()) in text
    formatter = parser._get_formatter()
    for action in parser._actions:
        if action.option_strings and action.default not in (None, False, argparse.SUPPRESS) and not action.required:
            assert "default" in formatter._get_help_string(action).lower(), \
                f"ccedi {name} {action.option_strings[-1]}: default not shown"
