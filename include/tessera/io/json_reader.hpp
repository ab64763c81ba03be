#pragma once
// read_json / parse_json: a strict reader for the JSON files tessera writes (summary.json,
// calibrated.json) and for parameter files users hand to the drivers.
//
//     const io::json_value doc = io::read_json("calibrated.json");
//     for (const io::json_value& e : doc.at("entries").items())
//       std::cout << e.at("blocks").integer("blocks") << ' ' << e.at("strength_scale").number() << '\n';
//
// RFC 8259 values (object, array, string, number, true, false, null) with these limits, each
// refused with io_error naming the file, line and column: nesting deeper than 64, a duplicate
// key in one object, text after the value, \u escapes outside the Basic Multilingual Plane's
// ASCII range (tessera's files never need them), files over 64 MiB. Numbers are read as double
// (std::from_chars, round-trip exact for the 17-digit numbers summary_json writes).
// at("key") on a missing key and a value of the wrong kind also throw io_error, naming the
// key path, so a malformed parameter file fails with a message a user can act on.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "../core/errors.hpp"

namespace tessera::io {

/// A parsed JSON value; the accessors refuse (io_error naming its path) a value of another kind
class json_value {
 public:
  /** the JSON types */ enum class kind { null, boolean, number, string, array, object };

  [[nodiscard]] kind type() const noexcept { return kind_; }  ///< Its kind
  [[nodiscard]] bool is_null() const noexcept { return kind_ == kind::null; }  ///< True for null
  [[nodiscard]] const std::string& path() const noexcept { return path_; }  ///< Where it is, for messages (e.g. "file.json: entries[2].scale")

  /// The number; throws io_error if the value is not a number.
  [[nodiscard]] double number() const {
    expect(kind::number, "a number");
    return number_;
  }
  /// The number as an integer in [lo, hi]; throws io_error if it is not a whole number there.
  [[nodiscard]] long long integer(long long lo, long long hi) const {
    const double x = number();
    if (!(x == std::floor(x)) || x < static_cast<double>(lo) || x > static_cast<double>(hi))
      throw io_error(tessera::detail::concat(where(), ": ", x, " must be a whole number in [", lo, ", ", hi, "]"));
    return static_cast<long long>(x);
  }
  [[nodiscard]] bool boolean() const {  ///< The boolean; refuses another kind
    expect(kind::boolean, "true or false");
    return boolean_;
  }
  [[nodiscard]] const std::string& string() const {  ///< The string; refuses another kind
    expect(kind::string, "a string");
    return string_;
  }
  /// The elements of an array.
  [[nodiscard]] const std::vector<json_value>& items() const {
    expect(kind::array, "an array");
    return items_;
  }
  /// The members of an object, in file order.
  [[nodiscard]] const std::vector<std::pair<std::string, json_value>>& members() const {
    expect(kind::object, "an object");
    return members_;
  }
  [[nodiscard]] const json_value* find(std::string_view key) const {  ///< The member key of an object, or nullptr
    for (const auto& [k, v] : members())
      if (k == key) return &v;
    return nullptr;
  }
  /// The member `key`; throws io_error naming the key if it is missing.
  [[nodiscard]] const json_value& at(std::string_view key) const {
    const json_value* v = find(key);
    if (v == nullptr) throw io_error(tessera::detail::concat(where(), ": missing key \"", key, "\""));
    return *v;
  }

 private:
  friend class json_parser;
  [[nodiscard]] std::string where() const { return path_.empty() ? std::string("(top level)") : path_; }
  void expect(kind k, const char* what) const {
    static constexpr const char* names[] = {"null", "a boolean", "a number", "a string", "an array", "an object"};
    if (kind_ != k)
      throw io_error(tessera::detail::concat(where(), " must be ", what, ", got ", names[static_cast<int>(kind_)]));
  }

  kind kind_ = kind::null;
  bool boolean_ = false;
  double number_ = 0;
  std::string string_;
  std::vector<json_value> items_;
  std::vector<std::pair<std::string, json_value>> members_;
  std::string path_;  // e.g. "calibrated.json: entries[2].strength_scale"
};

/// A JSON parser (RFC 8259, nesting up to max_depth); refuses malformed text (io_error naming the line and column)
class json_parser {
 public:
  static constexpr int max_depth = 64;  ///< deepest nesting accepted

  json_parser(std::string_view text, std::string name) : text_(text), name_(std::move(name)) {}  ///< text to parse, its name for messages

  json_value parse() {  ///< The value of the whole text
    json_value v = value(name_ + ":", 0);
    skip_space();
    if (pos_ != text_.size()) fail("unexpected text after the JSON value");
    return v;
  }

