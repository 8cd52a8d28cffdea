using System;
using System.Globalization;
using System.Text;

namespace Lpnn.Probes.Core.Json
{
    /// <summary>Thrown for malformed JSON; carries the 1-based line and column of the problem.</summary>
    internal sealed class JsonParseException : LpnnException
    {
        public int Line { get; }
        public int Column { get; }
        public string Reason { get; }

        public JsonParseException(int line, int column, string reason)
            : base("line " + line + ", column " + column + ": invalid JSON: " + reason)
        {
            Line = line;
            Column = column;
            Reason = reason;
        }
    }

    /// <summary>A strict RFC 8259 parser (no comments, no trailing commas, no NaN), culture-invariant.</summary>
    internal static class JsonParser
    {
        private const int MaxDepth = 256;

        public static JsonValue Parse(string text)
        {
            if (text == null) throw new ArgumentNullException(nameof(text));
            var reader = new Reader(text);
            reader.SkipWhitespace();
            JsonValue value = reader.ParseValue(0);
            reader.SkipWhitespace();
            if (!reader.AtEnd) throw reader.Error("unexpected text after the value");
            return value;
        }

        private sealed class Reader
        {
            private readonly string _text;
            private int _position;

            public Reader(string text) { _text = text; }

            public bool AtEnd => _position >= _text.Length;

            public JsonParseException Error(string reason)
            {
                int line = 1, column = 1;
                for (int i = 0; i < _position && i < _text.Length; i++)
                {
                    if (_text[i] == '\n') { line++; column = 1; }
                    else column++;
                }
                return new JsonParseException(line, column, reason);
            }

            public void SkipWhitespace()
            {
                while (!AtEnd)
                {
                    char c = _text[_position];
                    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') _position++;
                    else break;
                }
            }

            public JsonValue ParseValue(int depth)
            {
                if (depth > MaxDepth) throw Error("nesting deeper than " + MaxDepth);
                if (AtEnd) throw Error("expected a value, found the end of the text");
                char c = _text[_position];
                switch (c)
                {
                    case '{': return ParseObject(depth);
                    case '[': return ParseArray(depth);
                    case '"': return JsonValue.From(ParseString());
                    case 't': Expect("true"); return JsonValue.From(true);
                    case 'f': Expect("false"); return JsonValue.From(false);
                    case 'n': Expect("null"); return JsonValue.Null;
                    default:
                        if (c == '-' || (c >= '0' && c <= '9')) return ParseNumber();
                        throw Error("unexpected character '" + c + "'");
                }
            }

            private void Expect(string word)
            {
                if (string.CompareOrdinal(_text, _position, word, 0, word.Length) != 0)
                    throw Error("expected '" + word + "'");
                _position += word.Length;
            }

            private JsonValue ParseObject(int depth)
            {
                var result = JsonValue.NewObject();
                _position++; // {
                SkipWhitespace();
                if (!AtEnd && _text[_position] == '}') { _position++; return result; }
                while (true)
                {
                    SkipWhitespace();
                    if (AtEnd || _text[_position] != '"') throw Error("expected a quoted key");
                    string key = ParseString();
                    if (result.Has(key)) throw Error("duplicate key '" + key + "'");
                    SkipWhitespace();
                    if (AtEnd || _text[_position] != ':') throw Error("expected ':' after key '" + key + "'");
                    _position++;
                    SkipWhitespace();
                    result.Set(key, ParseValue(depth + 1));
                    SkipWhitespace();
                    if (AtEnd) throw Error("expected ',' or '}', found the end of the text");
                    char c = _text[_position++];
                    if (c == '}') return result;
                    if (c != ',') { _position--; throw Error("expected ',' or '}'"); }
                }
            }

            private JsonValue ParseArray(int depth)
            {
                var result = JsonValue.NewArray();
                _position++; // [
                SkipWhitespace();
                if (!AtEnd && _text[_position] == ']') { _position++; return result; }
                while (true)
                {
                    SkipWhitespace();
                    result.Add(ParseValue(depth + 1));
                    SkipWhitespace();
                    if (AtEnd) throw Error("expected ',' or ']', found the end of the text");
                    char c = _text[_position++];
                    if (c == ']') return result;
                    if (c != ',') { _position--; throw Error("expected ',' or ']'"); }
                }
            }

            private string ParseString()
            {
                _position++; // opening quote
                var builder = new StringBuilder();
                while (true)
                {
                    if (AtEnd) throw Error("unterminated string");
                    char c = _text[_position++];
                    if (c == '"') return builder.ToString();
                    if (c < 0x20) { _position--; throw Error("control character in string"); }
                    if (c != '\\') { builder.Append(c); continue; }
                    if (AtEnd) throw Error("unterminated escape");
                    char e = _text[_position++];
                    switch (e)
                    {
                        case '"': builder.Append('"'); break;
                        case '\\': builder.Append('\\'); break;
                        case '/': builder.Append('/'); break;
                        case 'b': builder.Append('\b'); break;
                        case 'f': builder.Append('\f'); break;
                        case 'n': builder.Append('\n'); break;
                        case 'r': builder.Append('\r'); break;
                        case 't': builder.Append('\t'); break;
                        case 'u':
                            if (_position + 4 > _text.Length) throw Error("truncated \\u escape");
                            if (!int.TryParse(_text.Substring(_position, 4), NumberStyles.AllowHexSpecifier,
                                    CultureInfo.InvariantCulture, out int code))
                                throw Error("bad \\u escape");
                            builder.Append((char)code);
                            _position += 4;
                            break;
                        default:
                            _position--;
                            throw Error("unknown escape '\\" + e + "'");
                    }
                }
            }

            private JsonValue ParseNumber()
            {
                int start = _position;
                if (_text[_position] == '-') _position++;
                if (AtEnd || !char.IsDigit(_text[_position])) throw Error("expected a digit");
                if (_text[_position] == '0') _position++;
                else while (!AtEnd && char.IsDigit(_text[_position])) _position++;
                if (!AtEnd && _text[_position] == '.')
                {
                    _position++;
                    if (AtEnd || !char.IsDigit(_text[_position])) throw Error("expected a digit after '.'");
                    while (!AtEnd && char.IsDigit(_text[_position])) _position++;
                }
                if (!AtEnd && (_text[_position] == 'e' || _text[_position] == 'E'))
                {
                    _position++;
                    if (!AtEnd && (_text[_position] == '+' || _text[_position] == '-')) _position++;
                    if (AtEnd || !char.IsDigit(_text[_position])) throw Error("expected a digit in the exponent");
                    while (!AtEnd && char.IsDigit(_text[_position])) _position++;
                }
                string literal = _text.Substring(start, _position - start);
                // .NET Framework/Mono throw on overflow where .NET Core returns infinity: treat both as out of range.
                if (!double.TryParse(literal, NumberStyles.Float, CultureInfo.InvariantCulture, out double value) || double.IsInfinity(value))
                {
                    _position = start;
                    throw Error("number " + literal + " is out of range");
                }
                return JsonValue.From(value);
            }
        }
    }
}
