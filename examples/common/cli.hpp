#pragma once
// Command-line handling shared by every example driver: a small typed option parser, the
// standard options of DESIGN.md §5 (--out, --quick, --seed, --threads, --help), a progress
// line on stderr and a wall-clock timer. Header-only, no dependencies beyond the standard
// library.
//
//     tessera::cli::parser cli("tessellate", "Random Voronoi tessellation of a box, zoned into tets.");
//     tessera::cli::standard_options std_opts;
//     cli.add_standard(std_opts);                       // --out results/tessellate, --quick, --seed, --threads
//     int blocks = 100;
//     std::array<double, 3> size{0.068, 0.068, 0.6};
//     cli.option("--blocks", blocks, "number of blocks", "N");
//     cli.option("--size", size, "box edge lengths (m)", {"LX", "LY", "LZ"});
//     cli.parse_or_exit(argc, argv);                   // --help: usage, exit 0; bad input: message, exit 2
//
// Options take their default from the bound variable's value at registration time; the usage
// block prints it. Both "--name value" and "--name=value" are accepted.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <unistd.h>

#include "threads.hpp"
#include "tessera/core/errors.hpp"

namespace tessera::cli {

/// Bad command line: unknown option, missing or malformed value. what() names the option and value.
class usage_error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {
template <class T>
[[nodiscard]] std::string type_hint() {
  if constexpr (std::is_same_v<T, std::string>) return "text";
  else if constexpr (std::is_floating_point_v<T>) return "real";
  else if constexpr (std::is_unsigned_v<T>) return "non-negative integer";
  else return "integer";
}

/// Parses the whole of `text` as a T; throws usage_error naming `option` otherwise.
template <class T>
[[nodiscard]] T parse_value(std::string_view option, const std::string& text) {
  if constexpr (std::is_same_v<T, std::string>) {
    return text;
  } else {
    const auto bad = [&]() {
      return usage_error(std::string(option) + ": invalid value '" + text + "' (expected " + type_hint<T>() + ")");
    };
    if (text.empty()) throw bad();
    // Decimal only: no white space, no hexadecimal ("0x10", "0x1p3"), no "nan"/"inf", and an
    // integer has no fraction or exponent ("1e6").
    const std::string_view allowed = std::is_floating_point_v<T> ? "0123456789+-.eE" : "0123456789+-";
    if (text.find_first_not_of(allowed) != std::string::npos) throw bad();
    std::size_t used = 0;
    try {
      if constexpr (std::is_floating_point_v<T>) {
        const double v = std::stod(text, &used);
        if (used != text.size()) throw bad();
        if (!std::isfinite(v))
          throw usage_error(std::string(option) + ": invalid value '" + text + "' (expected a finite real)");
        return static_cast<T>(v);
      } else if constexpr (std::is_unsigned_v<T>) {
        if (text.front() == '-') throw bad();
        const unsigned long long v = std::stoull(text, &used, 10);
        if (used != text.size() || v > std::numeric_limits<T>::max()) throw bad();
        return static_cast<T>(v);
      } else {
        const long long v = std::stoll(text, &used, 10);
        if (used != text.size() || v < std::numeric_limits<T>::min() || v > std::numeric_limits<T>::max()) throw bad();
        return static_cast<T>(v);
      }
    } catch (const usage_error&) {
      throw;
    } catch (const std::exception&) {
      throw bad();
    }
  }
}

template <class T>
[[nodiscard]] std::string to_text(const T& v) {
  if constexpr (std::is_same_v<T, std::string>) {
    return v.empty() ? std::string("\"\"") : v;
  } else {
    std::ostringstream os;
    os << v;
    return os.str();
  }
}

}  // namespace detail

/// Prints an error that ended a run as "<program>: <message>" on stderr, without doubling the
/// prefix when the message already starts with it (the drivers' own checks name themselves).
inline void print_error(const std::string& program, const std::exception& e) {
  const std::string message = e.what(), prefix = program + ": ";
  std::cerr << (message.rfind(prefix, 0) == 0 ? message : prefix + message) << '\n';
}

/// A comma-separated flag value ("100,250,500") split into its items. Throws invalid_input naming
/// `what` (say "calibrate: --blocks") and the text for an empty list, an empty item (a leading,
/// trailing or doubled comma) or an item given twice: the drivers' one rule for lists.
[[nodiscard]] inline std::vector<std::string> split_list(const std::string& text, const std::string& what) {
  std::vector<std::string> items;
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = std::min(text.find(',', from), text.size());
    std::string item = text.substr(from, comma - from);
    require(!item.empty(), what, " '", text, "' must be a comma-separated list without empty items, such as a,b,c");
    require(std::find(items.begin(), items.end(), item) == items.end(), what, " '", text, "' lists '", item,
            "' twice");
    items.push_back(std::move(item));
    if (comma == text.size()) return items;
    from = comma + 1;
  }
}

