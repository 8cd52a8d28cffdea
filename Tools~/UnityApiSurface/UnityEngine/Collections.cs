// Stand-ins for Unity.Collections / Unity.Jobs members (UnityEngine.CoreModule) used by LPNN (signatures only; see ../README.md).
using System;

namespace Unity.Collections
{
    // UnityCsReference 2022.3 Runtime/Export/Collections/NativeCollectionEnums.bindings.cs
    public enum Allocator { Invalid = 0, None = 1, Temp = 2, TempJob = 3, Persistent = 4 }

    // UnityCsReference 2022.3 Runtime/Export/NativeArray/NativeArray.cs
    public enum NativeArrayOptions { UninitializedMemory = 0, ClearMemory = 1 }

    // UnityCsReference 2022.3 Runtime/Export/NativeArray/NativeArray.cs
    public struct NativeArray<T> : IDisposable where T : struct
    {
        public NativeArray(int length, Allocator allocator, NativeArrayOptions options = NativeArrayOptions.ClearMemory) { throw null; }
        public int Length { get { throw null; } }
        public T this[int index] { get { throw null; } set { } }
        public void Dispose() { }
    }
}

namespace Unity.Jobs
{
    // UnityCsReference 2022.3 Runtime/Jobs/ScriptBindings/JobHandle.bindings.cs
    public struct JobHandle
    {
        public void Complete() { }
    }
}
