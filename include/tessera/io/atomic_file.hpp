#pragma once
// Atomic file output: every tessera writer writes to a temporary file in the target's own
// directory and renames it over the target only when the content is complete, so a crash or an
// exception never leaves a half-written file behind (rename within one file system is atomic
// on POSIX). Failures throw tessera::io_error naming the path and the operating system's reason.
//
// Not thread-safe per object; distinct objects writing distinct paths may be used concurrently.

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ios>
#include <string>
#include <system_error>
#include <utility>

#if defined(_WIN32)
#include <process.h>
#else
#include <unistd.h>
#endif

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"

namespace tessera::io {

namespace detail {
[[nodiscard]] inline long process_id() {
#if defined(_WIN32)
  return static_cast<long>(_getpid());
#else
  return static_cast<long>(::getpid());
#endif
}
/// The OS reason for the last failed C/C++ library call, e.g. "No such file or directory".
[[nodiscard]] inline std::string last_os_error() {
  return errno != 0 ? std::string(std::strerror(errno)) : std::string("unknown error");
}

/// Observers of the output (io::run_record sets them): a directory made ready by
/// ensure_directory, a file committed by atomic_ofstream (or drawn by plot_png).
using path_observer = void (*)(const std::filesystem::path&);
inline path_observer& directory_observer() {
  static path_observer observer = nullptr;
  return observer;
}
inline path_observer& output_observer() {
  static path_observer observer = nullptr;
  return observer;
}
inline void notify_output(const std::filesystem::path& file) {
  if (output_observer() != nullptr) output_observer()(file);
}

/// Temporary files of writes in progress, so a signal handler can remove them (async-signal-safe
/// unlink of fixed buffers). 64 concurrent writes at most are tracked; more are still written
/// atomically, only not cleaned up on a signal.
struct temporary_slot {
  std::atomic<bool> used{false};
  std::array<char, 4096> path{};
};
inline std::array<temporary_slot, 64>& temporary_slots() {
  static std::array<temporary_slot, 64> slots;
  return slots;
}
inline int register_temporary(const std::string& path) {
  if (path.size() >= 4096) return -1;
  auto& slots = temporary_slots();
  for (std::size_t i = 0; i < slots.size(); ++i) {
    if (slots[i].used.load()) continue;
    std::memcpy(slots[i].path.data(), path.c_str(), path.size() + 1);
    slots[i].used.store(true);
    return static_cast<int>(i);
  }
  return -1;
}
inline void unregister_temporary(int slot) {
  if (slot >= 0) temporary_slots()[static_cast<std::size_t>(slot)].used.store(false);
}
/// Async-signal-safe: unlinks every registered temporary file.
inline void remove_temporaries_in_progress() noexcept {
#if !defined(_WIN32)
  for (auto& slot : temporary_slots())
    if (slot.used.load()) ::unlink(slot.path.data());
#endif
}
}  // namespace detail

/// Creates `dir` (and its parents) if needed and checks that it is a writable directory.
/// Throws io_error "cannot create output directory '<dir>': <reason>" otherwise.
TESSERA_INLINE void ensure_directory(const std::filesystem::path& dir);

/// An output file stream that becomes visible at `target` only on commit().
///
///     io::atomic_ofstream out("results/run/curve.csv");
///     out.stream() << "u,F\n" << ...;
///     out.commit();                    // rename path.tmp.<pid> -> path; throws io_error on failure
///
/// Destroying it without commit() (e.g. during stack unwinding) removes the temporary file and
/// leaves any previous file at `target` untouched.
class atomic_ofstream {
 public:
  explicit atomic_ofstream(std::filesystem::path target, std::ios::openmode mode = std::ios::out | std::ios::trunc)
      : target_(std::move(target)) {  ///< Opens target's temporary (target.tmp.<pid>); io_error when it cannot be opened
    temp_ = target_;
    temp_ += ".tmp." + std::to_string(detail::process_id());
    errno = 0;
    out_.open(temp_, mode | std::ios::out);
    slot_ = detail::register_temporary(temp_.string());
    if (!out_) throw io_error(tessera::detail::concat("cannot open '", target_.string(), "' for writing (temporary '",
                                                      temp_.string(), "'): ", detail::last_os_error()));
  }
  atomic_ofstream(const atomic_ofstream&) = delete;
  atomic_ofstream& operator=(const atomic_ofstream&) = delete;
  ~atomic_ofstream() {
    if (!committed_) {
      out_.close();
      std::error_code ec;
      std::filesystem::remove(temp_, ec);
    }
    detail::unregister_temporary(slot_);
  }

  [[nodiscard]] std::ostream& stream() { return out_; }  ///< The stream written to
  template <class T>
  atomic_ofstream& operator<<(const T& value) {  ///< Writes value to the stream
    out_ << value;
    return *this;
  }
  [[nodiscard]] const std::filesystem::path& target() const { return target_; }  ///< The file the data appear in at commit()
  [[nodiscard]] const std::filesystem::path& temporary() const { return temp_; }  ///< The temporary file written until commit()

  /// Flushes, closes and renames the temporary file onto the target.
  void commit() {
    if (committed_) return;
    errno = 0;
    out_.flush();
    const bool write_ok = static_cast<bool>(out_);
    const std::string write_reason = detail::last_os_error();
    out_.close();
    std::error_code ec;
    if (!write_ok || out_.fail()) {
      std::filesystem::remove(temp_, ec);
      throw io_error(tessera::detail::concat("writing '", target_.string(), "' failed: ", write_reason));
    }
    std::filesystem::rename(temp_, target_, ec);
    if (ec) {
      std::error_code ignore;
      std::filesystem::remove(temp_, ignore);
      throw io_error(tessera::detail::concat("cannot move '", temp_.string(), "' to '", target_.string(), "': ", ec.message()));
    }
    committed_ = true;
    detail::unregister_temporary(slot_);
    slot_ = -1;
    detail::notify_output(target_);
  }

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  std::ofstream out_;
  bool committed_ = false;
  int slot_ = -1;  ///< registration of temp_ for removal on a signal
};

/// Writes `content` to `path` atomically.
inline void write_file_atomically(const std::filesystem::path& path, const std::string& content) {
  atomic_ofstream out(path, std::ios::out | std::ios::trunc | std::ios::binary);
  out.stream() << content;
  out.commit();
}

}  // namespace tessera::io

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/atomic_file.ipp"
#endif
