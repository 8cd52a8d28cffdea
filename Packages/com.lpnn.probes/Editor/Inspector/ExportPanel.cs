using System.IO;
using UnityEditor;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>The inspector's Capture export section: ground truth, the dataset folder, Save capture… and Append to dataset.</summary>
    internal static class ExportPanel
    {
        public static void Draw(LpnnVolume volume, LpnnSession session, StepStates steps, SerializedObject edited, LpnnVolumeProperties properties)
        {
            InspectorLayout.Header(LpnnVolumeStyles.ExportHeader);
            InspectorLayout.Field(properties.GroundTruthGroup);
            using (new EditorGUILayout.HorizontalScope())
            {
                InspectorLayout.Field(properties.DatasetFolder);
                if (GUILayout.Button(LpnnVolumeStyles.ChooseFolder, GUILayout.Width(70)))
                {
                    string folder = EditorUtility.SaveFolderPanel(LpnnVolumeStyles.DatasetFolderPanel, LpnnPaths.DatasetFolderFor(volume), "");
                    if (!string.IsNullOrEmpty(folder)) properties.DatasetFolder.stringValue = folder;
                    InspectorLayout.EndGuiAfterModal(edited);
                }
            }
            edited.ApplyModifiedProperties();
            string datasetFolder = LpnnPaths.DatasetFolderFor(volume);
            EditorGUILayout.LabelField(LpnnVolumeStyles.DatasetFolder, datasetFolder, EditorStyles.wordWrappedMiniLabel);
            if (LpnnPaths.IsInsideAssets(datasetFolder)) EditorGUILayout.HelpBox(LpnnVolumeStyles.DatasetInsideAssets, MessageType.Warning);
            using (new EditorGUI.DisabledScope(session.Features == null))
            using (new EditorGUILayout.HorizontalScope())
            {
                if (GUILayout.Button(LpnnVolumeStyles.SaveCapture))
                {
                    Directory.CreateDirectory(datasetFolder);
                    string path = EditorUtility.SaveFilePanel(LpnnVolumeStyles.SaveCapturePanel, datasetFolder, CaptureExport.DefaultStem(volume), "lpnncap");
                    if (!string.IsNullOrEmpty(path))
                        StepRunner.Run(volume, steps.Export, (progress, cancel) =>
                        {
                            string written = CaptureExport.Save(volume, session, path, out string labels);
                            return "saved " + written + "; " + labels;
                        });
                    InspectorLayout.EndGuiAfterModal(edited);
                }
                if (GUILayout.Button(LpnnVolumeStyles.AppendToDataset))
                {
                    StepRunner.Run(volume, steps.Export, (progress, cancel) =>
                    {
                        string written = CaptureExport.Append(volume, session, datasetFolder, CaptureExport.DefaultStem(volume), out string labels);
                        return "appended " + written + "; " + labels;
                    });
                    InspectorLayout.EndGuiAfterModal(edited);
                }
            }
            InspectorLayout.Status(steps.Export);
        }
    }
}
