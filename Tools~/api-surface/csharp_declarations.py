"""Reads the declarations of one C# source file: namespaces, using directives, types and their members.

Only what a signature-only surface needs is read: attribute lists, declaration headers and where each
body ends. Bodies are skipped by brace matching on a copy of the text whose comments, string and
character literals are blanked, so braces inside them never count. Preprocessor blocks are resolved
with the symbols given (Unity's C# reference sources are compiled for the editor: UNITY_EDITOR).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import List, Optional, Set, Tuple

TYPE_KEYWORDS = ("class", "struct", "interface", "enum")


@dataclass
class Member:
    name: str                 # "Foo", "Foo<T>", "this[]", "operator ==", ".ctor"
    kind: str                 # method, ctor, property, indexer, field, event, operator, delegate
    attributes: List[str]     # attribute list texts, e.g. 'Obsolete("...", true)'
    header: str               # declaration text before the body (masked literals restored)
    body: str                 # body text ('{...}', '=> ...', ';' or '= ...;')
    line: int
    parameters: Optional[List[str]] = None   # normalised parameter types for methods/ctors/operators/indexers


@dataclass
class TypeDecl:
    full_name: str            # Namespace.Outer.Inner
    name: str
    kind: str                 # class, struct, interface, enum
    attributes: List[str]
    header: str
    body: str                 # enum bodies are copied whole
    line: int
    namespace: str
    usings: List[str]
    members: List[Member] = field(default_factory=list)
    nested: List["TypeDecl"] = field(default_factory=list)


def _blank(text: str) -> str:
    return re.sub(r"[^\n]", " ", text)


def strip_comments_and_mask(source: str) -> Tuple[str, str]:
    """Returns (code, masked): comments blanked in both; in `masked` also the contents of literals."""
    code, masked = [], []
    i, n = 0, len(source)
    while i < n:
        c = source[i]
        if source.startswith("//", i):
            j = source.find("\n", i)
            j = n if j < 0 else j
            code.append(_blank(source[i:j])); masked.append(_blank(source[i:j])); i = j
        elif source.startswith("/*", i):
            j = source.find("*/", i + 2)
            j = n if j < 0 else j + 2
            code.append(_blank(source[i:j])); masked.append(_blank(source[i:j])); i = j
        elif source.startswith('"""', i):
            j = source.find('"""', i + 3)
            j = n if j < 0 else j + 3
            code.append(source[i:j]); masked.append('"' + _blank(source[i + 1:j - 1]).replace(" ", "_") + '"'); i = j
        elif c == '"' or (c in "@$" and i + 1 < n and source[i + 1] in '"@$'):
            start = i
            verbatim = False
            while source[i] in "@$":
                verbatim = verbatim or source[i] == "@"
                i += 1
            i += 1  # opening quote
            while i < n:
                if verbatim and source.startswith('""', i):
                    i += 2
                elif not verbatim and source[i] == "\\":
                    i += 2
                elif source[i] == '"':
                    i += 1
                    break
                else:
                    i += 1
            literal = source[start:i]
            code.append(literal)
            masked.append(literal[0] + re.sub(r"[^\n]", "_", literal[1:-1]) + literal[-1])
        elif c == "'":
            j = i + 1
            while j < n and source[j] != "'":
                j += 2 if source[j] == "\\" else 1
            literal = source[i:j + 1]
            code.append(literal); masked.append("'" + "_" * (len(literal) - 2) + "'"); i = j + 1
        else:
            code.append(c); masked.append(c); i += 1
    return "".join(code), "".join(masked)


def _evaluate_condition(expression: str, defined: Set[str]) -> bool:
    python = re.sub(r"&&", " and ", expression)
    python = re.sub(r"\|\|", " or ", python)
    python = re.sub(r"!(?!=)", " not ", python)
    python = re.sub(r"\b(true|false)\b", lambda m: m.group(1).capitalize(), python)
    python = re.sub(r"\b(?!and\b|or\b|not\b|True\b|False\b)([A-Za-z_]\w*)\b",
                    lambda m: "True" if m.group(1) in defined else "False", python)
    return bool(eval(python, {"__builtins__": {}}, {}))  # noqa: S307 — only True/False/and/or/not remain


def resolve_preprocessor(code: str, masked: str, defined: Set[str]) -> Tuple[str, str]:
    """Blanks directive lines and the lines of inactive #if/#elif/#else branches (line numbers are kept)."""
    defined = set(defined)
    out_code, out_masked = [], []
    stack: List[List[bool]] = []  # [parent active, this branch active, some branch taken]
    for line_code, line_masked in zip(code.split("\n"), masked.split("\n")):
        stripped = line_masked.strip()
        active = all(frame[1] for frame in stack)
        if stripped.startswith("#"):
            directive = re.match(r"#\s*(\w+)\s*(.*)", stripped)
            word, rest = (directive.group(1), directive.group(2)) if directive else ("", "")
            if word == "if":
                value = active and _evaluate_condition(rest, defined)
                stack.append([active, value, value])
            elif word == "elif" and stack:
                frame = stack[-1]
                value = frame[0] and not frame[2] and _evaluate_condition(rest, defined)
                frame[1] = value; frame[2] = frame[2] or value
            elif word == "else" and stack:
                frame = stack[-1]
                frame[1] = frame[0] and not frame[2]; frame[2] = True
            elif word == "endif" and stack:
                stack.pop()
            elif word == "define" and active:
                defined.add(rest.split()[0])
            elif word == "undef" and active:
                defined.discard(rest.split()[0])
            out_code.append(_blank(line_code)); out_masked.append(_blank(line_masked))
        elif active:
            out_code.append(line_code); out_masked.append(line_masked)
        else:
            out_code.append(_blank(line_code)); out_masked.append(_blank(line_masked))
    return "\n".join(out_code), "\n".join(out_masked)


