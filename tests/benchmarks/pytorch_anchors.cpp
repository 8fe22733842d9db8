#include "tests/benchmarks/pytorch_anchors.h"

#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <thread>
#include <nlohmann/json.hpp>

namespace fscil {

namespace {

constexpr const char* kVariable = "FSCIL_PYTORCH_ANCHORS";

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  fmt::print(stderr, "{}: {}: expected the JSON pytorch_anchors.py writes in this run, {{\"threads\": {}, \"rates\": "
             "{{figure: samples/s}}}}\n", file, what, std::thread::hardware_concurrency());
  std::exit(1);
}

std::map<std::string, double> read_rates(const std::string& file) {
  std::ifstream in(file);
  try {
    if (!in) throw std::runtime_error("cannot be read");
    const nlohmann::json record = nlohmann::json::parse(in);
    // The same threads as ours (torch_benchmark_main.cpp), or the ratio compares unlike work.
    if (record.at("threads") != std::thread::hardware_concurrency()) {
      throw std::runtime_error("measured with " + record.at("threads").dump() + " threads");
    }
    if (!record.at("rates").is_object()) throw std::runtime_error("rates is not an object");
    std::map<std::string, double> rates;
    for (const auto& [figure, rate] : record.at("rates").items()) {
      if (!rate.is_number() || rate.get<double>() <= 0) throw std::runtime_error("rate of " + figure + " is not positive");
      rates[figure] = rate.get<double>();
    }
    return rates;
  } catch (const std::exception& error) {
    fail(file, error.what());
  }
}

}  // namespace

std::optional<double> pytorch_rate(const std::string& figure) {
  const char* file = std::getenv(kVariable);
  if (file == nullptr || *file == '\0') return std::nullopt;
  static const std::map<std::string, double> rates = read_rates(file);
  const auto found = rates.find(figure);
  // A figure the script did not measure means the two name their work differently: loud, not
  // a label nobody reads.
  if (found == rates.end()) fail(file, "no rate for " + figure);
  return found->second;
}

std::string anchor_label(double ours, const std::optional<double>& theirs, double target, const std::string& whose) {
  if (!theirs) {
    return fmt::format("no {} rate: {} unset (`cmake --build build --target bench` measures it)",
                       whose, kVariable);
  }
  const double ratio = ours / *theirs;
  return fmt::format("{:.2f}x {}, target >= {}x: {}", ratio, whose, target, ratio >= target ? "met" : "MISSED");
}

}  // namespace fscil
