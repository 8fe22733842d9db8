#pragma once
#include <cstdint>

#include "methods/cop_fscil/context_probe.h"

namespace fscil {

class ParameterSet;

// Which of CoP-FSCIL's components a variant runs. CPI is in every variant, as in the paper's
// ablation tables; without PCQA and PSPC the remaining stages are PITS-SC's.
struct CopFscilComponents {
  bool pcqa = true;
  bool pspc = true;
};

// CoP-FSCIL's own hyper-parameters as named options (the PITS-SC stages read theirs).
// docs/methods.md marks which defaults are ours.
struct CopFscilSettings {
  ContextProbeSettings cpi;        // cpi_global_bias, cpi_channel_bias, cpi_tilt, cpi_noise, cpi_max_shift,
                                   // cpi_reference, cpi_mix_alpha, cpi_bank
  double support_coverage = 0.6;   // share of an episode's support samples CPI perturbs (paper's best)
  double query_coverage = 1.0;     // share of its query samples (the kept classes' samples count as queries)

  std::int64_t reflections = 8;      // pcqa_reflections, m (ours)
  double invariant_fraction = 0.75;  // pcqa_invariant_fraction, d_inv / D (ours)
  double pic_weight = 0.1;           // lambda of L_PIC (paper)
  int pic_probes = 2;                // N_cp (ours)

  int pspc_probes = 0;     // N_ps; 0 = by input size: 100 for HapTex-shaped, 10 for LMT108-shaped (paper)
  double pspc_beta = 8.0;  // paper

  static CopFscilSettings from(const ParameterSet& params);
};

// The paper's N_ps for an input of this many values per sample: HapTex-sized inputs (5 x 64 x 24)
// get 100 probes, LMT108-sized ones (3 x 64 x 493) 10; the boundary between them is ours.
int default_pspc_probes(std::int64_t values_per_sample);

}  // namespace fscil