/// Options every example driver has (DESIGN.md §5).
struct standard_options {
  std::string out;          ///< output directory (default results/<program>)
  bool quick = false;       ///< reduced run for tests
  std::uint64_t seed = 1;   ///< random seed (tessellation, perturbations)
  int threads = 0;          ///< OpenMP threads; 0 on the command line = choose_threads() after parsing (auto)
};

class parser {
 public:
  parser(std::string program, std::string description)
      : program_(std::move(program)), description_(std::move(description)) {}

  /// A boolean switch: present = true.
  parser& flag(std::string name, bool& target, std::string help) {
    check_name(name);
    options_.push_back({std::move(name), {}, std::move(help), "", 0,
                        [&target](const std::vector<std::string>&) { target = true; }, false, {}, {}});
    return *this;
  }

  /// A single-valued option of type T (integer, floating point or std::string).
  template <class T>
  parser& option(std::string name, T& target, std::string help, std::string metavar = "") {
    check_name(name);
    if (metavar.empty()) metavar = default_metavar<T>();
    const std::string n = name;
    options_.push_back({std::move(name), {std::move(metavar)}, std::move(help), detail::to_text(target), 1,
                        [&target, n](const std::vector<std::string>& v) { target = detail::parse_value<T>(n, v[0]); },
                        std::is_arithmetic_v<T>, {}, {}});
    return *this;
  }

  // ---- value checks on the option registered last (numbers only; applied to each given value) ----
  /// value >= lo
  parser& at_least(double lo) { return check(">= " + detail::to_text(lo), [lo](double v) { return v >= lo; }); }
  /// value > lo
  parser& greater_than(double lo) { return check("> " + detail::to_text(lo), [lo](double v) { return v > lo; }); }
  /// value <= hi
  parser& at_most(double hi) { return check("<= " + detail::to_text(hi), [hi](double v) { return v <= hi; }); }
  /// value in [lo, hi]
  parser& within(double lo, double hi) { return at_least(lo).at_most(hi); }
  /// One of the listed numbers.
  parser& one_of_numbers(std::vector<double> values) {
    std::string rule = "one of";
    for (std::size_t i = 0; i < values.size(); ++i) rule += (i ? ", " : " ") + detail::to_text(values[i]);
    return check(rule, [values](double v) { return std::find(values.begin(), values.end(), v) != values.end(); });
  }
  /// One of the listed words (a text option).
  parser& one_of(std::vector<std::string> words) {
    option_entry& o = options_.back();
    o.words = std::move(words);
    o.help += " (" + join(o.words, "|") + ")";
    return *this;
  }

  /// True when the option was given on the command line (so --quick can leave it alone).
  [[nodiscard]] bool given(const std::string& name) const {
    return std::find(given_.begin(), given_.end(), name) != given_.end();
  }

  /// A fixed-count multi-value option, e.g. --size LX LY LZ.
  template <class T, std::size_t N>
  parser& option(std::string name, std::array<T, N>& target, std::string help, std::vector<std::string> metavars) {
    check_name(name);
    if (metavars.size() != N) throw std::logic_error("cli: option " + name + " needs " + std::to_string(N) + " metavars");
    std::string def;
    for (std::size_t i = 0; i < N; ++i) {
      if (i) def += " ";
      def += detail::to_text(target[i]);
    }
    const std::string n = name;
    options_.push_back({std::move(name), std::move(metavars), std::move(help), def, static_cast<int>(N),
                        [&target, n](const std::vector<std::string>& v) {
                          for (std::size_t i = 0; i < N; ++i) target[i] = detail::parse_value<T>(n, v[i]);
                        },
                        std::is_arithmetic_v<T>, {}, {}});
    return *this;
  }

  /// Registers --out (default results/<program>), --quick, --seed and --threads.
  parser& add_standard(standard_options& s) {
    if (s.out.empty()) s.out = std::string("results/").append(program_);
    option("--out", s.out, "output directory (not empty)", "DIR");
    check("not empty", {}, [](const std::string& text) { return !text.empty(); });
    flag("--quick", s.quick, "reduced run (used by the tests); changes only the values not given on the command line");
    option("--seed", s.seed, "random seed", "N");
    option("--threads", s.threads,
           "worker threads: N > 0 runs N threads throughout; 0 (auto) starts on one per core that other "
           "processes leave idle (measured over 0.2 s) and every few seconds of run tries fewer or more and keeps "
           "the faster, so a run that loses a core to another program falls back to fewer threads (same results; "
           "the OpenMP default if OMP_NUM_THREADS is set)",
           "N").within(0, max_threads);
    standard_ = &s;
    return *this;
  }

