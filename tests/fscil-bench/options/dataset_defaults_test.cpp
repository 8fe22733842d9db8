#include "tools/fscil-bench/options/dataset_defaults.h"

#include <gtest/gtest.h>

#include "core/parameter_set.h"

namespace fscil {
namespace {

// The released PITS-SC configs, now files (configs/ls100.json, configs/ns100.json), as defaults
// that --set still overrides; other datasets get none.
TEST(DatasetDefaults, TheReleasedConfigsAreDefaultsThatSetOverrides) {
  ParameterSet ls100;
  apply_dataset_defaults("ls100", ls100);
  ls100.set_assignment("pit_alpha=1.5");  // --set comes after
  EXPECT_EQ(ls100.text("pretrain_epochs", ""), "10");
  EXPECT_EQ(ls100.text("pit_lr", ""), "0.01");
  EXPECT_EQ(ls100.text("p_cutmix", ""), "0.6");
  EXPECT_EQ(ls100.text("pit_alpha", ""), "1.5");
  ParameterSet ns100;
  apply_dataset_defaults("ns100", ns100);
  EXPECT_EQ(ns100.text("epochs_new", ""), "200");
  EXPECT_EQ(ns100.text("lr_new", ""), "0.01");
  EXPECT_EQ(ns100.text("p_cutmix", ""), "0.0");
  EXPECT_EQ(ns100.text("pit_alpha", ""), "3.0");
  // The rendered NS-100 stand-ins run with NS-100's config, as the real set they stand in for.
  for (const char* stand_in : {"sf-instruments", "sf-instruments-mini"}) {
    ParameterSet rendered;
    apply_dataset_defaults(stand_in, rendered);
    EXPECT_EQ(rendered.text("pit_lr", ""), "0.1") << stand_in;
    EXPECT_EQ(rendered.text("p_cutmix", ""), "0.0") << stand_in;
  }
  ParameterSet simtex;
  apply_dataset_defaults("simtex", simtex);
  EXPECT_FALSE(simtex.contains("pretrain_epochs"));
}

}  // namespace
}  // namespace fscil
