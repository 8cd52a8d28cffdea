"""The progress bar of `lpnn label` and `lpnn place`'s reference runs."""

from __future__ import annotations

from typing import Callable


def progress_bar(description: str, disable: bool = False) -> tuple[Callable[[int, int], None], Callable[[], None]]:
    """A tqdm bar driven by progress(done, total) callbacks, and a function that closes it."""
    from tqdm import tqdm

    bar = tqdm(desc=description, unit="probe", disable=disable, leave=False, mininterval=0.5)

    def update(done: int, total: int) -> None:
        bar.total = total
        bar.n = done
        bar.refresh() if done == total else bar.update(0)

    return update, bar.close
