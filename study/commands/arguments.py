"""Command-line arguments shared by several sub-commands (nothing heavy is imported here).

Output paths are declared with :func:`add_output_argument` and checked by
:func:`check_output_paths` before a command computes anything, so that a run is never
lost to a path it cannot write at the end.
"""
# Imports inside functions: building the parser imports no library, so that `ccedi --help`
# answers at once (tests/conventions/test_layout.py); each command loads what it runs.
import argparse
import os
import warnings
from contextlib import contextmanager
from pathlib import Path

from ccedi.distributed import SERIAL, check_scheduler
from ccedi.errors import InputError, ValidityWarning
from ccedi.fea.solvers.budget import MAX_STEPS, STEPS_ENV


class DefaultsHelpFormatter(argparse.HelpFormatter):
    """Help that ends every option's text with its default, unless the text already says
    it or there is none to say (no default, a switch that is off, a required option)."""

    def _get_help_string(self, action):
        text = action.help or ""
        default = action.default
        if ("default" in text.lower() or action.required or default in (None, False, argparse.SUPPRESS)
                or not action.option_strings):
            return text
        shown = " ".join(map(str, default)) if isinstance(default, (list, tuple)) else default
        return f"{text} (default: {shown})"


def add_command(sub, name, help):
    """Register the sub-command ``name`` on ``sub``, its one-line ``help`` also the
    description of its own ``--help``, every option's default shown there.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-command registry of the ``ccedi`` parser.
    name : str
        The sub-command.
    help : str
        What it does, in one sentence.

    Returns
    -------
    argparse.ArgumentParser
        The sub-command's parser.
    """
    parser = sub.add_parser(name, help=help, description=help[0].upper() + help[1:] + ".",
                            formatter_class=DefaultsHelpFormatter)
    parser.add_argument("--max-steps", type=int, default=None, metavar="N",
                        help=f"step budget of each explicit run: a longer one is refused before it starts, with its "
                             f"step count and expected time (default {MAX_STEPS:.0e}, or {STEPS_ENV})")
    return parser


def add_scheduler_argument(parser, default=SERIAL):
    """Add ``--scheduler serial|local|ADDRESS`` to ``parser``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The sub-command's parser.
    default : str or None
        Default scheduler; ``None`` leaves the choice to the command (e.g. a config file).
    """
    said = f"default {default}" if default is not None else "default: the config's scheduler"
    parser.add_argument("--scheduler", default=default, metavar="serial|local|ADDRESS",
                        help="where independent runs go: serial (this process), local (a 2-worker Dask local "
                             f"cluster) or a Dask scheduler address such as tcp://host:8786 ({said})")


MATERIAL_KEYS = ("material.E_Pa", "material.nu", "material.rho_kg_m3")
FINGER_KEYS = MATERIAL_KEYS + ("finger.section_semi_axes_m", "finger.mesh", "finger.mesh_unit", "finger.clamp",
                               "finger.tip", "finger.bending_direction")
"""The keys that make a finger: its material and section, or its mesh."""
IMPULSE_FINGER_KEYS = FINGER_KEYS + ("finger.impulse_length_in",)
CONTACT_KEYS = FINGER_KEYS + ("finger.contact_length_in", "finger.contact_taper_ratio", "drum")
"""The finger on the drum: the drum set-up and the contact finger's length and taper."""


def add_config_argument(parser, uses):
    """Add ``--config TOML`` (the finger's material and section, the drum set-up) to ``parser``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The sub-command's parser.
    uses : tuple of str or callable
        What the command reads of the file: sections (``"drum"``) and keys
        (``"finger.mesh"``), or a function of the parsed arguments giving them;
        :func:`load_config` names every other key the file sets to a value other than
        its default, which the command would otherwise ignore without a word.
    """
    parser.add_argument("--config", help="inputs TOML ([material], [finger], [drum]; see ccedi init); "
                        "default: the paper's rubber finger and drum test")
    parser.set_defaults(config_uses=uses)


def load_config(args):
    """The validated inputs of ``--config`` (all defaults when it is not given).

    A key the file sets (to other than its default) that the command does not read is
    named in one validity warning line, before anything runs.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments, with an optional ``config`` path and the ``config_uses`` of
        :func:`add_config_argument`.

    Returns
    -------
    dict
        ``{section: {key: value}}`` as :func:`ccedi.study.config.load` returns it.

    Raises
    ------
    ccedi.errors.InputError
        The file is missing, not TOML, or holds a bad key or value.
    """
    from ccedi.study.config import changed_keys, load

    path = getattr(args, "config", None)
    cfg = load(path)
    uses = getattr(args, "config_uses", None)
    if path is not None and uses is not None:
        uses = uses(args) if callable(uses) else uses
        unused = [f"[{s}] {k}" for s, k in changed_keys(cfg) if s not in uses and f"{s}.{k}" not in uses]
        if unused:
            warnings.warn(ValidityWarning(f"{path} sets {', '.join(unused)}, which ccedi {args.command} does not "
                                          "use: its results are what they would be without "
                                          + ("it" if len(unused) == 1 else "them")))
    return cfg


