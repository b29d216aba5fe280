"""Where the repository is, for tests that read its bundled files (materials/, docs/, README)."""

import os

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
