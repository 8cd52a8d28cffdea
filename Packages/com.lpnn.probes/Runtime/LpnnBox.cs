using System;
using UnityEngine;

namespace Lpnn.Probes
{
    /// <summary>One box of an LPNN volume, in the volume object's local space. The object's transform (position,
    /// rotation and scale, including non-uniform scale) maps it to the world, where it becomes a parallelepiped.</summary>
    [Serializable]
    public struct LpnnBox
    {
        [Tooltip("Centre of the box in the volume's local space.")]
        public Vector3 center;

        [Tooltip("Edge lengths of the box in the volume's local space.")]
        public Vector3 size;

        [Tooltip("Rotation of the box inside the volume, as Euler angles in degrees.")]
        public Vector3 rotation;

        public LpnnBox(Vector3 center, Vector3 size, Vector3 rotation)
        {
            this.center = center;
            this.size = size;
            this.rotation = rotation;
        }

        /// <summary>The box's own rotation inside the volume.</summary>
        public Quaternion LocalRotation => Quaternion.Euler(rotation);
    }
}
