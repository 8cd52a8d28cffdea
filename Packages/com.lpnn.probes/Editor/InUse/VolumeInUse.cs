using System.Threading;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Editor
{
    /// <summary>The in-use rule of a volume at the Grid step (Documentation~/in-use.md): floors and walls by physics rays
    /// against the scene's colliders (the <see cref="PhysicsRaycaster"/> inside a <see cref="RaycastScope"/>, as the Features
    /// step casts), or floors from the scene's baked NavMesh (<see cref="NavMeshFloor"/>) with walls still by physics.</summary>
    internal static class VolumeInUse
    {
        /// <summary>Which points of <paramref name="all"/> are in use by the volume's settings. For Band and Reachable an error
        /// names the fix when the rule cannot be applied (no seed, seeds away from floors, no point in use); for All the mask
        /// is only reported, so a rule that cannot be applied leaves it unknown (<see cref="InUsePoints.Unavailable"/>).</summary>
        public static InUsePoints Compute(LpnnVolume volume, EvaluationGrid all, ProgressCallback progress, CancellationToken cancel)
        {
            var rule = volume.InUseRule;
            InUseRules.Name(rule);  // an unknown stored value stops here, named
            var parameters = Checked(volume, volume.GetInUseParameters);
            // Band reads no seed (an empty entry in the list does not matter to it).
            var seeds = rule == InUseRule.Band ? new System.Numerics.Vector3[0] : volume.GetInUseSeedPositions();
            // Reachable walks from seeds; a volume without any (a new one) keeps the band, as `lpnn scene import` does on a
            // level without spawns, and says so in the grid summary (FloorSource) rather than stopping the first Build grid.
            string fallback = "";
            if (rule == InUseRule.Reachable && seeds.Length == 0)
            {
                rule = InUseRule.Band;
                fallback = "; Band: no In Use Seeds to walk from (add the scene's spawn points for Reachable)";
            }
            // All reports the error at the reachable points, or at the band points where there are no seeds (in-use.md).
            var maskRule = rule != InUseRule.All ? rule : seeds.Length > 0 ? InUseRule.Reachable : InUseRule.Band;
            using (new RaycastScope(volume, volume.AddTemporaryColliders))
            {
                var walls = new PhysicsRaycaster(volume.gameObject.scene);  // the volume's physics scene (Prefab Mode too)
                var navMesh = volume.UseNavMesh ? NavMeshFloor.Baked() : null;
                IRaycaster floors = navMesh ?? (IRaycaster)walls;
                string floorSource = (navMesh == null ? "physics rays" : "the NavMesh (" + InvariantFormat.Count(navMesh.TriangleCount) + " triangles)") +
                                     fallback;
                bool[] mask;
                string unavailable = "";
                try
                {
                    mask = InUseMask.Compute(all, floors, walls, parameters, maskRule, seeds, progress, cancel);
                }
                catch (InUseException e)
                {
                    if (rule != InUseRule.All) throw InVolume(volume, e);
                    mask = null;
                    unavailable = e.Message;
                }
                return new InUsePoints(rule, maskRule, parameters, seeds.Length, floorSource, Kept(all, rule), mask, unavailable);
            }
        }

        /// <summary>The points before the rule as the session keeps them (for the gizmos and the reports): for All the grid itself
        /// (it is the session's grid); for Band and Reachable a copy without the id lookup the rule's walk built on it (a
        /// dictionary of every point, tens of MB at 10^6 points, which nothing needs afterwards).</summary>
        private static EvaluationGrid Kept(EvaluationGrid all, InUseRule rule)
        {
            if (rule == InUseRule.All) return all;
            var every = new bool[all.Count];
            for (int p = 0; p < every.Length; p++) every[p] = true;
            return all.Subset(every);
        }

        private static InUseParameters Checked(LpnnVolume volume, System.Func<InUseParameters> parameters)
        {
            try
            {
                return parameters();
            }
            catch (InUseException e)
            {
                throw InVolume(volume, e);
            }
        }

        /// <summary>The core's message, with where the settings are in the inspector.</summary>
        private static LpnnException InVolume(LpnnVolume volume, InUseException e) =>
            new LpnnException("volume '" + volume.name + "': " + e.Message + " (the In Use settings are in the inspector's Volume section)");
    }
}
