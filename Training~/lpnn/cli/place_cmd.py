"""`lpnn place`: probe positions for a capture by one of the placement methods (Documentation~/methods.md).

  lpnn place CAPTURE [--method NAME] [--model M.onnx | --scores SCORES.csv] [--no-report]
             [--keep PINS.json [--keep-distance D]] [--leaks avoid|ignore]
             (--budget FRACTION | --tolerance TAU) --out PROBES.json

--method names the method (quality/placement/methods.py, the one table): insertion-refined (the default, quality.md
§5.3: the best method measured where the capture's dense lighting is available, which `lpnn place` always has, and
what a new Unity volume does; benchmarks.md "The speed/accuracy trade, every method": 1.01x the reference's probes at tau = 0.05 on the validation crops,
where insertion alone keeps 1.66x and guided-refined 1.04x), insertion, the methods that read the network's scores
(guided-refined, guided, network: the spread ranking, milliseconds; network-topk; guided-exact-refined: closest to
the reference, 1.00x, at minutes on large levels), the fast reference, the leak-aware reference (the exact greedy of the
leak-weighted error the default refines: its yardstick, quality.md §3.2; needs the capture's geometry, one process) and
the baselines (uniform, heuristic, apv, random). --model M.onnx or --scores SCORES.csv (what `lpnn score` writes:
index,i,j,k,score) only supply the scores: required by the methods that read them, refused by the others. The refined
methods' seed factor is RECOMMENDED_REFINE (2).

Budget keeps the first FRACTION of the ranking; tolerance keeps the smallest prefix whose mean
placement error is <= TAU (Documentation~/quality.md §4). Both end with the tetrahedron guarantee.
--keep PINS.json (a *.probes.json, e.g. the artist's probes exported from Unity; Documentation~/pins.md): every
probe in it is kept, counted in the budget and the error, and no new probe comes within --keep-distance (default one
cell) of one; insertion-refined, insertion and the ranking methods (heuristic, apv, random: pins first)
take it; the references, the uniform lattice and the methods that read the scores refuse it. The file written holds
the pins at their own positions.
Prints the probes kept, the error and (methods that read the scores) the time split; --no-report (those methods) skips
the final error evaluation, which at 10^6 points costs as much as the placement itself (benchmarks.md "Scale: whole levels").
--leaks avoid (the default) makes the methods refined in batches (insertion-refined, guided-refined) leak-aware where
the capture's geometry is known (leaks.md "A leak-aware default": more probes, far fewer points lit through a wall);
--leaks ignore places leak-blind (fewer probes, leaks accepted). The references keep their names: fast-reference is
leak-blind, leak-aware-reference leak-aware (it refuses --leaks ignore).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

    from ..core.capture import Capture
    from ..core.features import Raycaster
    from ..quality.metric.metric import PlacementQuality, ReferenceField
    from ..quality.placement.leak_aware import LeakWeighting
    from ..quality.placement.pins import Pins



def register(subparsers: argparse._SubParsersAction) -> None:
    from ..quality.placement.methods import BY_NAME, DEFAULT_METHOD, PLACEABLE
    from ..quality.placement.policy_rules import LEAK_CHOICES
    from .arguments import add_policy_arguments

    parser = subparsers.add_parser("place", help="place probes in a capture (budget or error tolerance)",
                                   description="Choose probe positions for a capture and write *.probes.json.",
                                   formatter_class=argparse.RawDescriptionHelpFormatter,
                                   epilog="methods (Documentation~/methods.md):\n" + "\n".join(
                                       f"  {name:<22}{BY_NAME[name].summary}"
                                       + (" [needs --model or --scores]" if BY_NAME[name].needs_scores else "")
                                       for name in PLACEABLE))
    parser.add_argument("capture", metavar="CAPTURE", help="capture file (*.lpnncap)")
    parser.add_argument("--method", choices=PLACEABLE, default=DEFAULT_METHOD, metavar="NAME",
                        help=f"the placement method (default {DEFAULT_METHOD}; listed below): " + ", ".join(PLACEABLE))
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--model", metavar="M.onnx",
                        help="the network's scores for the methods that read them: score the points with this model "
                             "(and its card)")
    source.add_argument("--scores", metavar="SCORES.csv",
                        help="the network's scores for the methods that read them, from `lpnn score` (index,i,j,k,score)")
    add_policy_arguments(parser)
    parser.add_argument("--out", required=True, metavar="PROBES.json", help="output probe positions")
    parser.add_argument("--seed", type=int, default=0, help="seed of --method random (default 0)")
    parser.add_argument("--keep", metavar="PINS.json",
                        help="probes to keep (a *.probes.json in the capture's units; Documentation~/pins.md): every "
                             "method keeps them, counts them in the budget and the error, and puts no new probe near one")
    parser.add_argument("--keep-distance", type=float, metavar="D",
                        help="with --keep: no new probe closer than D to a kept probe (capture units; default one cell)")
    parser.add_argument("--leaks", choices=LEAK_CHOICES, default="avoid",
                        help="the methods refined in batches (insertion-refined, guided-refined): avoid light leaking through "
                             "walls where the capture's geometry is known "
                             "(the default; Documentation~/leaks.md: more probes, far fewer leaking points) or ignore them "
                             "(fewer probes, leaks accepted)")
    parser.add_argument("--no-report", action="store_true",
                        help="with a method that reads the scores: skip the final error evaluation (the dense lighting "
                             "of every point, one tetrahedralisation of the probes, every point located; ~half of a "
                             "budget placement at 10^6 points): the probe file then holds no p95 error, and a mean "
                             "error only with --tolerance (the search's, for the kept prefix)")
    parser.add_argument("--workers", type=int, choices=(1, 2),
                        help="processes for --method fast-reference and guided-exact-refined (default 1; 2 helps only "
                             "on an idle second core)")
    parser.set_defaults(handler=run)


def method_problem(method: str, scored: bool, no_report: bool) -> str | None:
    """Why `lpnn place --method METHOD` cannot run with (`scored`) or without scores, or with --no-report; None when it
    can. The rule is the table's `needs_scores`."""
    from ..quality.placement.methods import BY_NAME, SCORED

    if BY_NAME[method].needs_scores and not scored:
        return (f"--method {method} reads the network's scores: add --model M.onnx (or --scores SCORES.csv from "
                f"`lpnn score`)")
    if not BY_NAME[method].needs_scores and scored:
        return (f"--method {method} needs no model: drop --model/--scores, or choose a method that reads the scores "
                f"({', '.join(SCORED)})")
    if no_report and not BY_NAME[method].needs_scores:
        return (f"--no-report applies to the methods that read the network's scores ({', '.join(SCORED)}), "
                f"not to --method {method}")
    return None


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..core.capture_file import read_capture
    from ..core.validity import BACK_FACE_THRESHOLD, valid_points, without_invalid
    from ..errors import UserError
    from .errors import user_errors

    from ..quality.placement.methods import BY_NAME

    problem = method_problem(args.method, args.model is not None or args.scores is not None, args.no_report)
    if problem:
        raise UserError(problem)
    if args.keep_distance is not None and args.keep is None:
        raise UserError("--keep-distance applies to pinned probes: give it with --keep PINS.json")
    if args.keep is not None and BY_NAME[args.method].needs_scores:
        raise UserError(f"--keep does not apply to --method {args.method} (the methods that read the scores) yet: use "
                        "--method insertion-refined (the default), which keeps the pins")
    if args.keep is not None and args.method == "uniform":
        raise UserError("--keep does not apply to --method uniform: a lattice of K points is no ranking the pins could "
                        "head; use --method insertion-refined (the default) or a ranking method (heuristic, apv, random)")
    if args.keep is not None and args.method in ("fast-reference", "leak-aware-reference"):
        raise UserError(f"--keep does not apply to --method {args.method}: the references are pin-free yardsticks "
                        "(a full greedy decimation of every point); use --method insertion-refined (the default) to "
                        "keep the pins")
    if args.method == "leak-aware-reference" and args.leaks == "ignore":
        raise UserError("--method leak-aware-reference with --leaks ignore is the leak-blind reference: use --method "
                        "fast-reference")
    if args.method == "leak-aware-reference" and args.workers == 2:
        raise UserError("--method leak-aware-reference runs in one process (its second process would need the level's "
                        "raycaster, which cannot be sent to it): drop --workers 2")
    capture = read_capture(args.capture)
    # The one place where points inside geometry leave (a capture exported from Unity carries their back-face
    # fractions): every method below sees, places and is measured on the valid points only.
    try:
        valid = valid_points(capture)
        candidates = without_invalid(capture, valid)
    except ValueError as exc:
        raise UserError(f"{args.capture}: {exc}") from exc
    if valid is not None and not valid.all():
        print(f"{Path(args.capture).name}: {int(np.count_nonzero(~valid)):,} of {capture.point_count:,} points are inside "
              f"geometry (back-face fraction above {BACK_FACE_THRESHOLD:g}) and are never probes", file=sys.stderr)
    with user_errors(args.capture):
        if BY_NAME[args.method].needs_scores:
            return _place_lpnn(args, candidates, capture.ids, valid)
        pins = None
        if args.keep is not None:
            from ..quality.placement.pins import pin_probes, read_pins_json

            pins = pin_probes(read_pins_json(args.keep, capture.units), candidates.positions, candidates.cell_size,
                              args.keep_distance)
        return _place(args, candidates, pins)


