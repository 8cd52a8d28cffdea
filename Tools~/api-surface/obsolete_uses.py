#!/usr/bin/env python3
"""Lists where each inference package version uses a Unity member that a Unity version marks [Obsolete(..., true)].

Our compile check builds only our code, never the package the editor installs; a compile error in that package
stops Unity loading any new assembly (issue 31: com.unity.ai.inference 2.4.0 calls EditorUtility.InstanceIDToObject(int),
Editor/Visualizer/Editor/ModelAssetOpenHandler.cs:13, which UnityCsReference 6000.5 marks obsolete as an error in
Editor/Mono/EditorUtility.bindings.cs). This reads every [Obsolete(..., true)] type, member and enum value of each Unity
branch and every .cs file of each package tag, and writes Generated/obsolete-error-uses.txt:

    checked unity-6000.5 inference-engine-2.4.0 1
    use unity-6000.5 inference-engine-2.4.0 Editor/Visualizer/...cs:13 UnityEditor.EditorUtility.InstanceIDToObject(int) @ Editor/Mono/...cs:61

The Core test InferencePackageCompatibilityTests reads it and refuses a policy that installs, for a Unity version, a
package with a `use` line. Matching is by text, without compiling the package (it needs hundreds of members the
surfaces do not declare):
  * an obsolete type: its simple name used as an identifier, unless the package declares a type of that name;
  * an obsolete static member or enum value: `Type.Name` with the declaring type's simple name (and, for a method,
    the same number of arguments as one obsolete overload);
  * an obsolete instance member of UnityEngine.Object or a class the package names from UnityEngine/UnityEditor:
    `.Name(` with that argument count, unless the package itself declares a member of that name.
An overload of the same arity that is not obsolete is still reported (IsDirty(int) and IsDirty(Object)): the check
errs towards refusing, and a refused pair is read by hand before the policy changes. Output is deterministic.

    python3 Tools~/api-surface/obsolete_uses.py --unity-csreference PATH --sentis PATH --inference-engine PATH
"""
from __future__ import annotations

import argparse
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Set

sys.path.insert(0, str(Path(__file__).resolve().parent))
from csharp_declarations import FileDeclarations, TypeDecl, split_top_level, strip_comments_and_mask  # noqa: E402
from generate import DEFINED, INFERENCE_ENGINE_VERSIONS, OUTPUT, SENTIS_VERSIONS, UNITY_VERSIONS, Source  # noqa: E402

OBSOLETE_ERROR = re.compile(r"^(System\.)?Obsolete(Attribute)?\s*\(.*,\s*(error\s*:\s*)?true\s*\)$", re.S)
ENUM_VALUE = re.compile(r"\[\s*(?P<attributes>[^\]]*)\]\s*(?P<name>[A-Za-z_]\w*)\s*(=|,|$)")
IDENTIFIER = re.compile(r"(?<![\w@])(?P<dot>\.\s*)?(?P<name>[A-Za-z_]\w*)")
# Instance members are matched only when the receiver is plausibly a Unity object; plain `.Add(` on a List is not.
DECLARED_TYPE = re.compile(r"\b(class|struct|interface|enum|delegate\s+\w+)\s+([A-Za-z_]\w*)")
DECLARED_METHOD = re.compile(r"\b(?:public|private|protected|internal|static|override|virtual|abstract|void)\b[^;{}()=]*?\b([A-Za-z_]\w*)\s*(?:<[^<>()]*>)?\s*\(")
INSTANCE_OWNERS = ("UnityEngine.Object", "UnityEngine.Component", "UnityEngine.GameObject", "UnityEngine.ScriptableObject",
                   "UnityEditor.Editor", "UnityEditor.EditorWindow")


@dataclass(frozen=True)
class Obsolete:
    owner: str                     # full name of the declaring type ("UnityEditor.EditorUtility")
    name: Optional[str]            # member or enum value name; None when the type itself is obsolete
    kind: str                      # type, method, property, field, event, enum-value, ...
    parameters: Optional[tuple]    # parameter types of a method, None otherwise
    static: bool
    where: str                     # path:line in UnityCsReference

    def describe(self) -> str:
        if self.name is None:
            return self.owner
        signature = f"({','.join(self.parameters)})" if self.parameters is not None else ""
        return f"{self.owner}.{self.name}{signature}"


def _walk(types: Iterable[TypeDecl]) -> Iterable[TypeDecl]:
    for decl in types:
        yield decl
        yield from _walk(decl.nested)


def _is_obsolete_error(attributes: List[str]) -> bool:
    return any(OBSOLETE_ERROR.match(a.strip()) for a in attributes)


