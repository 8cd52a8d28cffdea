namespace Lpnn.Probes.Core.InUse
{
    /// <summary>Which evaluation points are in use (Documentation~/in-use.md "Rules"): reachable ⊆ band ⊆ all. Values are
    /// stored in scenes (Unity serializes the number), so new rules are only ever appended. Public: a volume's setting
    /// (LpnnVolume.InUseRule).</summary>
    public enum InUseRule
    {
        /// <summary>Every evaluation point (dynamic objects fly: the volume's old behaviour).</summary>
        All = 0,
        /// <summary>The points within the band height above a walkable surface.</summary>
        Band = 1,
        /// <summary>The band points a character walks to from a seed (a spawn, an item, a marked position).</summary>
        Reachable = 2,
    }

    /// <summary>The rules' names as the spec, the command line and captures write them ("all", "band", "reachable").</summary>
    internal static class InUseRules
    {
        /// <summary>The rule of a new Unity volume (and of a saved volume from before the rule existed): the one place it is
        /// chosen on the C# side. Issue 29 item 3 measures all / band / reachable on real levels (Documentation~/benchmarks.md
        /// "Points in use") and may change it; until then, reachable (Documentation~/in-use.md: it follows the floors
        /// characters walk on, not the tops of walls).</summary>
        public const InUseRule Default = InUseRule.Reachable;

        public static string Name(InUseRule rule)
        {
            switch (rule)
            {
                case InUseRule.All: return "all";
                case InUseRule.Band: return "band";
                case InUseRule.Reachable: return "reachable";
                default: throw new InUseException("in-use rule " + (int)rule + " is not one of all, band, reachable");
            }
        }

        public static InUseRule Parse(string name)
        {
            switch (name)
            {
                case "all": return InUseRule.All;
                case "band": return InUseRule.Band;
                case "reachable": return InUseRule.Reachable;
                default: throw new InUseException("in-use rule '" + name + "' is not one of reachable, band, all");
            }
        }
    }
}
