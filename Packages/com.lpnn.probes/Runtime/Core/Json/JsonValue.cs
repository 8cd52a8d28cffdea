using System;
using System.Collections.Generic;

namespace Lpnn.Probes.Core.Json
{
    public enum JsonKind { Null, Boolean, Number, String, Array, Object }

    /// <summary>A parsed JSON value. Objects keep their key order, so files written from a value are
    /// byte-for-byte deterministic and unknown keys survive a read-modify-write.</summary>
    public sealed class JsonValue
    {
        private readonly bool _boolean;
        private readonly double _number;
        private readonly string _string;
        private readonly List<JsonValue> _items;
        private readonly List<KeyValuePair<string, JsonValue>> _members;

        public JsonKind Kind { get; }

        private JsonValue(JsonKind kind, bool boolean = false, double number = 0, string text = null,
            List<JsonValue> items = null, List<KeyValuePair<string, JsonValue>> members = null)
        {
            Kind = kind;
            _boolean = boolean;
            _number = number;
            _string = text;
            _items = items;
            _members = members;
        }

        public static readonly JsonValue Null = new JsonValue(JsonKind.Null);
        public static JsonValue From(bool value) => new JsonValue(JsonKind.Boolean, boolean: value);
        public static JsonValue From(double value)
        {
            if (double.IsNaN(value) || double.IsInfinity(value))
                throw new ArgumentException("JSON cannot hold " + value + "; only finite numbers", nameof(value));
            return new JsonValue(JsonKind.Number, number: value);
        }
        public static JsonValue From(string value) => value == null ? Null : new JsonValue(JsonKind.String, text: value);
        public static JsonValue NewArray() => new JsonValue(JsonKind.Array, items: new List<JsonValue>());
        public static JsonValue NewObject() => new JsonValue(JsonKind.Object, members: new List<KeyValuePair<string, JsonValue>>());

        public static JsonValue ArrayOf(IEnumerable<JsonValue> values)
        {
            var array = NewArray();
            foreach (var value in values) array.Add(value);
            return array;
        }

        public bool IsNull => Kind == JsonKind.Null;

        public bool AsBoolean => Kind == JsonKind.Boolean ? _boolean : throw WrongKind(JsonKind.Boolean);
        public double AsNumber => Kind == JsonKind.Number ? _number : throw WrongKind(JsonKind.Number);
        public string AsString => Kind == JsonKind.String ? _string : throw WrongKind(JsonKind.String);

        /// <summary>True for a number with no fractional part that fits a long.</summary>
        public bool IsInteger => Kind == JsonKind.Number && Math.Floor(_number) == _number && Math.Abs(_number) < 9.007199254740992E15;

        public IReadOnlyList<JsonValue> Items => Kind == JsonKind.Array ? _items : throw WrongKind(JsonKind.Array);
        public IReadOnlyList<KeyValuePair<string, JsonValue>> Members =>
            Kind == JsonKind.Object ? _members : throw WrongKind(JsonKind.Object);

        public void Add(JsonValue value)
        {
            if (Kind != JsonKind.Array) throw WrongKind(JsonKind.Array);
            _items.Add(value ?? Null);
        }

        /// <summary>Sets a member, replacing an existing key in place (order kept) or appending.</summary>
        public void Set(string key, JsonValue value)
        {
            if (Kind != JsonKind.Object) throw WrongKind(JsonKind.Object);
            for (int i = 0; i < _members.Count; i++)
            {
                if (_members[i].Key == key)
                {
                    _members[i] = new KeyValuePair<string, JsonValue>(key, value ?? Null);
                    return;
                }
            }
            _members.Add(new KeyValuePair<string, JsonValue>(key, value ?? Null));
        }

        public bool TryGet(string key, out JsonValue value)
        {
            if (Kind == JsonKind.Object)
            {
                foreach (var member in _members)
                {
                    if (member.Key == key)
                    {
                        value = member.Value;
                        return true;
                    }
                }
            }
            value = null;
            return false;
        }

        public bool Has(string key) => TryGet(key, out _);

        private InvalidOperationException WrongKind(JsonKind expected) =>
            new InvalidOperationException("JSON value is " + Kind + ", not " + expected);

        public override string ToString() => JsonWriter.Write(this);
    }
}
