using System;
using Lpnn.Probes.Core.Numerics;
using UnityEditor;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>The pieces every section of the LPNN volume inspector draws the same way: headers, property fields, a step's
    /// status, and leaving the GUI pass after a modal panel.</summary>
    internal static class InspectorLayout
    {
        public static void Header(string title)
        {
            EditorGUILayout.Space();
            EditorGUILayout.LabelField(title, EditorStyles.boldLabel);
        }

        public static void Field(SerializedProperty property) => EditorGUILayout.PropertyField(property, true);

        /// <summary>The step's ✓ line, its caveat and its last error.</summary>
        public static void Status(StepState step)
        {
            if (step.Done)
                EditorGUILayout.LabelField("✓ " + step.Summary + Timing(step), EditorStyles.wordWrappedMiniLabel);
            if (step.Warning.Length > 0) EditorGUILayout.HelpBox(step.Warning, MessageType.Warning);
            if (step.Error.Length > 0) EditorGUILayout.HelpBox(step.Error + Timing(step), MessageType.Error);
        }

        /// <summary>After a modal panel or a long step run from inside layout scopes, the IMGUI event has changed under the
        /// open groups; finishing the layout then fails with "EndLayoutGroup: BeginLayoutGroup must be called first". Unity's
        /// own inspectors end the GUI pass instead (UnityCsReference Modules/IMGUI/GUIUtility.cs ExitGUI, which throws
        /// ExitGUIException that Unity catches). Pending serialized edits are applied first so the choice is not lost.</summary>
        public static void EndGuiAfterModal(SerializedObject edited)
        {
            edited.ApplyModifiedProperties();
            GUIUtility.ExitGUI();
        }

        private static string Timing(StepState step) =>
            step.Seconds < 0 ? "" : " (" + InvariantFormat.Number(Math.Round(step.Seconds, 2)) + " s)";
    }
}
