using System;
using System.Collections.Generic;
using System.IO;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Captures;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Pipeline;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>The editor-free Apply on a real level's capture (Documentation~/ci.md "Apply rehearsal"):
    /// <see cref="ApplySteps.Rehearse"/> with fakes of Unity's light sampler (the capture's SH), features (the capture's:
    /// their rays were cast by the importer) and probe group (the writes are recorded). The tetrahedraliser is the caller's:
    /// <see cref="PythonTetrahedralizer"/>, or a wrapper of it. Shared by Tests/Core/ApplyRehearsalTests.cs and the Apply
    /// benchmark (Tools~/experiments/SelectionBench, <c>csharp-selection-bench.sh --apply</c>).</summary>
    public static class RehearsalApply
    {
        /// <summary>ApplySteps.Rehearse on <paramref name="capture"/> (its grid: <paramref name="grid"/>, Capture.ToGrid()),
        /// the positions written added to <paramref name="writes"/>. <paramref name="leakRays"/> (null: leak-blind): the level's
        /// rays, for the leak-aware refinement a volume that avoids light leaks runs (<see cref="TriangleSoupRaycaster"/> over
        /// the capture's triangles standing in for Unity's physics); <paramref name="rememberSegments"/> false casts every
        /// segment anew instead of remembering it (the same probes, more rays: LeakWeighting's switch, for the benchmark).</summary>
        public static SelectionResult Run(Capture capture, EvaluationGrid grid, ITetrahedralizer tetrahedralizer, SelectionSettings settings, bool refine,
            List<Vector3[]> writes, ProgressCallback progress, CancellationToken cancel, IRaycaster leakRays = null, bool rememberSegments = true)
        {
            if (capture == null) throw new ArgumentNullException(nameof(capture));
            if (writes == null) throw new ArgumentNullException(nameof(writes));
            var leaks = leakRays == null ? null : new LeakWeighting(leakRays, LeakWeighting.DefaultWeight, rememberSegments);
            return ApplySteps.Rehearse(grid, new CaptureLighting(capture, grid), CaptureFeatures(capture), tetrahedralizer, settings, refine,
                new RecordingWriter(writes), progress, cancel, null, leaks);
        }

        /// <summary>The capture's SH at the points asked for (the Lighting step asks in batches of grid points: each position is
        /// found back as its grid point, so a point the capture does not hold is an error, not a wrong answer).</summary>
        private sealed class CaptureLighting : ILightSampler
        {
            private readonly Capture _capture;
            private readonly Dictionary<Vector3, int> _index = new Dictionary<Vector3, int>();

            public CaptureLighting(Capture capture, EvaluationGrid grid)
            {
                if (grid.Count != capture.PointCount)
                    throw new InvalidOperationException("the grid has " + grid.Count + " points, the capture " + capture.PointCount);
                _capture = capture;
                for (int n = 0; n < grid.Count; n++) _index[grid.GetPosition(n)] = n;
            }

            public void Sample(Vector3[] positions, float[] sh)
            {
                for (int p = 0; p < positions.Length; p++)
                {
                    if (!_index.TryGetValue(positions[p], out int n))
                        throw new InvalidOperationException("the lighting was asked for a point the capture does not hold: " + positions[p]);
                    Array.Copy(_capture.Sh, 27 * n, sh, 27 * p, 27);
                }
            }
        }

        private static FeatureStep CaptureFeatures(Capture capture) => (grid, sh, progress, cancel) =>
        {
            if (grid.Count != capture.PointCount)
                throw new InvalidOperationException("features asked for " + grid.Count + " points, the capture has " + capture.PointCount);
            return new FeatureSet(FeatureSchema.ById(capture.Schema), capture.PointCount, capture.Features, capture.LightingScale);
        };

        private sealed class RecordingWriter : IProbeGroupWriter
        {
            private readonly List<Vector3[]> _writes;
            public RecordingWriter(List<Vector3[]> writes) { _writes = writes; }
            public void Write(Vector3[] positions) => _writes.Add(positions);
        }
    }

    /// <summary>Python's tetrahedralisation (Training~/tests/quality/rehearsal_tetrahedralizer.py, started through a shell
    /// script that runs it on the capture): a level's lattice is cospherical, so the Delaunay tetrahedralisation is not unique
    /// and only the same tie-breaking gives the same errors; <see cref="BowyerWatsonDelaunay"/> needs general position and is
    /// O(n²). Protocol: the script's docstring.</summary>
    public sealed class PythonTetrahedralizer : ITetrahedralizer, IDisposable
    {
        private readonly ScriptPipe _pipe;
        /// <summary>Tetrahedralisations asked for so far.</summary>
        public int Calls;

        /// <param name="script">A shell script that execs rehearsal_tetrahedralizer.py on the capture.</param>
        public PythonTetrahedralizer(string script)
        {
            _pipe = new ScriptPipe(script, "rehearsal tetrahedraliser");
        }

        public int[] Tetrahedralize(Vector3[] positions)
        {
            Calls++;
            var request = new byte[4 + 12 * positions.Length];
            BitConverter.GetBytes(positions.Length).CopyTo(request, 0);
            for (int n = 0; n < positions.Length; n++)
            {
                BitConverter.GetBytes(positions[n].X).CopyTo(request, 4 + 12 * n);
                BitConverter.GetBytes(positions[n].Y).CopyTo(request, 8 + 12 * n);
                BitConverter.GetBytes(positions[n].Z).CopyTo(request, 12 + 12 * n);
            }
            _pipe.Send(request);
            int count = BitConverter.ToInt32(_pipe.Read(4), 0);
            if (count < 0)
            {
                int length = BitConverter.ToInt32(_pipe.Read(4), 0);
                throw new PlacementErrorException(System.Text.Encoding.UTF8.GetString(_pipe.Read(length)));
            }
            var bytes = _pipe.Read(16 * count);
            var tets = new int[4 * count];
            Buffer.BlockCopy(bytes, 0, tets, 0, bytes.Length);
            return tets;
        }

        public void Dispose() => _pipe.Dispose();
    }
}