  /// The usage block: one line per option with its metavariables, help text and default.
  [[nodiscard]] std::string usage() const {
    std::ostringstream os;
    os << "usage: " << program_ << " [options]\n";
    if (!description_.empty()) os << "\n" << description_ << "\n";
    os << "\noptions:\n";
    std::vector<std::string> left;
    std::size_t width = 0;
    for (const auto& o : options_) {
      std::string l = "  " + o.name;
      for (const auto& m : o.metavars) l += " " + m;
      width = std::max(width, l.size());
      left.push_back(std::move(l));
    }
    left.push_back("  --help");
    width = std::max(width, left.back().size());
    for (std::size_t i = 0; i < options_.size(); ++i) {
      os << std::left << std::setw(static_cast<int>(width) + 2) << left[i] << options_[i].help;
      if (options_[i].arity > 0) os << " [default: " << options_[i].default_text << "]";
      os << '\n';
    }
    os << std::left << std::setw(static_cast<int>(width) + 2) << left.back() << "print this help and exit\n";
    return os.str();
  }

  /// Parses argv[1..argc). Returns false if --help was given (nothing else is applied after
  /// it); throws usage_error for an unknown option or a missing/invalid value.
  bool parse(int argc, const char* const* argv) {
    for (int i = 1; i < argc; ++i) {
      std::string arg = argv[i];
      if (arg == "--help" || arg == "-h") return false;
      std::string inline_value;
      bool has_inline = false;
      if (const auto eq = arg.find('='); arg.rfind("--", 0) == 0 && eq != std::string::npos) {
        inline_value = arg.substr(eq + 1);
        arg.resize(eq);
        has_inline = true;
      }
      const option_entry* o = find(arg);
      if (o == nullptr) throw usage_error("unknown option '" + arg + "' (see " + program_ + " --help)");
      std::vector<std::string> values;
      if (o->arity == 0) {
        if (has_inline) throw usage_error(arg + " takes no value, got '" + inline_value + "'");
      } else if (has_inline) {
        if (o->arity != 1) throw usage_error(arg + " takes " + std::to_string(o->arity) + " values, use '" + arg + " " +
                                             join(o->metavars) + "'");
        values.push_back(inline_value);
      } else {
        for (int k = 0; k < o->arity; ++k) {
          if (i + 1 >= argc) throw usage_error(arg + ": missing value (expected " + arg + " " + join(o->metavars) + ")");
          values.emplace_back(argv[++i]);
        }
      }
      o->apply(values);
      for (const std::string& text : values) validate(*o, text);
      given_.push_back(o->name);
    }
    return true;
  }

  /// Largest --threads accepted (more threads than this on a 2-core machine is a typo).
  static constexpr int max_threads = 256;

  /// parse(); on --help prints usage() to stdout and exits 0; on a usage_error prints
  /// "<program>: <message>" to stderr and exits 2.
  void parse_or_exit(int argc, const char* const* argv) {
    bool proceed = true;
    try {
      proceed = parse(argc, argv);
    } catch (const usage_error& e) {
      std::cerr << program_ << ": " << e.what() << '\n';
      std::exit(2);
    }
    if (!proceed) {
      std::cout << usage();
      std::exit(0);
    }
    if (standard_ != nullptr && standard_->threads == 0) standard_->threads = choose_threads(program_, 0);
  }
  void parse_or_exit(int argc, char** argv) { parse_or_exit(argc, const_cast<const char* const*>(argv)); }

  [[nodiscard]] const std::string& program() const { return program_; }

 private:
  standard_options* standard_ = nullptr;  ///< set by add_standard: --threads 0 is resolved after parsing
  struct value_check {
    std::string rule;                                  ///< e.g. "> 0", printed in the error
    std::function<bool(double)> number;                ///< for numeric options
    std::function<bool(const std::string&)> text;      ///< for text options
  };
  struct option_entry {
    std::string name;
    std::vector<std::string> metavars;
    std::string help;
    std::string default_text;
    int arity;
    std::function<void(const std::vector<std::string>&)> apply;
    bool numeric = false;
    std::vector<value_check> checks;
    std::vector<std::string> words;  ///< allowed values of a text option (empty: any)
  };
  parser& check(std::string rule, std::function<bool(double)> number, std::function<bool(const std::string&)> text = {}) {
    if (options_.empty()) throw std::logic_error("cli: a value check needs an option registered before it");
    option_entry& o = options_.back();
    if (number && !o.numeric) throw std::logic_error("cli: numeric check on text option " + o.name);
    if (number) o.help += " [" + rule + "]";
    o.checks.push_back({rule, std::move(number), std::move(text)});
    return *this;
  }
  /// Throws usage_error naming the option, the value and the rule it breaks.
  static void validate(const option_entry& o, const std::string& text) {
    if (!o.words.empty() && std::find(o.words.begin(), o.words.end(), text) == o.words.end())
      throw usage_error(o.name + ": invalid value '" + text + "' (expected " + join(o.words, " or ") + ")");
    for (const value_check& c : o.checks) {
      const bool ok = c.number ? c.number(std::stod(text)) : c.text(text);
      if (!ok) throw usage_error(o.name + ": value '" + text + "' must be " + c.rule);
    }
  }
  template <class T>
  static std::string default_metavar() {
    if constexpr (std::is_same_v<T, std::string>) return "TEXT";
    else if constexpr (std::is_floating_point_v<T>) return "X";
    else return "N";
  }
  static std::string join(const std::vector<std::string>& v, const std::string& separator = " ") {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (i) s += separator;
      s += v[i];
    }
    return s;
  }
  void check_name(const std::string& name) const {
    if (name.rfind("--", 0) != 0 || name.size() < 3) throw std::logic_error("cli: option name '" + name + "' must start with --");
    if (find(name) != nullptr || name == "--help") throw std::logic_error("cli: option " + name + " registered twice");
  }
  [[nodiscard]] const option_entry* find(const std::string& name) const {
    for (const auto& o : options_)
      if (o.name == name) return &o;
    return nullptr;
  }

  std::string program_;
  std::string description_;
  std::vector<option_entry> options_;
  std::vector<std::string> given_;  ///< options given on the command line, in order
};

