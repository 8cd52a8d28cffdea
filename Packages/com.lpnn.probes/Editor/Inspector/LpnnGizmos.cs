using System.Collections.Generic;
using Lpnn.Probes.Core.Selection;
using UnityEditor;
using UnityEngine;
using Lpnn.Probes.Core.Scoring;

namespace Lpnn.Probes.Editor
{
    /// <summary>Scene-view drawing of a volume (DrawGizmo: UnityCsReference Editor/Mono/DrawGizmo.cs; Gizmos:
    /// Runtime/Export/Gizmos/Gizmos.bindings.cs): the boxes always, and when selected the points the in-use rule left out
    /// (small grey cubes) and the points in use (green until scored), the scored evaluation points coloured by remapped
    /// score (blue low, red high), the probes of the target group and the edges of the leaking tetrahedra (magenta).</summary>
    internal static class LpnnGizmos
    {
        /// <summary>Gizmos are immediate mode; beyond this many points only every n-th is drawn.</summary>
        private const int MaxDrawnPoints = 20000;
        private static readonly Color BoxColor = new Color(1f, 0.75f, 0.2f, 0.9f);
        private static readonly Color ProbeColor = new Color(1f, 0.95f, 0.3f, 1f);
        private static readonly Color InUseColor = new Color(0.2f, 0.9f, 0.35f, 0.8f);
        private static readonly Color NotInUseColor = new Color(0.55f, 0.55f, 0.55f, 0.3f);
        /// <summary>Edges of the tetrahedra holding a leaking point (Documentation~/leaks.md).</summary>
        private static readonly Color LeakColor = new Color(1f, 0.2f, 0.75f, 0.9f);
        private static readonly Dictionary<ObjectKey, ScoreCloud> Clouds = new Dictionary<ObjectKey, ScoreCloud>();
        private static readonly Dictionary<ObjectKey, InUseCloud> InUseClouds = new Dictionary<ObjectKey, InUseCloud>();

        /// <summary>The session's points before the in-use rule, split into in use and not, at most MaxDrawnPoints of them.</summary>
        private sealed class InUseCloud
        {
            public InUsePoints Source;
            public Vector3[] InUse;
            public Vector3[] Other;
        }

        private sealed class ScoreCloud
        {
            public float[] Source;
            public Vector3[] Positions;
            public Color[] Colors;
        }

        [DrawGizmo(GizmoType.Selected | GizmoType.NonSelected | GizmoType.Active)]
        private static void Draw(LpnnVolume volume, GizmoType type)
        {
            if (!volume.ShowGizmos) return;
            bool selected = (type & (GizmoType.Selected | GizmoType.Active)) != 0;
            DrawBoxes(volume, selected);
            if (!selected) return;
            DrawInUse(volume);
            DrawScores(volume);
            DrawProbes(volume.TargetGroup, volume.CellSize);
            DrawLeaks(volume);
        }

        /// <summary>The edges of the leaking tetrahedra of the volume's last leak report (at most
        /// <see cref="LeaksAtPointsInUse.MaxDrawnTetrahedra"/>; the inspector line says when more leak).</summary>
        private static void DrawLeaks(LpnnVolume volume)
        {
            var entry = LeaksAtPointsInUse.Last(volume);
            if (entry == null) return;
            var c = entry.Corners;
            Gizmos.color = LeakColor;
            for (int t = 0; t + 3 < c.Length; t += 4)
            {
                // Gizmos.DrawLine: UnityCsReference Runtime/Export/Gizmos/Gizmos.bindings.cs
                Gizmos.DrawLine(c[t], c[t + 1]);
                Gizmos.DrawLine(c[t], c[t + 2]);
                Gizmos.DrawLine(c[t], c[t + 3]);
                Gizmos.DrawLine(c[t + 1], c[t + 2]);
                Gizmos.DrawLine(c[t + 1], c[t + 3]);
                Gizmos.DrawLine(c[t + 2], c[t + 3]);
            }
        }

        private static void DrawBoxes(LpnnVolume volume, bool selected)
        {
            var previous = Gizmos.matrix;
            Gizmos.color = selected ? BoxColor : new Color(BoxColor.r, BoxColor.g, BoxColor.b, 0.35f);
            foreach (var box in volume.Boxes)
            {
                Gizmos.matrix = volume.transform.localToWorldMatrix * Matrix4x4.TRS(box.center, box.LocalRotation, Vector3.one);
                Gizmos.DrawWireCube(Vector3.zero, box.size);
            }
            Gizmos.matrix = previous;
        }

