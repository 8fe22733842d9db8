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
  // With removal: classes each removing session takes away, FCIAC's rule (its
  // `dataloader/dataloader.py` L276-L335; `CANetwork.py` L531-L559 zeroes their rows): the highest
  // remaining base classes, and the last classes of the newest added block.
  int removed_base = 1, removed_novel = 1;
  std::vector<int> class_order;

  // Whether `session` (>= 1) adds classes; false for a removing session.
  bool adds_classes(int session) const;
  // Adding sessions among 1..session.
  int adding_sessions_up_to(int session) const;
  int total_classes() const { return base_classes + way * adding_sessions_up_to(sessions - 1); }
  // Classes introduced in sessions 0..session, removed ones included: the classifier's rows.
  int seen_after(int session) const { return base_classes + way * adding_sessions_up_to(session); }
  // Classes seen after sessions 0..session and not removed by then.
  int present_after(int session) const { return seen_after(session) - static_cast<int>(removed_by(session).size()); }
  // The first class `session` adds (its range [first_class_of, seen_after) is empty when it adds none).
  int first_class_of(int session) const;
  int session_of_class(int protocol_class) const;
  // The classes `session` removes, in increasing order; empty for the base and adding sessions.
  std::vector<int> removed_in(int session) const;
  // Every class removed in sessions 1..session, in increasing order.
  std::vector<int> removed_by(int session) const;
};

// One line for a run's progress and the docs: "" without removal, else which sessions add and which
// classes each removing session removes, e.g. "class-variable sessions (removal=fciac): sessions 1,
// 3 add 5 classes each; session 2 removes 9, 14; 13 of 15 classes remain".
std::string describe_removal(const SessionPlan& plan);

// Reads base_classes, way, shot, sessions, class_order (natural|shuffled) and removal
// (none|fciac, with removed_base and removed_novel) from params, defaulting to the dataset's
// published protocol. Throws ProtocolError when impossible.
SessionPlan make_session_plan(int dataset_classes, const SessionDefaults& defaults,
                              const ParameterSet& params, std::uint64_t seed);
// The class orders a plan takes: natural, shuffled (from the seed).
const std::vector<std::string>& class_orders();
// ProtocolError "class order 'X': expected natural or shuffled" unless `name` is one of them.
void require_class_order(const std::string& name);

}  // namespace fscil