/// Wall-clock stopwatch (steady clock), started at construction.
class wall_timer {
 public:
  wall_timer() : start_(clock::now()) {}
  void restart() { start_ = clock::now(); }
  [[nodiscard]] double seconds() const { return std::chrono::duration<double>(clock::now() - start_).count(); }

 private:
  using clock = std::chrono::steady_clock;
  clock::time_point start_;
};

/// A run's progress on stderr. On a terminal: one self-overwriting status line ("\r<label>
/// <message>"), refreshed at most every `interval_s` seconds so a fast loop is not slowed by
/// terminal output; finish() ends the line. Elsewhere (a log file, a batch system, CTest): a full
/// line at the first update and then at most every log_interval_s (10 s), so a log shows from
/// its first minute that the run is alive. TESSERA_PROGRESS=0 silences it, =1 forces the
/// terminal form.
class progress_line {
 public:
  static constexpr double log_interval_s = 10.0;
  explicit progress_line(std::string label, double interval_s = 0.5)
      : label_(std::move(label)), mode_(wanted()), interval_(mode_ == mode::log ? log_interval_s : interval_s) {}
  ~progress_line() { finish(); }
  progress_line(const progress_line&) = delete;
  progress_line& operator=(const progress_line&) = delete;

  /// Shows a bar for `fraction` (0..1) done, a free-form message, the elapsed time and an
  /// estimate of the time left (elapsed x (1 - f) / (f - f0), f0 the fraction at the first
  /// update, so a resumed run counts only its own progress), if the refresh interval has passed.
  void update(double fraction, const std::string& message = "") {
    if (mode_ == mode::off) return;
    const double now = timer_.seconds();
    if (shown_ && now - last_ < interval_) return;
    last_ = now;
    const double f = std::clamp(fraction, 0.0, 1.0);
    if (!shown_) first_ = f;
    shown_ = true;
    constexpr int width = 20;
    const int filled = static_cast<int>(f * width);
    std::ostringstream os;
    if (mode_ == mode::terminal) os << '\r';
    os << label_ << " [" << std::string(static_cast<std::size_t>(filled), '#')
       << std::string(static_cast<std::size_t>(width - filled), '.') << "] " << std::fixed << std::setprecision(1)
       << 100.0 * f << "% " << message << "  " << std::setprecision(1) << now << " s";
    if (f - first_ > 0.01) os << ", ~" << std::setprecision(0) << now * (1 - f) / (f - first_) << " s left";
    std::string line = os.str();
    if (mode_ == mode::log) {
      std::cerr << line << '\n' << std::flush;
      return;
    }
    if (line.size() < last_width_) line.append(last_width_ - line.size(), ' ');
    last_width_ = line.size();
    std::cerr << line << std::flush;
  }
  void finish() {
    if (mode_ == mode::terminal && shown_ && !finished_) std::cerr << '\n';
    finished_ = true;
  }

 private:
  enum class mode { off, terminal, log };
  static mode wanted() {
    if (const char* e = std::getenv("TESSERA_PROGRESS"); e != nullptr) {
      if (std::string(e) == "0") return mode::off;
      if (std::string(e) == "1") return mode::terminal;
    }
    return ::isatty(2) != 0 ? mode::terminal : mode::log;
  }
  std::string label_;
  mode mode_;
  double interval_;
  wall_timer timer_;
  double last_ = 0.0;
  double first_ = 0.0;  // the fraction shown first (a resumed run's starting point)
  bool shown_ = false;
  bool finished_ = false;
  std::size_t last_width_ = 0;
};

}  // namespace tessera::cli
