"""``python -m ccedi ...``: the ``ccedi`` command line."""
import sys

from ccedi.study.cli import main

sys.exit(main())
