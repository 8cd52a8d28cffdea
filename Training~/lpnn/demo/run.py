"""The README's main job: one real level the shipped model never saw, placed with the tolerance policy
and compared with the reference and the baselines (Documentation~/benchmarks.md "Demo").

Steps, each timed: import (BSP, grid, solid test, light grid SH, features — what Unity's steps 1–4 do),
inference (onnxruntime, after one warm-up run, as a Unity worker is created once per model), selection:
insertion-refined (the package's default, quality.md §5.3: its insertion rounds and tolerance search timed
as selection, the batched refinement as refinement), guided-refined (insertion guided by the scores, refined the same
way), guided (quality.md §5.2), network (the spread ranking: the milliseconds tier) and guided-exact-refined (the
guided insertion's seed decimated by the exact greedy); names and labels from Documentation~/methods.md.
The fast reference (leak-blind), the leak-aware reference (the exact greedy of the leak-weighted error the default
refines, quality.md §3.2: the default's own yardstick, when the level's geometry is known) and the baselines run
afterwards, for comparison only.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..core.capture import Capture
from ..core.grid import EvaluationGrid
from ..quality.placement.policy_rules import DEFAULT_TOLERANCE
from ..quality.placement.baselines import heuristic_ranking, uniform_selector
from ..quality.metric.leaks import field_with_geometry
from ..quality.placement.insertion import guide_of, insertion_ranking
from ..quality.placement.decimation.decimation import Decimation
from ..quality.placement.lpnn_placement import LpnnPlacement, lpnn_placement
from ..quality.placement.methods import BATCHED, BY_NAME, DEFAULT_METHOD
from ..quality.metric.metric import PlacementQuality, ReferenceField, evaluate_placement
from ..quality.placement.policies import SelectionForCount, place_tolerance, prefix_selection, reference_tolerance
from ..quality.placement.decimation.reference_fast import fast_decimation
from ..quality.placement.leak_aware import LeakWeighting, leaks_to_avoid
from ..quality.placement.refined_insertion import refined_insertion

Log = Callable[[str], None]
PRIMARY = DEFAULT_METHOD  # the package's default (Unity: Method = Insertion, refined): probes.json


@dataclass(frozen=True)
class MethodResult:
    method: str
    indices: np.ndarray  # probes kept (sorted point indices)
    quality: PlacementQuality
    seconds: dict[str, float]  # stage -> seconds (placement only; reporting is not timed)

    @property
    def probes(self) -> int:
        return int(self.indices.shape[0])


@dataclass
class DemoResult:
    level: str
    capture: Capture
    held_out: bool | None  # the level is in the model card's held-out list (None: the card has no recipe)
    import_seconds: dict[str, float]
    scores: np.ndarray
    tolerance: float
    methods: dict[str, MethodResult] = field(default_factory=dict)
    reference: Decimation | None = None
    same_count: dict[str, PlacementQuality] = field(default_factory=dict)  # every method at the PRIMARY method's count
    curves: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)  # method -> (counts, errors)
    # The default placed on every point of the volume (rule `all`, the old behaviour) when the demo's capture holds the
    # points in use only: its capture (with the `in_use` section) and its answer, whose error at those points shows
    # the dilution by the air.
    every_point: Capture | None = None
    every_point_default: MethodResult | None = None
    compile_seconds: float = 0.0  # numba's compilation of the import's and placement's kernels, before anything is timed


def held_out_in_card(card: Any, level: str) -> bool | None:
    """Whether the card lists `level` as held out; None when the card does not say (not made by the recipe)."""
    recipe = card.training.get("recipe") if isinstance(card.training, dict) else None
    levels = recipe.get("levels") if isinstance(recipe, dict) else None
    held_out = levels.get("held_out") if isinstance(levels, dict) else None
    if not isinstance(held_out, list):
        return None
    return level in held_out


def _lpnn(name: str, placement: LpnnPlacement, inference: float) -> MethodResult:
    t = placement.timing
    seconds = {"features": t.features or 0.0, "inference": inference, "selection": t.selection}
    if placement.refine is not None:
        seconds["refinement"] = t.refinement
    return MethodResult(name, placement.indices, placement.quality, seconds)


def _default_placement(capture: Capture, tolerance: float, field_: ReferenceField | None = None,
                       grid: EvaluationGrid | None = None) -> MethodResult:
    """The package's default on a capture: insertion refined in batches at the tolerance, leak-aware with the level's
    geometry (leaks.md "A leak-aware default"; the demo's OpenArena levels have it), timed."""
    field_ = field_with_geometry(capture) if field_ is None else field_
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids) if grid is None else grid
    placed = refined_insertion(field_, grid, tolerance=tolerance, leaks=leaks_to_avoid(field_))
    return MethodResult("insertion-refined", placed.indices, evaluate_placement(field_, placed.indices),
                        {"selection": placed.selection_seconds, "refinement": placed.refinement_seconds})


def _searched(name: str, field_: ReferenceField, select: SelectionForCount, tolerance: float,
              ranking_seconds: float) -> MethodResult:
    start = time.perf_counter()
    placement = place_tolerance(field_, select, tolerance)
    seconds = {"selection": ranking_seconds + time.perf_counter() - start}
    return MethodResult(name, placement.indices, evaluate_placement(field_, placement.indices), seconds)


