#pragma once
// A flat JSON object on one line: the manifest's record format. Values are strings, numbers or
// booleans; nesting is not needed (parameters travel as one canonical string), which keeps the
// reader small enough to trust and lets any tool (jq, Python) read the manifest.
#include <map>
#include <string>

namespace tumble::campaign {

struct JsonValue {
  enum Kind { String, Number, Bool } kind = String;
  std::string text;  // String: the decoded text; Number/Bool: the literal as written
  double number = 0;
};
using JsonObject = std::map<std::string, JsonValue>;

class JsonWriter {
 public:
  JsonWriter& add(const std::string& key, const std::string& value);
  JsonWriter& add(const std::string& key, const char* value) {
    return add(key, std::string(value));
  }
  JsonWriter& add(const std::string& key, double value);
  JsonWriter& add(const std::string& key, long long value);
  JsonWriter& add(const std::string& key, int value) {
    return add(key, static_cast<long long>(value));
  }
  JsonWriter& add(const std::string& key, bool value);
  // The object without a trailing newline.
  std::string str() const { return body_ + "}"; }

 private:
  void key(const std::string& k);
  std::string body_ = "{";
};

std::string json_escape(const std::string& s);
// Parses one line; returns false (and leaves `out` unspecified) when it is not a complete flat
// object, e.g. a line torn by a crash in the middle of a write.
bool parse_json_line(const std::string& line, JsonObject& out);

}  // namespace tumble::campaign
