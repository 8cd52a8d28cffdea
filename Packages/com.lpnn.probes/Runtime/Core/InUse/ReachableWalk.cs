using System.Collections.Generic;

namespace Lpnn.Probes.Core.InUse
{
    /// <summary>Documentation~/in-use.md "Definitions" 5: every point the directed moves reach from the start points, by a
    /// breadth-first walk over the moves grouped by source (an index array, as Python's).</summary>
    internal static class ReachableWalk
    {
        public static bool[] Reach(int pointCount, int[] starts, List<int> sources, List<int> targets)
        {
            // Moves grouped by source: the targets of point p are following[offsets[p] .. offsets[p + 1]).
            var offsets = new int[pointCount + 1];
            foreach (int source in sources) offsets[source + 1]++;
            for (int p = 0; p < pointCount; p++) offsets[p + 1] += offsets[p];
            var following = new int[targets.Count];
            var next = (int[])offsets.Clone();
            for (int m = 0; m < sources.Count; m++) following[next[sources[m]]++] = targets[m];

            var reached = new bool[pointCount];
            var queue = new Queue<int>();
            foreach (int start in starts)
            {
                if (reached[start]) continue;
                reached[start] = true;
                queue.Enqueue(start);
            }
            while (queue.Count > 0)
            {
                int point = queue.Dequeue();
                for (int m = offsets[point]; m < offsets[point + 1]; m++)
                {
                    int target = following[m];
                    if (reached[target]) continue;
                    reached[target] = true;
                    queue.Enqueue(target);
                }
            }
            return reached;
        }
    }
}
