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

// `values` and the keys of `more` it lacks.
inline std::map<std::string, std::string> with_more(std::map<std::string, std::string> values,
                                                    const std::map<std::string, std::string>& more) {
  values.insert(more.begin(), more.end());
  return values;
}

// A method's name as a parameterised test's name: '-', '/' and '+' become '_'.
inline std::string test_name_of(std::string method) {
  for (char& c : method) {
    if (c == '-' || c == '/' || c == '+') c = '_';
  }
  return method;
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
