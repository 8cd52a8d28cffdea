using System;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Editor
{
    /// <summary>What the Grid step's in-use rule decided (Documentation~/in-use.md "What placement does with the mask"):
    /// the grid before the rule, which of its points are in use, and how that was found. For Band and Reachable the
    /// session's grid holds the in-use points only; for All it holds every point and <see cref="GridMask"/> says which are
    /// in use by the report rule (Reachable, or Band without seeds), so the error at them can be shown.</summary>
    internal sealed class InUsePoints
    {
        /// <summary>The volume's rule when the grid was built.</summary>
        public InUseRule Rule { get; }
        /// <summary>The rule <see cref="InUseOfAll"/> was computed with: <see cref="Rule"/>, or for All the report rule.</summary>
        public InUseRule MaskRule { get; }
        /// <summary>Band height, slope limit and step height; null when the points were restored from stored scores.</summary>
        public InUseParameters Parameters { get; }
        public int SeedCount { get; }
        /// <summary>Where the floors came from ("physics rays", "the NavMesh (N triangles)", "the stored scores").</summary>
        public string FloorSource { get; }
        /// <summary>Every point of the volume's boxes, before the rule.</summary>
        public EvaluationGrid AllPoints { get; }
        /// <summary>One flag per point of <see cref="AllPoints"/>: in use by <see cref="MaskRule"/>; null when unknown (All, when
        /// the report mask could not be computed: <see cref="Unavailable"/> says why).</summary>
        public bool[] InUseOfAll { get; }
        /// <summary>Why there is no mask ("" when there is one).</summary>
        public string Unavailable { get; }

        public InUsePoints(InUseRule rule, InUseRule maskRule, InUseParameters parameters, int seedCount, string floorSource,
            EvaluationGrid allPoints, bool[] inUseOfAll, string unavailable)
        {
            AllPoints = allPoints ?? throw new ArgumentNullException(nameof(allPoints));
            if (inUseOfAll != null && inUseOfAll.Length != allPoints.Count)
                throw new ArgumentException("the mask has " + inUseOfAll.Length + " flags for " + allPoints.Count + " points", nameof(inUseOfAll));
            Rule = rule;
            MaskRule = maskRule;
            Parameters = parameters;
            SeedCount = seedCount;
            FloorSource = floorSource ?? "";
            InUseOfAll = inUseOfAll;
            Unavailable = unavailable ?? "";
            if (inUseOfAll != null) foreach (bool flag in inUseOfAll) if (flag) InUseCount++;
        }

        public int PointsBefore => AllPoints.Count;
        /// <summary>Points in use by <see cref="MaskRule"/> (0 when unknown).</summary>
        public int InUseCount { get; }
        public bool Known => InUseOfAll != null;
        /// <summary>True when the session's grid holds the in-use points only (Band, Reachable).</summary>
        public bool Filters => Rule != InUseRule.All;

        /// <summary>One flag per point of the session's grid, for the error at the points in use: the report mask for All
        /// (null when unknown); null for Band and Reachable, whose grid holds the in-use points only (all of them count).</summary>
        public bool[] GridMask => Filters ? null : InUseOfAll;

        /// <summary>"1,234 of 5,678 points in use (reachable from 3 seeds, floors from physics rays)".</summary>
        public string Describe()
        {
            if (!Known) return "in use: n/a (" + Unavailable + ")";
            if (Parameters == null)
                return InvariantFormat.Count(InUseCount) + " of " + InvariantFormat.Count(PointsBefore) + " points in use (" + InUseRules.Name(MaskRule) +
                       ": the points the stored scores were made for; build the grid again to apply the rule anew)";
            string how = InUseRules.Name(MaskRule) + (MaskRule == InUseRule.Reachable ? " from " + SeedCount + (SeedCount == 1 ? " seed" : " seeds") : "") +
                         ", floors from " + FloorSource;
            return InvariantFormat.Count(InUseCount) + " of " + InvariantFormat.Count(PointsBefore) + " points in use (" + how + ")" +
                   (Filters ? "" : "; rule all keeps every point");
        }
    }
}