 private:
  [[noreturn]] void fail(std::string_view what) const {
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i < pos_ && i < text_.size(); ++i) {
      if (text_[i] == '\n') { ++line; col = 1; } else { ++col; }
    }
    throw io_error(tessera::detail::concat(name_, ":", line, ":", col, ": ", what));
  }
  void skip_space() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\n' || text_[pos_] == '\r'))
      ++pos_;
  }
  bool take(char c) {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == c) { ++pos_; return true; }
    return false;
  }
  void literal(std::string_view word) {
    if (text_.substr(pos_, word.size()) != word) fail("expected a JSON value");
    pos_ += word.size();
  }

  json_value value(const std::string& path, int depth) {
    if (depth > max_depth) fail(tessera::detail::concat("nesting deeper than ", max_depth));
    skip_space();
    if (pos_ >= text_.size()) fail("unexpected end of file (truncated?)");
    json_value v;
    v.path_ = path;
    const char c = text_[pos_];
    if (c == '{') {
      ++pos_;
      v.kind_ = json_value::kind::object;
      if (take('}')) return v;
      do {
        skip_space();
        if (pos_ >= text_.size() || text_[pos_] != '"') fail("expected a key string");
        const std::size_t key_pos = pos_;
        std::string key = string_literal();
        for (const auto& m : v.members_)
          if (m.first == key) {
            pos_ = key_pos;
            fail("duplicate key \"" + key + "\"");
          }
        if (!take(':')) fail("expected ':' after a key");
        const std::string child = path + (path.back() == ':' ? " " : ".") + key;
        v.members_.emplace_back(key, value(child, depth + 1));
      } while (take(','));
      if (!take('}')) fail("expected ',' or '}' in an object");
    } else if (c == '[') {
      ++pos_;
      v.kind_ = json_value::kind::array;
      if (take(']')) return v;
      do {
        v.items_.push_back(value(tessera::detail::concat(path, "[", v.items_.size(), "]"), depth + 1));
      } while (take(','));
      if (!take(']')) fail("expected ',' or ']' in an array");
    } else if (c == '"') {
      v.kind_ = json_value::kind::string;
      v.string_ = string_literal();
    } else if (c == 't') {
      literal("true");
      v.kind_ = json_value::kind::boolean;
      v.boolean_ = true;
    } else if (c == 'f') {
      literal("false");
      v.kind_ = json_value::kind::boolean;
    } else if (c == 'n') {
      literal("null");
    } else {
      v.kind_ = json_value::kind::number;
      v.number_ = number_literal();
    }
    return v;
  }

  double number_literal() {
    // JSON grammar: -? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?
    const std::size_t start = pos_;
    const auto digit = [&] { return pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9'; };
    const auto digits = [&] {
      if (!digit()) fail("malformed number");
      while (digit()) ++pos_;
    };
    if (pos_ < text_.size() && text_[pos_] == '-') ++pos_;
    if (pos_ < text_.size() && text_[pos_] == '0') ++pos_;
    else digits();
    if (pos_ < text_.size() && text_[pos_] == '.') { ++pos_; digits(); }
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
      ++pos_;
      if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
      digits();
    }
    double x = 0;
    const auto [end, ec] = std::from_chars(text_.data() + start, text_.data() + pos_, x);
    if (ec != std::errc() || end != text_.data() + pos_ || !std::isfinite(x)) {
      pos_ = start;
      fail("number out of range");
    }
    return x;
  }

  std::string string_literal() {
    ++pos_;  // opening quote
    std::string s;
    while (true) {
      if (pos_ >= text_.size()) fail("unterminated string");
      const char c = text_[pos_++];
      if (c == '"') return s;
      if (static_cast<unsigned char>(c) < 0x20) fail("control character in a string");
      if (c != '\\') { s += c; continue; }
      if (pos_ >= text_.size()) fail("unterminated string");
      const char e = text_[pos_++];
      switch (e) {
        case '"': s += '"'; break;
        case '\\': s += '\\'; break;
        case '/': s += '/'; break;
        case 'b': s += '\b'; break;
        case 'f': s += '\f'; break;
        case 'n': s += '\n'; break;
        case 'r': s += '\r'; break;
        case 't': s += '\t'; break;
        case 'u': {
          unsigned code = 0;
          const auto [end, ec] = std::from_chars(text_.data() + pos_, text_.data() + std::min(pos_ + 4, text_.size()), code, 16);
          if (ec != std::errc() || end != text_.data() + pos_ + 4) fail("malformed \\u escape");
          if (code >= 0x80) fail("\\u escape beyond ASCII is not supported");
          pos_ += 4;
          s += static_cast<char>(code);
          break;
        }
        default: fail("unknown escape in a string");
      }
    }
  }

  std::string_view text_;
  std::string name_;
  std::size_t pos_ = 0;
};

/// Parses `text`; `name` (a file name) prefixes every error message.
[[nodiscard]] inline json_value parse_json(std::string_view text, const std::string& name) {
  return json_parser(text, name).parse();
}

/// Reads and parses a JSON file (at most 64 MiB); throws io_error naming the file.
[[nodiscard]] inline json_value read_json(const std::filesystem::path& path) {
  constexpr std::uintmax_t max_bytes = 64u << 20;
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw io_error(tessera::detail::concat("cannot read '", path.string(), "': ", ec.message()));
  if (size > max_bytes)
    throw io_error(tessera::detail::concat("'", path.string(), "' is ", size, " bytes; JSON inputs are limited to ", max_bytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error(tessera::detail::concat("cannot open '", path.string(), "'"));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse_json(text, path.string());
}

}  // namespace tessera::io
