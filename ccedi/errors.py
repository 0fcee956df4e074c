"""Exceptions raised by ccedi with messages that name the offending field."""


class InputError(ValueError):
    """A user-supplied value is invalid; the message names the field and its allowed range."""


class SolverError(RuntimeError):
    """The explicit solver cannot continue (divergence, inverted element, unstable step)."""


def require_finite_positive(name, value, allow_zero=False):
    """Return ``float(value)`` or raise :class:`InputError` naming ``name``.

    ``value`` must be a finite real number, > 0 (or >= 0 when ``allow_zero``).
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
