#!/usr/bin/env python3
"""Writes the missing .meta files of the package (standard library only).

GUIDs are a hash of the package-relative path, so reruns and other machines produce the same files. Existing metas are
never changed (a GUID others reference must not move). `--prune` also deletes metas whose asset is gone.
Run after adding, renaming or deleting any file Unity imports: python3 "Tools~/gen-meta.py"
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import unity_meta  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", type=Path, default=Path(__file__).resolve().parent.parent, help="package root (package.json)")
    parser.add_argument("--prune", action="store_true", help="delete metas whose file or folder no longer exists")
    args = parser.parse_args()
    root = args.root.resolve()
    written = 0
    for path in unity_meta.importable(root):
        meta = unity_meta.meta_path(path)
        if meta.exists():
            continue
        text = unity_meta.meta_text(path, unity_meta.guid_for(root, path))
        temporary = meta.with_name("." + meta.name + ".tmp")
        temporary.write_text(text, encoding="utf-8", newline="\n")
        temporary.replace(meta)
        written += 1
        print(f"wrote {meta.relative_to(root).as_posix()}")
    pruned = 0
    if args.prune:
        for meta in unity_meta.all_metas(root):
            target = meta.with_name(meta.name[: -len(".meta")])
            if not target.exists():
                meta.unlink()
                pruned += 1
                print(f"deleted orphan {meta.relative_to(root).as_posix()}")
    print(f"gen-meta: {written} metas written" + (f", {pruned} orphans deleted" if args.prune else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