_OPEN = {"(": ")", "[": "]", "{": "}"}


def _match(masked: str, i: int) -> int:
    """Index just past the bracket that closes the one at i."""
    depth, n = 0, len(masked)
    while i < n:
        c = masked[i]
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
            if depth == 0:
                return i + 1
        i += 1
    raise ValueError("unbalanced brackets")


def _until_semicolon(masked: str, i: int) -> int:
    """Index just past the next ';' outside brackets."""
    n = len(masked)
    while i < n:
        c = masked[i]
        if c in "([{":
            i = _match(masked, i)
            continue
        if c == ";":
            return i + 1
        i += 1
    raise ValueError("missing ';'")


def split_top_level(text: str, separator: str = ",") -> List[str]:
    parts, depth, start = [], 0, 0
    for i, c in enumerate(text):
        if c in "([{<":
            depth += 1
        elif c in ")]}>":
            depth -= 1
        elif c == separator and depth == 0:
            parts.append(text[start:i]); start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts if p.strip()]


def normalise_parameters(parameter_text: str) -> List[str]:
    """Parameter types only: attributes, names, defaults, `this` and `params` dropped; ref/out/in kept."""
    result = []
    for parameter in split_top_level(parameter_text):
        parameter = re.sub(r"^\s*(\[[^\]]*\]\s*)+", "", parameter)
        parameter = parameter.split("=")[0].strip()
        parameter = re.sub(r"^(this|params)\s+", "", parameter)
        parameter = re.sub(r"\s*\b[A-Za-z_@]\w*$", "", parameter)  # the name
        result.append(re.sub(r"\s+", "", parameter))
    return result


def _last_identifier(text: str) -> str:
    match = re.search(r"(@?[A-Za-z_]\w*)\s*(<[^<>()]*(?:<[^<>()]*>[^<>()]*)*>)?\s*$", text)
    if not match:
        raise ValueError(f"no name in '{text.strip()}'")
    name = match.group(1).lstrip("@")
    return name + (re.sub(r"\s+", "", match.group(2)) if match.group(2) else "")


