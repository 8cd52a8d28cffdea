"""Runs the default-model recipe step by step in a work folder; every step's output is kept, so a rerun
with the same options resumes where it stopped (and a rerun from scratch gives the same results)."""

from __future__ import annotations

import json
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable

from ..errors import UserError
from ..core.atomic import write_text_atomic
from ..core.capture_file import read_capture, write_capture
from ..core.engine import Engine
from ..scenes.bsp import BspError
from ..scenes.levels import load_pak_member
from .config import RecipeConfig
from .crops import crops_of_level
from ..quality.bench.results import BenchRow, rows_csv
from ..train.modelcard import ModelCard, card_path, json_ready
from .evaluation import evaluate_crops, goal_checks, summarize
from .labelling import label_source, labelled
from .publish import card_with_recipe, inference_milliseconds, install
from .levels import LevelSplit, split_levels

MODEL_NAME = "lpnn_default"
Log = Callable[[str], None]


@dataclass
class StepTimes:
    """Wall seconds per step, summed over the runs that worked on one folder (a resumed recipe's
    total is the sum of its runs), kept in `file`."""

    file: Path | None = None
    seconds: dict[str, float] = field(default_factory=dict)

    @classmethod
    def load(cls, file: Path) -> "StepTimes":
        stored = read_work_json(file) if file.exists() else {}
        try:
            return cls(file=file, seconds={str(k): float(v) for k, v in stored.items()})
        except (AttributeError, TypeError, ValueError) as exc:
            raise _damaged(file, "not a table of seconds per step") from exc

    def record(self, step: str, start: float) -> None:
        self.seconds[step] = round(self.seconds.get(step, 0.0) + time.perf_counter() - start, 3)
        if self.file is not None:
            write_text_atomic(self.file, json.dumps(self.seconds, indent=2) + "\n")


@dataclass(frozen=True)
class RecipePaths:
    work: Path

    @property
    def manifest(self) -> Path:
        return self.work / "recipe.json"

    @property
    def crops(self) -> Path:
        return self.work / "crops"

    @property
    def labelled(self) -> Path:
        return self.work / "labelled"

    @property
    def model(self) -> Path:
        return self.work / "model" / f"{MODEL_NAME}.onnx"

    @property
    def checkpoint(self) -> Path:
        return self.work / "model" / f"{MODEL_NAME}.ckpt.npz"

    @property
    def rigs(self) -> Path:
        return self.work / "rigs"

    @property
    def times(self) -> Path:
        return self.work / "times.json"

    @property
    def evaluation(self) -> Path:
        return self.work / "evaluation.json"

    def survey_record(self, level: str, cell_size: float) -> Path:
        return self.crops / f"{level}@{cell_size:.4g}m.done.json"


def _damaged(path: Path, reason: str) -> UserError:
    return UserError(f"{path} is damaged ({reason}): delete it to redo that step, or use a new --work folder")


