"""ccedi: a design tool for compliant (joint-less) robot fingers.

Built from Liu & Lee, "Dynamic Modeling of Damping Effects in Highly Damped Compliant
Fingers for Applications Involving Contacts", ASME J. Dyn. Sys., Meas., Control 134 (2012).

Libraries: :mod:`ccedi.fea` (explicit dynamic FE solver), :mod:`ccedi.rom` (reduced
models and damping identification), :mod:`ccedi.design` (casadi/IPOPT optimiser),
:mod:`ccedi.calibrate` (closing the loop with measured data). Shared by all of them:
:mod:`ccedi.errors` and the model interface :mod:`ccedi.models`. The application on top:
:mod:`ccedi.study` (the ``ccedi`` command line and the end-to-end study).

Importing ``ccedi`` imports none of them.
"""

__version__ = "0.1.0"