def _place_lpnn(args: argparse.Namespace, capture: Capture, all_ids: np.ndarray, valid: np.ndarray | None) -> int:
    """The methods that read the network's scores (--model / --scores supply them): the table's `lpnn_options`
    (quality/placement/methods.py) at RECOMMENDED_REFINE. A scores file lists every point of the capture file
    (`all_ids`); only the valid points' scores are used."""
    from ..quality.placement.insertion import GUIDED_POINT_LIMIT, guide_applies
    from ..quality.placement.lpnn_placement import lpnn_placement
    from ..quality.placement.methods import BATCHED, BY_NAME, EXACT, RECOMMENDED_REFINE
    from .progress import rounds_bar

    method = BY_NAME[args.method]
    if args.model is not None:
        from ..train.onnx_scoring import OnnxScorer

        scorer, scores, what = OnnxScorer(args.model), None, f"model {Path(args.model).name}"
    else:
        from .scores_file import read_scores_csv

        scores = read_scores_csv(args.scores, all_ids)
        scorer, scores, what = None, scores if valid is None else scores[valid], f"scores {Path(args.scores).name}"
    with_bar = method.guided and method.refinement is None  # only guided insertion reports its rounds
    update, close_bar = rounds_bar(f"{Path(args.capture).name}: guided insertion") if with_bar else (None, None)
    reference, leaks = None, None
    if method.refinement == BATCHED:  # guided-refined avoids leaks as the default does (leaks.md)
        from ..quality.metric.leaks import field_with_geometry

        reference = field_with_geometry(capture)
        leaks = _leaks_to_avoid(args, reference)
    try:
        placement = lpnn_placement(capture, scorer, scores=scores, budget=args.budget, tolerance=args.tolerance,
                                   reference=reference, leaks=leaks, workers=args.workers, name=args.capture,
                                   full_ranking=False, report=not args.no_report, progress=update,
                                   **method.lpnn_options())
    finally:
        if close_bar is not None:
            close_bar()
    tier = "top-K" if method.topk else "guided insertion" if method.guided else "spread"
    if method.refinement is not None:
        tier += f" + {'' if method.refinement == EXACT else 'batched '}refine {RECOMMENDED_REFINE:g}"
    if method.guided and not guide_applies(capture.point_count):
        tier += f"; above {GUIDED_POINT_LIMIT:,} points without the guide: plain insertion"
    t = placement.timing
    split = (f"features {t.features * 1000:.0f} ms, " if t.features is not None else "") + (
        f"inference {t.inference * 1000:.0f} ms, selection {t.selection * 1000:.0f} ms"
        + (f", refinement {t.refinement:.2f} s" if method.refinement is not None else ""))
    searched = placement.checked.get(placement.requested) if args.tolerance is not None else None
    _write(args, capture, placement.indices, placement.quality, placement.added_for_tetrahedron,
           f"{what} ({tier})", {"scores": what, "seconds": round(t.total, 4)}, f"; {split}", searched)
    return 0