def read_work_json(path: Path) -> Any:
    """A JSON file of the work folder; a damaged one (cut short, edited by hand) is a UserError naming it."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise _damaged(path, str(exc)) from exc


def config_record(config: RecipeConfig) -> dict:
    record = asdict(config)
    record["levels"] = list(config.levels) if config.levels is not None else None
    return json.loads(json.dumps(record))  # tuples -> lists, as stored in the manifest


def check_manifest(paths: RecipePaths, config: RecipeConfig, pak: Path) -> None:
    """A work folder belongs to one set of options: resuming with other options would mix results."""
    record = {"pak": str(pak), "config": config_record(config)}
    if paths.manifest.exists():
        stored = read_work_json(paths.manifest)
        if stored != record:
            raise UserError(f"{paths.work} was made with other recipe options or another pak; "
                            "use a new --work folder (or delete this one) to start over")
        return
    write_text_atomic(paths.manifest, json.dumps(record, indent=2) + "\n")


# ------------------------------------------------------------------------------------------ crops

def _crop_task(task: tuple[str, str, float, RecipeConfig, str]) -> dict:
    """In a worker: survey one level at one cell size and write its crops. Returns the record."""
    pak, member, cell_size, config, crops_dir = task
    start = time.perf_counter()
    try:
        level = load_pak_member(Path(pak), member)
        crops = crops_of_level(level, cell_size, config)
    except BspError as exc:
        return {"level": Path(member).stem, "cell_size": cell_size, "importable": False, "reason": str(exc), "crops": []}
    names = []
    for crop in crops:
        write_capture(Path(crops_dir) / f"{crop.name}.lpnncap", crop.capture)
        names.append(crop.name)
    return {"level": level.name, "cell_size": cell_size, "importable": True, "crops": names,
            "points": [c.capture.point_count for c in crops], "seconds": round(time.perf_counter() - start, 3)}


def make_crops(paths: RecipePaths, pak: Path, members: list[str], config: RecipeConfig, log: Log,
               engine: Engine) -> dict[str, dict]:
    """Crop records per level (for the first cell size: whether the level is importable), each written as it
    arrives (a rerun skips it)."""
    paths.crops.mkdir(parents=True, exist_ok=True)
    todo, records = [], {}
    for member in members:
        name = Path(member).stem
        for cell in config.cell_sizes:
            record_path = paths.survey_record(name, cell)
            if record_path.exists():
                records[f"{name}@{cell}"] = read_work_json(record_path)
            else:
                todo.append((str(pak), member, cell, config, str(paths.crops)))
    for done in _progress(engine.unordered(_crop_task, todo), len(todo), "cropping levels"):
        record = done.value()
        cell = record["cell_size"]
        write_text_atomic(paths.survey_record(record["level"], cell), json.dumps(record, indent=2) + "\n")
        records[f"{record['level']}@{cell}"] = record
        status = f"{len(record['crops'])} crops" if record["importable"] else f"skipped: {record['reason']}"
        log(f"  {record['level']} at {cell:g} m: {status}")
    return records


def make_variants(paths: RecipePaths, pak: Path, names: list[str], split: LevelSplit, config: RecipeConfig,
                  log: Log) -> list[str]:
    """The relit variants of the given crops (relit.py), written beside the crops; returns their names.
    Every crop's level must be a training level (relit.variants_of_crop refuses the others)."""
    from ..scenes.levels import pak_members
    from .relit import level_rig, require_training, variant_name, variants_of_crop

    paths.rigs.mkdir(parents=True, exist_ok=True)
    members = {Path(m).stem: m for m in pak_members(pak)}
    by_level: dict[str, list[str]] = {}
    for name in names:
        by_level.setdefault(name.split("@")[0], []).append(name)
    for level_name in by_level:  # before any rig is fitted
        require_training(f"level {level_name}", split.role(level_name))
    made: list[str] = []
    for level_name, crop_names in _progress(sorted(by_level.items()), len(by_level), "relighting crops"):
        role = split.role(level_name)
        todo = [c for c in crop_names if any(not (paths.crops / f"{variant_name(c, v)}.lpnncap").exists()
                                             and not (paths.crops / f"{variant_name(c, v)}.skipped").exists()
                                             for v in range(1, config.variants_per_crop + 1))]
        if todo:
            level = load_pak_member(pak, members[level_name])
            rig = level_rig(level, paths.rigs / f"{level_name}.json", config.variant_rig_scheme)
            for crop in todo:
                variants = dict(variants_of_crop(level, crop, read_capture(paths.crops / f"{crop}.lpnncap"), rig,
                                                 role, config))
                for number in range(1, config.variants_per_crop + 1):
                    name = variant_name(crop, number)
                    if name in variants:
                        write_capture(paths.crops / f"{name}.lpnncap", variants[name])
                    else:  # remembered, so a resumed run does not retry it
                        write_text_atomic(paths.crops / f"{name}.skipped", "outside the crop's point range\n")
        made += [variant_name(c, v) for c in crop_names for v in range(1, config.variants_per_crop + 1)
                 if (paths.crops / f"{variant_name(c, v)}.lpnncap").exists()]
    log(f"  {len(made)} relit variants of {len(names)} training crops")
    return made


