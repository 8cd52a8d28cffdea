#!/usr/bin/env python3
"""Generates the signature-only API surfaces the Unity-layer compile check builds against.

Reads the real sources from local git clones (bare or not; nothing is checked out) and emits, for exactly
the types and members named in members.txt, their real declarations: accessibility, static/instance,
ref/out/in, generic constraints, default values, `[Obsolete(message, error)]`. Bodies become `throw null`.
One surface per Unity version (UnityEngine.cs, UnityEditor.cs; a file under Editor/ belongs to the editor
assembly, as in Unity) and one per inference package version. Each declaration cites repository, branch or
tag, commit and file:line. Output is deterministic: the same sources give the same bytes.

    python3 Tools~/api-surface/generate.py --unity-csreference PATH --sentis PATH --inference-engine PATH

Obtaining the sources: Documentation~/unity-api-surface.md. Never commit their code; only this output.
"""
from __future__ import annotations

import argparse
import re
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Tuple

sys.path.insert(0, str(Path(__file__).resolve().parent))
from csharp_declarations import FileDeclarations, Member, TypeDecl, split_top_level  # noqa: E402

HERE = Path(__file__).resolve().parent
OUTPUT = HERE.parent / "UnityApiSurface" / "Generated"
UNITY_VERSIONS = ["2022.3", "6000.0", "6000.3", "6000.5", "6000.7"]
SENTIS_VERSIONS = ["2.1.3"]
INFERENCE_ENGINE_VERSIONS = ["2.2.2", "2.3.0", "2.4.0"]
DEFINED = {"UNITY_EDITOR"}
# Bases kept although the surface does not declare them (the framework has them).
# Bases kept although the surface does not declare them: the framework has them and LPNN relies on them (using, foreach,
# attributes). IEnumerable is kept only where GetEnumerator is selected; other interfaces (IEquatable<>, IFormattable...)
# would need members LPNN never calls.
FRAMEWORK_BASES = {"IDisposable", "System.IDisposable", "Attribute", "System.Attribute"}
KEPT_ATTRIBUTES = ("Obsolete", "System.Obsolete", "ObsoleteAttribute", "Flags", "System.Flags", "AttributeUsage")
# DIVERGENCES forced by Mono's mcs (C# 7.2); each is applied visibly and marked in the output.
UNMANAGED = re.compile(r"\bunmanaged\b")


def version_key(version: str) -> Tuple[int, ...]:
    return tuple(int(p) for p in version.split("."))


@dataclass
class Wanted:
    name: str                      # as written in members.txt, e.g. 'Foo<T>(int,out float)' or 'name'
    since: Optional[str] = None
    until: Optional[str] = None

    def applies(self, version: str) -> bool:
        return ((self.since is None or version_key(version) >= version_key(self.since))
                and (self.until is None or version_key(version) <= version_key(self.until)))


@dataclass
class WantedType(Wanted):
    members: List[Wanted] = field(default_factory=list)
    whole: bool = False


def parse_range(text: str) -> Tuple[Optional[str], Optional[str]]:
    match = re.fullmatch(r"@(\d+\.\d+)?(\+|-(\d+\.\d+))?", text)
    if not match:
        raise SystemExit(f"members.txt: bad version range '{text}' (write @6000.3+ or @-6000.4)")
    if match.group(2) == "+":
        return match.group(1), None
    return match.group(1), match.group(3)


def read_manifest(path: Path) -> Dict[str, List[WantedType]]:
    sections: Dict[str, List[WantedType]] = {}
    current: Optional[List[WantedType]] = None
    for number, raw in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        line = raw.split("#", 1)[0].rstrip()
        if not line.strip():
            continue
        if line.startswith("["):
            current = sections.setdefault(line.strip("[] "), []); continue
        text, _, range_text = line.strip().partition(" @")
        since, until = parse_range("@" + range_text.strip()) if range_text else (None, None)
        if not raw.startswith((" ", "\t")):
            whole = text.endswith(" *")
            current.append(WantedType(text.replace(" *", "").strip(), since, until, whole=whole))
        else:
            current[-1].members.append(Wanted(text.strip(), since, until))
    return sections


