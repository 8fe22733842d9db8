#include "methods/cop_fscil/cop_fscil_settings.h"

#include <fmt/format.h>

#include <cmath>

#include "methods/method.h"
#include "core/named_choice.h"
#include "core/parameter_set.h"

namespace fscil {

CopFscilSettings CopFscilSettings::from(const ParameterSet& params) {
  CopFscilSettings s;
  ContextProbeSettings& cpi = s.cpi;
  cpi.space = named_choice(params, "cpi_space", cpi.space,
                           {{"standardised", ProbeSpace::standardised}, {"raw", ProbeSpace::raw}});
  ViewRanges& view = cpi.view;
  view.global_bias = params.real("cpi_global_bias", view.global_bias, ValidRange::at_least(0));
  view.channel_bias = params.real("cpi_channel_bias", view.channel_bias, ValidRange::at_least(0));
  view.tilt = params.real("cpi_tilt", view.tilt, ValidRange::at_least(0));
  view.noise = params.real("cpi_noise", view.noise, ValidRange::at_least(0));
  view.max_shift_fraction = params.real("cpi_max_shift", view.max_shift_fraction, ValidRange::from_up_to(0, 1));
  cpi.reference = named_choice(params, "cpi_reference", cpi.reference,
                               {{"farthest", ReferenceChoice::farthest}, {"random", ReferenceChoice::random}});
  cpi.standardised_distance =
      named_choice(params, "cpi_distance", cpi.standardised_distance, {{"standardised", true}, {"raw", false}});
  cpi.ranked_references =
      named_choice(params, "cpi_references", cpi.ranked_references, {{"ranked", true}, {"same", false}});
  cpi.mix_alpha = params.real("cpi_mix_alpha", cpi.mix_alpha, ValidRange::above(0));
  cpi.bank_capacity = params.integer("cpi_bank", cpi.bank_capacity, ValidRange::at_least(1));
  s.support_coverage = params.real("cpi_support_coverage", s.support_coverage, ValidRange::between(0, 1));
  s.query_coverage = params.real("cpi_query_coverage", s.query_coverage, ValidRange::between(0, 1));
  s.kept = named_choice(params, "cpi_kept", s.kept,
                        {{"query", KeptCoverage::query}, {"clean", KeptCoverage::clean}, {"split", KeptCoverage::split}});
  s.episode_statistics = named_choice(params, "cpi_bn_statistics", s.episode_statistics,
                                      {{"update", EpisodeStatistics::update},
                                       {"guarded", EpisodeStatistics::guarded},
                                       {"reestimate", EpisodeStatistics::reestimate}});
  s.pretrain_coverage = params.real("cpi_pretrain_coverage", s.pretrain_coverage, ValidRange::between(0, 1));

  s.reflections = params.integer("pcqa_reflections", s.reflections, ValidRange::at_least(1));
  s.invariant_fraction = params.real("pcqa_invariant_fraction", s.invariant_fraction, ValidRange::above_up_to(0, 1));
  s.sensitive_dim = params.integer("pcqa_sensitive_dim", s.sensitive_dim, ValidRange::at_least(0));
  s.hidden = params.integer("pcqa_hidden", s.hidden, ValidRange::at_least(0));
  s.pic_weight = params.real("pic_weight", s.pic_weight, ValidRange::at_least(0));
  s.pic_probes = params.count("pic_probes", s.pic_probes, ValidRange::at_least(0));
  s.pic_space = named_choice(params, "pic_space", s.pic_space,
                             {{"raw", PicSpace::raw}, {"normalised", PicSpace::normalised}, {"invariant", PicSpace::invariant}});

  s.session_new_and_old =
      named_choice(params, "session_loss", s.session_new_and_old, {{"new-old", true}, {"joint", false}});
  s.pspc_probes = params.count("pspc_probes", s.pspc_probes, ValidRange::at_least(0));
  s.pspc_beta = params.real("pspc_beta", s.pspc_beta, ValidRange::at_least(0));
  s.pspc_q_from_original = named_choice(params, "pspc_q", s.pspc_q_from_original, {{"original", true}, {"own", false}});
  s.pspc_instability_normalised =
      named_choice(params, "pspc_instability", s.pspc_instability_normalised, {{"normalised", true}, {"raw", false}});
  s.pspc_mean_of_views =
      named_choice(params, "pspc_mean", s.pspc_mean_of_views, {{"views", true}, {"original", false}});

  return s;
}

std::int64_t CopFscilSettings::sensitive_dim_for(std::int64_t dim) const {
  if (sensitive_dim > 0) {
    if (sensitive_dim >= dim) {
      throw MethodError(fmt::format("pcqa_sensitive_dim={}: expected fewer than the embedding's {} dimensions",
                                    sensitive_dim, dim));
    }
    return sensitive_dim;
  }
  const auto invariant = static_cast<std::int64_t>(std::lround(invariant_fraction * static_cast<double>(dim)));
  return dim - std::max<std::int64_t>(1, invariant);
}

int default_pspc_probes(std::int64_t values_per_sample) { return values_per_sample <= 32768 ? 100 : 10; }

std::set<std::string> cop_fscil_parameter_names() {
  const ParameterSet defaults;
  CopFscilSettings::from(defaults);
  std::set<std::string> names;
  for (const auto& [name, value] : defaults.used()) names.insert(name);
  return names;
}

}  // namespace fscil
