using System;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Grid
{
    /// <summary>One box of a volume in world space: a parallelepiped with a centre and three half-edge
    /// vectors (an axis-aligned box has half-edges along x, y, z; a rotated or scaled Unity box transforms
    /// its local half-extents into them). Half-edges may be zero: flat boxes, lines and points are valid.</summary>
    public readonly struct GridBox
    {
        public readonly Double3 Center;
        public readonly Double3 U;
        public readonly Double3 V;
        public readonly Double3 W;

        public GridBox(Double3 center, Double3 u, Double3 v, Double3 w)
        {
            Center = center;
            U = u;
            V = v;
            W = w;
        }

        public static GridBox AxisAligned(Double3 min, Double3 max)
        {
            if (max.X < min.X || max.Y < min.Y || max.Z < min.Z)
                throw new GridException("box min " + min + " is above its max " + max + " on some axis; swap the corners");
            var half = (max - min) * 0.5;
            return new GridBox((min + max) * 0.5, new Double3(half.X, 0, 0), new Double3(0, half.Y, 0), new Double3(0, 0, half.Z));
        }

        public Double3 HalfEdge(int index)
        {
            switch (index)
            {
                case 0: return U;
                case 1: return V;
                case 2: return W;
                default: throw new ArgumentOutOfRangeException(nameof(index), index, "half-edge index must be 0, 1 or 2");
            }
        }

        /// <summary>Corner <paramref name="index"/> (0..7): bit 0 picks ±U, bit 1 ±V, bit 2 ±W.</summary>
        public Double3 Corner(int index)
        {
            if ((uint)index > 7) throw new ArgumentOutOfRangeException(nameof(index), index, "corner index must be 0..7");
            return Center + ((index & 1) != 0 ? U : -U) + ((index & 2) != 0 ? V : -V) + ((index & 4) != 0 ? W : -W);
        }

        /// <summary>Half-size of the box's world-axis-aligned bounding box along <paramref name="axis"/>.</summary>
        public double AxisExtent(int axis) => Math.Abs(U[axis]) + Math.Abs(V[axis]) + Math.Abs(W[axis]);

        public void Validate(int boxIndex)
        {
            if (!Center.IsFinite || !U.IsFinite || !V.IsFinite || !W.IsFinite)
                throw new GridException("box " + boxIndex + " has a non-finite centre or size (centre " + Center +
                                        "); check its transform for NaN or infinite scale");
        }
    }
}
