#!/usr/bin/env bash
# Compiles every .tex the LaTeX fixture writes (every kind the program writes) with pdflatex, each
# in a document that loads exactly the packages its first line names ("requires
# \usepackage{...}", or "loads \usepackage{...}" for a figure): a table that needs a package its
# header does not name, or that LaTeX cannot typeset, fails here. pdflatex missing is a failure,
# never a skip (tools/bootstrap.sh --tests installs Debian's texlive-latex-base,
# texlive-latex-recommended and texlive-pictures).
# Usage: latex_compile_test.sh FIXTURE WORK_DIR
set -euo pipefail
fixture=$1 work=$2
command -v pdflatex > /dev/null || { echo "pdflatex is not installed (bash tools/bootstrap.sh --tests)"; exit 1; }
rm -rf "$work"
"$fixture" "$work"

compiled=0
while IFS= read -r -d '' tex; do
  packages=$(head -n 5 "$tex" | grep -o 'usepackage{[^}]*}' | sed 's/usepackage{\(.*\)}/\1/' | paste -sd, -)
  [ -n "$packages" ] || { echo "FAIL $tex names no package it needs in its first lines"; exit 1; }
  document="$work/compile-$(basename "$tex" .tex)"
  mkdir -p "$document"
  {
    echo '\documentclass[twocolumn]{article}'  # a paper's layout: table for a column, table* for the page
    echo "\\usepackage{$packages}"
    if [[ $packages == *pgfplots* ]]; then echo '\pgfplotsset{compat=1.16}'; fi
    echo '\begin{document}'
    echo "\\input{$tex}"
    echo '\end{document}'
  } > "$document/main.tex"
  if ! (cd "$document" && pdflatex -interaction=nonstopmode -halt-on-error main.tex > log.txt 2>&1); then
    echo "FAIL $tex does not compile with \\usepackage{$packages}:"
    grep -A3 '^!' "$document/log.txt" | head -n 12
    exit 1
  fi
  echo "OK $(basename "$tex") with \\usepackage{$packages}"
  compiled=$((compiled + 1))
done < <(find "$work" -name '*.tex' ! -path '*/compile-*' -print0 | sort -z)
[ "$compiled" -ge 10 ] || { echo "FAIL only $compiled .tex files written; expected every kind"; exit 1; }
echo "all $compiled .tex files compile"
