#!/usr/bin/env python3
"""Checks the package layout Unity depends on (standard library only); exits non-zero on any problem.

- every file and folder Unity imports has a .meta (a git-installed package is immutable: Unity cannot write missing metas
  and ignores those assets with a warning); no .meta is orphaned; GUIDs are well-formed and unique; each meta's importer
  matches its asset type;
- package.json parses and names the package, a version, the physics module and no inference package; every declared sample folder exists;
- every .asmdef parses, its name matches its file name and is unique, its references are assemblies that exist (ours or
  the Unity/Sentis ones we rely on), and the runtime assemblies never reference editor-only ones;
- no UnityEditor in the runtime sources, no UnityEngine in the engine-agnostic core.
Run: python3 "Tools~/check-package.py"   (fix missing metas with: python3 "Tools~/gen-meta.py")
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import unity_meta  # noqa: E402

# Assemblies outside this package that our asmdefs may name (Unity Test Framework; Sentis 2.1 / Inference Engine 2.2+,
# referenced by name and compiled in only where the package exists, via versionDefines).
# Each registers a ScriptedImporter for .onnx, so the package may depend on neither (InferencePackagePolicy.cs).
INFERENCE_PACKAGES = ("com.unity.sentis", "com.unity.ai.inference")
# Built-in modules the Unity layer calls: RaycastCommand, QueryParameters, MeshCollider (UnityEngine.PhysicsModule).
REQUIRED_MODULES = ("com.unity.modules.physics",)
EXTERNAL_ASSEMBLIES = {"UnityEngine.TestRunner", "UnityEditor.TestRunner", "Unity.Sentis", "Unity.InferenceEngine"}
RUNTIME_ASSEMBLIES = {"Lpnn.Probes.Core", "Lpnn.Probes"}


def check_metas(root: Path, problems: list[str]) -> tuple[int, int]:
    assets = unity_meta.importable(root)
    expected = {unity_meta.meta_path(p) for p in assets}
    guids: dict[str, Path] = {}
    for path in assets:
        meta = unity_meta.meta_path(path)
        relative = path.relative_to(root).as_posix()
        if not meta.exists():
            problems.append(f"{relative}: no .meta (run python3 \"Tools~/gen-meta.py\")")
            continue
        guid, importer = unity_meta.read_meta(meta)
        if guid is None:
            problems.append(f"{relative}.meta: no 32-hex-digit 'guid:' line")
            continue
        if guid in guids:
            problems.append(f"{relative}.meta: GUID {guid} is also used by {guids[guid].relative_to(root).as_posix()}")
        guids[guid] = meta
        want = unity_meta.importer_for(path)
        if importer != want:
            problems.append(f"{relative}.meta: importer {importer} but a {path.suffix or 'folder'} needs {want}")
    for meta in unity_meta.all_metas(root):
        if meta not in expected:
            problems.append(f"{meta.relative_to(root).as_posix()}: orphaned .meta (its asset is gone or hidden; "
                            "run python3 \"Tools~/gen-meta.py\" --prune)")
    files = sum(1 for p in assets if p.is_file())
    return files, len(assets) - files


def check_manifest(root: Path, problems: list[str]) -> None:
    try:
        manifest = json.loads((root / "package.json").read_text(encoding="utf-8"))
    except (OSError, ValueError) as error:
        problems.append(f"package.json: {error}")
        return
    if manifest.get("name") != unity_meta.PACKAGE_NAME:
        problems.append(f"package.json: name is {manifest.get('name')!r}, expected {unity_meta.PACKAGE_NAME!r}")
    if not re.fullmatch(r"\d+\.\d+\.\d+(-[0-9A-Za-z.-]+)?", str(manifest.get("version", ""))):
        problems.append(f"package.json: version {manifest.get('version')!r} is not SemVer")
    dependencies = manifest.get("dependencies", {})
    for inference in INFERENCE_PACKAGES:
        if inference in dependencies:
            problems.append(f"package.json: depends on {inference}; a project with the other inference package would then have two "
                            ".onnx importers (Documentation~/index.md, 'Inference package')")
    for module in REQUIRED_MODULES:
        if module not in dependencies:
            problems.append(f"package.json: dependencies lack {module}")
    for sample in manifest.get("samples", []):
        if not (root / sample.get("path", "")).is_dir():
            problems.append(f"package.json: sample path {sample.get('path')!r} does not exist")


def check_asmdefs(root: Path, problems: list[str]) -> int:
    asmdefs = [p for p in unity_meta.importable(root) if p.suffix == ".asmdef"]
    parsed: dict[str, tuple[Path, dict]] = {}
    for path in asmdefs:
        relative = path.relative_to(root).as_posix()
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except ValueError as error:
            problems.append(f"{relative}: invalid JSON: {error}")
            continue
        name = data.get("name")
        if name != path.stem:
            problems.append(f"{relative}: name {name!r} differs from the file name {path.stem!r}")
        if name in parsed:
            problems.append(f"{relative}: assembly name {name!r} is also declared by {parsed[name][0].relative_to(root).as_posix()}")
        parsed[name] = (path, data)
    known = set(parsed) | EXTERNAL_ASSEMBLIES
    editor_only = {n for n, (_, d) in parsed.items() if d.get("includePlatforms") == ["Editor"]}
    for name, (path, data) in parsed.items():
        relative = path.relative_to(root).as_posix()
        for reference in data.get("references", []):
            if reference not in known:
                problems.append(f"{relative}: reference {reference!r} is no assembly of this package nor a known Unity one")
            if name in RUNTIME_ASSEMBLIES and (reference in editor_only or "Editor" in reference or "TestRunner" in reference):
                problems.append(f"{relative}: the runtime assembly references the editor-only {reference!r}")
        for define in data.get("versionDefines", []):
            if not all(define.get(k) for k in ("name", "expression", "define")):
                problems.append(f"{relative}: versionDefines entry {define} needs name, expression and define")
    return len(parsed)


def check_sources(root: Path, problems: list[str]) -> None:
    runtime = root / "Packages" / unity_meta.PACKAGE_NAME / "Runtime"
    core = runtime / "Core"
    for source in sorted(runtime.rglob("*.cs")):
        text = source.read_text(encoding="utf-8")
        relative = source.relative_to(root).as_posix()
        if re.search(r"\bUnityEditor\b", text):
            problems.append(f"{relative}: the runtime assembly must not use UnityEditor (move this to Editor/)")
        if core in source.parents and re.search(r"\busing\s+Unity(Engine)?\b|\bUnityEngine\.", text):
            problems.append(f"{relative}: the engine-agnostic core must not use UnityEngine")


def main() -> int:
    root = Path(__file__).resolve().parent.parent
    problems: list[str] = []
    files, folders = check_metas(root, problems)
    check_manifest(root, problems)
    assemblies = check_asmdefs(root, problems)
    check_sources(root, problems)
    for problem in problems:
        print(f"check-package: {problem}")
    print(f"check-package: {files} files and {folders} folders imported by Unity, {assemblies} asmdefs; "
          f"{len(problems)} problem{'s' if len(problems) != 1 else ''}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
