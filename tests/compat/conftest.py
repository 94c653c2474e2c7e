"""Fixtures for the compatibility tests."""

from __future__ import annotations

from pathlib import Path

import pytest
from compat_support import DATA


@pytest.fixture
def data() -> Path:
    """The fixture folder."""
    return DATA
