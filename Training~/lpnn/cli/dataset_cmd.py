"""`lpnn dataset`: inspect, validate and convert captures (Documentation~/file-formats.md).

  lpnn dataset info PATHS...              what each capture holds, and totals
  lpnn dataset validate PATHS...          every problem of every capture, one line each (exit 1 if any)
  lpnn dataset convert-legacy FEATURES_TXT [COMPARISONS_TXT] --out CAPTURE_OR_FOLDER [--scene NAME] [--append]

PATHS are capture files or dataset folders (searched recursively). Nothing here ever modifies an
existing file: convert-legacy writes a new capture, and refuses an existing name unless --append
(which picks the next free name `<stem>-2.lpnncap`, ...).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..core.atomic import write_new_atomic
from ..core.capture import Capture, CaptureError
from ..core.capture_encoder import encode_capture
from ..core.capture_file import append_capture, dataset_files, read_capture, safe_file_stem, validate_capture
from ..core.capture_format import EXTENSION
from ..core.in_use_section import capture_rule, in_use_points
from ..core.legacy import LegacyFormatError, legacy_to_capture
from ..errors import UserError

EXIT_PROBLEMS = 1


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("dataset", help="inspect, validate and convert captures",
                                   description="Inspect, validate and convert capture files (*.lpnncap).")
    commands = parser.add_subparsers(dest="dataset_command", metavar="ACTION", required=True)

    info = commands.add_parser("info", help="points, features, labels and provenance of each capture")
    info.add_argument("paths", nargs="+", metavar="PATH", help="capture files or dataset folders")
    info.set_defaults(handler=_info)

    validate = commands.add_parser("validate", help="report every problem of every capture (exit 1 if any)")
    validate.add_argument("paths", nargs="+", metavar="PATH", help="capture files or dataset folders")
    validate.set_defaults(handler=_validate)

    convert = commands.add_parser("convert-legacy", help="convert the thesis' features.txt (+ comparisons.txt)")
    convert.add_argument("features", metavar="FEATURES_TXT", help="the thesis' features.txt")
    convert.add_argument("labels", nargs="?", metavar="COMPARISONS_TXT", help="the thesis' comparisons.txt (labels)")
    convert.add_argument("--out", required=True, metavar="CAPTURE_OR_FOLDER",
                         help=f"a new {EXTENSION} file, or a dataset folder (the file is named after --scene)")
    convert.add_argument("--scene", metavar="NAME", help="scene name stored in the capture (default: the features file's name)")
    convert.add_argument("--append", action="store_true",
                         help="add beside existing captures under the next free name instead of refusing an existing one")
    convert.set_defaults(handler=_convert_legacy)


def _files(paths: list[str]) -> list[Path]:
    try:
        files = dataset_files(paths)
    except CaptureError as exc:
        raise UserError(str(exc)) from exc
    if not files:
        raise UserError(f"no {EXTENSION} files found in {', '.join(paths)}")
    return files


def in_use_summary(capture: Capture) -> str:
    """The capture's in-use rule and counts (in-use.md), as `dataset info` prints them."""
    rule = capture_rule(capture)
    mask = in_use_points(capture)
    if rule != "all":
        before = capture.source.get("points_before_in_use")
        return f"{rule}: all {capture.point_count:,}" + (f" (of {before:,} valid points)" if isinstance(before, int) else "")
    if mask is None:
        return "all points kept; which are in use is not recorded (imported before the rule)"
    return (f"all points kept; {int(mask.sum()):,} in use by the {capture.source.get('in_use_report_rule', '?')} rule "
            f"(section in_use)")


def _describe(path: Path, capture: Capture) -> list[str]:
    lines = [str(path),
             f"  points: {capture.point_count:,}   features: {capture.feature_count} ({capture.schema})",
             f"  cell size: {capture.cell_size:g} {capture.units}   lighting scale: {capture.lighting_scale:g}"]
    if capture.labels is None:
        lines.append("  labels: none")
    else:
        positive = int(capture.labels.sum())
        lines.append(f"  labels: {positive:,} positive of {capture.point_count:,} "
                     f"({100.0 * positive / capture.point_count:.2f} %) from {capture.label_source}")
    lines.append(f"  points in use: {in_use_summary(capture)}")
    provenance = ", ".join(f"{key}={value}" for key, value in capture.source.items()) or "(none)"
    lines.append(f"  source: {provenance}")
    if capture.extra_sections:
        lines.append(f"  extra sections: {', '.join(sorted(capture.extra_sections))}")
    return lines


def _info(args: argparse.Namespace) -> int:
    captures = points = labelled = positive = failed = 0
    for path in _files(args.paths):
        try:
            capture = read_capture(path)
        except CaptureError as exc:
            print(f"error: {exc}")
            failed += 1
            continue
        print("\n".join(_describe(path, capture)))
        captures += 1
        points += capture.point_count
        if capture.labels is not None:
            labelled += capture.point_count
            positive += int(capture.labels.sum())
    fraction = f" ({100.0 * positive / labelled:.2f} %)" if labelled else ""
    print(f"total: {captures:,} captures, {points:,} points, {labelled:,} labelled, {positive:,} positive{fraction}"
          + (f", {failed:,} unreadable" if failed else ""))
    return EXIT_PROBLEMS if failed else 0


def _validate(args: argparse.Namespace) -> int:
    files = _files(args.paths)
    bad = 0
    for path in files:
        problems = validate_capture(path)
        if problems:
            bad += 1
            for problem in problems:
                print(problem)
        else:
            print(f"{path}: ok")
    print(f"{len(files):,} captures checked, {bad:,} with problems")
    return EXIT_PROBLEMS if bad else 0


def _target(out: str, scene: str) -> Path:
    """--out as a capture file path: itself when it names a capture, else <folder>/<scene>.lpnncap."""
    path = Path(out)
    if path.suffix == EXTENSION and not path.is_dir():
        return path
    return path / f"{safe_file_stem(scene)}{EXTENSION}"


def _convert_legacy(args: argparse.Namespace) -> int:
    features = Path(args.features)
    scene = args.scene or features.stem
    try:
        capture = legacy_to_capture(features, args.labels, scene)
    except LegacyFormatError as exc:
        raise UserError(str(exc)) from exc
    target = _target(args.out, scene)
    if args.append:
        written = append_capture(target.parent, capture, target.stem)
    else:
        data = encode_capture(capture)
        if not write_new_atomic(target, lambda handle: handle.write(data)):
            raise UserError(f"{target} already exists; pass --append to add a new capture beside it "
                            "(nothing was overwritten)")
        written = target
    labels = "no labels" if capture.labels is None else f"{int(capture.labels.sum()):,} positive labels"
    print(f"wrote {written}: {capture.point_count:,} points, {capture.feature_count} features ({capture.schema}), {labels}")
    return 0
