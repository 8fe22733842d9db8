#pragma once
#include <set>
#include <string>
#include <cstdint>

#include "methods/cop_fscil/context_probe.h"
#include "methods/cop_fscil/quotient_adapter.h"

namespace fscil {

class ParameterSet;

// Which of CoP-FSCIL's components a variant runs. CPI is in every variant, as in the paper's
// ablation tables; without PCQA and PSPC the remaining stages are PITS-SC's.
struct CopFscilComponents {
  bool pcqa = true;
  bool pspc = true;
};

// How the kept base classes' samples of a pseudo-incremental episode count for CPI's coverage
// (cpi_kept): as queries (they are classified), left clean, or split like a pseudo-novel class
// into pit_shot support samples and the rest queries.
enum class KeptCoverage { query, clean, split };

// What the encoder's batch-norm running statistics learn during CPI episodes
// (cpi_bn_statistics): updated by every episode forward (probes included), left as pretraining
// left them (guarded), or re-estimated on the clean base data after the episodes.
enum class EpisodeStatistics { update, guarded, reestimate };

// CoP-FSCIL's own hyper-parameters as named options (the PITS-SC stages read theirs).
// docs/methods.md marks which defaults are ours and the validation numbers that chose them.
struct CopFscilSettings {
  ContextProbeSettings cpi;        // cpi_space, cpi_global_bias, cpi_channel_bias, cpi_tilt, cpi_noise,
                                   // cpi_max_shift, cpi_reference, cpi_distance, cpi_references,
                                   // cpi_mix_alpha, cpi_bank
  double support_coverage = 0.6;   // share of an episode's support samples CPI perturbs (paper's best)
  double query_coverage = 1.0;     // share of its query samples (paper's best)
  KeptCoverage kept = KeptCoverage::clean;
  EpisodeStatistics episode_statistics = EpisodeStatistics::update;
  double pretrain_coverage = 0.0;  // cpi_pretrain_coverage: share of each pretraining batch CPI perturbs

  std::int64_t reflections = 8;      // pcqa_reflections, m (ours)
  double invariant_fraction = 0.75;  // pcqa_invariant_fraction, d_inv / D (ours)
  std::int64_t sensitive_dim = 0;    // pcqa_sensitive_dim, d_sen; 0 = D - d_inv from the fraction
  std::int64_t hidden = 0;           // pcqa_hidden, g's hidden width; 0 = D (ours)
  double pic_weight = 0.1;           // lambda of L_PIC (paper)
  int pic_probes = 2;                // N_cp (ours)
  PicSpace pic_space = PicSpace::raw;  // pic_space=raw|normalised|invariant: what L_PIC compares (paper: raw)

  // session_loss=new-old: L_Inc = L_New + L_Old, the paper's incremental objective (Eq. 24-26) in
  // every variant; joint: PITS-SC's cross-entropy over every seen class, as the baseline has it.
  bool session_new_and_old = true;

  int pspc_probes = 0;     // N_ps; 0 = by input size: 100 for HapTex-shaped, 10 for LMT108-shaped (paper)
  double pspc_beta = 8.0;  // paper
  bool pspc_q_from_original = true;       // pspc_q=original|own: probes mapped with Q_i from z_i^(0) (paper)
  // Both (ours), chosen on validation across simtex and sf-instruments (docs/methods.md, PSPC).
  bool pspc_instability_normalised = true;  // pspc_instability=normalised|raw: U_i on unit-length z_hat
  bool pspc_mean_of_views = false;          // pspc_mean=views|original: zbar_i over the views, or z_hat_i^(0)

  static CopFscilSettings from(const ParameterSet& params);
  // d_sen as this embedding size gives it.
  std::int64_t sensitive_dim_for(std::int64_t dim) const;
};

// The paper's N_ps for an input of this many values per sample: HapTex-sized inputs (5 x 64 x 24)
// get 100 probes, LMT108-sized ones (3 x 64 x 493) 10; the boundary between them is ours.
int default_pspc_probes(std::int64_t values_per_sample);

// Every parameter CopFscilSettings::from() reads, as it reads them (never a list kept by hand).
std::set<std::string> cop_fscil_parameter_names();

}  // namespace fscil
