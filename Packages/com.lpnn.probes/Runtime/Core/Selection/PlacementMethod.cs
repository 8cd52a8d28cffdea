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
        /// <summary>The best method measured with the dense lighting and a model — both always there in the Unity pipeline,
        /// whose Lighting step samples SH at every evaluation point and whose volumes come with the shipped model: on the
        /// validation crops of Documentation~/benchmarks.md §10 (the choice) guided insertion needs 1.60× the reference's
        /// probes at τ = 0.05 against plain insertion's 1.66× and the network's 1.99×, with lower error at 10, 20 and 30 %
        /// budgets (1.40× the reference's at 20 % against 1.47× and 1.87×; a tie at 1 % and 5 %).</summary>
        public const PlacementMethod Default = PlacementMethod.GuidedInsertion;

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
