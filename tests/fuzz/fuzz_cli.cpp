// libFuzzer target: arbitrary bytes as a driver's command line (examples/common/cli.hpp).
//
// The bytes are split at NUL into argv[1..]. The parser is the one every example driver uses,
// with the kinds of options they register: integers with a listed set and a range, reals with
// open and closed bounds, a three-real option, a text option with known words, a flag and the
// standard options. Acceptable outcomes: parse() returns (true, or false for --help) with every
// bound variable inside its declared range, or throws cli::usage_error with a message naming an
// option. Anything else (another exception, a sanitizer report, a value outside its range
// accepted) is a finding.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "../../examples/common/cli.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace cli = tessera::cli;
  std::vector<std::string> words{"prog"};
  std::string current;
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == 0) {
      words.push_back(current);
      current.clear();
    } else {
      current.push_back(static_cast<char>(data[i]));
    }
  }
  words.push_back(current);
  std::vector<const char*> argv;
  for (const auto& w : words) argv.push_back(w.c_str());

  cli::standard_options common;
  int blocks = 100;
  double rate = 5e-3, dt = 0;
  std::array<double, 3> size3{1, 1, 1};
  std::string law = "power";
  bool rigid = false;
  cli::parser p("prog", "fuzzed");
  p.add_standard(common);
  p.option("--blocks", blocks, "blocks", "N").one_of_numbers({100, 250, 500, 750});
  p.option("--rate", rate, "rate", "V").greater_than(0);
  p.option("--dt", dt, "dt", "DT").at_least(0).at_most(1);
  p.option("--size", size3, "size", {"X", "Y", "Z"}).greater_than(0);
  p.option("--law", law, "law", "NAME").one_of({"power", "linear"});
  p.flag("--rigid", rigid, "rigid");
  try {
    (void)p.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const cli::usage_error& e) {
    if (std::string(e.what()).empty()) tessera::fuzz::finding("usage_error with an empty message");
    return 0;
  }
  // Accepted: every value inside its declared range.
  if (!(blocks == 100 || blocks == 250 || blocks == 500 || blocks == 750)) tessera::fuzz::finding("blocks accepted");
  if (!(std::isfinite(rate) && rate > 0)) tessera::fuzz::finding("rate accepted out of range");
  if (!(std::isfinite(dt) && dt >= 0 && dt <= 1)) tessera::fuzz::finding("dt accepted out of range");
  for (double v : size3)
    if (!(std::isfinite(v) && v > 0)) tessera::fuzz::finding("size accepted out of range");
  if (law != "power" && law != "linear") tessera::fuzz::finding("law accepted: " + law);
  if (common.out.empty()) tessera::fuzz::finding("empty --out accepted");
  if (common.threads < 0 || common.threads > cli::parser::max_threads) tessera::fuzz::finding("threads accepted");
  return 0;
}
