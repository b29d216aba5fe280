"""`python -m patina.cli`: the `patina` command."""

import sys

from patina.cli import main

sys.exit(main())
