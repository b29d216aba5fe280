"""Radiance tensor trees (python/patina/table/formats/tensor_tree.py): trees written from
the format's definition (tests/python/tensor_tree_writer.py) read back exactly at every
cell, at every branch depth; direction pairs mapped to the squares Radiance uses; bad
trees refused with one line naming the block and the token; random damage fuzzed."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from patina.errors import FormatError
from patina.synthetic.analytic import plastic
from patina.table.formats.tensor_tree import parse_tree, tree_coordinates
from reader_fuzz import load_damaged
from tensor_tree_writer import cell_centres, tree_directions, tree_document, tree_grid, tree_text

MODEL = plastic(diffuse=(0.5,), specular=0.04, roughness=0.3)


@pytest.mark.parametrize(("dims", "log2", "levels"), [(3, 4, 0), (3, 4, 2), (4, 3, 1), (4, 3, 3)])
def test_every_cell_reads_back_exactly(dims, log2, levels):
    grid = tree_grid(MODEL, dims, log2)
    tree = parse_tree(tree_text(grid, levels), dims, "t.xml", "block")
    want = np.array([float(f"{v:.7g}") for v in grid.ravel()])
    assert np.array_equal(tree.lookup(cell_centres(dims, log2)), want)


def test_a_uniform_branch_is_one_value():
    grid = np.zeros((4, 4, 4))
    grid[2:, 2:, 2:] = 7.0  # child 7 (every upper half) uniform, the others zero
    text = tree_text(grid, 1)
    assert text.count("{ 7 }") == 1 and text.count("{ 0 }") == 7
    tree = parse_tree(text, 3, "t.xml", "block")
    assert tree.lookup(np.array([[0.9, 0.6, 0.7], [0.1, 0.6, 0.7]])).tolist() == [7.0, 0.0]


@pytest.mark.parametrize("dims", [3, 4])
def test_direction_pairs_map_to_radiance_squares(dims):
    """The reader's coordinates of the writer's directions at cell centres are those centres."""
    g = cell_centres(dims, 3)
    if dims == 3:
        g = g[g[:, 0] < 0.5]
    assert np.allclose(tree_coordinates(dims, *tree_directions(dims, g)), g, atol=1e-5)


@pytest.mark.parametrize("dims", [3, 4])
def test_a_mirror_pair_has_one_square_position(dims):
    """Radiance's convention: incident (-x, -y) and outgoing (x, y) squares, so the mirror
    direction of wi lands where wi does (TensorTree4), on the +x axis (TensorTree3)."""
    rng = np.random.default_rng(1)
    t, p = rng.uniform(0.05, 1.4, 50), rng.uniform(0, 2 * np.pi, 50)
    wi = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=1)
    mirror = wi * [-1, -1, 1]
    c = tree_coordinates(dims, wi, mirror)
    if dims == 4:
        assert np.allclose(c[:, :2], c[:, 2:])
    else:
        assert np.allclose(c[:, 2], 0.5) and np.all(c[:, 1] > 0.5)


@pytest.mark.parametrize(
    ("text", "token", "problem"),
    [
        ("", "", "empty ScatteringData"),
        ("1 2 3", "token 1", "'1': '{' expected"),
        ("{ 1 2 3 }", "token 2", "a leaf of 3 values: expected 2^(3 k)"),
        ("{ 1 2 3 4 5 6 7 x }", "token 9", "'x' is not a number"),
        ("{ 1 2 3 4 5 6 7 -8 }", "token 9", "-8: negative or not finite"),
        ("{ 1 2 3 4 5 6 7 nan }", "token 9", "nan: negative or not finite"),
        ("{ { 1 } { 2 } }", "token 8", "'}': '{' expected"),
        ("{ 1 2 3 4 5 6 7 8", "token 10", "'}' expected: the tree ends early"),
        ("{ 1 } }", "token 4", "'}' after the end of the tree"),
        ("{" * 30, "token 26", "more than 24 levels deep"),
    ],
)
def test_bad_trees_name_the_token(text, token, problem):
    with pytest.raises(FormatError) as e:
        parse_tree(text, 3, "t.xml", "WavelengthData 1 block 1 ScatteringData")
    assert e.value.path == "t.xml" and e.value.where.startswith("WavelengthData 1 block 1 ScatteringData")
    assert e.value.where.endswith(token) and problem in e.value.problem


SMALL = tree_document([("Reflection Front", "Visible", tree_text(np.round(tree_grid(MODEL, 3, 2), 3), 1))], 3)
FUZZ = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@FUZZ
@given(at=st.integers(min_value=0, max_value=len(SMALL) - 1), value=st.integers(0, 255), cut=st.booleans())
def test_damaged_tree_documents_raise_one_format_error(at, value, cut):
    import patina

    load_damaged(SMALL.encode(), at, value, cut, "tree.xml", patina.load_brdf)


@FUZZ
@given(
    tokens=st.lists(st.sampled_from(["{", "}", "0.5", "1", "-1", "x", ","]), max_size=60),
    dims=st.sampled_from([3, 4]),
)
def test_random_token_streams_parse_or_raise_one_format_error(tokens, dims):
    try:
        tree = parse_tree(" ".join(tokens), dims, "t.xml", "block")
    except FormatError as e:
        assert e.path == "t.xml" and e.where.startswith("block")
        return
    assert np.all(tree.lookup(np.random.default_rng(0).uniform(0, 1, (20, dims))) >= 0)