class Source:
    """One git repository at one ref, read with git (works on bare clones)."""

    def __init__(self, repository: Path, ref: str, label: str):
        self.repository, self.ref, self.label = repository, ref, label
        self.commit = self._git("rev-parse", f"{ref}^{{commit}}").strip()
        self._cache: Dict[str, FileDeclarations] = {}
        self._index: Optional[Dict[str, set]] = None

    def _git(self, *args: str) -> str:
        return subprocess.run(["git", "--git-dir", str(self._git_dir()), *args], check=True,
                              capture_output=True, text=True, encoding="utf-8", errors="replace").stdout

    def _git_dir(self) -> Path:
        return self.repository / ".git" if (self.repository / ".git").exists() else self.repository

    def files_declaring(self, simple_name: str) -> List[str]:
        if self._index is None:  # one grep per ref: simple type name -> files that may declare it
            result = subprocess.run(["git", "--git-dir", str(self._git_dir()), "grep", "-o", "-E",
                                     r"(class|struct|interface|enum)\s+[A-Za-z_][A-Za-z0-9_]*", self.commit, "--", "*.cs"],
                                    capture_output=True, text=True, encoding="utf-8", errors="replace")
            self._index = {}
            for line in result.stdout.splitlines():
                _, path, match = line.split(":", 2)
                self._index.setdefault(match.split()[-1], set()).add(path)
        return sorted(self._index.get(simple_name, ()))

    def declarations(self, path: str) -> FileDeclarations:
        if path not in self._cache:
            try:
                self._cache[path] = FileDeclarations(self._git("show", f"{self.commit}:{path}"), DEFINED)
            except (ValueError, AttributeError) as error:
                raise SystemExit(f"generate.py: cannot read the declarations of {self.label} {path}: {error}")
        return self._cache[path]


def find_type(types: List[TypeDecl], full_name: str) -> List[TypeDecl]:
    found = []
    for decl in types:
        if decl.full_name == full_name:
            found.append(decl)
        elif full_name.startswith(decl.full_name + "."):
            found.extend(find_type(decl.nested, full_name))
    return found


def member_matches(member: Member, wanted: str) -> bool:
    if "(" in wanted:
        name, params = wanted[:wanted.index("(")].strip(), wanted[wanted.index("(") + 1:wanted.rindex(")")]
        wanted_params = [re.sub(r"\s+", "", p) for p in split_top_level(params)]
        member_name = ".ctor" if member.kind == "ctor" else member.name
        return member_name == name and member.parameters == wanted_params
    return member.name == wanted


def is_public_api(member_or_type_header: str, in_interface: bool) -> bool:
    words = re.sub(r"\(.*", "", member_or_type_header).split()
    if "private" in words or ("internal" in words and "protected" not in words):
        return False
    explicit_implementation = re.search(r"\.\w+(<[^<>]*>)?\s*\(", member_or_type_header) is not None
    return in_interface or "public" in words or "protected" in words or explicit_implementation


