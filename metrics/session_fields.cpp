#include "metrics/session_fields.h"

namespace fscil {

namespace {

using Kind = SessionField::Kind;

// A field from its member (nested members such as accuracy.all included) and the member's type.
#define FSCIL_SESSION_FIELD(key, column, kind, member, type)                           \
  SessionField {                                                                        \
    key, column, kind, [](const SessionOutcome& o) { return static_cast<double>(o.member); }, \
        [](SessionOutcome& o, double v) { o.member = static_cast<type>(v); }           \
  }

}  // namespace

const std::vector<SessionField>& session_fields() {
  static const std::vector<SessionField> fields = {
      FSCIL_SESSION_FIELD("session", "session", Kind::count, session, int),
      FSCIL_SESSION_FIELD("seen_classes", "seen_classes", Kind::count, seen_classes, int),
      FSCIL_SESSION_FIELD("accuracy", "accuracy", Kind::percent, accuracy.all, double),
      FSCIL_SESSION_FIELD("base_accuracy", "base", Kind::percent, accuracy.base, double),
      FSCIL_SESSION_FIELD("novel_accuracy", "novel", Kind::novel_percent, accuracy.novel, double),
      FSCIL_SESSION_FIELD("current_accuracy", "current", Kind::novel_percent, accuracy.current, double),
      FSCIL_SESSION_FIELD("harmonic_mean", "harmonic_mean", Kind::novel_percent, accuracy.harmonic, double),
      FSCIL_SESSION_FIELD("test_samples", nullptr, Kind::samples, accuracy.samples, std::int64_t),
      FSCIL_SESSION_FIELD("train_seconds", "train_seconds", Kind::seconds, train_seconds, double),
      FSCIL_SESSION_FIELD("test_seconds", "test_seconds", Kind::seconds, test_seconds, double),
      FSCIL_SESSION_FIELD("context_ratio_mean", "R", Kind::ratio, context_ratio_mean, double),
      FSCIL_SESSION_FIELD("context_ratio_max", nullptr, Kind::ratio, context_ratio_max, double),
  };
  return fields;
}

#undef FSCIL_SESSION_FIELD

}  // namespace fscil
