"""Reference runs and progress bars shared by `lpnn label`, `lpnn place` and `lpnn bench`."""

from __future__ import annotations

import contextlib
from typing import Callable, Iterator

from ..cli.errors import UserError
from ..core.selection import SelectionError
from .arguments import REFERENCE_METHODS
from .decimation import Decimation
from .metric import MetricError, ReferenceField
from .policies import PolicyError
from .reference_faithful import FAITHFUL_MAX_CANDIDATES, faithful_decimation
from .reference_fast import fast_decimation
from .triangulation import GeometryError


def run_reference(field: ReferenceField, method: str, source: str, workers: int | None = None,
                  progress: Callable[[int, int], None] | None = None) -> Decimation:
    """The reference decimation of one capture; UserError when the faithful one would take too long."""
    if method == "faithful":
        if field.point_count > FAITHFUL_MAX_CANDIDATES:
            raise UserError(f"{source}: the faithful decimation is O(n^3) and limited to {FAITHFUL_MAX_CANDIDATES} "
                            f"candidates; this capture has {field.point_count:,}: use --method fast")
        return faithful_decimation(field, progress=progress)
    if method == "fast":
        return fast_decimation(field, workers=workers, progress=progress)
    raise UserError(f"unknown reference method {method!r}: use one of {', '.join(REFERENCE_METHODS)}")


def progress_bar(description: str, disable: bool = False) -> tuple[Callable[[int, int], None], Callable[[], None]]:
    """A tqdm bar driven by progress(done, total) callbacks, and a function that closes it."""
    from tqdm import tqdm

    bar = tqdm(desc=description, unit="probe", disable=disable, leave=False, mininterval=0.5)

    def update(done: int, total: int) -> None:
        bar.total = total
        bar.n = done
        bar.refresh() if done == total else bar.update(0)

    return update, bar.close


@contextlib.contextmanager
def user_errors(source: str) -> Iterator[None]:
    """Turn the quality package's input errors into one-line UserErrors naming the capture."""
    try:
        yield
    except (GeometryError, MetricError, PolicyError, SelectionError) as exc:
        raise UserError(f"{source}: {exc}") from exc
