"""Exceptions raised by ccedi with messages that name the offending field."""


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


class ValidityWarning(UserWarning):
    """A run's results leave the model's range of validity, but the numbers still mean
    something (see :mod:`ccedi.fea.validity`).

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
