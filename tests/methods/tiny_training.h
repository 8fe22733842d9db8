#pragma once
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>

#include "methods/method_registry.h"
#include "core/parameter_set.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {

// A registered method with `values` set, made as every tiny training starts: torch seeded at 5.
inline std::unique_ptr<Method> tiny_method(const std::string& name, const std::map<std::string, std::string>& values) {
  ParameterSet params;
  for (const auto& [key, value] : values) params.set(key, value);
  torch::manual_seed(5);
  return create_method(name, params);
}

// Every tensor of `expected` is in `actual`, equal to the bit, and nothing else is.
inline void expect_same_state(const MethodState& expected, const MethodState& actual, const std::string& what) {
  ASSERT_EQ(actual.size(), expected.size()) << what;
  for (const auto& [name, tensor] : expected) {
    ASSERT_EQ(actual.count(name), 1u) << what << ": " << name;
    EXPECT_TRUE(torch::equal(actual.at(name), tensor)) << what << " changes " << name;
  }
}

}  // namespace fscil
