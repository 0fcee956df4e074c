"""The ``ccedi`` sub-commands, one module per library they drive.

Each module has ``add_parsers(sub)``, which registers its sub-commands without importing
any library (so ``ccedi --help`` stays fast), ``cmd_*(args)`` functions that turn parsed
arguments into objects, and ``write_*`` functions that take those objects, run the
library and write the outputs. The study (:mod:`ccedi.study.run`) calls the ``write_*``
functions directly, with inputs parsed and validated once.
"""