class SurfaceWriter:
    """Turns selected declarations into compilable signature-only C#."""

    def __init__(self, source: Source, declared_names: set, diverged_interfaces: set):
        self.source = source
        self.declared_names = declared_names          # simple names of every type in this and referenced surfaces
        self.diverged_interfaces = diverged_interfaces

    def cite(self, path: str, line: int) -> str:
        return f"{path}:{line}"

    def attributes(self, attributes: List[str], indent: str) -> List[str]:
        kept = [a for a in attributes if re.match(r"(System\.)?(Obsolete|ObsoleteAttribute|Flags|AttributeUsage)\b", a)]
        return [f"{indent}[{a}]" for a in kept]

    def type_header(self, decl: TypeDecl) -> str:
        header = decl.header
        if decl.kind == "interface" and decl.full_name in self.diverged_interfaces:
            header = re.sub(r"\binterface\b", "abstract class", header)
        # Split '<modifiers> kind Name<T> : bases where ...'.
        match = re.match(r"(?P<head>.*?\b(class|struct|interface|enum)\s+\w+(<[^:]*?>)?)\s*(:(?P<bases>.*?))?(?P<where>\s+where\s.*)?$", header)
        head, bases, where = match.group("head"), match.group("bases"), match.group("where") or ""
        head = re.sub(r"\b(unsafe|partial|readonly|ref)\s+(?=.*\b(class|struct|interface)\b)", "", head)
        if decl.kind != "enum":
            head = re.sub(r"\b(class|struct|interface)\b", r"partial \1", head, count=1)
        kept_bases = []
        for base in split_top_level(bases or ""):
            simple = re.sub(r"<.*>", "<>", base.split(".")[-1] if "<" not in base else base[base.rfind(".", 0, base.index("<")) + 1:])
            enumerable = simple in ("IEnumerable", "IEnumerable<>") and any(m.name == "GetEnumerator" for m in self.selected_members)
            if decl.kind == "enum" or simple in FRAMEWORK_BASES or enumerable or re.sub(r"<>", "", simple) in self.declared_names:
                kept_bases.append(base)
        if decl.kind == "struct" and "readonly" in decl.header.split():
            head = head.replace("partial struct", "readonly partial struct")
        text = head + (" : " + ", ".join(kept_bases) if kept_bases else "") + UNMANAGED.sub("struct", where)
        return text

    def member(self, member: Member, owner: TypeDecl, indent: str, overrides: set) -> List[str]:
        interface = owner.kind == "interface" and owner.full_name not in self.diverged_interfaces
        diverged = owner.full_name in self.diverged_interfaces
        lines = [f"{indent}// {self.cite(self.path, member.line)}"] + self.attributes(member.attributes, indent)
        header = re.sub(r"(?<=[(,])\s*(\[[^\]]*\]\s*)+", " ", member.header)   # parameter attributes
        header = re.sub(r"\(\s+", "(", header)
        header = re.sub(r"\b(extern|unsafe|partial|readonly)\s+", "", header) if member.kind != "field" else re.sub(r"\b(extern|unsafe)\s+", "", header)
        header = UNMANAGED.sub("struct", header)
        if interface:
            header = re.sub(r"\b(public|virtual|abstract)\s+", "", header)
        if diverged and member.kind in ("method", "property"):
            header = re.sub(r"\bpublic\s+", "public abstract ", header, count=1)
        if member.name in overrides and "override" not in header.split():
            header = re.sub(r"\bpublic\s+", "public override ", header, count=1)
        if member.kind == "ctor":
            header = header[:_close_paren(header)]                               # drops ': base(...)' / ': this(...)'
        abstract = interface or "abstract" in header.split()
        if member.kind in ("method", "ctor", "operator"):
            lines.append(f"{indent}{header}" + (";" if abstract else " { throw null; }"))
        elif member.kind in ("property", "indexer"):
            lines.append(f"{indent}{header} {{ {self.accessors(member, abstract)} }}")
        elif member.kind == "event":
            lines.append(f"{indent}{header}" + (";" if abstract or member.body == ";" else " { add { } remove { } }"))
        elif member.kind == "delegate":
            lines.append(f"{indent}{header};")
        else:  # field: constants keep their value, other fields lose their initializer
            keep_value = "const" in header.split()
            lines.append(f"{indent}{header}{' ' + member.body if keep_value else ';'}")
        return lines

    def accessors(self, member: Member, abstract: bool) -> str:
        if member.body.startswith("=>"):
            return "get;" if abstract else "get { throw null; }"
        body = member.body[1:-1]
        body = re.sub(r"\[[^\]]*\]", " ", body)
        depth, flat = 0, []
        for c in body:                       # drop accessor bodies
            if c == "{":
                depth += 1
            if depth == 0:
                flat.append(c)
            if c == "}":
                depth -= 1
                if depth == 0:
                    flat.append(";")
        flat_text = re.sub(r"=>[^;]*;", ";", "".join(flat))
        result = []
        for modifiers, accessor in re.findall(r"((?:(?:private|protected|internal)\s+)*)\b(get|set|init)\b", flat_text):
            if "private" in modifiers or ("internal" in modifiers and "protected" not in modifiers):
                continue
            accessor = "set" if accessor == "init" else accessor
            body_text = ";" if abstract else (" { throw null; }" if accessor == "get" else " { }")
            result.append(f"{modifiers}{accessor}{body_text}")
        return " ".join(result)

    path = ""


