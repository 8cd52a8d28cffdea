"""What Unity imports from this package and which .meta each asset needs (shared by gen-meta.py and check-package.py).

Unity skips, inside a package as anywhere else, files and folders whose name starts with '.', ends with '~', is 'cvs', or
ends with '.tmp' (Unity Manual, "Special folder names" / hidden assets). Everything else — including Makefile at the
package root — is imported and needs a .meta, and a git-installed package is immutable, so the metas must be committed.
Samples~ is skipped by the package import but copied into Assets/ when a sample is imported: its contents get metas too.
"""

from __future__ import annotations

import hashlib
import os
import re
from pathlib import Path

PACKAGE_NAME = "com.lpnn.probes"


TEXT_ASSET_EXTENSIONS = {".txt", ".html", ".htm", ".xml", ".bytes", ".json", ".csv", ".yaml", ".yml", ".fnt", ".md"}


def is_hidden(name: str) -> bool:
    lower = name.lower()
    return name.startswith(".") or name.endswith("~") or lower == "cvs" or lower.endswith(".tmp")


def importable(root: Path) -> list[Path]:
    """Every file and folder Unity imports from the package at `root`, plus the contents of each Samples~/<sample>/."""
    found: list[Path] = []

    def walk(directory: Path, include_self: bool) -> None:
        if include_self:
            found.append(directory)
        for entry in sorted(directory.iterdir()):
            if is_hidden(entry.name) or entry.name.endswith(".meta"):
                continue
            if entry.is_dir():
                walk(entry, True)
            else:
                found.append(entry)

    walk(root, False)
    samples = root / "Samples~"
    if samples.is_dir():
        for sample in sorted(p for p in samples.iterdir() if p.is_dir() and not is_hidden(p.name)):
            walk(sample, False)
    return found


def guid_for(root: Path, path: Path) -> str:
    """Deterministic GUID: MD5 of the package name and the package-relative POSIX path (stable across machines and reruns)."""
    relative = path.relative_to(root).as_posix()
    return hashlib.md5(f"{PACKAGE_NAME}/{relative}".encode("utf-8")).hexdigest()


def importer_for(path: Path) -> str | None:
    if path.is_dir():
        return "DefaultImporter"
    suffix = path.suffix.lower()
    if suffix == ".cs":
        return "MonoImporter"
    if suffix == ".asmdef":
        return "AssemblyDefinitionImporter"
    if suffix == ".asmref":
        return "AssemblyDefinitionReferenceImporter"
    if suffix == ".onnx":
        # Whichever inference package the project has imports it (com.unity.sentis and com.unity.ai.inference register
        # different ScriptedImporter scripts for .onnx): the .meta names no importer, only the GUID.
        return None
    if suffix in TEXT_ASSET_EXTENSIONS:
        return "TextScriptImporter"
    if suffix == ".prefab":
        return "PrefabImporter"
    return "DefaultImporter"


def meta_text(path: Path, guid: str) -> str:
    """The .meta Unity writes for this importer (formats as in the Sentis / Test Framework packages' own metas)."""
    importer = importer_for(path)
    head = f"fileFormatVersion: 2\nguid: {guid}\n"
    tail = "  externalObjects: {}\n  userData: \n  assetBundleName: \n  assetBundleVariant: \n"
    if path.is_dir():
        return head + "folderAsset: yes\nDefaultImporter:\n" + tail
    if importer == "MonoImporter":
        return (head + "MonoImporter:\n  externalObjects: {}\n  serializedVersion: 2\n  defaultReferences: []\n  executionOrder: 0\n"
                "  icon: {instanceID: 0}\n  userData: \n  assetBundleName: \n  assetBundleVariant: \n")
    if importer is None:
        return head
    return head + f"{importer}:\n" + tail


GUID_LINE = re.compile(r"^guid: ([0-9a-f]{32})\s*$", re.MULTILINE)
IMPORTER_LINE = re.compile(r"^([A-Za-z]+Importer):\s*$", re.MULTILINE)


def read_meta(meta: Path) -> tuple[str | None, str | None]:
    """(guid, importer) of an existing .meta, None where absent or malformed."""
    text = meta.read_text(encoding="utf-8", errors="replace")
    guid = GUID_LINE.search(text)
    importer = IMPORTER_LINE.search(text)
    return (guid.group(1) if guid else None, importer.group(1) if importer else None)


def meta_path(path: Path) -> Path:
    return path.with_name(path.name + ".meta")


def all_metas(root: Path) -> list[Path]:
    """Every .meta below `root` that is not inside a hidden folder (Samples~ contents included)."""
    metas: list[Path] = []
    for directory, subdirs, files in os.walk(root):
        here = Path(directory)
        subdirs[:] = sorted(d for d in subdirs if not is_hidden(d) or (here == root and d == "Samples~"))
        metas.extend(here / f for f in sorted(files) if f.endswith(".meta"))
    return metas
