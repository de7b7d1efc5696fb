"""Shared fixtures of the Python tests (run by ctest as python.pytest, or by hand:
PYTHONPATH=build/python /usr/bin/python3 -m pytest python/tests)."""

import os

import numpy as np
import pytest

SOURCE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


@pytest.fixture
def counts():
    """A small corpus of counts with two clear topics (60 documents, 20 words)."""
    rng = np.random.RandomState(0)
    topics = np.zeros((2, 20))
    topics[0, :10] = 1.0 / 10
    topics[1, 10:] = 1.0 / 10
    rows = []
    for d in range(60):
        theta = rng.dirichlet([0.2, 0.2])
        p = theta @ topics
        rows.append(rng.multinomial(30, p))
    return np.array(rows, dtype=np.int64)
