#pragma once
// summary_json: builder for the one flat JSON object every example driver writes as
// DIR/summary.json (inputs, key figures, errors against the reference, runtime_s, steps).
//
//     io::summary_json s;
//     s.set("blocks", 100).set("volume_error_rel", 3e-16).set("quick", false).set("law", "power");
//     s.write(out / "summary.json");
//
// Keys keep their insertion order; setting an existing key replaces its value in place.
// Values: string, floating-point number (17 significant digits; NaN and infinities are written as
// null, since JSON has no such numbers), integer, bool, array of numbers, array of strings, an
// object, array of objects. io/json_reader.hpp reads such files back.
// Not thread-safe per object.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "atomic_file.hpp"

namespace tessera::io {

/// A flat JSON object written atomically (summary.json): set(key, value) in insertion order, a non-finite number as null
class summary_json {
 public:
  summary_json& set(std::string_view key, std::string_view value) { return put(key, quote(value)); }  ///< A string value
  summary_json& set(std::string_view key, const char* value) { return put(key, quote(value)); }  ///< A string value
  summary_json& set(std::string_view key, const std::string& value) { return put(key, quote(value)); }  ///< A string value
  summary_json& set(std::string_view key, bool value) { return put(key, value ? "true" : "false"); }  ///< true or false
  template <class T>
    requires(std::is_integral_v<T> && !std::is_same_v<T, bool>)
  summary_json& set(std::string_view key, T value) {  ///< An integer value
    return put(key, std::to_string(value));
  }
  template <class T>
    requires std::is_floating_point_v<T>
  summary_json& set(std::string_view key, T value) {  ///< A number (null when not finite)
    return put(key, number(static_cast<double>(value)));
  }
  summary_json& set(std::string_view key, std::span<const double> values) {  ///< An array of numbers
    std::string s = "[";
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (i) s += ", ";
      s += number(values[i]);
    }
    return put(key, s + "]");
  }
  summary_json& set(std::string_view key, const std::vector<double>& values) {  ///< An array of numbers
    return set(key, std::span<const double>(values));
  }
  summary_json& set(std::string_view key, const std::vector<std::string>& values) {  ///< An array of strings
    std::string s = "[";
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (i) s += ", ";
      s += quote(values[i]);
    }
    return put(key, s + "]");
  }

  /// A nested object (written one key per line, indented under the key).
  summary_json& set(std::string_view key, const summary_json& object) { return put(key, indented(object, "  ")); }
  /// An array of objects (each written one key per line, indented under the key).
  summary_json& set(std::string_view key, const std::vector<summary_json>& objects) {
    std::string s = "[";
    for (std::size_t i = 0; i < objects.size(); ++i) s += (i ? ",\n    " : "\n    ") + indented(objects[i], "    ");
    return put(key, s + (objects.empty() ? "]" : "\n  ]"));
  }

  [[nodiscard]] bool contains(std::string_view key) const { return find(key) != entries_.size(); }  ///< True when key was set
  [[nodiscard]] std::size_t size() const { return entries_.size(); }  ///< Number of keys

  /// The object as pretty-printed JSON text (one key per line), ending with a newline.
  [[nodiscard]] std::string str() const {
    std::string s = "{\n";
    for (std::size_t i = 0; i < entries_.size(); ++i)
      s += "  " + quote(entries_[i].first) + ": " + entries_[i].second + (i + 1 < entries_.size() ? ",\n" : "\n");
    return s + "}\n";
  }
  /// Writes str() to `path` atomically (throws io_error naming the path on failure).
  void write(const std::filesystem::path& path) const { write_file_atomically(path, str()); }

  /// JSON number text with 17 significant digits, or null when not finite.
  [[nodiscard]] static std::string number(double x) {
    if (!std::isfinite(x)) return "null";
    std::ostringstream os;
    os << std::setprecision(std::numeric_limits<double>::max_digits10) << x;
    return os.str();
  }
  /// JSON string literal with the mandatory escapes (quote, backslash, control characters).
  [[nodiscard]] static std::string quote(std::string_view s) {
    std::string q = "\"";
    for (const char c : s) {
      switch (c) {
        case '"': q += "\\\""; break;
        case '\\': q += "\\\\"; break;
        case '\n': q += "\\n"; break;
        case '\t': q += "\\t"; break;
        case '\r': q += "\\r"; break;
        default:
          if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
            q += buf;
          } else {
            q += c;
          }
      }
    }
    return q + '"';
  }

 private:
  // str() of `object` without its final newline, every further line prefixed by `indent`.
  [[nodiscard]] static std::string indented(const summary_json& object, std::string_view indent) {
    const std::string text = object.str();
    std::string out;
    for (std::size_t i = 0; i + 1 < text.size(); ++i) {
      out += text[i];
      if (text[i] == '\n') out += indent;
    }
    return out;
  }
  [[nodiscard]] std::size_t find(std::string_view key) const {
    for (std::size_t i = 0; i < entries_.size(); ++i)
      if (entries_[i].first == key) return i;
    return entries_.size();
  }
  summary_json& put(std::string_view key, std::string value) {
    const std::size_t i = find(key);
    if (i < entries_.size()) entries_[i].second = std::move(value);
    else entries_.emplace_back(std::string(key), std::move(value));
    return *this;
  }
  std::vector<std::pair<std::string, std::string>> entries_;
};

}  // namespace tessera::io
