"""Python port of the engine-agnostic C# core (Packages/com.lpnn.probes/Runtime/Core).

Every module here implements a spec in Documentation~ and is pinned to the C# numbers by the
golden files in Tests/Data.
"""