def _reference_leaks(args: argparse.Namespace, field: ReferenceField) -> LeakWeighting | None:
    """The leak weighting of --method leak-aware-reference (the default's, leak_aware.LEAK_WEIGHT), None for
    fast-reference; UserError when the capture's geometry is unknown (there is nothing to weigh leaks with)."""
    from ..errors import UserError
    from ..quality.placement.leak_aware import NO_GEOMETRY, LeakWeighting

    if args.method != "leak-aware-reference":
        return None
    if field.geometry is None:
        raise UserError(f"{Path(args.capture).name}: {NO_GEOMETRY.split(':')[0]}, so --method leak-aware-reference "
                        "has no walls to weigh leaks with: use --method fast-reference (the leak-blind reference)")
    return LeakWeighting(field.geometry)


def _leaks_to_avoid(args: argparse.Namespace, field: ReferenceField) -> Raycaster | None:
    """The raycaster the refined methods avoid leaks with (--leaks; leak_aware.leaks_to_avoid), telling stderr, under
    the capture's name, when its geometry is unknown and the placement is leak-blind."""
    from ..quality.placement.leak_aware import leaks_to_avoid

    name = Path(args.capture).name
    return leaks_to_avoid(field, args.leaks, lambda text: print(f"{name}: {text}", file=sys.stderr))

