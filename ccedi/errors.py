"""Exceptions raised by ccedi with messages that name the offending field, and the two
helpers that keep such a message one short printable line whatever the input held."""
import math
import reprlib

MAX_SHOWN = 120
"""Most characters a message gives a value it shows (:func:`brief_repr`); twice that to
another library's message it quotes (:func:`one_line`)."""


class InputError(ValueError):
    """A user-supplied value is invalid; the message names the field and its allowed range.

    A subclass of :class:`ValueError`, so callers that catch ``ValueError`` also catch it.
    The command line turns it into a one-line error message and a non-zero exit status.
    """


class SolverError(RuntimeError):
    """The explicit solver cannot continue (divergence, inverted element, unstable step).

    A subclass of :class:`RuntimeError`: the inputs were valid but the computation failed
    (e.g. an element with Jacobian J <= 0, a Newton iteration that did not converge).
    """


class ModelInadequate(Exception):
    """The declared model cannot explain a measured record: exit status 3 on the command line.

    Every input was valid, but the finger the sidecar declares is not the one in the record
    (its first-mode frequency lies outside what the declared E tolerance allows, E is
    pressed onto its bound, or the record is too short to show the declared first mode).
    ``ccedi calibrate`` raises it *after* writing its complete JSON (``model_adequate:
    false`` with the evidence) and report, having added no effect; the message is one line
    naming the failed checks and the record's own first-mode frequency. Not an
    :class:`InputError`: the exit status tells "fix the declaration" (3) from "fix the
    input file" (1).
    """


class RequirementsUnmet(Exception):
    """No design in the design space meets the designer's requirements: exit status 4 on
    the command line.

    Every input was valid and the design space was searched; ``ccedi design`` raises it
    *after* writing its complete result (``feasible: false``, the design closest to
    meeting them and by how much it misses each requirement) and report. The message is
    one line naming the requirements missed and by how much.
    """


class ValidityWarning(UserWarning):
    """A run's results leave the model's range of validity, but the numbers still mean
    something (see :mod:`ccedi.fea.solvers.validity`).

    The run records the same message in its summary (``warnings``); the command line
    prints each one as ``ccedi <command>: warning: <message>`` on stderr.
    """


def require_finite_positive(name, value, allow_zero=False):
    """Return ``float(value)`` or raise :class:`InputError` naming ``name``.

    Parameters
    ----------
    name : str
        How the field is named in the error message, ideally with its unit,
        e.g. ``"length_m (finger length, m)"``.
    value : object
        The value to check; anything ``float()`` accepts.
    allow_zero : bool, optional
        Accept ``value == 0`` (the check becomes ``>= 0``). Default False (``> 0``).

    Returns
    -------
    float
        ``float(value)``, finite and > 0 (or >= 0 when ``allow_zero``).

    Raises
    ------
    InputError
        If ``value`` is not a real number, is NaN or infinite, or is negative
        (or zero, unless ``allow_zero``).
    """
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a real number, got {value!r}") from None
    bound = ">= 0" if allow_zero else "> 0"
    if x != x or x in (float("inf"), float("-inf")):
        raise InputError(f"{name} must be finite and {bound}, got {value!r}")
    if x < 0 or (x == 0 and not allow_zero):
        raise InputError(f"{name} must be {bound}, got {value!r}")
    return x


class _BriefRepr(reprlib.Repr):
    """:class:`reprlib.Repr` that never spells out a huge integer (``repr`` refuses one of
    more than 4300 digits)."""

    def repr_int(self, x, level):
        if x.bit_length() > 4 * self.maxlong:
            return f"<an integer of about {math.floor(x.bit_length() * math.log10(2)) + 1} digits>"
        return super().repr_int(x, level)


_BRIEF = _BriefRepr()
_BRIEF.maxlevel, _BRIEF.maxlist, _BRIEF.maxdict = 3, 6, 4
_BRIEF.maxstring = _BRIEF.maxother = 60


def brief_repr(value):
    """``repr(value)`` short enough for a one-line message: what the input held, elided.

    Parameters
    ----------
    value : object
        A value as it was read (a number, a string, a list or table of them, ...).

    Returns
    -------
    str
        Its ``repr`` (control characters and line breaks escaped), with long strings,
        lists and tables elided (``'aaa...aaa'``, ``[1, 2, 3, 4, 5, 6, ...]``) and at most
        :data:`MAX_SHOWN` characters.
    """
    text = _BRIEF.repr(value)
    if len(text) <= MAX_SHOWN:
        return text
    half = (MAX_SHOWN - 3) // 2
    return text[:half] + "..." + text[-half:]


def one_line(err):
    """The message of another library's exception as one line, for an :class:`InputError`.

    Parameters
    ----------
    err : BaseException
        The exception (a parser's, a decoder's).

    Returns
    -------
    str
        Its message, every run of whitespace (line breaks included) one space, non-printable
        characters escaped, at most 2 :data:`MAX_SHOWN` characters.
    """
    text = " ".join(str(err).split())
    if not text.isprintable():
        text = repr(text)[1:-1]
    return text if len(text) <= 2 * MAX_SHOWN else text[:2 * MAX_SHOWN - 3] + "..."
