"""A missing golden file fails its test: the cross-language suites never drop out silently."""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import pytest


def test_a_missing_golden_file_fails_instead_of_skipping(golden_path: Callable[[str], Path]) -> None:
    with pytest.raises(BaseException) as raised:  # BaseException: pytest's skip and fail outcomes are not Exceptions
        golden_path("no_such_golden.json")
    assert raised.type is pytest.fail.Exception, f"a missing golden file gave {raised.type.__name__}, not a failure"
    assert "golden file missing" in str(raised.value) and "regenerate-golden.sh" in str(raised.value)