        private static void DrawScores(LpnnVolume volume)
        {
            var record = LpnnScores.For(volume);
            if (record.IsEmpty) return;
            var cloud = CloudOf(volume, record);
            var size = Vector3.one * (float)(record.CellSize * 0.15);
            for (int p = 0; p < cloud.Positions.Length; p++)
            {
                Gizmos.color = cloud.Colors[p];
                Gizmos.DrawCube(cloud.Positions[p], size);
            }
        }

        /// <summary>The points the in-use rule left out, and the points in use until scores colour them.</summary>
        private static void DrawInUse(LpnnVolume volume)
        {
            var inUse = LpnnSession.For(volume).InUse;
            if (inUse == null || !inUse.Known) return;
            var cloud = InUseCloudOf(volume, inUse);
            float cell = (float)inUse.AllPoints.CellSize;
            Gizmos.color = NotInUseColor;
            var small = Vector3.one * (cell * 0.06f);
            foreach (var position in cloud.Other) Gizmos.DrawCube(position, small);
            if (!LpnnScores.For(volume).IsEmpty) return;
            Gizmos.color = InUseColor;
            var size = Vector3.one * (cell * 0.12f);
            foreach (var position in cloud.InUse) Gizmos.DrawCube(position, size);
        }

        /// <summary>Recomputed only when the Grid step replaces the session's in-use outcome.</summary>
        private static InUseCloud InUseCloudOf(LpnnVolume volume, InUsePoints inUse)
        {
            var key = ObjectKey.Of(volume);
            if (InUseClouds.TryGetValue(key, out var cloud) && cloud.Source == inUse) return cloud;
            var all = inUse.AllPoints;
            int stride = Mathf.Max(1, Mathf.CeilToInt(all.Count / (float)MaxDrawnPoints));
            var inside = new List<Vector3>();
            var other = new List<Vector3>();
            for (int p = 0; p < all.Count; p += stride) (inUse.InUseOfAll[p] ? inside : other).Add(all.GetPosition(p).ToUnity());
            cloud = new InUseCloud { Source = inUse, InUse = inside.ToArray(), Other = other.ToArray() };
            InUseClouds[key] = cloud;
            return cloud;
        }

        /// <summary>Positions and colours are recomputed only when the scores array changes.</summary>
        private static ScoreCloud CloudOf(LpnnVolume volume, ScoreRecord record)
        {
            var key = ObjectKey.Of(volume);
            if (Clouds.TryGetValue(key, out var cloud) && cloud.Source == record.Scores) return cloud;
            double[] remapped = ScoreRanking.Remap(record.Scores);
            int stride = Mathf.Max(1, Mathf.CeilToInt(record.Count / (float)MaxDrawnPoints));
            int drawn = (record.Count + stride - 1) / stride;
            cloud = new ScoreCloud { Source = record.Scores, Positions = new Vector3[drawn], Colors = new Color[drawn] };
            var ids = record.Ids;
            for (int d = 0, p = 0; d < drawn; d++, p += stride)
            {
                cloud.Positions[d] = new Vector3((float)(record.CellSize * ids[3 * p]), (float)(record.CellSize * ids[3 * p + 1]),
                    (float)(record.CellSize * ids[3 * p + 2]));
                var c = Color.Lerp(new Color(0.1f, 0.3f, 1f), new Color(1f, 0.15f, 0.1f), (float)remapped[p]);
                c.a = 0.35f + 0.65f * (float)remapped[p];
                cloud.Colors[d] = c;
            }
            Clouds[key] = cloud;
            return cloud;
        }

        private static void DrawProbes(LightProbeGroup group, float cellSize)
        {
            if (group == null) return;
            var local = group.probePositions;
            int stride = Mathf.Max(1, Mathf.CeilToInt(local.Length / (float)MaxDrawnPoints));
            Gizmos.color = ProbeColor;
            for (int p = 0; p < local.Length; p += stride)
                Gizmos.DrawWireSphere(group.transform.TransformPoint(local[p]), cellSize * 0.25f);
        }
    }
}