def _close_paren(text: str) -> int:
    depth = 0
    for k, c in enumerate(text):
        if c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
            if depth == 0:
                return k + 1
    return len(text)


def select(source: Source, wanted_types: List[WantedType], version: str, namespace_root: str = ""):
    """For each wanted type: [(path, TypeDecl, [Member...], [nested selections])]; errors name what is missing."""
    selections = []
    errors = []
    by_full = {}
    for wanted in wanted_types:
        if not wanted.applies(version):
            continue
        full = wanted.name.replace("{ns}", namespace_root)
        by_full[full] = wanted
    for full, wanted in sorted(by_full.items()):
        simple = re.sub(r"<.*", "", full).split(".")[-1]
        occurrences = []
        for path in source.files_declaring(simple):
            for decl in find_type(source.declarations(path).types, full):
                occurrences.append((path, decl))
        if not occurrences:
            errors.append(f"{source.label}: type {full} not found"); continue
        chosen: Dict[Tuple[str, int], List[Member]] = {(p, d.line): [] for p, d in occurrences}
        for want in wanted.members:
            if not want.applies(version):
                continue
            every_overload = want.name.endswith(" *")
            name = want.name[:-2] if every_overload else want.name
            hits = [(p, d, m) for p, d in occurrences for m in d.members
                    if member_matches(m, name) and is_public_api(m.header, d.kind == "interface")]
            if not hits:
                errors.append(f"{source.label}: {full}.{want.name} not found (public)"); continue
            if every_overload:
                for path, decl, member in hits:
                    chosen[(path, decl.line)].append(member)
                continue
            if len(hits) > 1:
                errors.append(f"{source.label}: {full}.{want.name} is overloaded; name the parameter types: "
                              + "; ".join(f"{m.name}({','.join(m.parameters or [])})" for _, _, m in hits)); continue
            path, decl, member = hits[0]
            chosen[(path, decl.line)].append(member)
        for path, decl in occurrences:
            selections.append((full, path, decl, chosen[(path, decl.line)], wanted.whole))
    return selections, errors


