"""Radiance's variable-resolution BSDF tensor trees (the `ScatteringData` of a BSDF XML
block whose `IncidentDataStructure` is TensorTree3 or TensorTree4): the nested-brace text,
read into flat arrays, and looked up for many direction pairs at once.

The text, as Radiance's `src/common/bsdf_t.c` reads it: a node is `{` ... `}`; it holds
either 2^D child nodes (a branch: child n covers the half of each dimension i whose bit i
of n is set, so dimension 0 varies fastest among the children) or a grid of (2^L)^D
values (a leaf, L >= 0, the last dimension varying fastest). Numbers are separated by
white space or commas. Each dimension spans [0, 1); a lookup takes the value of the cell
that holds the point (no interpolation).

The coordinates (Shirley-Chiu squares of the projected disc, `SDdisk2square`):
- TensorTree4 (anisotropic): (x, y) of the square of (-wi.x, -wi.y), then of (wo.x, wo.y),
  so the mirror direction of wi has the same square position as wi;
- TensorTree3 (isotropic): wo turned about the normal so that wi lies at azimuth 180
  degrees, then 0.5 - 0.5 sin(theta_i) and the square of the turned (wo.x, wo.y); the
  upper half of the first dimension is unused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from patina.errors import FormatError

MAX_DEPTH = 24  # branch levels; Radiance's trees are 4-7 deep
MAX_LEAF_LOG2 = 12  # a leaf grid of 2^12 per dimension at most


@dataclass
class TensorTree:
    """A parsed tree: node k is a branch when log2[k] < 0 (its children are
    children[first[k] : first[k] + 2^D]) or a leaf grid of (2^log2[k])^D values
    starting at values[first[k]]."""

    dims: int
    log2: np.ndarray
    first: np.ndarray
    children: np.ndarray
    values: np.ndarray

    def lookup(self, points: np.ndarray) -> np.ndarray:
        """The value of the cell holding each point (N, D) of [0, 1)^D."""
        p = np.clip(np.asarray(points, dtype=np.float64), 0.0, np.nextafter(1.0, 0.0))
        node = np.zeros(len(p), dtype=np.int64)
        for _ in range(MAX_DEPTH + 1):
            branch = np.flatnonzero(self.log2[node] < 0)
            if branch.size == 0:
                break
            q = 2.0 * p[branch]
            upper = q >= 1.0
            child = (upper.astype(np.int64) << np.arange(self.dims)).sum(axis=1)
            node[branch] = self.children[self.first[node[branch]] + child]
            p[branch] = q - upper
        size = np.int64(1) << self.log2[node]
        cell = np.minimum((p * size[:, None]).astype(np.int64), size[:, None] - 1)
        flat = np.zeros(len(p), dtype=np.int64)
        for i in range(self.dims):
            flat = flat * size + cell[:, i]
        return self.values[self.first[node] + flat]


def parse_tree(text: str, dims: int, path: str, where: str) -> TensorTree:
    """The tree in `text` (D = dims); FormatError naming `where` and the token on any fault."""
    tokens = text.replace("{", " { ").replace("}", " } ").replace(",", " ").split()
    log2: list[int] = []
    first: list[int] = []
    children: list[int] = []
    chunks: list[np.ndarray] = []
    count = [0]  # values so far

    def fail(at: int, problem: str) -> FormatError:
        return FormatError(path, f"{where}, token {at + 1}", problem)

    def node(at: int, depth: int) -> int:
        """Parses the node starting at token `at`; returns the token after its `}`."""
        if at >= len(tokens):
            raise fail(at, "the tree ends early: '{' expected")
        if tokens[at] != "{":
            raise fail(at, f"'{tokens[at][:20]}': '{{' expected")
        if depth > MAX_DEPTH:
            raise fail(at, f"the tree is more than {MAX_DEPTH} levels deep")
        k = len(log2)
        log2.append(-1)
        first.append(0)
        at += 1
        if at < len(tokens) and tokens[at] == "{":
            first[k] = len(children)
            children.extend([0] * (1 << dims))
            for n in range(1 << dims):
                children[first[k] + n] = len(log2)
                at = node(at, depth + 1)
        else:
            end = at
            while end < len(tokens) and tokens[end] not in ("{", "}"):
                end += 1
            n = end - at
            grid = round(math.log2(n) / dims) if n else -1
            if n == 0 or grid > MAX_LEAF_LOG2 or 1 << (grid * dims) != n:
                raise fail(at, f"a leaf of {n} values: expected 2^({dims} k) (1, {1 << dims}, {1 << 2 * dims}, ...)")
            try:
                leaf = np.array(tokens[at:end], dtype=np.float64)
            except ValueError:
                bad = next(i for i in range(at, end) if not _is_number(tokens[i]))
                raise fail(bad, f"'{tokens[bad][:20]}' is not a number") from None
            wrong = ~np.isfinite(leaf) | (leaf < 0)
            if wrong.any():
                i = int(np.argmax(wrong))
                raise fail(at + i, f"{leaf[i]:g}: negative or not finite")
            log2[k], first[k] = grid, count[0]
            chunks.append(leaf)
            count[0] += n
            at = end
        if at >= len(tokens) or tokens[at] != "}":
            raise fail(at, "'}' expected" + ("" if at < len(tokens) else ": the tree ends early"))
        return at + 1

    if not tokens:
        raise FormatError(path, where, "no tensor tree (empty ScatteringData)")
    end = node(0, 0)
    if end != len(tokens):
        raise fail(end, f"'{tokens[end][:20]}' after the end of the tree")
    return TensorTree(
        dims,
        np.array(log2, dtype=np.int64),
        np.array(first, dtype=np.int64),
        np.array(children, dtype=np.int64),
        np.concatenate(chunks),
    )


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def disk_to_square(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Shirley and Chiu's concentric map, inverse: points of the unit disc to [0, 1]^2 (N, 2),
    with Radiance's orientation (SDdisk2square)."""
    r = np.hypot(x, y)
    phi = np.arctan2(y, x)
    phi = np.where(phi < -math.pi / 4, phi + 2 * math.pi, phi)  # [-pi/4, 7 pi/4)
    quarter = math.pi / 4
    a = np.select(
        [phi < quarter, phi < 3 * quarter, phi < 5 * quarter],
        [r, -(phi - math.pi / 2) * r / quarter, -r],
        -(phi - 3 * math.pi / 2) * -r / quarter,
    )
    b = np.select(
        [phi < quarter, phi < 3 * quarter, phi < 5 * quarter],
        [phi * r / quarter, r, (phi - math.pi) * -r / quarter],
        -r,
    )
    return np.stack([(a + 1) * 0.5, (b + 1) * 0.5], axis=1)


def tree_coordinates(dims: int, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
    """The tree's position (N, dims) of each direction pair (upper hemisphere, wi towards the light)."""
    if dims == 4:
        return np.concatenate([disk_to_square(-wi[:, 0], -wi[:, 1]), disk_to_square(wo[:, 0], wo[:, 1])], axis=1)
    turn = -np.arctan2(-wi[:, 1], -wi[:, 0])  # Radiance's spinvector: -wi onto the +x axis
    c, s = np.cos(turn), np.sin(turn)
    x = c * wo[:, 0] - s * wo[:, 1]
    y = s * wo[:, 0] + c * wo[:, 1]
    first = 0.5 - 1e-6 - 0.5 * np.hypot(wi[:, 0], wi[:, 1])
    return np.concatenate([first[:, None], disk_to_square(x, y)], axis=1)
