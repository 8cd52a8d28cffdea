using System;
using System.Numerics;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The dense lighting a placement must reproduce (Documentation~/quality.md §2): for every evaluation point
    /// its position and its SH evaluated in the 14 directions of D14, RGB — 42 values in double, direction-major —
    /// plus the scene scale S. Built once per grid and lighting and shared by every placement evaluated on it
    /// (the tolerance search evaluates ~2·log₂N of them). Memory: 24 + 12 + 336 bytes per point.</summary>
    public sealed class ReferenceLighting
    {
        /// <summary>14 directions × RGB.</summary>
        public const int LightValues = 42;

        private readonly Vector3[] _positions;

        public int Count => _positions.Length;

        /// <summary>S of Documentation~/features.md (median DC luminance; 1 for a black capture).</summary>
        public double SceneScale { get; }

        internal LocalFrame Frame { get; }

        /// <summary>Positions in <see cref="Frame"/>, x, y, z per point.</summary>
        internal double[] Local { get; }

        /// <summary>E(p, d) per point: 42 values, direction d of D14 major, then r, g, b.</summary>
        internal double[] Light { get; }

        private double[] _tieHeights;

        /// <summary>Each point's tie-breaking height (<see cref="TieBreak"/>), computed on first use: only the batched
        /// refinement's star refills need it (a k-d tree over every point for the spacing).</summary>
        internal double[] TieHeights => _tieHeights ?? (_tieHeights = TieBreak.Heights(this));

        private ReferenceLighting(Vector3[] positions, double[] local, LocalFrame frame, double[] light, double sceneScale)
        {
            _positions = positions;
            Local = local;
            Frame = frame;
            Light = light;
            SceneScale = sceneScale;
        }

        public Vector3 GetPosition(int index) => _positions[index];

        public static ReferenceLighting FromGrid(EvaluationGrid grid, float[] sh)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            return Create(Positions(grid), sh);
        }

        public static ReferenceLighting FromGrid(EvaluationGrid grid, float[] sh, double sceneScale)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            return Create(Positions(grid), sh, sceneScale);
        }

        /// <summary>With the scene scale computed from the SH (<see cref="Features.SceneScale"/>).</summary>
        public static ReferenceLighting Create(Vector3[] positions, float[] sh)
        {
            CheckSh(positions, sh);
            return Build(positions, sh, Features.SceneScale.Compute(sh, positions.Length));
        }

        /// <param name="positions">Evaluation points (also the candidate probe positions).</param>
        /// <param name="sh">27 floats per point (Documentation~/sh.md).</param>
        /// <param name="sceneScale">S, e.g. a capture's <c>lighting_scale</c>.</param>
        public static ReferenceLighting Create(Vector3[] positions, float[] sh, double sceneScale)
        {
            CheckSh(positions, sh);
            return Build(positions, sh, sceneScale);
        }

        private static ReferenceLighting Build(Vector3[] positions, float[] sh, double sceneScale)
        {
            if (!(sceneScale > 0) || double.IsInfinity(sceneScale))
                throw new PlacementErrorException("scene scale " + InvariantFormat.Number(sceneScale) + " must be a finite number greater than 0");
            int count = positions.Length;
            var local = new double[3 * count];
            for (int n = 0; n < count; n++)
            {
                var p = positions[n];
                if (!IsFinite(p.X) || !IsFinite(p.Y) || !IsFinite(p.Z))
                    throw new PlacementErrorException("evaluation point " + n + " has a non-finite position " + InvariantFormat.Vector(p) +
                                                      "; every point needs finite coordinates");
                local[3 * n] = p.X;
                local[3 * n + 1] = p.Y;
                local[3 * n + 2] = p.Z;
            }
            var frame = LocalFrame.Of(local);
            if (!(frame.Scale > 0))
                throw new PlacementErrorException("all " + InvariantFormat.Count(count) + " evaluation points coincide at " + InvariantFormat.Vector(positions[0]) +
                                                  ": a placement needs points that span a volume");
            frame.ToLocal(local);
            return new ReferenceLighting((Vector3[])positions.Clone(), local, frame, Evaluate(sh, count), sceneScale);
        }

        private static Vector3[] Positions(EvaluationGrid grid)
        {
            var positions = new Vector3[grid.Count];
            for (int n = 0; n < positions.Length; n++) positions[n] = grid.GetPosition(n);
            return positions;
        }

        private static void CheckSh(Vector3[] positions, float[] sh)
        {
            if (positions == null) throw new ArgumentNullException(nameof(positions));
            if (sh == null) throw new ArgumentNullException(nameof(sh));
            if (positions.Length == 0) throw new PlacementErrorException("there are no evaluation points: the error of an empty grid is undefined");
            if (sh.Length != ShMath.FloatsPerProbe * positions.Length)
                throw new PlacementErrorException("need 27 SH coefficients per evaluation point: got " + InvariantFormat.Count(sh.Length) + " values for " +
                                                  InvariantFormat.Count(positions.Length) + " points");
            int firstBad = -1, bad = 0;
            for (int n = 0; n < positions.Length; n++)
            {
                if (ShMath.IsFinite(sh, n * ShMath.FloatsPerProbe)) continue;
                if (firstBad < 0) firstBad = n;
                bad++;
            }
            if (firstBad < 0) return;
            int offset = firstBad * ShMath.FloatsPerProbe, column = 0;
            while (!float.IsNaN(sh[offset + column]) && !float.IsInfinity(sh[offset + column])) column++;
            throw new PlacementErrorException(
                "the reference SH of point " + firstBad + " is not finite (sh[" + "rgb"[column / ShMath.CoefficientsPerChannel] + "," +
                column % ShMath.CoefficientsPerChannel + "] = " + InvariantFormat.Number(sh[offset + column]) + "; " + InvariantFormat.Count(bad) +
                " points affected): sample the lighting again");
        }

        /// <summary>E(p, d) over D14 in double (Documentation~/sh.md Evaluate, without the float32 rounding).</summary>
        private static double[] Evaluate(float[] sh, int count)
        {
            int directions = DirectionSets.D14.GetLength(0);
            var light = new double[LightValues * count];
            for (int n = 0; n < count; n++)
            {
                for (int d = 0; d < directions; d++)
                {
                    ShMath.Evaluate(sh, n * ShMath.FloatsPerProbe, DirectionSets.D14[d, 0], DirectionSets.D14[d, 1], DirectionSets.D14[d, 2],
                        out double r, out double g, out double b);
                    int o = LightValues * n + 3 * d;
                    light[o] = r;
                    light[o + 1] = g;
                    light[o + 2] = b;
                }
            }
            return light;
        }

        private static bool IsFinite(float v) => !float.IsNaN(v) && !float.IsInfinity(v);
    }
}