def obsolete_members(source: Source) -> List[Obsolete]:
    """Every type, member and enum value of one UnityCsReference branch marked [Obsolete(..., true)]."""
    listing = source._git("grep", "-l", "-E", r"Obsolete.*true\s*\)", source.commit, "--", "*.cs")
    found: List[Obsolete] = []
    for line in sorted(listing.splitlines()):
        path = line.split(":", 1)[1]
        declarations = source.declarations(path)
        for decl in _walk(declarations.types):
            if _is_obsolete_error(decl.attributes):
                found.append(Obsolete(decl.full_name, None, "type", None, True, f"{path}:{decl.line}"))
            if decl.kind == "enum":
                for match in ENUM_VALUE.finditer(decl.body):
                    if _is_obsolete_error(split_top_level(match.group("attributes"))):
                        line_number = decl.line + decl.body.count("\n", 0, match.start())
                        found.append(Obsolete(decl.full_name, match.group("name"), "enum-value", None, True, f"{path}:{line_number}"))
                continue
            for member in decl.members:
                if member.kind in ("ctor", "operator", "indexer") or not _is_obsolete_error(member.attributes):
                    continue
                static = decl.kind != "interface" and (" static " in f" {member.header} " or " const " in f" {member.header} ")
                parameters = tuple(member.parameters) if member.kind == "method" and member.parameters is not None else None
                found.append(Obsolete(decl.full_name, re.sub(r"<.*", "", member.name), member.kind, parameters, static,
                                      f"{path}:{member.line}"))
    return found


def _argument_count(code: str, open_paren: int) -> int:
    depth, i = 0, open_paren
    while i < len(code):
        if code[i] in "([{":
            depth += 1
        elif code[i] in ")]}":
            depth -= 1
            if depth == 0:
                inner = code[open_paren + 1:i]
                return len(split_top_level(inner)) if inner.strip() else 0
        i += 1
    return -1


def _package_files(source: Source) -> List[str]:
    return sorted(p for p in source._git("ls-tree", "-r", "--name-only", source.commit).splitlines() if p.endswith(".cs"))


def _declared_names(source: Source, files: List[str]) -> Set[str]:
    """Simple names of the types and methods the package declares itself (they shadow Unity's of the same name).
    Read by pattern, not by the declaration parser: some package files (assembly attributes only) are not types."""
    names: Set[str] = set()
    for path in files:
        code, _ = strip_comments_and_mask(source._git("show", f"{source.commit}:{path}"))
        names.update(m.group(2) for m in DECLARED_TYPE.finditer(code))
        names.update(m.group(1) for m in DECLARED_METHOD.finditer(code))
    return names


def uses(package: Source, obsolete: List[Obsolete]) -> List[str]:
    """`path:line description @ where` for every use in the package of a member in `obsolete`."""
    files = _package_files(package)
    declared = _declared_names(package, files)
    by_name: Dict[str, List[Obsolete]] = {}
    for item in obsolete:
        by_name.setdefault(item.name if item.name is not None else item.owner.split(".")[-1], []).append(item)
    found: List[str] = []
    for path in files:
        code, _ = strip_comments_and_mask(package._git("show", f"{package.commit}:{path}"))
        for match in IDENTIFIER.finditer(code):
            name = match.group("name")
            for item in by_name.get(name, ()):
                if _uses(code, match, item, declared):
                    line = code.count("\n", 0, match.start("name")) + 1
                    found.append(f"{path}:{line} {item.describe()} @ {item.where}")
    return sorted(set(found))


def _uses(code: str, match: re.Match, item: Obsolete, declared: Set[str]) -> bool:
    name = match.group("name")
    if item.name is None:  # an obsolete type, used by its simple name
        return name not in declared and match.group("dot") is None
    after = code[match.end("name"):]
    call = re.match(r"\s*(<[^<>()]*>)?\s*\(", after)
    if item.parameters is not None:
        if call is None:
            return False
        arity = _argument_count(code, match.end("name") + call.end() - 1)
        if arity != len(item.parameters):
            return False
    owner_simple = item.owner.split(".")[-1]
    qualified = re.search(r"(?<![\w])" + re.escape(owner_simple) + r"\s*\.\s*$", code[max(0, match.start() - 200):match.start("name")])
    if item.static:
        return qualified is not None
    if qualified is not None:
        return True
    return item.owner in INSTANCE_OWNERS and match.group("dot") is not None and name not in declared


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--unity-csreference", type=Path, required=True)
    parser.add_argument("--sentis", type=Path, required=True)
    parser.add_argument("--inference-engine", type=Path, required=True)
    parser.add_argument("--output", type=Path, default=OUTPUT / "obsolete-error-uses.txt")
    args = parser.parse_args()
    packages = [(f"sentis-{v}", Source(args.sentis, v, f"needle-mirror/com.unity.sentis {v}")) for v in SENTIS_VERSIONS]
    packages += [(f"inference-engine-{v}", Source(args.inference_engine, v, f"needle-mirror/com.unity.ai.inference {v}"))
                 for v in INFERENCE_ENGINE_VERSIONS]
    lines = ["# Uses of Unity members marked [Obsolete(..., true)] by each Unity version, in each inference package version",
             "# (written by Tools~/api-surface/obsolete_uses.py; read by Tests/Core/InferencePackageCompatibilityTests.cs).",
             "# checked UNITY PACKAGE USES | use UNITY PACKAGE package-path:line member @ UnityCsReference-path:line"]
    for version in UNITY_VERSIONS:
        unity = Source(args.unity_csreference, version, f"UnityCsReference {version}")
        obsolete = obsolete_members(unity)
        lines.append(f"# unity-{version}: UnityCsReference {version} {unity.commit}, {len(obsolete)} obsolete-as-error declarations")
        for label, package in packages:
            found = uses(package, obsolete)
            lines.append(f"checked unity-{version} {label} {len(found)}")
            lines.extend(f"use unity-{version} {label} {use}" for use in found)
    args.output.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
