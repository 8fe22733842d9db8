#pragma once
#include <cstdint>

namespace fscil {

class ParameterSet;

// PCTS's pseudo-removal half-step: how many pseudo-classes it forgets and how its two terms weigh
// (methods/pa_pct/pcts_episode.h).
struct PctsRemovalWeights {
  int forgotten = 2;                                        // pseudo-classes forgotten (P L123)
  double separation_weight = 0.8, separation_margin = 0.5;  // lambda_F, m_f (P L66-L68)
  double topology_weight = 1.0, topology_sigma = 0.5;       // lambda_T (P L66), sigma (P L6)
};

// PA-PCT's own hyper-parameters as named options (PAN's stages read PAN's: PanSettings), their
// defaults the release's LS-100 config (cgq2971-afk/FCIAC configs/stdu_LS-100_FCIAC.yml at
// 6ccc2082, "cfg") or its code where the config is silent (PCA.py = "P", CANetwork.py = "N");
// docs/methods.md, "pa-pct".
struct PaPctSettings {
  // PCTS, the pseudo class-variable training after PAN's stages (fscil_trainer.py L227-L295).
  int pcts_epochs = 10;             // pa_pct_epochs (epochs_base, cfg L25)
  int pcts_episodes = 50;           // pa_pct_episodes (episode2.train_episode, cfg L89)
  int pcts_way = 20;                // episode classes (episode2.episode_way, cfg L90)
  int pcts_kept = 10;               // of them keeping their labels (episode2.base, cfg L91)
  int pcts_samples = 20;            // per class (episode_shot 5 + episode_query 15, cfg L93-L94)
  int pcts_prototype_shots = 5;     // mixed samples a pseudo-class's prototype is the mean of (P L91)
  double pcts_alpha = 0.8;          // pa_pct_alpha: Beta(alpha, alpha) of the mixing (pit_mixup_alpha, cfg L5)
  double pcts_encoder_lr = 0.01;    // pa_pct_encoder_lr (lr_mix_base, cfg L32)
  double pcts_attention_lr = 2e-4;  // pa_pct_attention_lr, inc_attn's (lr_inc, cfg L33)
  double pcts_gate_lr = 0.02;       // the gate's, hard-coded (P L37)
  PctsRemovalWeights removal;
  // Sessions (update_fc_ad, N L368-L529).
  double session_attention_lr = 1e-5;  // pa_pct_session_lr: inc_attn and the gate (lr_inc2, cfg L34)

  static PaPctSettings from(const ParameterSet& params);
};

}  // namespace fscil
