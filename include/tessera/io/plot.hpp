#pragma once
// PNG plots of CSV curves through gnuplot (Debian: gnuplot-nox). plot_png writes a gnuplot
// script next to the PNG (<name>.gp, kept so the figure can be restyled by hand) and runs it.
// Plotting is a convenience: it never throws and never fails a run. When gnuplot is not
// installed it prints one line on stderr and returns false; any other problem (missing CSV
// column, gnuplot error) is also reported on one stderr line.
//
//     io::plot_spec p{.title = "RC tie", .xlabel = "elongation (mm)", .ylabel = "force (kN)"};
//     p.series.push_back({.csv = out / "curve.csv", .x_column = "elongation_m", .y_column = "force_N",
//                         .title = "tessera", .x_scale = 1e3, .y_scale = 1e-3});
//     p.series.push_back({.csv = out / "bare_bar.csv", ..., .style = "lines dt 2"});
//     io::plot_png(out / "curve.png", p);

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "atomic_file.hpp"

namespace tessera::io {

/// One curve: columns of a CSV file with a header row (as written by csv_writer).
struct plot_series {
  std::filesystem::path csv;  ///< the CSV file
  std::string x_column;            ///< header name of the abscissa
  std::string y_column;            ///< header name of the ordinate
  std::string title;               ///< legend entry (empty: the y column name)
  std::string style = "lines lw 2";  ///< gnuplot `with` clause, e.g. "lines dt 2", "points pt 7"
  double x_scale = 1.0;            ///< plotted x = x_scale * column (unit conversion, e.g. 1e3 for m -> mm)
  double y_scale = 1.0;  ///< factor on y
};

/// A figure: its title, axes, curves and size (io::plot draws it with gnuplot)
struct plot_spec {
  std::string title;  ///< figure title
  std::string xlabel;  ///< x axis label
  std::string ylabel;  ///< y axis label
  std::vector<plot_series> series;  ///< the curves
  int width_px = 1000;  ///< width (pixels)
  int height_px = 700;  ///< height (pixels)
  bool log_x = false;  ///< logarithmic x axis (every x value must be > 0)
  bool log_y = false;  ///< logarithmic y axis (every y value must be > 0)
  /// Extra gnuplot commands after the axis labels (ranges, aspect ratio, outline objects).
  std::vector<std::string> preamble{};
  /// Point sizes from a third CSV column (times scale) for series `series`, whose style then
  /// reads "points ... ps variable" (a crack map drawn by width, say).
  struct variable_size {
    std::size_t series = 0;  ///< index of the series
    std::string column;  ///< column giving the point size
    double scale = 1.0;  ///< factor on it
  };
  std::vector<variable_size> variable_sizes{};  ///< point sizes read from columns
};

namespace detail {
/// gnuplot single-quoted string: only the quote itself needs doubling.
[[nodiscard]] inline std::string gp_quote(const std::string& s) {
  std::string q = "'";
  for (const char c : s) q += (c == '\'') ? std::string("''") : std::string(1, c);
  return q + "'";
}
/// POSIX shell single-quoted word.
[[nodiscard]] inline std::string sh_quote(const std::string& s) {
  std::string q = "'";
  for (const char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
/// 1-based column of `name` in the CSV header, 0 if absent or unreadable.
[[nodiscard]] inline int csv_column(const std::filesystem::path& csv, const std::string& name) {
  std::ifstream in(csv);
  std::string header;
  if (!in || !std::getline(in, header)) return 0;
  std::stringstream ss(header);
  std::string cell;
  for (int column = 1; std::getline(ss, cell, ','); ++column) {
    if (!cell.empty() && cell.back() == '\r') cell.pop_back();
    if (cell.size() >= 2 && cell.front() == '"' && cell.back() == '"') cell = cell.substr(1, cell.size() - 2);
    if (cell == name) return column;
  }
  return 0;
}
[[nodiscard]] inline bool gnuplot_available() {
#if defined(_WIN32)
  return std::system("where gnuplot >NUL 2>&1") == 0;
#else
  return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
#endif
}
}  // namespace detail

/// Writes <png without extension>.gp and runs gnuplot to produce `png`. Returns true when the
/// PNG was produced; never throws.
TESSERA_INLINE bool plot_png(const std::filesystem::path& png, const plot_spec& spec) noexcept;

}  // namespace tessera::io

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/plot.ipp"
#endif
