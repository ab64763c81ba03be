// The definitions of the larger functions that io/csv.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../csv.hpp"

namespace tessera::io {

TESSERA_INLINE void write_csv(const std::filesystem::path& path, const std::vector<std::string>& names,
                              const std::vector<std::vector<double>>& columns) {
  require<invalid_input>(names.size() == columns.size(), "write_csv '", path.string(), "': ", names.size(),
                         " names for ", columns.size(), " columns");
  csv_writer csv(path, names);
  const std::size_t rows = columns.empty() ? 0 : columns.front().size();
  std::vector<double> row(columns.size());
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      require<invalid_input>(columns[c].size() == rows, "write_csv '", path.string(), "': column '", names[c], "' has ",
                             columns[c].size(), " rows, expected ", rows);
      row[c] = columns[c][r];
    }
    csv.row(row);
  }
  csv.commit();
}

}  // namespace tessera::io
