// The definitions of the larger functions that io/atomic_file.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../atomic_file.hpp"

namespace tessera::io {

TESSERA_INLINE void ensure_directory(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  if (dir.empty()) return;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw io_error(tessera::detail::concat("cannot create output directory '", dir.string(), "': ", ec.message()));
  if (!fs::is_directory(dir, ec))
    throw io_error(tessera::detail::concat("output path '", dir.string(), "' exists and is not a directory"));
  // Probe writability with a real file: permission bits alone do not tell (root, ACLs, read-only mounts).
  const fs::path probe = dir / (".tessera_probe." + std::to_string(detail::process_id()));
  errno = 0;
  {
    std::ofstream out(probe, std::ios::binary | std::ios::trunc);
    if (!out) throw io_error(tessera::detail::concat("output directory '", dir.string(), "' is not writable: ", detail::last_os_error()));
  }
  fs::remove(probe, ec);
  if (detail::directory_observer() != nullptr) detail::directory_observer()(dir);
}

}  // namespace tessera::io
