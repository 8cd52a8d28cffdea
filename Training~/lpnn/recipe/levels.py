"""Which levels train, validate and test: fixed rules on the alphabetical level list."""

from __future__ import annotations

from dataclasses import dataclass

from .config import RecipeConfig


@dataclass(frozen=True)
class LevelSplit:
    train: tuple[str, ...]
    validation: tuple[str, ...]
    held_out: tuple[str, ...]

    def role(self, level: str) -> str:
        if level in self.held_out:
            return "held_out"
        return "validation" if level in self.validation else "train"


def split_levels(names: list[str], config: RecipeConfig) -> LevelSplit:
    """Held-out = every k-th level from an offset; validation likewise among the rest; train = the others."""
    ordered = sorted(names)
    held_out = tuple(ordered[config.held_out_offset::config.held_out_every])
    rest = [n for n in ordered if n not in held_out]
    validation = tuple(rest[config.validation_offset::config.validation_every])
    train = tuple(n for n in rest if n not in validation)
    if not train or not validation or not held_out:
        raise ValueError(f"the level split of {len(ordered)} levels leaves an empty part "
                         f"(train {len(train)}, validation {len(validation)}, held out {len(held_out)})")
    return LevelSplit(train=train, validation=validation, held_out=held_out)
