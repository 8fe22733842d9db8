#pragma once
#include <cstdint>

#include "methods/common/supervised_training.h"

namespace fscil {

class ParameterSet;

// PAN's hyper-parameters as named options. Defaults are the released LS-100 config's
// (vinceasvp/FCAC configs/stdu_LS-100_PQA_AP.yml at 3ddc7af7); docs/methods.md gives each line.
// Its own keys (pan_*) stand apart from PITS-SC's (epochs_new, lr_new, pit_*), which the ls100
// and ns100 configs set for PITS-SC.
struct PanSettings {
  SupervisedSchedule standard;  // stages (a) and (c): the shared pretraining schedule (epochs_std 10, lr_std 0.1, ...)
  double temperature = 16;      // cfg L36
  int pit_epochs = 1;           // pan_pit_epochs (epochs_stdu_base, cfg L20)
  int pit_episodes = 50;        // pan_pit_episodes (train_episode, cfg L44)
  double encoder_lr = 2e-4;     // pan_encoder_lr (lr_stdu_base, cfg L24)
  double attention_lr = 2e-4;   // pan_attention_lr (lrg, cfg L25)
  int way = 5, shot = 5, query = 15;  // per part of an episode (cfg L45-L49)
  int session_steps = 10;       // pan_session_steps (epochs_new, cfg L21)
  double session_lr = 0.1;      // pan_session_lr (lr_new, cfg L26)
  std::int64_t temporary_base = 0;  // pan_temporary_base: 0 takes the release's share (ours)

  static PanSettings from(const ParameterSet& params);
};

// The temporary base classes of the pseudo-incremental stage: 35 of LS-100's 60 base classes in
// the release (cfg L55-L56); by default the same share, rounded, of another protocol's (ours), at
// least one on each side; `requested` (pan_temporary_base) when not 0, which must leave at least
// one temporary novel class.
std::int64_t temporary_base_classes(std::int64_t base_classes, std::int64_t requested = 0);

}  // namespace fscil
