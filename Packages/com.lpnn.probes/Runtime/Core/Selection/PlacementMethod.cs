using System;
using System.Collections.Generic;
using System.Linq;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>What places the evaluation points: the C# rows of the table of placement methods (Documentation~/methods.md;
    /// <see cref="PlacementMethods.All"/> holds their names and labels). Values are stored in scenes (Unity serializes the
    /// number), so new methods are appended, never renumbered: the refined methods, which replaced the separate "Refine in
    /// batches" toggle, came last (3 and 4) so that every value saved before them, pinned by the 0.1.0 serialization test
    /// (Tests/Editor/Data/LpnnVolume_0.1.0.expected.json: 0 is Network), still names the same ranking.</summary>
    public enum PlacementMethod
    {
        /// <summary><c>network</c>: the network's scores (Scoring step), through the spread ranking (Documentation~/selection.md):
        /// milliseconds, but needs features and a model, and measured worse than the insertion methods.</summary>
        Network = 0,
        /// <summary><c>insertion</c>: error-driven insertion on the sampled lighting (Quality.InsertionRanking, quality.md §5):
        /// no features, no model; about a second per 1,000 points of Unity tetrahedralisations.</summary>
        Insertion = 1,
        /// <summary><c>guided</c>: guided insertion (Quality.InsertionRanking with the scores as guide, quality.md §5.2): <see cref="Insertion"/>
        /// whose tetrahedra take, among their badly interpolated points, the one the network rates highest (error ×
        /// sqrt(score / median)); needs the lighting, the Features and Scoring steps, and the rounds of insertion. On volumes of
        /// more than Quality.InsertionRanking.GuidedPointLimit valid points the guide is not used (plain insertion).</summary>
        GuidedInsertion = 2,
        /// <summary><c>insertion-refined</c>: <see cref="Insertion"/>, then Apply refines its first 2K points (3K at small budgets) in batches down to
        /// K (Quality.BatchedRefinement, quality.md §5.3). The default.</summary>
        InsertionRefined = 3,
        /// <summary><c>guided-refined</c>: <see cref="GuidedInsertion"/>, then Apply refines in batches as
        /// <see cref="InsertionRefined"/> does.</summary>
        GuidedInsertionRefined = 4,
    }

    /// <summary>One row of the table of placement methods (Documentation~/methods.md): the method, its name (what
    /// <c>lpnn place --method</c>, batch mode's <c>-lpnnMethod</c> and a probes file's source.method say) and label (what the
    /// inspector shows), and what it needs and runs.</summary>
    public sealed class PlacementMethodInfo
    {
        internal PlacementMethodInfo(PlacementMethod method, string name, string label, bool needsScores, bool ranksByInsertion,
            bool guidesInsertion, bool refinesInBatches)
        {
            Method = method;
            Name = name;
            Label = label;
            NeedsScores = needsScores;
            RanksByInsertion = ranksByInsertion;
            GuidesInsertion = guidesInsertion;
            RefinesInBatches = refinesInBatches;
        }

        public PlacementMethod Method { get; }
        public string Name { get; }
        public string Label { get; }
        /// <summary>The method reads the network's scores (the Features and Scoring steps must run first).</summary>
        public bool NeedsScores { get; }
        /// <summary>The insertion rounds rank the points (on the sampled lighting), not the spread ranking of the scores.</summary>
        public bool RanksByInsertion { get; }
        /// <summary>The stored scores guide the insertion rounds.</summary>
        public bool GuidesInsertion { get; }
        /// <summary>Apply refines the ranking's first 2K points (3K at small budgets) in batches down to K (quality.md §5.3).</summary>
        public bool RefinesInBatches { get; }
    }

    /// <summary>The table of the placement methods the C# core implements, the default, and what each one needs. The same
    /// rows as Python's <c>lpnn.quality.placement.methods</c>: both are pinned to Tests/Data/placement_methods.json
    /// (Tests/Core/PlacementMethodsTests.cs, Training~/tests/quality/test_placement_methods.py).</summary>
    public static class PlacementMethods
    {
        /// <summary>The best method measured with the dense lighting, which the Unity pipeline always has (its Lighting step
        /// samples SH at every evaluation point; Documentation~/quality.md §5.3): on the 10 validation crops
        /// (Documentation~/benchmarks.md "The speed/accuracy trade, every method", the choice) insertion refined in batches keeps 1.01× the reference's probes at
        /// τ = 0.05 (the default policy) against 1.04× for guided insertion refined the same way, and 1.00/1.08/1.05/1.04/1.05×
        /// the reference's error at 1/5/10/20/30 % against 1.01/1.08/1.04/1.02/1.04×: the guide helps little after the
        /// refinement (0.5–2 % at 5–30 %, not at τ or 1 %), and plain insertion needs neither the Features nor the Scoring
        /// step. (Before the refinement, guided insertion was the default: 1.60× against 1.66× at τ.)</summary>
        public const PlacementMethod Default = PlacementMethod.InsertionRefined;

        /// <summary>Every C# method, in the table's order (Documentation~/methods.md).</summary>
        public static readonly IReadOnlyList<PlacementMethodInfo> All = new[]
        {
            new PlacementMethodInfo(PlacementMethod.InsertionRefined, "insertion-refined", "Insertion, refined",
                needsScores: false, ranksByInsertion: true, guidesInsertion: false, refinesInBatches: true),
            new PlacementMethodInfo(PlacementMethod.Insertion, "insertion", "Insertion",
                needsScores: false, ranksByInsertion: true, guidesInsertion: false, refinesInBatches: false),
            new PlacementMethodInfo(PlacementMethod.GuidedInsertionRefined, "guided-refined", "Guided insertion, refined",
                needsScores: true, ranksByInsertion: true, guidesInsertion: true, refinesInBatches: true),
            new PlacementMethodInfo(PlacementMethod.GuidedInsertion, "guided", "Guided insertion",
                needsScores: true, ranksByInsertion: true, guidesInsertion: true, refinesInBatches: false),
            new PlacementMethodInfo(PlacementMethod.Network, "network", "Network",
                needsScores: true, ranksByInsertion: false, guidesInsertion: false, refinesInBatches: false),
        };

        /// <summary>The row of <paramref name="method"/>.</summary>
        public static PlacementMethodInfo Of(PlacementMethod method)
        {
            foreach (var row in All)
                if (row.Method == method) return row;
            throw new ArgumentOutOfRangeException(nameof(method), method, "not a placement method");
        }

        /// <summary>The method called <paramref name="name"/> (the table's name, any case), or false.</summary>
        public static bool TryParse(string name, out PlacementMethod method)
        {
            foreach (var row in All)
            {
                if (string.Equals(row.Name, name, StringComparison.OrdinalIgnoreCase))
                {
                    method = row.Method;
                    return true;
                }
            }
            method = Default;
            return false;
        }

        /// <summary>Every name, comma-separated, in the table's order (for messages that list the choices).</summary>
        public static string Names => string.Join(", ", All.Select(row => row.Name));

        /// <summary>The table's name, e.g. "insertion-refined".</summary>
        public static string Name(PlacementMethod method) => Of(method).Name;

        /// <summary>The table's label, e.g. "Insertion, refined" (the inspector's Method).</summary>
        public static string Label(PlacementMethod method) => Of(method).Label;

        /// <summary>True when the method reads the network's scores (the Features and Scoring steps must run first): the
        /// network's ranking, or guided insertion's guide.</summary>
        public static bool NeedsScores(PlacementMethod method) => Of(method).NeedsScores;

        /// <summary>True when the insertion rounds rank the points (on the sampled lighting; guided by the scores for the
        /// guided methods), false when the spread ranking of the scores does (Network).</summary>
        public static bool RanksByInsertion(PlacementMethod method) => Of(method).RanksByInsertion;

        /// <summary>True when the stored scores guide the insertion rounds.</summary>
        public static bool GuidesInsertion(PlacementMethod method) => Of(method).GuidesInsertion;

        /// <summary>True when Apply refines the ranking in batches (quality.md §5.3).</summary>
        public static bool RefinesInBatches(PlacementMethod method) => Of(method).RefinesInBatches;
    }
}