def curve_counts(point_count: int, samples: int = 24) -> np.ndarray:
    """Probe counts from 4 to N, evenly spaced on a log axis, distinct."""
    if point_count <= 4:
        return np.array([point_count], dtype=np.int64)
    counts = np.geomspace(4, point_count, samples)
    return np.unique(np.round(counts).astype(np.int64))


def run_demo(capture: Capture, level: str, scorer: Any, import_seconds: dict[str, float], held_out: bool | None,
             tolerance: float = DEFAULT_TOLERANCE, log: Log = print, every_point: Capture | None = None,
             compile_seconds: float = 0.0) -> DemoResult:
    """Every method on the imported `capture`, timed. `compile_seconds`: the warm-up the caller ran before the import
    (quality/placement/warmup.py), reported apart so that no method's time holds numba's compilation."""
    field_ = field_with_geometry(capture)  # with the level's surfaces: every method's leaks are reported
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    n = capture.point_count

    scorer.score_capture(capture, level)  # warm-up: onnxruntime optimises the graph on the first run
    start = time.perf_counter()
    scores = scorer.score_capture(capture, level)
    inference = time.perf_counter() - start
    result = DemoResult(level, capture, held_out, import_seconds, scores, tolerance)
    result.compile_seconds = compile_seconds

    log(f"placing: {BY_NAME[PRIMARY].label} ({PRIMARY}, the package's default), tolerance {tolerance:g}")
    result.methods["insertion-refined"] = _default_placement(capture, tolerance, field_, grid)
    if every_point is not None:
        log(f"placing: the default on every point of the volume (rule all, {every_point.point_count:,} points)")
        result.every_point = every_point
        result.every_point_default = _default_placement(every_point, tolerance)
    lpnn = {}  # name -> its LpnnPlacement, each run as the table says (quality/placement/methods.py)
    # full_ranking=False: guided insertion ranks only as far as the tolerance search reads (as `lpnn place` does)
    for name, full_ranking in (("guided-refined", True), ("guided", False), ("network", True),
                               ("guided-exact-refined", True)):
        log(f"placing: {BY_NAME[name].label} ({name}), tolerance {tolerance:g}")
        leaks = leaks_to_avoid(field_) if BY_NAME[name].refinement == BATCHED else None  # as the default (leaks.md)
        lpnn[name] = lpnn_placement(capture, scores=scores, tolerance=tolerance, reference=field_, name=level,
                                    full_ranking=full_ranking, leaks=leaks, **BY_NAME[name].lpnn_options())
        result.methods[name] = _lpnn(name, lpnn[name], inference)

    log("comparing: fast reference (exact greedy decimation; seconds)")
    start = time.perf_counter()
    reference = fast_decimation(field_, workers=1)
    reference_seconds = time.perf_counter() - start
    target = reference_tolerance(reference, tolerance)
    result.reference = reference
    result.methods["fast-reference"] = MethodResult("fast-reference", target.indices,
                                                    evaluate_placement(field_, target.indices),
                                                    {"reference": reference_seconds})
    raycaster = leaks_to_avoid(field_)
    if raycaster is not None:  # the default is leak-aware here: its own yardstick too (seconds on the demo's level)
        log("comparing: leak-aware reference (exact greedy decimation of the leak-weighted error; seconds)")
        start = time.perf_counter()
        aware = fast_decimation(field_, workers=1, leaks=LeakWeighting(raycaster))
        aware_seconds = time.perf_counter() - start
        answer = reference_tolerance(aware, tolerance)
        result.methods["leak-aware-reference"] = MethodResult("leak-aware-reference", answer.indices,
                                                              evaluate_placement(field_, answer.indices),
                                                              {"reference": aware_seconds})
    log("comparing: uniform grid, heuristic and insertion (the best non-learned method, quality.md)")
    uniform = uniform_selector(grid)
    start = time.perf_counter()
    heuristic = heuristic_ranking(grid, capture.sh, capture.lighting_scale)
    heuristic_seconds = time.perf_counter() - start
    heuristic_select = prefix_selection(grid, heuristic)
    result.methods["uniform"] = _searched("uniform", field_, uniform, tolerance, 0.0)
    result.methods["heuristic"] = _searched("heuristic", field_, heuristic_select, tolerance, heuristic_seconds)
    start = time.perf_counter()
    insertion = insertion_ranking(field_, grid)
    insertion_seconds = time.perf_counter() - start
    insertion_select = prefix_selection(grid, insertion)
    result.methods["insertion"] = _searched("insertion", field_, insertion_select, tolerance, insertion_seconds)

    count = result.methods[PRIMARY].probes
    guided_select = prefix_selection(grid, insertion_ranking(field_, grid, guide=guide_of(scores)))  # for the curves
    selections: dict[str, SelectionForCount] = {
        "guided": guided_select, "network": prefix_selection(grid, lpnn["network"].ranking), "uniform": uniform,
        "heuristic": heuristic_select, "insertion": insertion_select,
        "fast-reference": lambda k: reference.prefix(max(k, reference.smallest_count))}
    result.same_count = {name: evaluate_placement(field_, select(count)) for name, select in selections.items()}
    result.same_count[PRIMARY] = result.methods[PRIMARY].quality  # not a ranking's prefix: its own answer
    counts = curve_counts(n)
    for name, select in selections.items():
        if name == "fast-reference":
            result.curves[name] = (np.arange(reference.smallest_count, n + 1),
                                   reference.error_curve[reference.smallest_count:])
        else:
            errors = np.array([evaluate_placement(field_, select(int(k))).irradiance.mean for k in counts])
            result.curves[name] = (counts, errors)
    return result