def emit(selections, writer: SurfaceWriter, title: str) -> str:
    out = [f"// GENERATED by Tools~/api-surface/generate.py from {writer.source.label} (commit {writer.source.commit}).",
           f"// {title}. Signatures only, no behaviour: compiling against this proves nothing about running in Unity.",
           "// Do not edit; rerun the generator (Documentation~/unity-api-surface.md).", ""]
    # Group nested types under their outer type declaration of the same file.
    full_names = {full for full, *_ in selections}
    nested_of: Dict[Tuple[str, int], List] = {}
    top = []
    for selection in selections:
        full, path, decl, members, whole = selection
        outer = next((o for o in sorted(full_names, key=len, reverse=True) if full.startswith(o + ".")), None)
        if outer:
            owner = next(((p, d) for f, p, d, *_ in selections if f == outer and p == path
                          and decl.line > d.line and decl in _all_nested(d)), None)
            if owner is None:
                raise SystemExit(f"{writer.source.label}: nested type {full} in {path} has no selected outer declaration there")
            nested_of.setdefault((owner[0], owner[1].line), []).append(selection)
        else:
            top.append(selection)

    # A type with nothing selected in any part is still declared once: by its public part with a base list, else the first.
    primary: Dict[str, Tuple[str, int]] = {}
    for full, path, decl, members, whole in sorted(selections, key=lambda s: (s[0], "public" not in s[2].header.split(), ":" not in s[2].header, s[1], s[2].line)):
        if members or nested_of.get((path, decl.line)):
            primary[full] = (path, decl.line)
        primary.setdefault(full, (path, decl.line))

    # Partial parts may omit the accessibility another part declares; an emitted part carries it.
    access: Dict[str, str] = {}
    for full, path, decl, members, whole in selections:
        declared = next((w for w in decl.header.split() if w in ("public", "protected", "internal")), None)
        if declared:
            access.setdefault(full, declared)

    def render(selection, indent: str) -> List[str]:
        full, path, decl, members, whole = selection
        nested = nested_of.get((path, decl.line), [])
        if not members and not nested and decl.kind != "enum" and primary.get(full) != (path, decl.line):
            return []                                             # another part of a partial type is emitted
        writer.path = path
        lines = [f"{indent}// {writer.cite(path, decl.line)}"]
        if decl.full_name in writer.diverged_interfaces:
            lines.append(f"{indent}// DIVERGENCE: an interface with nested types (C# 8); mcs -langversion:7.2 needs an abstract class.")
        if "unmanaged" in decl.header or any("unmanaged" in m.header for m in members):
            lines.append(f"{indent}// DIVERGENCE: `unmanaged` constraints (C# 7.3) are written as `struct` for mcs -langversion:7.2.")
        lines += writer.attributes(decl.attributes, indent)
        writer.selected_members = members
        type_header = writer.type_header(decl)
        if full in access and not re.match(r"(public|protected|internal|private)\b", type_header):
            type_header = f"{access[full]} {type_header}"
        lines.append(f"{indent}{type_header}")
        if decl.kind == "enum":
            body = re.sub(r"\[[^\]]*\]\s*", "", decl.body)
            lines.append(f"{indent}{body}")
            return lines
        lines.append(f"{indent}{{")
        overrides = set()
        for base in re.findall(r"\b\w+\b", type_header.split(":", 1)[1] if ":" in type_header else ""):
            overrides |= writer.abstract_members.get(base, set())
        if decl.full_name in writer.diverged_interfaces and re.search(r"\bIDisposable\b", type_header):
            lines.append(f"{indent}    // DIVERGENCE: as a class it must declare the IDisposable.Dispose its implementers provide.")
            lines.append(f"{indent}    public abstract void Dispose();")
        for member in sorted(members, key=lambda m: m.line):
            lines += writer.member(member, decl, indent + "    ", overrides)
        for child in sorted(nested, key=lambda s: s[2].line):
            lines += render(child, indent + "    ")
            writer.path = path
        lines.append(f"{indent}}}")
        return lines

    by_namespace: Dict[Tuple[str, Tuple[str, ...]], List] = {}
    for selection in sorted(top, key=lambda s: (s[2].namespace, s[0], s[1], s[2].line)):
        decl = selection[2]
        by_namespace.setdefault((decl.namespace, tuple(writer.usable_usings(decl.usings))), []).append(selection)
    for (namespace, usings), group in by_namespace.items():
        body = []
        for selection in group:
            body += render(selection, "    ")
        if not body:
            continue
        out.append(f"namespace {namespace}")
        out.append("{")
        out += [f"    {u};" for u in usings]
        out += body
        out.append("}")
        out.append("")
    return "\n".join(out)


def _all_nested(decl: TypeDecl) -> List[TypeDecl]:
    result = []
    for child in decl.nested:
        result.append(child)
        result.extend(_all_nested(child))
    return result


def usable_usings_factory(namespaces: set, type_names: set):
    def usable(usings: List[str]) -> List[str]:
        kept = []
        for using in usings:
            target = using.split("=", 1)[1].strip() if "=" in using else re.sub(r"^using\s+(static\s+)?", "", using)
            target = target.replace("global::", "")
            if "=" in using:
                ok = target.split(".")[0] == "System" or target.split(".")[-1] in type_names
            else:
                ok = target == "System" or target in {"System.Collections", "System.Collections.Generic", "System.Runtime.InteropServices",
                                                      "System.Runtime.CompilerServices", "System.Linq", "System.IO", "System.Text"} \
                     or target in namespaces
            if ok and not using.startswith("using static"):
                kept.append(using if "global::" not in using else using.replace("global::", ""))
        return sorted(set(kept))
    return usable