def add_output_argument(parser, flag, kind, **kwargs):
    """Add an output path option (or positional) that :func:`check_output_paths` checks
    before the command runs.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The sub-command's parser.
    flag : str
        Option string (``"--json"``) or positional name (``"path"``).
    kind : {"file", "dir"}
        What the path names: a file to write, or a directory to write into.
    **kwargs
        Passed to ``parser.add_argument``.

    Returns
    -------
    argparse.Action
    """
    if kind not in ("file", "dir"):
        raise ValueError(f"kind must be 'file' or 'dir', got {kind!r}")
    action = parser.add_argument(flag, **kwargs)
    declared = parser.get_default("output_paths") or ()
    parser.set_defaults(output_paths=(*declared, (action.dest, flag, kind)))
    return action


def _existing_ancestor(path):
    """The nearest of ``path`` and its parents that exists."""
    for candidate in (path, *path.parents):
        if candidate.exists():
            return candidate
    return Path.cwd()


def output_file(path, option):
    """Check that a file can be written at ``path`` (the directories to it are made later).

    Parameters
    ----------
    path : str or Path
        The file to write.
    option : str
        The option that named it, for the message.

    Returns
    -------
    Path

    Raises
    ------
    InputError
        ``path`` is a directory, a parent of it is a file, or its directory is not writable.
    """
    p = Path(path)
    if p.is_dir():
        raise InputError(f"{option} {path}: is a directory; expected a file name")
    base = _existing_ancestor(p.parent)
    if not base.is_dir():
        raise InputError(f"{option} {path}: {base} is a file, not a directory")
    if p.exists() and not os.access(p, os.W_OK):
        raise InputError(f"{option} {path}: the file is not writable")
    if not p.exists() and not os.access(base, os.W_OK | os.X_OK):
        raise InputError(f"{option} {path}: cannot write in {base}")
    return p


def output_dir(path, option):
    """Check that ``path`` is, or can be made, a writable directory.

    Parameters
    ----------
    path : str or Path
        The directory to write into.
    option : str
        The option that named it, for the message.

    Returns
    -------
    Path

    Raises
    ------
    InputError
        ``path`` or a parent of it is a file, or the directory is not writable.
    """
    p = Path(path)
    base = _existing_ancestor(p)
    if not base.is_dir():
        raise InputError(f"{option} {path}: {base} is a file, not a directory")
    if not os.access(base, os.W_OK | os.X_OK):
        raise InputError(f"{option} {path}: cannot write in {base}")
    return p


@contextmanager
def step_budget_of(args):
    """``--max-steps`` in force while the command runs: set as ``CCEDI_MAX_STEPS`` (so a
    local cluster's workers see it too) and restored after.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments.

    Raises
    ------
    InputError
        ``--max-steps`` below 1.
    """
    given = getattr(args, "max_steps", None)
    if given is None:
        yield
        return
    if given < 1:
        raise InputError(f"--max-steps = {given}: must be an integer >= 1 (steps)")
    before = os.environ.get(STEPS_ENV)
    os.environ[STEPS_ENV] = str(given)
    try:
        yield
    finally:
        if before is None:
            os.environ.pop(STEPS_ENV, None)
        else:
            os.environ[STEPS_ENV] = before


def check_output_paths(args):
    """Check every output path a parsed command line declares (:func:`add_output_argument`),
    and its ``--scheduler`` (:func:`ccedi.distributed.check_scheduler`).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments.

    Raises
    ------
    InputError
        The first output path that cannot be written, named with its option, or a
        scheduler that is neither a known word nor an address.
    """
    for dest, flag, kind in getattr(args, "output_paths", ()):
        value = getattr(args, dest, None)
        if value is not None:
            (output_file if kind == "file" else output_dir)(value, flag)
    if getattr(args, "scheduler", None) is not None:
        check_scheduler(args.scheduler)


def check_flag(flag, value, *, section, key):
    """Check a command-line value against the inputs schema's range for ``[section] key``
    (one rule whichever way the value comes).

    Parameters
    ----------
    flag : str
        The option, for the message (``"--length-in"``).
    value : object
        The parsed value (None: not given, nothing checked).
    section, key : str
        The schema entry (:data:`ccedi.study.config.SCHEMA`).

    Returns
    -------
    object
        ``value``.

    Raises
    ------
    InputError
        ``FLAG = VALUE: must be in LO..HI (UNIT)``.
    """
    if value is None:
        return value
    from ccedi.study.config import check_value

    return check_value(section, key, value, name=flag)
