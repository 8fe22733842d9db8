#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "datasets/prepared_dataset.h"

namespace fscil {

class ParameterSet;

// Which classes arrive in which session. Protocol class p is dataset class class_order[p];
// session 0 holds protocol classes [0, base_classes), session s adds the next `way`.
struct SessionPlan {
  int base_classes = 0;
  int way = 0;
  int shot = 0;
  int sessions = 0;  // including the base session
  std::vector<int> class_order;

  int total_classes() const { return base_classes + way * (sessions - 1); }
  int seen_after(int session) const { return base_classes + way * session; }
  int first_class_of(int session) const { return session == 0 ? 0 : base_classes + way * (session - 1); }
  int session_of_class(int protocol_class) const;
};

// Reads base_classes, way, shot, sessions and class_order (natural|shuffled) from params,
// defaulting to the dataset's published protocol. Throws ProtocolError when impossible.
SessionPlan make_session_plan(int dataset_classes, const SessionDefaults& defaults,
                              const ParameterSet& params, std::uint64_t seed);

}  // namespace fscil
