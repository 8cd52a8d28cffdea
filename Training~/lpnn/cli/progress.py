"""The progress bars of `lpnn label` and `lpnn place`: probes for the runs that remove or rank one probe at a time (the
references, batched refinement), rounds for insertion (each round ranks a batch of points)."""

from __future__ import annotations

from typing import Callable


def progress_bar(description: str, disable: bool = False) -> tuple[Callable[[int, int], None], Callable[[], None]]:
    """A tqdm bar of probes driven by progress(done, total) callbacks, and a function that closes it."""
    from tqdm import tqdm

    bar = tqdm(desc=description, unit="probe", disable=disable, leave=False, mininterval=0.5)

    def update(done: int, total: int) -> None:
        bar.total = total
        bar.n = done
        bar.refresh() if done == total else bar.update(0)

    return update, bar.close


def rounds_bar(description: str, disable: bool = False) -> tuple[Callable[[int, int], None], Callable[[], None]]:
    """A tqdm bar of insertion rounds: each progress(ranked, asked) callback is one round, counted as such (its rate in
    rounds per second or seconds per round), with the points ranked so far of those asked for beside it. No total: the
    tolerance search asks for more points as it goes."""
    from tqdm import tqdm

    bar = tqdm(desc=description, unit="round", disable=disable, leave=False, mininterval=0.5)

    def update(ranked: int, asked: int) -> None:  # shown every round: there are a few dozen at most
        bar.update(1)
        bar.set_postfix_str(f"{ranked:,} of {asked:,} points ranked")

    return update, bar.close
