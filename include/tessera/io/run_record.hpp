#pragma once
// io::run_record: an output directory whose state cannot be mistaken (DESIGN.md §8).
//
//     io::run_record record(out, "rc_tie", argc, argv);   // writes nothing yet
//     ...checks...; io::ensure_directory(out);             // now: old outputs removed, run.json "running"
//     ...every file written through atomic_ofstream is listed in run.json as it is committed...
//     record.complete();                                   // run.json "complete"
//
// - run.json is written first, when the driver creates its output directory (after its input
//   checks, so bad input leaves nothing behind): program, version, commit, arguments,
//   "status": "running" and the files written so far.
// - A rerun into the same directory first removes the files its earlier run listed in run.json
//   (only plain file names inside the directory, so a corrupt run.json cannot reach elsewhere).
// - SIGINT/SIGTERM: the handler removes the temporary files of writes in progress, writes
//   run.json with "status": "interrupted" (pre-rendered, with async-signal-safe calls only) and
//   ends the process with the signal's status. An exception that leaves the driver marks it
//   "failed". summary.json is the drivers' last write, so it exists only after a complete run.
// One record per process (the signal handler is global). Not thread-safe: drive it from the
// driver's main thread.

#include <array>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "../core/version.hpp"
#include "atomic_file.hpp"
#include "json.hpp"

#ifndef TESSERA_GIT_COMMIT
#define TESSERA_GIT_COMMIT "unknown"  ///< the build's git commit, set by CMake; "unknown" outside it
#endif

namespace tessera::io {

/// run.json in an output directory: running, complete or interrupted, with the program, its arguments, the commit and the files written
class run_record {
 public:
  run_record(std::filesystem::path dir, std::string program, int argc, const char* const* argv)
      : dir_(std::move(dir)), program_(std::move(program)) {  ///< Writes nothing yet: run.json appears when the driver creates dir (io::ensure_directory, file comment)
    for (int i = 1; i < argc; ++i) arguments_.emplace_back(argv[i]);
    active() = this;
    detail::directory_observer() = [](const std::filesystem::path& d) {
      if (active() != nullptr) active()->on_directory(d);
    };
    detail::output_observer() = [](const std::filesystem::path& f) {
      if (active() != nullptr) active()->on_file(f);
    };
  }
  run_record(const run_record&) = delete;
  run_record& operator=(const run_record&) = delete;
  ~run_record() {
    if (started_ && !completed_) {
      try {
        write("failed");
      } catch (...) {
      }
    }
    detail::directory_observer() = nullptr;
    detail::output_observer() = nullptr;
    active() = nullptr;
  }

  /// Marks the run complete in run.json (after the driver's last file, summary.json).
  void complete() {
    if (!started_) return;
    completed_ = true;
    write("complete");
  }
  [[nodiscard]] const std::vector<std::string>& files() const { return files_; }  ///< The files recorded

 private:
  static run_record*& active() {
    static run_record* record = nullptr;
    return record;
  }

  void on_directory(const std::filesystem::path& d) {
    if (started_ || std::filesystem::weakly_canonical(d) != std::filesystem::weakly_canonical(dir_)) return;
    started_ = true;
    remove_earlier_outputs();
    started_at_ = static_cast<long long>(std::time(nullptr));
    write("running");
    std::signal(SIGINT, &run_record::on_signal);
    std::signal(SIGTERM, &run_record::on_signal);
  }
  void on_file(const std::filesystem::path& f) {
    if (!started_ || f.filename() == "run.json") return;
    std::error_code ec;
    if (std::filesystem::weakly_canonical(f.parent_path(), ec) != std::filesystem::weakly_canonical(dir_, ec)) return;
    const std::string name = f.filename().string();
    for (const auto& known : files_)
      if (known == name) return;
    files_.push_back(name);
    write(completed_ ? "complete" : "running");
  }

  /// Removes the plain files the earlier run.json lists (a flat string array "files": [...]).
  void remove_earlier_outputs() const {
    std::ifstream in(dir_ / "run.json");
    if (!in) return;
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    const auto key = text.find("\"files\"");
    if (key == std::string::npos) return;
    const auto open = text.find('[', key), close = text.find(']', key);
    if (open == std::string::npos || close == std::string::npos || close < open) return;
    std::size_t i = open;
    while (true) {
      const auto a = text.find('"', i + 1);
      if (a == std::string::npos || a > close) break;
      const auto b = text.find('"', a + 1);
      if (b == std::string::npos || b > close) break;
      const std::string name = text.substr(a + 1, b - a - 1);
      if (!name.empty() && name.find('/') == std::string::npos && name.find('\\') == std::string::npos &&
          name != "." && name != "..") {
        std::error_code ec;
        if (std::filesystem::is_regular_file(dir_ / name, ec)) std::filesystem::remove(dir_ / name, ec);
      }
      i = b;
    }
  }

  [[nodiscard]] std::string render(const char* status) const {
    summary_json js;
    js.set("program", program_)
        .set("version", std::string(TESSERA_VERSION_STRING))
        .set("commit", std::string(TESSERA_GIT_COMMIT))
        .set("arguments", arguments_)
        .set("status", std::string(status))
        .set("started_unix_s", static_cast<double>(started_at_))
        .set("files", files_);
    return js.str();
  }
  void write(const char* status) {
    write_file_atomically(dir_ / "run.json", render(status));
    // The text the signal handler writes, in the buffer it does not read now.
    const std::string interrupted = render("interrupted");
    auto& slot = buffers()[1 - current().load()];
    const std::size_t n = std::min(interrupted.size(), slot.text.size() - 1);
    std::memcpy(slot.text.data(), interrupted.data(), n);
    slot.size = n;
    const std::string target = (dir_ / "run.json").string(), temp = target + ".interrupted";
    std::snprintf(slot.target.data(), slot.target.size(), "%s", target.c_str());
    std::snprintf(slot.temp.data(), slot.temp.size(), "%s", temp.c_str());
    current().store(1 - current().load());
  }

  struct signal_buffer {
    std::array<char, 1 << 16> text{};
    std::size_t size = 0;
    std::array<char, 4096> target{}, temp{};
  };
  static std::array<signal_buffer, 2>& buffers() {
    static std::array<signal_buffer, 2> b;
    return b;
  }
  static std::atomic<int>& current() {
    static std::atomic<int> c{0};
    return c;
  }
  /// Async-signal-safe: unlink, open, write, close, rename, signal, raise.
  static void on_signal(int sig) {
    detail::remove_temporaries_in_progress();
    const signal_buffer& b = buffers()[current().load()];
    if (b.size > 0) {
      const int fd = ::open(b.temp.data(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        const ssize_t written = ::write(fd, b.text.data(), b.size);
        ::close(fd);
        if (written == static_cast<ssize_t>(b.size)) ::rename(b.temp.data(), b.target.data());
        else ::unlink(b.temp.data());
      }
    }
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }

  std::filesystem::path dir_;
  std::string program_;
  std::vector<std::string> arguments_;
  std::vector<std::string> files_;
  long long started_at_ = 0;
  bool started_ = false;
  bool completed_ = false;
};

}  // namespace tessera::io
