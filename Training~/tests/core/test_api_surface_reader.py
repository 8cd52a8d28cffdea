"""The C# declaration reader behind Tools~/api-surface/generate.py (the generated Unity API surfaces), on a small source
that has what the real UnityCsReference files have: preprocessor blocks, comments and strings with braces, attributes,
overloads, generics with constraints, expression bodies, explicit interface implementations, file-scoped namespaces."""

from __future__ import annotations

import sys
from pathlib import Path

TOOLS = Path(__file__).resolve().parents[3] / "Tools~" / "api-surface"
sys.path.insert(0, str(TOOLS))

from csharp_declarations import FileDeclarations  # noqa: E402
from generate import member_matches, is_public_api  # noqa: E402

SOURCE = r'''
using System;
namespace UnityEngine
{
    // a comment with a brace {
    public partial class Object
    {
        const string k = "a string with } and \" inside";
#if UNITY_EDITOR
        [Obsolete("Use GetEntityId instead.", true)]
        public int GetInstanceID() => 0;
#else
        public int PlayerOnly() => 0;
#endif
        public static T[] FindObjectsByType<T>(FindObjectsSortMode sortMode) where T : Object { return null; }
        public static T[] FindObjectsByType<T>() where T : Object { return null; }
        public string name { get { return ""; } private set { } }
        public float x, y;
        System.Collections.IEnumerator System.Collections.IEnumerable.GetEnumerator() { return null; }
        private void Hidden() { }
        public struct Nested<T> where T : unmanaged { public Nested(in T value) { } }
    }
}
'''


def _object():
    declarations = FileDeclarations(SOURCE, {"UNITY_EDITOR"})
    (decl,) = declarations.types
    return decl


def test_types_members_and_preprocessor() -> None:
    decl = _object()
    assert decl.full_name == "UnityEngine.Object"
    names = [m.name for m in decl.members]
    assert "GetInstanceID" in names and "PlayerOnly" not in names, "only the UNITY_EDITOR branch is read"
    assert names.count("FindObjectsByType<T>") == 2
    assert {"x", "y", "name", "GetEnumerator", "Hidden", "k"} <= set(names)
    (nested,) = decl.nested
    assert nested.full_name == "UnityEngine.Object.Nested<T>"
    assert nested.members[0].kind == "ctor" and nested.members[0].parameters == ["inT"]


def test_obsolete_attribute_and_overload_selection() -> None:
    decl = _object()
    get_id = next(m for m in decl.members if m.name == "GetInstanceID")
    assert get_id.attributes == ['Obsolete("Use GetEntityId instead.", true)']
    by_sort = [m for m in decl.members if member_matches(m, "FindObjectsByType<T>(FindObjectsSortMode)")]
    assert len(by_sort) == 1 and "sortMode" in by_sort[0].header and "where T : Object" in by_sort[0].header
    assert [m for m in decl.members if member_matches(m, "FindObjectsByType<T>()")][0].parameters == []


def test_accessibility() -> None:
    decl = _object()
    visible = {m.name for m in decl.members if is_public_api(m.header, False)}
    assert "GetEnumerator" in visible, "explicit interface implementations are part of the public surface"
    assert "Hidden" not in visible and "k" not in visible
