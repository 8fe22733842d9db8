#!/usr/bin/env bash
# The validation protocol behind the defaults of CoP-FSCIL and OrCo (docs/methods.md): one
# configuration per reading, each run with --evaluate-on validation on simtex with strong, shifted
# context and on simtex as it is, fast profile, seeds 1-3. Never scored on test. Interrupted runs
# continue with the same command (--resume); finished configurations are kept.
#   bash tools/validation_protocol.sh GROUP OUT [CONFIG ...]  run a group (cop-fscil or orco;
#                                                            all its configurations by default)
#   bash tools/validation_protocol.sh GROUP OUT --table       AA, PD and the last session so far
# SETTINGS=shifted (or nominal) runs one of the two settings only; THREADS (default 2) sets
# --threads, so two queues of configurations can share a 2-core machine at THREADS=1 (numbers
# are comparable only between runs with the same thread count).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bench=${FSCIL_BENCH:-$root/build/tools/fscil-bench}
group=${1:?usage: $0 cop-fscil|orco OUT [CONFIG ...|--table]}
out=${2:?usage: $0 cop-fscil|orco OUT [CONFIG ...|--table]}
shift 2

# name | methods | --set assignments (space separated). The first of each group is the reading
# in force before the comparison; see docs/methods.md for which one each decision kept.
# The CPI comparisons ran in this order, before PITS-SC's CutMix moved after bn0 with alpha 0.8;
# each names every value it changed against the defaults then in force, that older CutMix
# included, so they still mean the same runs now that the chosen values are the defaults.
older_pretraining="cutmix_alpha=1 cutmix_space=raw"
first_view="cpi_global_bias=0.5 cpi_channel_bias=0.3 cpi_tilt=0.5 cpi_noise=0.1"
half_view="cpi_global_bias=0.25 cpi_channel_bias=0.15 cpi_tilt=0.25 cpi_noise=0.05"
before="$older_pretraining cpi_kept=query $first_view"
# PSPC's readings before its two options became the defaults (issue 39).
pspc_before="pspc_instability=raw pspc_mean=views"
cop_fscil_configs=(
  "pits-sc-older-pretraining|pits-sc|$older_pretraining"
  "cpi-legacy|cop-fscil/cpi|$before cpi_space=raw cpi_distance=raw cpi_references=same"
  "cpi|cop-fscil/cpi|$before"
  "cpi-raw|cop-fscil/cpi|$before cpi_space=raw"
  "cpi-guarded|cop-fscil/cpi|$before cpi_bn_statistics=guarded"
  "cpi-reestimate|cop-fscil/cpi|$before cpi_bn_statistics=reestimate"
  "cpi-kept-clean|cop-fscil/cpi|$older_pretraining $first_view cpi_kept=clean"
  "cpi-kept-split|cop-fscil/cpi|$older_pretraining $first_view cpi_kept=split"
  "cpi-distance-raw|cop-fscil/cpi|$before cpi_distance=raw"
  "cpi-alpha-0.5|cop-fscil/cpi|$before cpi_mix_alpha=0.5"
  "cpi-view-half|cop-fscil/cpi|$older_pretraining cpi_kept=query $half_view"
  "cpi-kept-clean-alpha-0.5|cop-fscil/cpi|$older_pretraining $first_view cpi_kept=clean cpi_mix_alpha=0.5"
  "cpi-kept-clean-view-half|cop-fscil/cpi|$older_pretraining cpi_kept=clean $half_view"
  "cpi-kept-clean-view-quarter|cop-fscil/cpi|$older_pretraining cpi_kept=clean cpi_global_bias=0.125 cpi_channel_bias=0.075 cpi_tilt=0.125 cpi_noise=0.025"
  # The full method's readings, with today's pretraining; pits-sc and CPI alone again beside them.
  "pits-sc-today|pits-sc|"
  "cpi-defaults|cop-fscil/cpi|"
  "full|cop-fscil|$pspc_before"
  "full-dsen-m|cop-fscil|$pspc_before pcqa_sensitive_dim=8"
  "full-pic-normalised|cop-fscil|$pspc_before pic_space=normalised"
  "full-pic-invariant|cop-fscil|pic_space=invariant"
  "full-pspc-normalised|cop-fscil|pspc_instability=normalised pspc_mean=views"
  "full-pspc-original|cop-fscil|pspc_instability=raw pspc_mean=original"
  "full-pretrain-cpi|cop-fscil|$pspc_before cpi_pretrain_coverage=0.5"
)
orco_legacy="orco_base_ce_weight=0 orco_session_orthogonality=all orco_session_warmup=0 orco_session_stop=last orco_exemplars_from=first"
orco_configs=(
  "orco-legacy|orco|$orco_legacy"
  "orco|orco|"
  "orco-no-base-ce|orco|orco_base_ce_weight=0"
  "orco-stop-last|orco|orco_session_stop=last"
  "orco-exemplars-first|orco|orco_exemplars_from=first"
  "orco-orthogonality-all|orco|orco_session_orthogonality=all"
)
case $group in
  cop-fscil) configs=("${cop_fscil_configs[@]}") ;;
  orco) configs=("${orco_configs[@]}") ;;
  *) echo "$0: unknown group '$group' (expected cop-fscil or orco)" >&2; exit 2 ;;
esac
settings=(
  "shifted|context_strength=2 context_shift=device"
  "nominal|context_strength=1"
)

if [ "${1:-}" = --table ]; then
  printf '| configuration | setting | AA | PD | last session |\n|---|---|---:|---:|---:|\n'
  for dir in "$out"/*/*/; do
    [ -f "$dir/summary.csv" ] || continue
    name=$(basename "$(dirname "$dir")") setting=$(basename "$dir")
    # summary.csv: method,dataset,split,seeds,AA,PD,ADR,acc_0..acc_S, then the _std and _ci95
    # columns (absent with one seed in the folder, empty for a row of one seed)
    awk -F, -v name="$name" -v setting="$setting" '
      function spread(key) { return (key in col) && $col[key] != "" ? sprintf("%.2f", $col[key]) : "-" }
      NR == 1 { for (i = 1; i <= NF; i++) { col[$i] = i; if ($i ~ /^acc_[0-9]+$/) last = i }; next }
      { printf "| %s | %s | %.2f ± %s | %.2f ± %s | %.2f |\n", name, setting, $col["AA"], spread("AA_std"),
               $col["PD"], spread("PD_std"), $last }' "$dir/summary.csv"
  done
  exit 0
fi

wanted=("$@")
for config in "${configs[@]}"; do
  IFS='|' read -r name methods assignments <<<"$config"
  if [ ${#wanted[@]} -gt 0 ] && [[ ! " ${wanted[*]} " =~ " $name " ]]; then continue; fi
  for setting in "${settings[@]}"; do
    IFS='|' read -r setting_name setting_assignments <<<"$setting"
    if [ -n "${SETTINGS:-}" ] && [ "$SETTINGS" != "$setting_name" ]; then continue; fi
    dir=$out/$name/$setting_name
    [ -f "$dir/summary.csv" ] && continue
    sets=() resume=()
    [ -d "$dir" ] && resume=(--resume "$dir")
    for assignment in $setting_assignments $assignments; do sets+=(--set "$assignment"); done
    echo "== $name on $setting_name: $methods ${sets[*]}" >&2
    "$bench" --methods "$methods" --dataset simtex --profile fast --seeds 1-3 --evaluate-on validation --quiet \
      --threads "${THREADS:-2}" --out "$dir" ${resume[@]+"${resume[@]}"} "${sets[@]}" >/dev/null
  done
done