# ------------------------------------------------------------------------------------------ labels

def _label_task(task: tuple[str, str, float]) -> tuple[str, float, int]:
    source, target, budget = task
    capture, seconds = labelled(read_capture(source), budget)
    write_capture(target, capture)
    return Path(target).stem, seconds, capture.point_count


def label_crops(paths: RecipePaths, names: list[str], config: RecipeConfig, log: Log,
                engine: Engine) -> dict[str, float]:
    """Reference labels for every crop not labelled yet (each written by its worker as it finishes: a rerun
    skips it); returns the reference's seconds per crop. Stops at the first crop that fails."""
    paths.labelled.mkdir(parents=True, exist_ok=True)
    todo = [(str(paths.crops / f"{n}.lpnncap"), str(paths.labelled / f"{n}.lpnncap"), config.label_budget)
            for n in names if not (paths.labelled / f"{n}.lpnncap").exists()]
    seconds: dict[str, float] = {}
    for done in _progress(engine.unordered(_label_task, todo), len(todo), "labelling crops"):
        name, spent, _points = done.value()
        seconds[name] = spent
    if todo:
        log(f"  labelled {len(todo)} crops with the fast reference ({sum(seconds.values()):.0f} s of reference time)")
    return seconds


def _progress(items: Iterable, total: int, description: str) -> Iterable:
    from tqdm import tqdm

    return tqdm(items, total=total, desc=description, unit="task", leave=False, disable=total == 0)


# ------------------------------------------------------------------------------------------ the recipe

@dataclass
class RecipeResult:
    split: LevelSplit
    skipped_levels: dict[str, str]
    crops: dict[str, list[str]]  # role -> crop names
    model: Path
    times: StepTimes
    held_out: dict | None = None  # the evaluation summary
    installed: tuple[Path, Path] | None = None


def crop_names_by_role(records: dict[str, dict], split: LevelSplit) -> dict[str, list[str]]:
    roles: dict[str, list[str]] = {"train": [], "validation": [], "held_out": []}
    for record in records.values():
        if record["importable"]:
            roles[split.role(record["level"])].extend(record["crops"])
    return {role: sorted(names) for role, names in roles.items()}


def _selected_members(pak: Path, config: RecipeConfig) -> list[str]:
    from ..scenes.levels import pak_members

    members = pak_members(pak)
    if config.levels is None:
        return members
    wanted = set(config.levels)
    members = [m for m in members if Path(m).stem in wanted]
    missing = wanted - {Path(m).stem for m in members}
    if missing:
        raise UserError(f"{pak}: no level named {', '.join(sorted(missing))}")
    return members


def run_recipe(pak: Path, work: Path, config: RecipeConfig, log: Log = print,
               install_to: Path | None = None, scheduler: str | None = None) -> RecipeResult:
    """Crops, split, labels, training, held-out evaluation, model card; then installs the model into
    `install_to` when given. Each step's output stays in `work`, so a rerun resumes. Crops, labels and the
    held-out evaluation run on `config.workers` local processes, or on the Dask cluster at `scheduler`
    (core/engine.py); the results are the same."""
    with Engine(config.workers, scheduler) as engine:
        return _run_recipe(pak, work, config, log, install_to, engine)