def _place(args: argparse.Namespace, capture: Capture, pins: Pins | None = None) -> int:
    from ..core.grid import EvaluationGrid
    from ..quality.placement.apv import apv_ranking
    from ..quality.placement.baselines import heuristic_ranking, random_ranking, uniform_selector
    from ..quality.placement.insertion import InsertionOrder
    from ..quality.metric.leaks import field_with_geometry
    from ..quality.placement.pins import checked_pinned_count, pinned_selection, pinned_smallest
    from ..quality.metric.metric import evaluate_placement
    from ..quality.placement.policies import (budget_count, place_count, place_tolerance, prefix_selection,
                                              reference_count, reference_tolerance)
    from ..quality.placement.reference import run_reference
    from .progress import progress_bar, rounds_bar

    field = field_with_geometry(capture)  # with the level's surfaces when known: the report names leaks
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    n = field.point_count
    if args.method in ("fast-reference", "leak-aware-reference"):
        leaks = _reference_leaks(args, field)
        update, close = progress_bar(f"{Path(args.capture).name}: {args.method.replace('-', ' ')}")
        try:
            # Without the surfaces: the leak-blind reference casts no rays, and its second process cannot receive
            # Embree's scene (the leak-aware one runs in one process: run() refuses --workers 2).
            decimation = run_reference(field if leaks is not None else replace(field, geometry=None), "fast",
                                       args.capture, args.workers, update, leaks)
        finally:
            close()
        placement = (reference_count(decimation, budget_count(args.budget, n)) if args.budget is not None
                     else reference_tolerance(decimation, args.tolerance))
        what = "fast reference"
        if leaks is not None:  # the reported errors below are the plain ones; this is the one it decimated
            what = (f"leak-aware reference (leaking points' errors x {leaks.weight:g}: leak-weighted mean error "
                    f"{decimation.error_curve[placement.indices.shape[0]]:.4g})")
    else:
        close_bar, error_of = None, None
        if args.method == "uniform":
            select = uniform_selector(grid)
            what = "uniform lattice"
        elif args.method == "insertion-refined":
            from ..quality.placement.refined_insertion import refined_insertion
            from ..quality.placement.warmup import compile_placement_kernels, kernels_warm

            name = Path(args.capture).name
            if not kernels_warm():  # a fresh checkout: compile on both cores first, so the times below are the work's
                print(f"{name}: compiling the placement kernels first (once per checkout, then cached)", file=sys.stderr,
                      flush=True)
                print(f"{name}: compiled in {compile_placement_kernels():.1f} s", file=sys.stderr, flush=True)
            ranked, close_ranked = rounds_bar(f"{name}: insertion")
            removed, close_removed = progress_bar(f"{name}: batched refinement")
            try:
                refined = refined_insertion(field, grid, budget=args.budget, tolerance=args.tolerance,
                                            insertion_progress=ranked, refinement_progress=removed, pins=pins,
                                            leaks=_leaks_to_avoid(args, field))
            finally:
                close_ranked()
                close_removed()
            timing = (f"; {refined.rounds} refinement rounds; insertion and search {refined.selection_seconds:.1f} s, "
                      f"refinement {refined.refinement_seconds:.1f} s")
            # The answer's fresh evaluation and the placement's remembered segments, when it made them, serve the report.
            report = evaluate_placement(field, refined.indices, refined.evaluation, refined.segments)
            _write(args, capture, refined.indices, report, 0, "insertion refined in batches", {}, timing, pins=pins)
            return 0
        elif args.method == "insertion":  # only the rounds the policy needs (InsertionOrder)
            update, close_bar = rounds_bar(f"{Path(args.capture).name}: insertion")
            order = InsertionOrder(field, grid, progress=update, pins=pins)
            select, error_of = order.selection(), order.mean_error
            what = "insertion (coarse-to-fine, error-driven)"
        else:
            if args.method == "heuristic":
                ranking, what = heuristic_ranking(grid, capture.sh, capture.lighting_scale), "farthest-point heuristic"
            elif args.method == "apv":
                ranking, what = apv_ranking(grid, capture.features, capture.feature_names), "APV-style geometry density"
            else:
                ranking, what = random_ranking(n, args.seed), f"random (seed {args.seed})"
            select = prefix_selection(grid, ranking) if pins is None else pinned_selection(grid, ranking, pins)
        try:
            placement = (place_count(field, select, checked_pinned_count(budget_count(args.budget, n), pins))
                         if args.budget is not None else place_tolerance(field, select, args.tolerance,
                                                                         smallest=pinned_smallest(pins),
                                                                         error_of=error_of))
        finally:
            if close_bar is not None:
                close_bar()
    _write(args, capture, placement.indices, evaluate_placement(field, placement.indices),
           placement.added_for_tetrahedron, what, {}, "", pins=pins)
    return 0


