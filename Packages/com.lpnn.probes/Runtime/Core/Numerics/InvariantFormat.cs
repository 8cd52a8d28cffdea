using System.Globalization;

namespace Lpnn.Probes.Core.Numerics
{
    /// <summary>Culture-invariant number text: the thesis tool wrote "0,0226" on a Greek locale;
    /// every number this package prints or stores goes through here instead.</summary>
    internal static class InvariantFormat
    {
        public static readonly CultureInfo Culture = CultureInfo.InvariantCulture;

        /// <summary>Shortest text that parses back to exactly the same double.</summary>
        public static string Number(double value)
        {
            string text = value.ToString("R", Culture);
            // .NET Framework's "R" can fail to round-trip some doubles; G17 always does.
            if (!double.IsNaN(value) && double.Parse(text, NumberStyles.Float, Culture) != value)
                text = value.ToString("G17", Culture);
            return text;
        }

        /// <summary>Shortest text that parses back to exactly the same float.</summary>
        public static string Number(float value)
        {
            string text = value.ToString("R", Culture);
            if (!float.IsNaN(value) && float.Parse(text, NumberStyles.Float, Culture) != value)
                text = value.ToString("G9", Culture);
            return text;
        }

        /// <summary>"(x, y, z)" with invariant numbers (System.Numerics' own ToString follows the current culture).</summary>
        public static string Vector(System.Numerics.Vector3 v) => "(" + Number(v.X) + ", " + Number(v.Y) + ", " + Number(v.Z) + ")";

        /// <summary>An integer count with thousands grouping for messages ("2,000,000").</summary>
        public static string Count(long value) => value.ToString("N0", Culture);

        /// <summary>A value rounded up to <paramref name="digits"/> significant digits (for suggestions
        /// such as "a cell size of at least 0.19 would fit").</summary>
        public static double RoundUpSignificant(double value, int digits)
        {
            if (value <= 0 || double.IsNaN(value) || double.IsInfinity(value)) return value;
            double magnitude = System.Math.Pow(10, System.Math.Floor(System.Math.Log10(value)) - (digits - 1));
            double rounded = System.Math.Ceiling(value / magnitude) * magnitude;
            // Trim binary noise (0.19000000000000003) while never going below the exact bound.
            double trimmed = double.Parse(rounded.ToString("G" + digits, Culture), Culture);
            return trimmed >= value ? trimmed : rounded;
        }
    }
}