def _run_recipe(pak: Path, work: Path, config: RecipeConfig, log: Log, install_to: Path | None,
                engine: Engine) -> RecipeResult:
    paths = RecipePaths(work)
    work.mkdir(parents=True, exist_ok=True)
    check_manifest(paths, config, pak)
    times = StepTimes.load(paths.times)
    members = _selected_members(pak, config)

    start = time.perf_counter()
    log(f"1/6 crops: {len(members)} levels x {len(config.cell_sizes)} cell size(s)")
    records = make_crops(paths, pak, members, config, log, engine)
    times.record("crops", start)
    first_cell = config.cell_sizes[0]
    importable = sorted(r["level"] for k, r in records.items() if k.endswith(f"@{first_cell}") and r["importable"])
    skipped = {r["level"]: r["reason"] for k, r in records.items() if k.endswith(f"@{first_cell}") and not r["importable"]}
    split = split_levels(importable, config)
    crops = crop_names_by_role(records, split)
    log(f"2/6 split by level: {len(split.train)} train, {len(split.validation)} validation, "
        f"{len(split.held_out)} held out ({', '.join(split.held_out)}); "
        f"crops {len(crops['train'])} / {len(crops['validation'])} / {len(crops['held_out'])}")

    if config.variants_per_crop:
        start = time.perf_counter()
        log(f"2b/6 relit variants: {config.variants_per_crop} per training crop ({len(crops['train'])} crops)")
        crops["train"] = sorted(crops["train"] + make_variants(paths, pak, crops["train"], split, config, log))
        times.record("variants", start)

    start = time.perf_counter()
    log("3/6 labels: the fast reference placement of every crop")
    label_crops(paths, crops["train"] + crops["validation"] + crops["held_out"], config, log, engine)
    times.record("labels", start)

    start = time.perf_counter()
    log("4/6 training (train and validation levels only)")
    if not paths.model.exists():
        from ..train.pipeline import train_and_export

        train_and_export([paths.labelled / f"{n}.lpnncap" for n in crops["train"]], paths.model, config.train,
                         paths.checkpoint, [paths.labelled / f"{n}.lpnncap" for n in crops["validation"]],
                         progress=True)
    times.record("training", start)

    start = time.perf_counter()
    log(f"5/6 held-out evaluation: {len(crops['held_out'])} crops of {len(split.held_out)} levels")
    held_out = evaluate_held_out(paths, crops["held_out"], log, engine)
    times.record("evaluation", start)

    log("6/6 model card" + (f" and installation into {install_to}" if install_to else ""))
    recipe = {"options": config_record(config), "pak": pak.name,
              "levels": {"train": list(split.train), "validation": list(split.validation),
                         "held_out": list(split.held_out), "skipped": skipped},
              "crops": {role: len(names) for role, names in crops.items()},
              "label_source": label_source(config.label_budget) + " (Documentation~/quality.md §3.2)",
              "seconds": dict(times.seconds)}
    card = card_with_recipe(ModelCard.read(card_path(paths.model)), recipe, held_out,
                            inference_milliseconds(paths.model))
    card.write(card_path(paths.model))
    installed = install(paths.model, install_to) if install_to is not None else None
    return RecipeResult(split=split, skipped_levels=skipped, crops=crops, model=paths.model, times=times,
                        held_out=held_out, installed=installed)


def evaluate_held_out(paths: RecipePaths, names: list[str], log: Log, engine: Engine) -> dict:
    """The held-out summary (cached in evaluation.json with the per-crop results, and bench.csv)."""
    if paths.evaluation.exists():  # the per-crop results are kept; the summary is recomputed from them
        stored = read_work_json(paths.evaluation)
        crops = stored.get("crops") if isinstance(stored, dict) else None
        if not isinstance(crops, list):
            raise _damaged(paths.evaluation, "no list of 'crops'")
    else:
        files = [paths.labelled / f"{n}.lpnncap" for n in names]
        crops = evaluate_crops(files, paths.model, engine,
                               lambda items, total: _progress(items, total, "evaluating held-out crops"))
    summary = summarize(crops)
    summary["goals"] = goal_checks(summary)
    rows = [BenchRow(**row) for crop in crops for row in crop["rows"]]
    write_text_atomic(paths.work / "held_out_bench.csv", rows_csv(rows))
    write_text_atomic(paths.evaluation, json.dumps(json_ready({"summary": summary, "crops": crops}), indent=1,
                                                   allow_nan=False) + "\n")
    for check, ok in summary["goals"].items():
        log(f"  {check}: {'met' if ok else 'missed'}")
    return json_ready(summary)
