"""as_float32: the array form the native kernels take."""

import numpy as np

from patina.kernel_arrays import as_float32


def test_a_strided_float64_view_becomes_contiguous_float32_of_the_same_values():
    rows = np.arange(12, dtype=np.float64).reshape(4, 3)[::2]
    out = as_float32(rows)
    assert out.dtype == np.float32 and out.flags.c_contiguous
    np.testing.assert_array_equal(out, rows.astype(np.float32))


def test_an_array_already_in_that_form_is_passed_as_it_is():
    rows = np.ones((5, 3), np.float32)
    assert as_float32(rows) is rows
