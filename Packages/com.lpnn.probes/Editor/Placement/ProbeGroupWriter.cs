using System.Collections.Generic;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Placement;
using UnityEditor;
using UnityEngine;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>Writes probe positions into a LightProbeGroup with Undo and prefab-override support.
    /// LightProbeGroup.probePositions is in the group's local space (UnityCsReference Runtime/Export/Graphics/LightProbeGroup.bindings.cs;
    /// the group inspector converts with TransformPoint: Editor/Mono/Inspector/LightProbeGroupInspector.cs).</summary>
    public static class ProbeGroupWriter
    {
        /// <summary>Throws, naming what to do, when there is no group to write to: a missing or destroyed component (Unity's
        /// == null is true for both: UnityCsReference Runtime/Export/Scripting/UnityEngineObject.bindings.cs, operator ==).
        /// Callers check before minutes of selection work, not only when writing.</summary>
        public static void RequireTarget(LightProbeGroup group)
        {
            if (group == null)
                throw new LpnnException("the volume has no target LightProbeGroup; assign one (GameObject > Light > LPNN Probes creates one)");
        }

        public static void Apply(LightProbeGroup group, IReadOnlyList<NumericsVector3> worldPositions, string undoName)
        {
            RequireTarget(group);
            var local = UnityCoreConversions.WorldToLocal(group.transform, worldPositions);
            // A complete copy for Undo, as Unity's own probe-group editor does for every probe edit (UnityCsReference
            // Editor/Mono/Inspector/LightProbeGroupInspector.cs: Undo.RegisterCompleteObjectUndo): the whole position array is
            // replaced, which RecordObject's property diff handles poorly. The prefab call keeps the change as an override
            // on prefab instances (Editor/Mono/Prefabs/PrefabUtility.bindings.cs).
            Undo.RegisterCompleteObjectUndo(group, undoName);
            group.probePositions = local;
            PrefabUtility.RecordPrefabInstancePropertyModifications(group);
            EditorUtility.SetDirty(group);
        }

        public static void Clear(LightProbeGroup group) => Apply(group, new NumericsVector3[0], "Clear LPNN probes");

        /// <summary>Imports a *.probes.json (world positions) written by `lpnn place` or by batch mode; returns the count.</summary>
        public static int Import(LightProbeGroup group, string path)
        {
            var content = ProbePositionsFile.Read(path);
            if (content.Units != "m")
                Debug.LogWarning("[LPNN] " + path + " states units '" + content.Units + "'; positions are used as they are (Unity units are metres)");
            Apply(group, content.Positions, "Import LPNN probes");
            return content.Positions.Length;
        }
    }
}
