using System;
using System.Runtime.ExceptionServices;
using System.Threading.Tasks;

namespace Lpnn.Probes.Core.Numerics
{
    /// <summary>A loop over 0 .. count − 1 run as contiguous chunks on every core (Parallel.For over the chunks), or on the
    /// calling thread when the loop is small. The answers must not depend on how the loop is split: a body writes each
    /// index's result to that index's own slots only (no shared sums, counts or lists), and every sum and tie over the
    /// indices is taken afterwards on the calling thread in index order, as before the loop ran in parallel
    /// (Documentation~/benchmarks.md "The C# core under Mono"). Scratch buffers are made per chunk. A body must not call
    /// the engine (Unity's physics and tetrahedraliser run on its main thread only) nor report progress: the callers cast
    /// rays, tetrahedralise and report on the calling thread, before or after the loop.</summary>
    internal static class ParallelChunks
    {
        /// <summary>Indices per chunk below which a loop is not split (a task's start costs tens of microseconds, a point's
        /// location and interpolation about a microsecond).</summary>
        internal const int MinimumChunk = 2048;

        /// <summary>Chunks per thread, so that a core that finishes early (its points inside the hull, cheap) takes another.</summary>
        private const int ChunksPerThread = 4;

        /// <summary>Tests only: 0 splits as above; k &gt; 0 splits every loop into exactly min(k, count) chunks whatever its size
        /// (1: serial). Read on the calling thread, per thread, so a test cannot leak it into another's run.</summary>
        [ThreadStatic] internal static int ForcedChunks;

        /// <summary>Runs <paramref name="body"/>(start, end) over contiguous ranges covering 0 .. <paramref name="count"/> − 1
        /// once each, possibly at the same time on several threads; returns when all have run. When bodies throw, the
        /// exception of the lowest range is rethrown as it was thrown (not wrapped) — the one a serial loop would have
        /// met first, whichever chunks happened to run.</summary>
        internal static void For(int count, Action<int, int> body)
        {
            if (body == null) throw new ArgumentNullException(nameof(body));
            if (count <= 0) return;
            int threads = Math.Max(1, Environment.ProcessorCount);
            int chunks = ForcedChunks > 0 ? Math.Min(ForcedChunks, count)
                : threads == 1 ? 1 : Math.Min(ChunksPerThread * threads, count / MinimumChunk);
            if (chunks <= 1)
            {
                body(0, count);
                return;
            }
            var thrown = new Exception[chunks];  // per chunk, so several failing chunks cannot race to be the one reported
            Parallel.For(0, chunks, new ParallelOptions { MaxDegreeOfParallelism = threads }, c =>
            {
                try
                {
                    body((int)((long)count * c / chunks), (int)((long)count * (c + 1) / chunks));
                }
                catch (Exception e)
                {
                    thrown[c] = e;
                }
            });
            foreach (var e in thrown)
                if (e != null) ExceptionDispatchInfo.Capture(e).Throw();
        }
    }
}
