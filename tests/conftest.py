import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED_DATA = os.path.normpath(os.path.join(ROOT, "..", "shared", "data"))
LOCAL_DATA = os.path.join(HERE, "data")
sys.path.insert(0, HERE)


def data_file(name: str) -> str:
    """A CAD file from tests/data (licensed copies) or ../shared/data; skip when absent."""
    for d in (LOCAL_DATA, SHARED_DATA):
        p = os.path.join(d, name)
        if os.path.exists(p):
            return p
    pytest.skip(f"{name} is not available (needs ../shared/data beside the repository)")


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
