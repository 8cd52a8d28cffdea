using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>The evaluation points that may become probes: those the validity rule did not find inside geometry
    /// (Documentation~/features.md "Probe validity"). Every selection path takes its points from these only — the
    /// policies' rankings, the tolerance search, the bounds corners and the tetrahedron guarantee — so an invalid point
    /// never becomes a probe (Documentation~/selection.md).</summary>
    internal static class ValidCandidates
    {
        /// <summary>One flag per point: true when its back-face fraction is within the threshold. A NaN fraction (no rays
        /// were cast for the point) is an error, not a valid point.</summary>
        public static bool[] FromBackFaceFractions(float[] fractions)
        {
            if (fractions == null) throw new ArgumentNullException(nameof(fractions));
            var valid = new bool[fractions.Length];
            for (int n = 0; n < fractions.Length; n++)
            {
                float f = fractions[n];
                if (float.IsNaN(f) || f < 0 || f > 1)
                    throw new SelectionException("the back-face fraction of point " + n + " is " + InvariantFormat.Number(f) +
                                                 "; it must be a share of rays in [0, 1]: extract the features again");
                valid[n] = !ProbeValidity.IsInvalid(f);
            }
            return valid;
        }

        public static int CountInvalid(IReadOnlyList<bool> valid)
        {
            if (valid == null) return 0;
            int invalid = 0;
            for (int n = 0; n < valid.Count; n++) if (!valid[n]) invalid++;
            return invalid;
        }

        /// <summary>Checks that the valid points can hold a light probe group — at least 4, not all in one plane (Unity
        /// tetrahedralises the probes) — and explains what to do when they cannot. Returns how many are valid.</summary>
        public static int Check(EvaluationGrid grid, IReadOnlyList<bool> valid)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (valid == null || valid.Count != grid.Count)
                throw new SelectionException("the validity mask needs one flag per evaluation point: got " + (valid?.Count ?? 0) + " for " + grid.Count + " points");
            var ids = new List<LatticeId>();
            for (int n = 0; n < grid.Count; n++) if (valid[n]) ids.Add(grid.GetId(n));
            string shape = Degeneracy(ids);
            if (shape == null) return ids.Count;
            throw new SelectionException(
                "only " + InvariantFormat.Count(ids.Count) + " of " + InvariantFormat.Count(grid.Count) + " evaluation points are valid (" + shape +
                "); the other " + InvariantFormat.Count(grid.Count - ids.Count) + " are inside geometry (more than " +
                InvariantFormat.Number(ProbeValidity.BackFaceThreshold * 100) + " % of their rays hit back faces), and Unity needs at least 4 probes " +
                "not in one plane: move or enlarge the volume's boxes so they cover open space, or check that the meshes in it are closed and " +
                "their faces point outwards (a mesh seen from behind counts as inside), then extract the features again");
        }

        /// <summary>The feature rows of the valid points, in grid order: the network's input. It pools over the whole cloud
        /// and was trained on clouds without points inside geometry (the importer removes them), so invalid points would
        /// shift every other point's score.</summary>
        public static FeatureSet ValidRows(FeatureSet features, IReadOnlyList<bool> valid)
        {
            if (features == null) throw new ArgumentNullException(nameof(features));
            if (valid == null) return features;
            if (valid.Count != features.PointCount)
                throw new SelectionException("the validity mask needs one flag per point: got " + valid.Count + " for " + features.PointCount + " points");
            int stride = features.Schema.Count, kept = features.PointCount - CountInvalid(valid);
            var values = new float[(long)kept * stride];
            var fractions = features.BackFaceFractions == null ? null : new float[kept];
            for (int n = 0, m = 0; n < features.PointCount; n++)
            {
                if (!valid[n]) continue;
                Array.Copy(features.Values, (long)n * stride, values, (long)m * stride, stride);
                if (fractions != null) fractions[m] = features.BackFaceFractions[n];
                m++;
            }
            return new FeatureSet(features.Schema, kept, values, features.LightingScale, fractions);
        }

        /// <summary>Scores of the valid points (in their order) put back in grid order; an invalid point gets 0, the least
        /// importance (it is never selected anyway).</summary>
        public static float[] Scatter(float[] validScores, IReadOnlyList<bool> valid)
        {
            if (validScores == null) throw new ArgumentNullException(nameof(validScores));
            if (valid == null) return validScores;
            int kept = valid.Count - CountInvalid(valid);
            if (validScores.Length != kept)
                throw new SelectionException("got " + validScores.Length + " scores for " + kept + " valid points");
            var scores = new float[valid.Count];
            for (int n = 0, m = 0; n < valid.Count; n++) scores[n] = valid[n] ? validScores[m++] : 0f;
            return scores;
        }

        /// <summary>The ranking without the invalid points, order kept.</summary>
        public static int[] Filter(int[] ranking, IReadOnlyList<bool> valid)
        {
            if (ranking == null) throw new ArgumentNullException(nameof(ranking));
            if (valid == null) return ranking;
            var kept = new List<int>(ranking.Length);
            foreach (int index in ranking) if (valid[index]) kept.Add(index);
            return kept.ToArray();
        }

        /// <summary>Null when the ids span a tetrahedron, otherwise the shape they are confined to.</summary>
        private static string Degeneracy(List<LatticeId> ids)
        {
            if (ids.Count == 0) return "none at all";
            int second = ids.FindIndex(id => !id.Equals(ids[0]));
            if (second < 0) return "a single point";
            LatticeId a = ids[0], b = ids[second];
            int third = ids.FindIndex(id => !LatticeGeometry.Collinear(a, b, id));
            if (third < 0) return "all on one line";
            LatticeGeometry.Cross(a, b, ids[third], out var nx, out var ny, out var nz);
            return ids.Exists(id => !LatticeGeometry.InPlane(a, nx, ny, nz, id)) ? null : "all in one plane";
        }
    }
}
