"""`python -m patina.cli`: the `patina` command."""

import sys

from patina.cli import command

sys.exit(command())
