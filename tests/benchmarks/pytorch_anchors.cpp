#include "tests/benchmarks/pytorch_anchors.h"

#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

namespace fscil {

namespace {

constexpr const char* kVariable = "FSCIL_PYTORCH_ANCHORS";

std::map<std::string, double> read_rates(const std::string& file) {
  std::ifstream in(file);
  try {
    if (!in) throw std::runtime_error("cannot be read");
    const nlohmann::json record = nlohmann::json::parse(in);
    std::map<std::string, double> rates;
    for (const auto& [figure, rate] : record.at("rates").items()) {
      if (!rate.is_number() || rate.get<double>() <= 0) throw std::runtime_error("rate of " + figure + " is not positive");
      rates[figure] = rate.get<double>();
    }
    return rates;
  } catch (const std::exception& error) {
    fmt::print(stderr, "{}: {}: expected the JSON pytorch_anchors.py writes, {{\"rates\": {{figure: samples/s}}}}\n",
               file, error.what());
    std::exit(1);
  }
}

}  // namespace

std::optional<double> pytorch_rate(const std::string& figure) {
  static const std::map<std::string, double> rates = [] {
    const char* file = std::getenv(kVariable);
    return file == nullptr || *file == '\0' ? std::map<std::string, double>{} : read_rates(file);
  }();
  const auto found = rates.find(figure);
  if (found == rates.end()) return std::nullopt;
  return found->second;
}

std::string anchor_label(double ours, const std::optional<double>& theirs, double target, const std::string& whose) {
  if (!theirs) {
    return fmt::format("no {} rate: {} unset or without this figure (`cmake --build build --target bench` measures it)",
                       whose, kVariable);
  }
  const double ratio = ours / *theirs;
  return fmt::format("{:.2f}x {}, target >= {}x: {}", ratio, whose, target, ratio >= target ? "met" : "MISSED");
}

}  // namespace fscil
