"""The placement steps' input errors as one-line messages naming the capture (`lpnn place`, `bench`, `label`, `demo`)."""

from __future__ import annotations

import contextlib
from typing import Iterator

from ..core.selection import SelectionError
from ..errors import UserError
from ..quality.metric.metric import MetricError
from ..quality.placement.policies import PolicyError
from ..quality.metric.triangulation import GeometryError


@contextlib.contextmanager
def user_errors(source: str) -> Iterator[None]:
    """Turn the quality package's input errors into one-line UserErrors naming the capture."""
    try:
        yield
    except (GeometryError, MetricError, PolicyError, SelectionError) as exc:
        raise UserError(f"{source}: {exc}") from exc
