#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "datasets/prepared_dataset.h"

namespace fscil {

class ParameterSet;

// Whether sessions only add classes (the FSCIL protocol) or alternately add and remove them, as the
// class-variable protocol of FCIAC (PA-PCT's release) runs them: odd sessions add `way` classes,
// even sessions add none and remove classes (`removal=fciac`).
enum class ClassRemoval { none, fciac };

// Which classes arrive in which session, and which leave. Protocol class p is dataset class
// class_order[p]; session 0 holds protocol classes [0, base_classes), each adding session the
// next `way`.
struct SessionPlan {
  int base_classes = 0;
  int way = 0;
  int shot = 0;
  int sessions = 0;  // including the base session
  ClassRemoval removal = ClassRemoval::none;
  // With removal: classes each removing session takes away, FCIAC's rule (its `CANetwork.py`
  // L531-L559): the highest remaining base classes, and the last classes of the newest added block.
  int removed_base = 1, removed_novel = 1;
  std::vector<int> class_order;

  // Whether `session` (>= 1) adds classes; false for a removing session.
  bool adds_classes(int session) const;
  // Adding sessions among 1..session.
  int adding_sessions_up_to(int session) const;
  int total_classes() const { return base_classes + way * adding_sessions_up_to(sessions - 1); }
  // Classes introduced in sessions 0..session, removed ones included: the classifier's rows.
  int seen_after(int session) const { return base_classes + way * adding_sessions_up_to(session); }
  // The first class `session` adds (its range [first_class_of, seen_after) is empty when it adds none).
  int first_class_of(int session) const;
  int session_of_class(int protocol_class) const;
  // The classes `session` removes, in increasing order; empty for the base and adding sessions.
  std::vector<int> removed_in(int session) const;
  // Every class removed in sessions 1..session, in increasing order.
  std::vector<int> removed_by(int session) const;
};

// Reads base_classes, way, shot, sessions, class_order (natural|shuffled) and removal
// (none|fciac, with removed_base and removed_novel) from params, defaulting to the dataset's
// published protocol. Throws ProtocolError when impossible.
SessionPlan make_session_plan(int dataset_classes, const SessionDefaults& defaults,
                              const ParameterSet& params, std::uint64_t seed);

}  // namespace fscil