def generate_unity(source: Source, wanted: List[WantedType], version: str, engine_file: Path, editor_file: Path) -> List[str]:
    selections, errors = select(source, wanted, version)
    if errors:
        return errors
    engine = [s for s in selections if not _is_editor_path(s[1])]
    editor = [s for s in selections if _is_editor_path(s[1])]
    diverged = {s[0] for s in selections if s[2].kind == "interface" and s[2].nested}
    namespaces = {s[2].namespace for s in selections}
    names = {s[0].split(".")[-1] for s in selections}
    writer = SurfaceWriter(source, names, diverged)
    writer.abstract_members = {s[0].split(".")[-1]: {m.name for m in s[3]} | {"Dispose"} for s in selections if s[0] in diverged}
    # The engine assembly sees only its own namespaces; the editor assembly references the engine's.
    writer.usable_usings = usable_usings_factory({s[2].namespace for s in engine}, names)
    engine_file.write_text(emit(engine, writer, f"UnityEngine assemblies, Unity {version}"), encoding="utf-8")
    writer.usable_usings = usable_usings_factory(namespaces, names)
    editor_file.write_text(emit(editor, writer, f"UnityEditor assemblies, Unity {version}"), encoding="utf-8")
    return []


def _is_editor_path(path: str) -> bool:
    return path.startswith("Editor/") or "/Editor/" in path


def generate_inference(source: Source, wanted: List[WantedType], version: str, namespace_root: str,
                       unity_names: set, unity_namespaces: set, output: Path) -> List[str]:
    selections, errors = select(source, wanted, version, namespace_root)
    if errors:
        return errors
    names = {s[0].split(".")[-1] for s in selections} | unity_names
    writer = SurfaceWriter(source, names, set())
    writer.usable_usings = usable_usings_factory({s[2].namespace for s in selections} | unity_namespaces, names)
    writer.abstract_members = {}
    output.write_text(emit(selections, writer, f"{namespace_root} {version}"), encoding="utf-8")
    return []


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--unity-csreference", type=Path, required=True, help="clone of Unity-Technologies/UnityCsReference (branches 2022.3, 6000.x)")
    parser.add_argument("--sentis", type=Path, required=True, help="clone of needle-mirror/com.unity.sentis (tags 2.1.3, ...)")
    parser.add_argument("--inference-engine", type=Path, required=True, help="clone of needle-mirror/com.unity.ai.inference (tags 2.2.2, ...)")
    parser.add_argument("--manifest", type=Path, default=HERE / "members.txt")
    parser.add_argument("--output", type=Path, default=OUTPUT)
    args = parser.parse_args()
    sections = read_manifest(args.manifest)
    errors: List[str] = []
    sources_lines = []
    unity_names, unity_namespaces = set(), set()
    for wanted in sections["unity"]:
        unity_names.add(wanted.name.split(".")[-1])
        unity_namespaces.add(wanted.name.rsplit(".", 1)[0])
    for version in UNITY_VERSIONS:
        source = Source(args.unity_csreference, version, f"UnityCsReference {version}")
        folder = args.output / f"unity-{version}"
        folder.mkdir(parents=True, exist_ok=True)
        errors += generate_unity(source, sections["unity"], version, folder / "UnityEngine.cs", folder / "UnityEditor.cs")
        sources_lines.append(f"unity-{version} Unity-Technologies/UnityCsReference {version} {source.commit}")
    for repository, versions, root, prefix, package in (
            (args.sentis, SENTIS_VERSIONS, "Unity.Sentis", "sentis", "needle-mirror/com.unity.sentis"),
            (args.inference_engine, INFERENCE_ENGINE_VERSIONS, "Unity.InferenceEngine", "inference-engine", "needle-mirror/com.unity.ai.inference")):
        for version in versions:
            source = Source(repository, version, f"{package} {version}")
            folder = args.output / f"{prefix}-{version}"
            folder.mkdir(parents=True, exist_ok=True)
            errors += generate_inference(source, sections["inference"], version, root, unity_names, unity_namespaces, folder / f"{root}.cs")
            sources_lines.append(f"{prefix}-{version} {package} {version} {source.commit}")
    (args.output / "SOURCES.txt").write_text("# surface repository ref commit (written by Tools~/api-surface/generate.py)\n"
                                             + "\n".join(sources_lines) + "\n", encoding="utf-8")
    for error in errors:
        print(f"generate.py: {error}", file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
