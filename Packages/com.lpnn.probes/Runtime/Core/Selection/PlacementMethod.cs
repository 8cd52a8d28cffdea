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
        /// <summary>Guided insertion (Quality.InsertionRanking with the scores as guide, quality.md §5.2): <see cref="Insertion"/>
        /// whose tetrahedra take, among their badly interpolated points, the one the network rates highest (error ×
        /// sqrt(score / median)); needs the lighting, the Features and Scoring steps, and the rounds of insertion. On volumes of
        /// more than Quality.InsertionRanking.GuidedPointLimit valid points the guide is not used (plain insertion).</summary>
        GuidedInsertion = 2,
    }

    /// <summary>The default method and what each one needs.</summary>
    public static class PlacementMethods
    {
        /// <summary>The best method measured with the dense lighting, which the Unity pipeline always has (its Lighting step
        /// samples SH at every evaluation point), once Apply refines in batches (LpnnVolume.RefineInBatches, on by default;
        /// Documentation~/quality.md §5.3): on the 10 validation crops (Documentation~/benchmarks.md "The speed/accuracy trade, every method", the choice) insertion
        /// refined in batches keeps 1.01× the reference's probes at τ = 0.05 (the default policy) against 1.04× for guided
        /// insertion refined the same way, and 1.00/1.08/1.05/1.04/1.05× the reference's error at 1/5/10/20/30 % against
        /// 1.01/1.08/1.04/1.02/1.04×: the guide helps little after the refinement (0.5–2 % at 5–30 %, not at τ or 1 %), and
        /// plain insertion needs neither the Features nor the Scoring step. (Before the refinement, guided insertion was the default: 1.60× against 1.66× at τ.)</summary>
        public const PlacementMethod Default = PlacementMethod.Insertion;

        /// <summary>True when the method reads the network's scores (the Features and Scoring steps must run first): the
        /// network's ranking, or guided insertion's guide.</summary>
        public static bool NeedsScores(PlacementMethod method) => method == PlacementMethod.Network || method == PlacementMethod.GuidedInsertion;

        /// <summary>True when the insertion rounds rank the points (on the sampled lighting; guided by the scores for
        /// <see cref="PlacementMethod.GuidedInsertion"/>), false when the spread ranking of the scores does (Network).</summary>
        public static bool RanksByInsertion(PlacementMethod method) => method == PlacementMethod.Insertion || method == PlacementMethod.GuidedInsertion;

        /// <summary>True when the stored scores guide the insertion rounds (<see cref="PlacementMethod.GuidedInsertion"/>).</summary>
        public static bool GuidesInsertion(PlacementMethod method) => method == PlacementMethod.GuidedInsertion;
    }
}
