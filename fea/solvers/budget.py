"""The step budget of an explicit run: a run of absurd length is refused in one line
before it starts (:func:`ccedi.fea.solvers.explicit.run`). Light on imports: the command line
reads it."""
import os

from ccedi.errors import InputError

MAX_STEPS = 20_000_000
"""Step budget of one run (:func:`ccedi.fea.solvers.explicit.run`) unless its caller or
``CCEDI_MAX_STEPS`` raises it: about twenty times ccedi's own longest runs (a design run
of 4 s at 10 rpm at SM-A's stable step of 4.4 us is about 1e6 steps; the tapered finger
with a hole at 8 mm takes 8830 steps per 0.05 s, 3.8e5 for its 2.16 s design run), so
that a run of absurd length (a stiff material, a sliver element: 5e8 steps, days) is
refused in one line before it starts instead of running silently."""

STEPS_ENV = "CCEDI_MAX_STEPS"
"""Environment variable that sets the step budget of :func:`ccedi.fea.solvers.explicit.run` (an integer >= 1); the
CLI's ``--max-steps`` sets it, so worker processes of a local cluster see it too."""


def step_budget(max_steps=None):
    """The step budget of a run: ``max_steps``, else ``CCEDI_MAX_STEPS``, else :data:`MAX_STEPS`.

    Parameters
    ----------
    max_steps : int, optional
        The caller's budget.

    Returns
    -------
    int

    Raises
    ------
    InputError
        A budget that is not an integer >= 1.
    """
    value = max_steps if max_steps is not None else os.environ.get(STEPS_ENV, MAX_STEPS)
    try:
        n = int(value)
    except (TypeError, ValueError):
        n = 0
    if n < 1 or (isinstance(value, float) and n != value):
        where = "max_steps" if max_steps is not None else STEPS_ENV
        raise InputError(f"{where} = {value!r}: must be an integer >= 1 (steps)")
    return n


MAX_OUTPUTS = 100_000
"""Most output rows of one run (:func:`ccedi.fea.solvers.explicit.run`): every 15 us of the
longest design run, 33 times the densest ccedi asks for (rom-check's 3000 over 1.5 s);
beyond, the history's memory (a row per output, a snapshot of every node with a VTU
animation) and the output overhead grow while the run resolves nothing more."""


def check_outputs(n_outputs, name="n_outputs"):
    """``n_outputs`` as an int in 1..:data:`MAX_OUTPUTS`.

    Parameters
    ----------
    n_outputs : int
        Output rows asked for.
    name : str, optional
        How the message names it (``--n-outputs`` on the command line).

    Returns
    -------
    int

    Raises
    ------
    InputError
        Not an integer in 1..MAX_OUTPUTS.
    """
    if isinstance(n_outputs, bool) or not isinstance(n_outputs, (int, float)) or int(n_outputs) != n_outputs \
            or not 1 <= n_outputs <= MAX_OUTPUTS:
        raise InputError(f"{name} = {n_outputs!r}: must be an integer in 1..{MAX_OUTPUTS} (output rows of a run)")
    return int(n_outputs)
