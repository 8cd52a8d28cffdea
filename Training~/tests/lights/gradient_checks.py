"""Checks the light-rig tests share for the objective's gradient (lights.md §3): closeness of two gradients, the same
bits on 1 and 2 threads, and central finite differences."""

from __future__ import annotations

from typing import Callable, Sequence

import numpy as np
import pytest

from lpnn.lights.model import ForwardModel, Gradient, Lights


def assert_close(a: Gradient, b: Gradient, tolerance: float, fields: Sequence[str]) -> None:
    """The value within a relative `tolerance`, and each field within `tolerance` of b's largest component."""
    assert a.value == pytest.approx(b.value, rel=tolerance)
    for name in fields:
        x, y = getattr(a, name), getattr(b, name)
        scale = np.max(np.abs(y))
        assert scale > 0, name  # every parameter takes part: the comparison is not of zeros
        assert np.max(np.abs(x - y)) <= tolerance * scale, name


def objectives_on_threads(model: ForwardModel, lights: Lights, visible: np.ndarray,
                          threads: Sequence[int] = (1, 2, 1)) -> list[Gradient]:
    """The objective and gradient computed on each thread count in turn (the model left on 1 thread)."""
    runs = []
    for count in threads:
        model.threads = count
        runs.append(model.objective(lights, visible))
    model.threads = 1
    return runs


def assert_same_bits(runs: Sequence[Gradient], fields: Sequence[str]) -> None:
    for run in runs[1:]:
        assert run.value == runs[0].value
        for name in fields:
            assert np.array_equal(getattr(run, name), getattr(runs[0], name)), name


def finite_difference(model: ForwardModel, lights: Lights, visible: np.ndarray, steps: dict[str, float],
                      skip: Callable[[str, tuple[int, ...]], bool] | None = None) -> dict[str, np.ndarray]:
    """Central differences of the objective per named parameter array, with that name's step; entries `skip` names
    stay 0."""
    out = {}
    for name, step in steps.items():
        values = getattr(lights, name)
        numeric = np.zeros_like(values)
        for index in np.ndindex(values.shape):
            if skip is not None and skip(name, index):
                continue
            kept = values[index]
            values[index] = kept + step
            up = model.objective(lights, visible, with_gradient=False).value
            values[index] = kept - step
            down = model.objective(lights, visible, with_gradient=False).value
            values[index] = kept
            numeric[index] = (up - down) / (2 * step)
        out[name] = numeric
    return out
