#pragma once
// CSV output with a header row and full precision (max_digits10 significant digits, so a
// double read back is bit-identical). Written atomically: nothing appears at the target path
// until commit() (io/atomic_file.hpp).
//
//     io::csv_writer curve("results/tie/curve.csv", {"displacement_m", "force_N"});
//     curve.row(u, F);            // any number of arithmetic values, one per column
//     curve.commit();
//
// Non-finite values are written as nan / inf / -inf. Not thread-safe per object.

#include <cmath>
#include <concepts>
#include <ostream>
#include <type_traits>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "atomic_file.hpp"

namespace tessera::io {

/// A CSV file written atomically (io::atomic_ofstream): a header row, then rows of numbers at full precision
class csv_writer {
 public:
  csv_writer(const std::filesystem::path& path, std::vector<std::string> header)
      : out_(path), header_(std::move(header)) {  ///< Opens path's temporary and writes the header; io_error when it cannot, invalid_input for an empty header
    require<invalid_input>(!header_.empty(), "csv_writer '", path.string(), "': header must name at least one column");
    out_.stream() << std::setprecision(std::numeric_limits<double>::max_digits10);
    for (std::size_t i = 0; i < header_.size(); ++i) out_.stream() << (i ? "," : "") << quoted(header_[i]);
    out_.stream() << '\n';
  }

  /// Appends one row; the number of values must match the header.
  template <class... T>
    requires(std::is_arithmetic_v<T> && ...)
  void row(T... values) {
    const double v[] = {static_cast<double>(values)...};
    row(std::span<const double>(v, sizeof...(T)));
  }
  void row(std::span<const double> values) {  ///< Writes a row; refuses (invalid_input) one whose length is not the header's
    require<invalid_input>(values.size() == header_.size(), "csv_writer '", out_.target().string(), "': row ", rows_,
                           " has ", values.size(), " values, expected ", header_.size());
    std::ostream& os = out_.stream();
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (i) os << ',';
      write_number(os, values[i]);
    }
    os << '\n';
    ++rows_;
  }
  [[nodiscard]] std::size_t rows() const { return rows_; }  ///< Rows written
  /// Makes the file visible at its path (throws io_error on failure).
  void commit() { out_.commit(); }

  static void write_number(std::ostream& os, double x) {  ///< x with 17 significant digits, nan and inf as such
    if (std::isfinite(x)) os << x;
    else os << (std::isnan(x) ? "nan" : (x > 0 ? "inf" : "-inf"));
  }

 private:
  static std::string quoted(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (const char c : s) q += (c == '"') ? std::string("\"\"") : std::string(1, c);
    return q + '"';
  }
  atomic_ofstream out_;
  std::vector<std::string> header_;
  std::size_t rows_ = 0;
};

/// Writes columns of equal length as one CSV file (header = column names), atomically.
TESSERA_INLINE void write_csv(const std::filesystem::path& path, const std::vector<std::string>& names,
                              const std::vector<std::vector<double>>& columns);

}  // namespace tessera::io

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/csv.ipp"
#endif
