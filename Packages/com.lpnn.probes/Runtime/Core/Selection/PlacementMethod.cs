namespace Lpnn.Probes.Core.Selection
{
    /// <summary>What ranks the evaluation points before a policy keeps a prefix of them. Values are stored in scenes (Unity
    /// serializes the number), so new methods are only ever appended.</summary>
    public enum PlacementMethod
    {
        /// <summary>The network's scores (Scoring step), through the spread ranking (Documentation~/selection.md):
        /// milliseconds, but needs features and a model, and measured worse than <see cref="Insertion"/>.</summary>
        Network = 0,
        /// <summary>Error-driven insertion on the sampled lighting (Quality.InsertionRanking, quality.md §5): no features,
        /// no model; about a second per 1,000 points of Unity tetrahedralisations.</summary>
        Insertion = 1,
    }

    /// <summary>The default method and what each one needs.</summary>
    public static class PlacementMethods
    {
        /// <summary>The best method measured where the dense lighting is available — always in the Unity pipeline, whose
        /// Lighting step samples SH at every evaluation point: on the held-out crops of Documentation~/benchmarks.md §7.1,
        /// insertion needs 1.63× the reference's probes at τ = 0.05 against the network's 2.06×, and has 1.43× the
        /// reference's error at a 20 % budget against 1.82× (lower at every budget from 5 %; a tie at 1 %).</summary>
        public const PlacementMethod Default = PlacementMethod.Insertion;

        /// <summary>True when the method ranks by the network's scores (the Features and Scoring steps must run first).</summary>
        public static bool NeedsScores(PlacementMethod method) => method == PlacementMethod.Network;
    }
}
