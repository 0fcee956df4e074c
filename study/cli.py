"""The ``ccedi`` command line: one parser, every sub-command, and ``main``.

Sub-commands (registered by the modules of :mod:`ccedi.study.commands`):

  table1, impulse, contact, contact-sweep, contact-report   explicit FEA (:mod:`ccedi.fea`)
  identify, damping-fits, rom-check                         identification and ROMs (:mod:`ccedi.rom`)
  design                                                    design optimiser (:mod:`ccedi.design`)
  calibrate                                                 close the loop (:mod:`ccedi.calibrate`)
  study, init, export                                       the whole study (:mod:`ccedi.study`)

Building the parser imports no library, so ``ccedi --help`` answers at once.
"""
# Imports inside functions: building the parser imports no library, so that `ccedi --help`
# answers at once (tests/conventions/test_layout.py); each command loads what it runs.
import argparse
import sys
import warnings

from ccedi.errors import InputError, ModelInadequate, RequirementsUnmet, SolverError, ValidityWarning
from ccedi.progress import close_progress_bars
from ccedi.study.commands import calibrate, design, fea, rom, study
from ccedi.study.commands.arguments import check_output_paths, step_budget_of


def build_parser():
    """The ``ccedi`` argument parser with every sub-command.

    Returns
    -------
    argparse.ArgumentParser
        Parsed arguments carry ``func``, the sub-command's function of them.
    """
    p = argparse.ArgumentParser(prog="ccedi", description="Compliant finger design: explicit FEA, "
                                "damping identification, reduced models, design optimisation.")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    for module in (fea, rom, calibrate, design, study):
        module.add_parsers(sub)
    return p


def main(argv=None):
    """Run ``ccedi`` with ``argv`` (default: ``sys.argv[1:]``).

    Parameters
    ----------
    argv : list of str, optional
        The command line after the program name.

    Returns
    -------
    int
        Exit status: 0 done, 1 bad input, a file that cannot be read or written, or a
        solver failure (one line on stderr), 2 no sub-command, 3 the declared model
        cannot explain a measured record (``calibrate``, ``identify``: its JSON, with
        ``model_adequate: false`` and the evidence, is written; one line on stderr names
        the failed check and the record's own first-mode frequency), 4 no design meets
        the requirements (``design``: its result and report, with the design closest to
        meeting them, are written; one line on stderr names the requirements missed and
        by how much), 130 interrupted.
        Output paths are checked before anything is computed. Each validity warning
        (:class:`ccedi.errors.ValidityWarning`) is printed as one line on stderr,
        ``ccedi <command>: warning: <message>``, and does not change the status.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("always", ValidityWarning)
            warnings.showwarning = _warning_printer(args.command, warnings.showwarning)
            check_output_paths(args)
            with step_budget_of(args):
                args.func(args)
    except (InputError, SolverError) as err:
        return _fail(args.command, f"error: {err}", 1)
    except ModelInadequate as err:
        return _fail(args.command, str(err), 3)
    except RequirementsUnmet as err:
        return _fail(args.command, str(err), 4)
    except OSError as err:
        where = f"{err.filename}: " if err.filename else ""
        return _fail(args.command, f"error: {where}{err.strerror or err}", 1)
    except KeyboardInterrupt:
        return _fail(args.command, "interrupted; no partial outputs were written", 130)
    return 0


def _fail(command, message, status):
    """Print ``ccedi COMMAND: MESSAGE`` as one line on stderr, after clearing any progress
    bar, and return the exit ``status``."""
    close_progress_bars()
    sys.stderr.flush()
    print(f"ccedi {command}: {message}", file=sys.stderr)
    return status


def _warning_printer(command, fallback):
    """A ``warnings.showwarning`` that prints a validity warning as one stderr line of
    ``ccedi <command>``, above any progress bar (tqdm.write), and leaves other warnings
    to ``fallback``."""
    def show(message, category, filename, lineno, file=None, line=None):
        if not issubclass(category, ValidityWarning):
            return fallback(message, category, filename, lineno, file, line)
        from tqdm import tqdm
        tqdm.write(f"ccedi {command}: warning: {message}", file=sys.stderr)
    return show