class FileDeclarations:
    """All namespaces, usings and types of one file."""

    def __init__(self, source: str, defined: Set[str]):
        code, masked = strip_comments_and_mask(source)
        self.code, self.masked = resolve_preprocessor(code, masked, defined)
        self.types: List[TypeDecl] = []
        self._parse_scope(0, len(self.masked), "", [], None, file_scope=True)

    def _line(self, i: int) -> int:
        return self.masked.count("\n", 0, i) + 1

    def _text(self, start: int, end: int) -> str:
        return re.sub(r"\s+", " ", self.code[start:end]).strip()

    def _parse_scope(self, start: int, end: int, namespace: str, usings: List[str],
                     owner: Optional[TypeDecl], file_scope: bool = False) -> None:
        masked = self.masked
        usings = list(usings)
        i = start
        while i < end:
            while i < end and masked[i] in " \t\r\n;":
                i += 1
            if i >= end:
                return
            attributes = []
            while masked[i] == "[":
                close = _match(masked, i)
                attributes.extend(split_top_level(self._text(i + 1, close - 1)))
                i = close
                while i < end and masked[i] in " \t\r\n":
                    i += 1
            header_start = i
            # The header ends at '{', ';', '=>' or a field initializer's '=' outside brackets.
            j, seen_operator, terminator = i, False, None
            while j < end:
                c = masked[j]
                if c in "([":
                    j = _match(masked, j); continue
                if c == "{" or c == ";":
                    terminator = c; break
                if c == "=" and masked[j + 1] == ">":
                    terminator = "=>"; break
                if c == "=" and not seen_operator and masked[j + 1] != "=" and masked[j - 1] not in "=!<>":
                    terminator = "="; break
                if masked.startswith("operator", j) and not re.match(r"\w", masked[j - 1]):
                    seen_operator = True
                j += 1
            header_masked = re.sub(r"\s+", " ", masked[header_start:j]).strip()
            header = self._text(header_start, j)
            words = re.findall(r"[A-Za-z_]\w*", re.sub(r"<[^{]*>|\([^{]*\)", " ", header_masked))
            line = self._line(header_start)
            if header_masked.startswith("using ") and terminator in (";", "="):
                stop = _until_semicolon(masked, j)
                usings.append(self._text(header_start, stop - 1)); i = stop; continue
            if header_masked.startswith("namespace "):
                name = header_masked.split()[1]
                full = f"{namespace}.{name}" if namespace else name
                if terminator == ";":  # file-scoped namespace
                    namespace = full; i = j + 1; continue
                close = _match(masked, j)
                self._parse_scope(j + 1, close - 1, full, usings, None)
                i = close; continue
            type_match = re.match(r"^[^(=]*?\b(class|struct|interface|enum)\s+@?\w+", re.split(r"\swhere\s", header_masked)[0])
            type_keyword = type_match.group(1) if type_match else None
            if type_keyword and "delegate" not in words and terminator == "{":
                close = _match(masked, j)
                name_match = re.search(rf"\b{type_keyword}\s+(@?\w+)(\s*<[^<>]*>)?", header_masked)
                name = name_match.group(1) + re.sub(r"\s+", "", name_match.group(2) or "")
                prefix = owner.full_name if owner else namespace
                decl = TypeDecl(full_name=f"{prefix}.{name}" if prefix else name, name=name, kind=type_keyword,
                                attributes=attributes, header=header, body=self._text(j, close), line=line,
                                namespace=namespace, usings=usings)
                if type_keyword != "enum":
                    self._parse_scope(j + 1, close - 1, namespace, usings, decl)
                (owner.nested if owner else self.types).append(decl)
                i = close; continue
            # A member.
            if terminator == "{":
                stop = _match(masked, j)
                if stop < end and re.match(r"\s*=", masked[stop:stop + 80]) and not re.match(r"\s*=>", masked[stop:stop + 80]):
                    stop = _until_semicolon(masked, stop)  # auto-property initializer
            elif terminator == ";":
                stop = j + 1
            else:
                stop = _until_semicolon(masked, j)
            if owner is not None:
                try:
                    owner.members.extend(self._members(attributes, header, header_masked, self._text(j, stop), line))
                except ValueError:
                    pass  # a declaration this reader does not understand (never one the manifest names: those are checked)
            i = stop

    def _members(self, attributes, header, header_masked, body, line) -> List[Member]:
        callable_header = re.search(r"\)\s*(where\s.*)?$", header_masked) is not None or re.search(r"\bthis\s*\[", header_masked)
        if callable_header or body.startswith("{") or body.startswith("=>"):
            return [self._member(attributes, header, header_masked, body, line)]
        # A field declaration, possibly with several declarators: one Member each.
        declarators = split_top_level((header + " " + body).rstrip().rstrip(";"))
        first = declarators[0].split("=")[0].strip()
        type_and_modifiers = first[:first.rindex(_last_identifier(first))].strip()
        members = []
        for k, declarator in enumerate(declarators):
            name_and_value = declarator if k else declarator[len(type_and_modifiers):]
            name = name_and_value.split("=")[0].strip()
            value = name_and_value[name_and_value.index("="):].strip() if "=" in name_and_value else ""
            members.append(Member(name, "field", attributes, f"{type_and_modifiers} {name}", (value + ";") if value else ";", line))
        return members

    def _member(self, attributes, header, header_masked, body, line) -> Member:
        words = re.findall(r"[A-Za-z_]\w*", re.sub(r"\([^{]*\)", " ", header_masked))
        if "delegate" in words:
            return Member(_last_identifier(header[:header.index("(")]), "delegate", attributes, header, body, line)
        if "event" in words:
            return Member(_last_identifier(header), "event", attributes, header, body, line)
        if re.search(r"\bthis\s*\[", header_masked):
            params = header[header.index("[", header.index("this")) + 1:header.rindex("]")]
            return Member("this[]", "indexer", attributes, header, body, line, normalise_parameters(params))
        if re.search(r"\)\s*(where\s.*)?$", header_masked):
            before = header[:header.index("(")]
            params = header[header.index("(") + 1:_paren_close(header, header.index("(")) - 1]
            operator = re.search(r"\boperator\s*(\S+)\s*$", before)
            if operator:
                conversion = re.search(r"\b(implicit|explicit)\s+operator\s+(.+)$", before)
                name = f"{conversion.group(1)} operator {conversion.group(2).strip()}" if conversion else f"operator {operator.group(1)}"
                return Member(name, "operator", attributes, header, body, line, normalise_parameters(params))
            name = _last_identifier(before)
            kind = "ctor" if _is_ctor(before) else "method"
            return Member(name, kind, attributes, header, body, line, normalise_parameters(params))
        return Member(_last_identifier(header), "property", attributes, header, body, line)


def _paren_close(text: str, i: int) -> int:
    depth = 0
    for k in range(i, len(text)):
        if text[k] == "(":
            depth += 1
        elif text[k] == ")":
            depth -= 1
            if depth == 0:
                return k + 1
    raise ValueError("unbalanced parentheses")


def _is_ctor(before: str) -> bool:
    """A constructor header is modifiers followed by the name only (no return type)."""
    modifiers = {"public", "private", "protected", "internal", "static", "extern", "unsafe"}
    tokens = before.split()
    return all(t in modifiers for t in tokens[:-1])
