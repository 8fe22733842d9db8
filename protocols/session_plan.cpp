#include "protocols/session_plan.h"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>

#include "core/parameter_set.h"
#include "core/error.h"
#include "core/seeded_shuffle.h"
#include "core/shown_text.h"

namespace fscil {

bool SessionPlan::adds_classes(int session) const {
  return session >= 1 && (removal == ClassRemoval::none || session % 2 == 1);
}

int SessionPlan::adding_sessions_up_to(int session) const {
  if (session <= 0) return 0;
  return removal == ClassRemoval::none ? session : (session + 1) / 2;
}

int SessionPlan::first_class_of(int session) const {
  if (session == 0) return 0;
  return adds_classes(session) ? seen_after(session - 1) : seen_after(session);
}

int SessionPlan::session_of_class(int protocol_class) const {
  if (protocol_class < base_classes) return 0;
  const int block = (protocol_class - base_classes) / way;
  return removal == ClassRemoval::none ? 1 + block : 1 + 2 * block;
}

std::vector<int> SessionPlan::removed_in(int session) const {
  if (session <= 0 || adds_classes(session)) return {};
  const int earlier = session / 2 - 1;  // removing sessions before this one: 2, 4, ...
  std::vector<int> classes;
  for (int c = base_classes - removed_base * (earlier + 1); c < base_classes - removed_base * earlier; ++c) {
    classes.push_back(c);
  }
  for (int c = seen_after(session) - removed_novel; c < seen_after(session); ++c) classes.push_back(c);
  return classes;
}

std::vector<int> SessionPlan::removed_by(int session) const {
  std::vector<int> classes;
  for (int s = 1; s <= session; ++s) {
    const std::vector<int> removed = removed_in(s);
    classes.insert(classes.end(), removed.begin(), removed.end());
  }
  std::sort(classes.begin(), classes.end());
  return classes;
}

std::string describe_removal(const SessionPlan& plan) {
  if (plan.removal == ClassRemoval::none) return "";
  std::vector<int> adding;
  std::vector<std::string> removing;
  for (int session = 1; session < plan.sessions; ++session) {
    if (plan.adds_classes(session)) {
      adding.push_back(session);
    } else {
      removing.push_back(fmt::format("session {} removes {}", session, fmt::join(plan.removed_in(session), ", ")));
    }
  }
  const int last = plan.sessions - 1;
  return fmt::format("class-variable sessions (removal=fciac): sessions {} add {} classes each; {}; {} of {} classes "
                     "remain",
                     fmt::join(adding, ", "), plan.way, fmt::join(removing, "; "),
                     plan.present_after(last), plan.seen_after(last));
}

SessionPlan make_session_plan(int dataset_classes, const SessionDefaults& defaults,
                              const ParameterSet& params, std::uint64_t seed) {
  SessionPlan plan;
  plan.base_classes = params.count("base_classes", defaults.base_classes, ValidRange::at_least(2));
  plan.way = params.count("way", defaults.way, ValidRange::at_least(1));
  plan.shot = params.count("shot", defaults.shot, ValidRange::at_least(1));
  plan.sessions = params.count("sessions", defaults.sessions, ValidRange::at_least(1));
  // Read only when given, so that add-only runs keep the identity they had before removal existed.
  if (params.contains("removal") &&
      params.choice("removal", "none", {"none", "fciac"}) == "fciac") {
    plan.removal = ClassRemoval::fciac;
    plan.removed_base = params.count("removed_base", plan.removed_base, ValidRange::at_least(0));
    plan.removed_novel =
        params.count("removed_novel", plan.removed_novel, ValidRange::between(0, plan.way));
    const int removing = (plan.sessions - 1) / 2;
    if (static_cast<std::int64_t>(plan.removed_base) * removing >= plan.base_classes) {
      throw ProtocolError(fmt::format("removal=fciac: {} removing sessions x removed_base={} would remove all {} base "
                                      "classes", removing, plan.removed_base, plan.base_classes));
    }
  }
  // Counted in 64 bits: the plan's own int arithmetic is safe only for a plan that fits the data.
  const std::int64_t adding = plan.adding_sessions_up_to(plan.sessions - 1);
  const std::int64_t needed = plan.base_classes + static_cast<std::int64_t>(plan.way) * adding;
  if (needed > dataset_classes) {
    throw ProtocolError(fmt::format("session plan needs {} classes ({} base + {} adding sessions x {}-way) but the "
                                    "dataset has {}", needed, plan.base_classes, adding, plan.way, dataset_classes));
  }
  std::vector<int> order(dataset_classes);
  std::iota(order.begin(), order.end(), 0);
  if (params.choice("class_order", "natural", class_orders()) == "shuffled") {
    seeded_shuffle(order, seed, SeedPurpose::class_order);
  }
  order.resize(plan.total_classes());
  plan.class_order = order;
  return plan;
}

const std::vector<std::string>& class_orders() {
  static const std::vector<std::string> names = {"natural", "shuffled"};
  return names;
}

void require_class_order(const std::string& name) {
  if (std::find(class_orders().begin(), class_orders().end(), name) != class_orders().end()) return;
  throw ProtocolError(fmt::format("class order '{}': expected {}", shown_text(name), fmt::join(class_orders(), " or ")));
}

}  // namespace fscil
