// The key table, derived from the one list of keys (scene/scene_keys.hpp) and the registered
// contact laws' keys: the schema the parser checks values against, setting a checked value on the
// struct, and the provenance text. Unknown keys are errors (typos must not silently fall back to
// defaults); every number has a closed range that the validator enforces.
#include "scene/scene_schema.hpp"

#include <sstream>
#include <type_traits>

#include "scene/law_registry.hpp"

namespace tumble {

namespace {

// How a member's C++ type reads and writes: numbers, free text, or an enum's names.
template <class T, class = void>
struct KeyKind {  // the enums
  static constexpr KeySpec::Type type = KeySpec::Text;
  static std::vector<std::string> choices() { return enum_names<T>(); }
};
template <>
struct KeyKind<double> {
  static constexpr KeySpec::Type type = KeySpec::Real;
  static std::vector<std::string> choices() { return {}; }
};
template <>
struct KeyKind<std::int64_t> {
  static constexpr KeySpec::Type type = KeySpec::Integer;
  static std::vector<std::string> choices() { return {}; }
};
// A number, or a word instead (ReposeTilt, StillSlope: "measured").
template <class T, class = void>
struct TakesWord : std::false_type {};
template <class T>
struct TakesWord<T, std::void_t<decltype(T::kWord)>> : std::true_type {};
template <class T>
struct KeyKind<T, std::enable_if_t<TakesWord<T>::value>> {
  static constexpr KeySpec::Type type = KeySpec::Real;
  static std::vector<std::string> choices() { return {}; }
};
template <>
struct KeyKind<std::string> {
  static constexpr KeySpec::Type type = KeySpec::Text;
  static std::vector<std::string> choices() { return {}; }
};

// `num` for numbers, `text` otherwise; both already checked against the key's spec.
template <class T, T Scene::*M>
void set_member(Scene& s, const std::string& text, double num) {
  if constexpr (std::is_same_v<T, double>)
    s.*M = num;
  else if constexpr (std::is_same_v<T, std::int64_t>)
    s.*M = static_cast<std::int64_t>(num);
  else if constexpr (std::is_same_v<T, std::string>)
    s.*M = text;
  else if constexpr (TakesWord<T>::value)
    s.*M = text == T::kWord ? T::pending() : T::given(num);
  else
    enum_from_name(text, s.*M);
}

// Numbers as the stream writes them (precision 17), text and enum names quoted.
template <class T, T Scene::*M>
void write_member(std::ostream& os, const Scene& s) {
  if constexpr (std::is_same_v<T, double> || std::is_same_v<T, std::int64_t>)
    os << s.*M;
  else if constexpr (TakesWord<T>::value) {
    if ((s.*M).known)
      os << (s.*M).deg;  // given, or measured and filled in: the number the run uses
    else
      os << '"' << T::kWord << '"';
  } else if constexpr (std::is_same_v<T, std::string>)
    os << toml_quoted(s.*M);
  else
    os << '"' << s.*M << '"';  // an enum's name
}

// The spec of a key whose type also takes a word: the word, for the parser and --list-keys.
template <class T>
KeySpec with_word(KeySpec spec) {
  if constexpr (TakesWord<T>::value) spec.word = T::kWord;
  return spec;
}

struct OwnKey {
  KeySpec spec;
  void (*set)(Scene&, const std::string&, double);
  void (*write)(std::ostream&, const Scene&);
};

const std::vector<OwnKey>& own_keys() {
#define TUMBLE_SCENE_KEY_ROW(T, MEMBER, KEY, DEFAULT, LO, HI, HELP)                         \
  OwnKey{with_word<T>(KeySpec(KEY, KeyKind<T>::type, LO, HI, KeyKind<T>::choices(), HELP)), \
         &set_member<T, &Scene::MEMBER>, &write_member<T, &Scene::MEMBER>},
  static const std::vector<OwnKey> keys = {TUMBLE_SCENE_KEYS(TUMBLE_SCENE_KEY_ROW)};
#undef TUMBLE_SCENE_KEY_ROW
  return keys;
}

const OwnKey* own_key(const std::string& key) {
  for (const OwnKey& k : own_keys())
    if (k.spec.key == key) return &k;
  return nullptr;
}

}  // namespace

const std::vector<KeySpec>& scene_schema() {
  // Built once per set of registered laws (laws register at start-up, before any scene is read;
  // a test may add one later): every key lookup of a scene's parse reads it, and rebuilding it
  // for each made a campaign's 8,100 case scenes cost seconds.
  static std::vector<KeySpec> keys;
  static std::size_t built_for_laws = 0;
  static bool built = false;
  if (built && built_for_laws == contact_laws().size()) return keys;
  keys.clear();
  built = true;
  built_for_laws = contact_laws().size();
  for (const OwnKey& k : own_keys()) {
    keys.push_back(k.spec);
    if (k.spec.key == "contact.law")
      for (const auto& law : contact_laws()) keys.back().choices.push_back(law.name);
    if (k.spec.key == "contact.tangential_damping")
      for (const auto& law : contact_laws())
        keys.insert(keys.end(), law.keys.begin(), law.keys.end());
  }
  return keys;
}

std::string toml_quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + '"';
}

std::string default_text(const KeySpec& spec) {
  std::ostringstream os;  // the stream's default precision: for reading, not for round trips
  if (!spec.law.empty())
    os << spec.def;
  else
    own_key(spec.key)->write(os, Scene{});
  return os.str();
}

void set_key(Scene& s, const KeySpec& spec, const std::string& text, double num) {
  if (!spec.law.empty())
    s.law_values[spec.key] = num;
  else
    own_key(spec.key)->set(s, text, num);
}

std::string scene_to_text(const Scene& s) {
  // Dotted keys at top level: valid TOML that parse_scene reads back to the same scene.
  std::ostringstream os;
  os.precision(17);
  for (const auto& spec : scene_schema()) {
    if (!spec.law.empty() && spec.law != s.law && !contact_law(spec.law).keys_in_every_text)
      continue;  // another law's key (scene/law_registry.hpp: keys_in_every_text)
    os << spec.key << " = ";
    if (spec.key == "fidelity.tier")  // already applied (fidelity.applied names it)
      os << "\"standard\"";
    else if (!spec.law.empty())
      os << s.law_value(spec.key);
    else
      own_key(spec.key)->write(os, s);
    os << "\n";
  }
  return os.str();
}

}  // namespace tumble
