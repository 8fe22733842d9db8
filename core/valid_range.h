#pragma once
#include <limits>
#include <string>

namespace fscil {

// The values a numeric parameter accepts. Its owner (the method, reader or protocol that reads
// it) says which as it reads it, so a value outside is refused, naming the key, before anything
// runs. Every range excludes NaN and infinities.
class ValidRange {
 public:
  static ValidRange any() { return {}; }
  static ValidRange at_least(double low) { return ValidRange(low, kInfinity, false, true); }
  static ValidRange above(double low) { return ValidRange(low, kInfinity, true, true); }
  static ValidRange at_most(double high) { return ValidRange(-kInfinity, high, true, false); }
  static ValidRange between(double low, double high) { return ValidRange(low, high, false, false); }
  // [low, high): shares of something that must leave a part, like a mask.
  static ValidRange from_up_to(double low, double high) { return ValidRange(low, high, false, true); }
  // (low, high]
  static ValidRange above_up_to(double low, double high) { return ValidRange(low, high, true, false); }

  bool contains(double value) const;
  // "> 0", ">= 1", "in [0, 1]", "in [0, 1)", "finite"
  std::string describe() const;

 private:
  static constexpr double kInfinity = std::numeric_limits<double>::infinity();
  ValidRange() = default;
  ValidRange(double low, double high, bool low_open, bool high_open)
      : low_(low), high_(high), low_open_(low_open), high_open_(high_open) {}

  double low_ = -kInfinity, high_ = kInfinity;
  bool low_open_ = true, high_open_ = true;
};

}  // namespace fscil
