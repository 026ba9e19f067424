#include "campaign/json_line.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace tumble::campaign {

std::string json_escape(const std::string& s) {
  std::string out;
  out.reserve(s.size() + 2);
  for (unsigned char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += static_cast<char>(c);  // UTF-8 passes through: valid JSON
        }
    }
  }
  return out;
}

void JsonWriter::key(const std::string& k) {
  if (body_.size() > 1) body_ += ",";
  body_ += "\"" + json_escape(k) + "\":";
}
JsonWriter& JsonWriter::add(const std::string& k, const std::string& v) {
  key(k);
  body_ += "\"" + json_escape(v) + "\"";
  return *this;
}
JsonWriter& JsonWriter::add(const std::string& k, double v) {
  key(k);
  if (!std::isfinite(v)) {
    body_ += "null";  // JSON has no NaN; readers treat null as absent
    return *this;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  body_ += buf;
  return *this;
}
JsonWriter& JsonWriter::add(const std::string& k, long long v) {
  key(k);
  body_ += std::to_string(v);
  return *this;
}
JsonWriter& JsonWriter::add(const std::string& k, bool v) {
  key(k);
  body_ += v ? "true" : "false";
  return *this;
}

namespace {
struct Parser {
  const std::string& s;
  std::size_t i = 0;
  void ws() {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
  }
  bool eat(char c) {
    ws();
    if (i < s.size() && s[i] == c) {
      ++i;
      return true;
    }
    return false;
  }
  bool string(std::string& out) {
    ws();
    if (i >= s.size() || s[i] != '"') return false;
    ++i;
    out.clear();
    while (i < s.size()) {
      const char c = s[i++];
      if (c == '"') return true;
      if (c != '\\') {
        out += c;
        continue;
      }
      if (i >= s.size()) return false;
      const char e = s[i++];
      switch (e) {
        case '"':
          out += '"';
          break;
        case '\\':
          out += '\\';
          break;
        case '/':
          out += '/';
          break;
        case 'n':
          out += '\n';
          break;
        case 'r':
          out += '\r';
          break;
        case 't':
          out += '\t';
          break;
        case 'b':
          out += '\b';
          break;
        case 'f':
          out += '\f';
          break;
        case 'u': {
          if (i + 4 > s.size()) return false;
          const long cp = std::strtol(s.substr(i, 4).c_str(), nullptr, 16);
          i += 4;
          if (cp < 0x80) {
            out += static_cast<char>(cp);
          } else if (cp < 0x800) {
            out += static_cast<char>(0xC0 | (cp >> 6));
            out += static_cast<char>(0x80 | (cp & 0x3F));
          } else {
            out += static_cast<char>(0xE0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
          }
          break;
        }
        default:
          return false;
      }
    }
    return false;  // unterminated: a torn line
  }
  bool value(JsonValue& v) {
    ws();
    if (i >= s.size()) return false;
    if (s[i] == '"') {
      v.kind = JsonValue::String;
      return string(v.text);
    }
    const std::size_t start = i;
    while (i < s.size() && s[i] != ',' && s[i] != '}' && s[i] != ' ') ++i;
    v.text = s.substr(start, i - start);
    if (v.text == "true" || v.text == "false") {
      v.kind = JsonValue::Bool;
      v.number = v.text == "true";
      return true;
    }
    if (v.text == "null") {
      v.kind = JsonValue::Number;
      v.number = std::nan("");
      return true;
    }
    char* end = nullptr;
    v.number = std::strtod(v.text.c_str(), &end);
    v.kind = JsonValue::Number;
    return !v.text.empty() && end && *end == '\0';
  }
};
}  // namespace

bool parse_json_line(const std::string& line, JsonObject& out) {
  out.clear();
  Parser p{line};
  if (!p.eat('{')) return false;
  if (p.eat('}')) return true;
  while (true) {
    std::string k;
    JsonValue v;
    if (!p.string(k) || !p.eat(':') || !p.value(v)) return false;
    out[k] = v;
    if (p.eat(',')) continue;
    if (!p.eat('}')) return false;
    p.ws();
    return p.i == line.size();
  }
}

}  // namespace tumble::campaign
