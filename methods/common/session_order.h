#pragma once
#include <fmt/format.h>

#include <cstdint>

#include "core/error.h"
#include "methods/method.h"

namespace fscil {

// A session's new classes start where the classes seen so far end; anything else means the runner
// and the method disagree about the protocol, and rows would land on the wrong classes.
inline void check_session_order(const SessionData& session, std::int64_t seen) {
  if (session.new_classes.front() != seen) {
    throw MethodError(fmt::format("session {} starts at class {}, expected {}", session.session,
                                  session.new_classes.front(), seen));
  }
}

}  // namespace fscil
