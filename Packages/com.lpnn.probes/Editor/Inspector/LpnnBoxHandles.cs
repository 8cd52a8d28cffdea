using UnityEditor;
using UnityEditor.IMGUI.Controls;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>Scene-view handles that resize and move each box of a volume (BoxBoundsHandle: UnityCsReference
    /// Editor/Mono/EditorHandles/BoundsHandle/BoxBoundsHandle.cs). Edits go through SerializedProperty, so they are
    /// undoable and recorded as prefab overrides.</summary>
    internal sealed class LpnnBoxHandles
    {
        private readonly BoxBoundsHandle _handle = new BoxBoundsHandle();

        /// <param name="boxes">The volume's serialized box list (LpnnVolumeProperties.Boxes), a property of <paramref name="edited"/>.</param>
        public void Draw(LpnnVolume volume, SerializedObject edited, SerializedProperty boxes)
        {
            if (boxes == null) return;
            for (int b = 0; b < boxes.arraySize; b++)
            {
                var box = boxes.GetArrayElementAtIndex(b);
                var center = box.FindPropertyRelative(nameof(LpnnBox.center));
                var size = box.FindPropertyRelative(nameof(LpnnBox.size));
                var rotation = Quaternion.Euler(box.FindPropertyRelative(nameof(LpnnBox.rotation)).vector3Value);
                // Handles.matrix: Editor/Mono/Handles.cs — the handle works in the box's own frame.
                using (new Handles.DrawingScope(new Color(1f, 0.75f, 0.2f), volume.transform.localToWorldMatrix *
                                                    Matrix4x4.TRS(center.vector3Value, rotation, Vector3.one)))
                {
                    _handle.center = Vector3.zero;
                    _handle.size = size.vector3Value;
                    EditorGUI.BeginChangeCheck();
                    _handle.DrawHandle();
                    if (!EditorGUI.EndChangeCheck()) continue;
                    center.vector3Value += rotation * _handle.center;
                    size.vector3Value = _handle.size;
                }
            }
            edited.ApplyModifiedProperties();
        }
    }
}
