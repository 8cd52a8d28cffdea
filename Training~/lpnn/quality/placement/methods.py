"""The table of placement methods (Documentation~/methods.md): one name per method, used by `lpnn place --method`,
`lpnn bench`'s rows and --methods, the demo, the recipe's evaluation, the model card's metrics and the docs.

The C# core holds the same rows for the methods it implements (Runtime/Core/Selection/PlacementMethod.cs,
`PlacementMethods`); both are pinned to the hand-written Tests/Data/placement_methods.json by a test in each
language (tests/quality/test_placement_methods.py, Tests/Core/PlacementMethodsTests.cs), so neither can drift.

Light on purpose (dataclasses only): the CLI builds `--method`'s choices and help from it at `lpnn --help` time,
before any heavy import.
"""

from __future__ import annotations

from dataclasses import dataclass

PYTHON = "Python"
CSHARP = "C#"

# The seed factor of the refined tiers: the seed holds this many times the wanted count. The CLI fixes it (a method's
# name names one placement); code that measures other factors (Tools~/experiments/refine-trade.py) passes its own to
# the Python API (lpnn_placement's `refine`, refined_insertion's `refine`).
RECOMMENDED_REFINE = 2.0

EXACT = "exact"  # refinement by the seeded exact greedy (decimation)
BATCHED = "batched"  # refinement in batches (batched_refinement.py, quality.md §5.3)


@dataclass(frozen=True)
class PlacementMethod:
    """One row of the table. `needs_scores`: the method reads the network's scores (`lpnn place` then wants --model or
    --scores); `placeable`: `lpnn place --method` offers it (False: a yardstick only `lpnn bench` computes).
    For the methods that read the scores, how `lpnn_placement` runs them: `guided` (ranks by insertion guided by the
    scores), `refinement` (None, EXACT or BATCHED, seeded by the guided insertion) and `topk` (the raw top-K)."""

    name: str
    label: str  # what the inspector and the demo print
    summary: str  # what it does, one line (`lpnn place --help`)
    needs_scores: bool
    languages: tuple[str, ...]
    placeable: bool = True
    guided: bool = False
    refinement: str | None = None
    topk: bool = False

    def lpnn_options(self, refine: float = RECOMMENDED_REFINE) -> dict[str, object]:
        """Keyword arguments of quality.placement.lpnn_placement.lpnn_placement for this method (one that reads the
        scores), with `refine` the refined tiers' seed factor."""
        if not self.needs_scores:
            raise ValueError(f"{self.name} does not read the network's scores: it is no LPNN tier")
        if self.refinement is not None:
            return {"refine": refine, "batched": self.refinement == BATCHED}
        return {"guided": self.guided, "topk": self.topk}


METHODS: tuple[PlacementMethod, ...] = (
    PlacementMethod("insertion-refined", "Insertion, refined",
                    "coarse-to-fine error-driven insertion, then refinement in batches (the default)",
                    False, (PYTHON, CSHARP), refinement=BATCHED),
    PlacementMethod("insertion", "Insertion", "coarse-to-fine error-driven insertion alone", False, (PYTHON, CSHARP)),
    PlacementMethod("guided-refined", "Guided insertion, refined",
                    "insertion guided by the network's scores, then refinement in batches",
                    True, (PYTHON, CSHARP), guided=True, refinement=BATCHED),
    PlacementMethod("guided", "Guided insertion", "insertion guided by the network's scores", True, (PYTHON, CSHARP),
                    guided=True),
    PlacementMethod("network", "Network", "the spread ranking of the network's scores (milliseconds)", True,
                    (PYTHON, CSHARP)),
    PlacementMethod("network-topk", "Network, top-K", "the raw top-K of the network's scores (for comparison)", True,
                    (PYTHON,), topk=True),
    PlacementMethod("guided-exact-refined", "Guided insertion, exact refinement",
                    "guided insertion's first 2K points refined by the exact greedy down to K (minutes on a level)",
                    True, (PYTHON,), guided=True, refinement=EXACT),
    PlacementMethod("fast-reference", "Fast reference", "the exact greedy decimation of every point (the yardstick)",
                    False, (PYTHON,)),
    PlacementMethod("leak-aware-reference", "Leak-aware reference",
                    "the exact greedy decimation of the leak-weighted error (the leak-aware default's yardstick; "
                    "needs the capture's geometry)", False, (PYTHON,)),
    PlacementMethod("uniform", "Uniform lattice", "a uniform lattice of K points", False, (PYTHON,)),
    PlacementMethod("heuristic", "Curvature heuristic", "curvature-weighted farthest-point sampling", False, (PYTHON,)),
    PlacementMethod("apv", "APV-style density", "an APV-style geometry density (denser near surfaces)", False,
                    (PYTHON,)),
    PlacementMethod("random", "Random", "random points (seeded by --seed)", False, (PYTHON,)),
    PlacementMethod("faithful-reference", "Faithful reference",
                    "the paper's greedy decimation, step by step (lpnn bench only, on captures of <= 200 points)",
                    False, (PYTHON,), placeable=False),
    PlacementMethod("blockwise-reference", "Blockwise reference",
                    "the greedy decimation block by block (lpnn bench's yardstick above its full-reference limit)",
                    False, (PYTHON,), placeable=False),
)

BY_NAME: dict[str, PlacementMethod] = {method.name: method for method in METHODS}
DEFAULT_METHOD = "insertion-refined"  # the Unity volume's default too (PlacementMethods.Default)
PLACEABLE = tuple(method.name for method in METHODS if method.placeable)  # `lpnn place --method`'s choices
SCORED = tuple(method.name for method in METHODS if method.needs_scores)  # the LPNN tiers
# Every method `lpnn bench --methods` can name: all but the yardsticks, which always run (fast or blockwise reference).
BENCH_METHODS = tuple(method.name for method in METHODS if method.name not in ("fast-reference", "blockwise-reference"))


def placement_method(name: str) -> PlacementMethod:
    """The row called `name`; KeyError naming the known ones otherwise."""
    try:
        return BY_NAME[name]
    except KeyError:
        raise KeyError(f"unknown placement method {name!r}; the methods are {', '.join(BY_NAME)}") from None
