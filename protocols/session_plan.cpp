#include "protocols/session_plan.h"

#include <fmt/format.h>

#include <numeric>

#include "core/parameter_set.h"
#include "core/error.h"
#include "core/seeded_shuffle.h"

namespace fscil {

int SessionPlan::session_of_class(int protocol_class) const {
  if (protocol_class < base_classes) return 0;
  return 1 + (protocol_class - base_classes) / way;
}

SessionPlan make_session_plan(int dataset_classes, const SessionDefaults& defaults,
                              const ParameterSet& params, std::uint64_t seed) {
  SessionPlan plan;
  plan.base_classes = static_cast<int>(params.integer("base_classes", defaults.base_classes, ValidRange::at_least(2)));
  plan.way = static_cast<int>(params.integer("way", defaults.way, ValidRange::at_least(1)));
  plan.shot = static_cast<int>(params.integer("shot", defaults.shot, ValidRange::at_least(1)));
  plan.sessions = static_cast<int>(params.integer("sessions", defaults.sessions, ValidRange::at_least(1)));
  if (plan.total_classes() > dataset_classes) {
    throw ProtocolError(fmt::format("session plan needs {} classes ({} base + {} sessions x {}-way) but the "
                                    "dataset has {}", plan.total_classes(), plan.base_classes, plan.sessions - 1,
                                    plan.way, dataset_classes));
  }
  std::vector<int> order(dataset_classes);
  std::iota(order.begin(), order.end(), 0);
  if (params.choice("class_order", "natural", {"natural", "shuffled"}) == "shuffled") {
    seeded_shuffle(order, seed, SeedPurpose::class_order);
  }
  order.resize(plan.total_classes());
  plan.class_order = order;
  return plan;
}

}  // namespace fscil
