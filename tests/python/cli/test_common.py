"""The helpers every command shares: third-party warnings shown as one line."""

from __future__ import annotations

import warnings

import numpy as np

from patina.cli.common import brief_warnings


def test_a_library_warning_is_one_line_naming_its_kind(capsys):
    with brief_warnings():
        warnings.simplefilter("default")
        np.float32(3e38) * np.float32(10)  # numpy: overflow encountered in scalar multiply
        warnings.warn("two\nlines", UserWarning, stacklevel=1)
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("patina: warning: RuntimeWarning: overflow encountered"), err
    assert err[1] == "patina: warning: UserWarning: two lines" and len(err) == 2, err


def test_python_s_own_display_is_back_after():
    before = warnings.showwarning
    with brief_warnings():
        assert warnings.showwarning is not before
    assert warnings.showwarning is before
