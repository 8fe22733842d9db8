#include "methods/cop_fscil/cop_fscil_settings.h"

#include <fmt/format.h>

#include "methods/method.h"
#include "protocols/parameter_set.h"

namespace fscil {

CopFscilSettings CopFscilSettings::from(const ParameterSet& params) {
  CopFscilSettings s;
  ViewRanges& view = s.cpi.view;
  view.global_bias = params.real("cpi_global_bias", view.global_bias);
  view.channel_bias = params.real("cpi_channel_bias", view.channel_bias);
  view.tilt = params.real("cpi_tilt", view.tilt);
  view.noise = params.real("cpi_noise", view.noise);
  view.max_shift_fraction = params.real("cpi_max_shift", view.max_shift_fraction);
  s.cpi.reference = params.choice("cpi_reference", "farthest", {"farthest", "random"}) == "random"
                        ? ReferenceChoice::random
                        : ReferenceChoice::farthest;
  s.cpi.mix_alpha = params.real("cpi_mix_alpha", s.cpi.mix_alpha);
  s.cpi.bank_capacity = params.integer("cpi_bank", s.cpi.bank_capacity);
  s.support_coverage = params.real("cpi_support_coverage", s.support_coverage);
  s.query_coverage = params.real("cpi_query_coverage", s.query_coverage);

  s.reflections = params.integer("pcqa_reflections", s.reflections);
  s.invariant_fraction = params.real("pcqa_invariant_fraction", s.invariant_fraction);
  s.pic_weight = params.real("pic_weight", s.pic_weight);
  s.pic_probes = static_cast<int>(params.integer("pic_probes", s.pic_probes));

  s.pspc_probes = static_cast<int>(params.integer("pspc_probes", s.pspc_probes));
  s.pspc_beta = params.real("pspc_beta", s.pspc_beta);

  const bool ranges_ok = view.global_bias >= 0 && view.channel_bias >= 0 && view.tilt >= 0 && view.noise >= 0 &&
                         view.max_shift_fraction >= 0 && view.max_shift_fraction < 1;
  if (!ranges_ok || s.cpi.mix_alpha <= 0 || s.cpi.bank_capacity < 1) {
    throw MethodError(fmt::format("cpi_global_bias={} cpi_channel_bias={} cpi_tilt={} cpi_noise={} cpi_max_shift={} "
                                  "cpi_mix_alpha={} cpi_bank={}: expected ranges >= 0, cpi_max_shift below 1, a "
                                  "positive alpha and a bank of at least 1",
                                  view.global_bias, view.channel_bias, view.tilt, view.noise, view.max_shift_fraction,
                                  s.cpi.mix_alpha, s.cpi.bank_capacity));
  }
  if (s.support_coverage < 0 || s.support_coverage > 1 || s.query_coverage < 0 || s.query_coverage > 1) {
    throw MethodError(fmt::format("cpi_support_coverage={} cpi_query_coverage={}: expected shares in [0, 1]",
                                  s.support_coverage, s.query_coverage));
  }
  if (s.reflections < 1 || s.invariant_fraction <= 0 || s.invariant_fraction > 1 || s.pic_weight < 0 ||
      s.pic_probes < 0 || s.pspc_probes < 0 || s.pspc_beta < 0) {
    throw MethodError(fmt::format("pcqa_reflections={} pcqa_invariant_fraction={} pic_weight={} pic_probes={} "
                                  "pspc_probes={} pspc_beta={}: expected at least 1 reflection, a fraction in (0, 1] "
                                  "and the rest >= 0 (pspc_probes 0 = by input size)",
                                  s.reflections, s.invariant_fraction, s.pic_weight, s.pic_probes, s.pspc_probes,
                                  s.pspc_beta));
  }
  return s;
}

int default_pspc_probes(std::int64_t values_per_sample) { return values_per_sample <= 32768 ? 100 : 10; }

}  // namespace fscil