def _write(args: argparse.Namespace, capture: Capture, indices: np.ndarray, quality: PlacementQuality | None,
           added: int, what: str, extra_source: dict, extra_text: str, searched_error: float | None = None,
           pins: Pins | None = None) -> None:
    """Write the probe file (source: capture, method (the table's name, as Unity's batch mode writes it), policy,
    errors, pinned; `scores` for the methods that read them) and print one summary line (`what`: how it placed).
    quality None (--no-report): only `searched_error`, the tolerance search's mean error, if any. A pinned probe is
    written at its own (the artist's) position, not at the evaluation point it stands for (pins.md)."""
    from ..core.in_use_section import in_use_label, in_use_text
    import numpy as np

    from ..quality.placement.probes_file import write_probes_json

    n = capture.point_count
    policy = f"budget={args.budget:g}" if args.budget is not None else f"tolerance={args.tolerance:g}"
    source = {"capture": Path(args.capture).name, "method": args.method, "policy": policy}
    if quality is not None:
        source.update(mean_error=round(quality.irradiance.mean, 6), p95_error=round(quality.irradiance.p95, 6))
        if quality.in_use_error == quality.in_use_error:  # NaN: the capture cannot say which points are in use
            source.update(in_use_error=round(quality.in_use_error, 6))
        if quality.leaking == quality.leaking:  # NaN: the capture's geometry is not known here
            source.update(leaking=round(quality.leaking, 6))
        errors = (f"mean error {quality.irradiance.mean:.4g}, p95 {quality.irradiance.p95:.4g} "
                  f"(SMAPE mean {quality.smape.mean:.4g}); in use ({in_use_label(capture)}): mean error "
                  f"{in_use_text(quality.in_use_error)}, leaking points {in_use_text(quality.leaking)}")
    elif searched_error is not None:
        source.update(mean_error=round(searched_error, 6))
        errors = f"mean error {searched_error:.4g} (no report)"
    else:
        errors = "error not evaluated (no report)"
    source.update(extra_source)
    pinned = 0 if pins is None else pins.count
    source.update(pinned=pinned)
    positions = capture.positions[indices].astype(np.float64)
    if pins is not None:
        at = np.searchsorted(indices, pins.indices)  # `indices` are sorted and hold every pin
        positions[at] = pins.positions
    write_probes_json(args.out, positions, capture.units, source)
    kept = indices.shape[0]
    added_text = f" ({added} added for a tetrahedron)" if added else ""
    print(f"{args.method}: {what}, {policy}: kept {kept:,} of {n:,} probes ({100.0 * kept / n:.1f} %), {pinned:,} pinned{added_text}; "
          f"{errors}{extra_text} -> {args.out}")
