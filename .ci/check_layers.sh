#!/usr/bin/env bash
# .ci/check_layers.sh [REPO_ROOT]: fails (exit 1) when an #include crosses a
# layer or a core folder the wrong way, when a layer includes a library it
# must not (core: no SQLite, HTTP or JSON; storage: no HTTP), or when
# project files include each other in a loop. Prints one line per offence:
# FILE:LINE: what is wrong. Runs in CI (phase "layers") and in every CMake
# build (target rollwear_layer_check), so a wrong-way include fails to build.
#
# The layers, each may include only itself and those to its right:
#   service -> api -> engine -> storage -> core
# storage holds the records, not the engine: of core it may include only
# base, dataset and model (no fitting, diagnosis, network or simulator),
# and of the model its types, not the functions that predict (the
# engine's predictor runs them for the store: storage/wear_predictor.h).
# Inside core (docs/architecture.md), each folder may include only the
# folders named after it:
set -euo pipefail
root="${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}"
cd "${root}"

declare -A allowed=(
  [core/base]="core/base"
  [core/dataset]="core/base core/dataset"
  [core/model]="core/base core/dataset core/model"
  [core/sim]="core/base core/dataset core/model core/sim"
  [core/fit]="core/base core/dataset core/model core/fit"
  [core/diagnosis]="core/base core/dataset core/model core/fit core/diagnosis"
  [core/ann]="core/base core/dataset core/model core/fit core/diagnosis core/ann"
  [core/report]="core/base core/dataset core/model core/fit core/diagnosis core/ann core/report"
  [storage]="core/base core/dataset core/model storage"
  [engine]="core storage engine"
  [api]="core storage engine api"
  [service]="core storage engine api service"
)
# Third-party headers a layer must not include (extended regex on the
# include's path).
declare -A forbidden=(
  [core]='^(sqlite3\.h|httplib\.h|nlohmann/|simdjson|spdlog/)'
  [storage]='^(httplib\.h|simdjson|CLI/)'
  [engine]='^(sqlite3\.h|httplib\.h|simdjson|CLI/)'
  [api]='^(sqlite3\.h|CLI/)'
)

# Project headers a layer must not include though their folder is allowed
# (extended regex on the header's path from the root): storage keeps the
# predicted states, the engine computes them.
declare -A forbidden_project=(
  [storage]='^core/model/(predictor|model_eval|roll_factor_update|remaining_life|profile_interval)\.h$'
)

# Layers whose units (a .cc with its .h) must not include each other in a
# loop: all of them.
loop_checked="core service storage engine api"

bad=0
edges="$(mktemp)"
trap 'rm -f "${edges}"' EXIT

# owner FILE: the key of `allowed` the file belongs to ("" if none; a core
# source outside the known folders gives "core/" or its unknown folder).
owner() {
  local f="$1"
  case "${f}" in
    core/*/*) echo "$(echo "${f}" | cut -d/ -f1-2)" ;;
    core/*) echo "core/" ;;  # a source directly in core/ has no folder
    storage/* | engine/* | api/* | service/*) echo "${f%%/*}" ;;
    *) echo "" ;;
  esac
}

while IFS= read -r file; do
  own="$(owner "${file}")"
  [[ -n "${own}" ]] || continue
  if [[ "${own}" == "core/" || -z "${allowed[${own}]:-}" ]]; then
    echo "${file}:1: ${own} is not a core folder this check knows: add it to" \
      "'allowed' here, to core/CMakeLists.txt and to docs/architecture.md"
    bad=1
    continue
  fi
  layer="${own%%/*}"
  while IFS=: read -r line inc; do
    # Project headers are spelled from the repository root, in quotes or
    # angle brackets alike (the root is on every target's include path).
    if [[ "${inc}" =~ ^[\"\<]((core|storage|engine|api|service)/[^\"\>]+)[\"\>] ]]; then
      target="${BASH_REMATCH[1]}"
      # A source and its header are one unit for loops (x.cc -> y.h -> x.h);
      # a folder's *_internal.h is part of the units that include it.
      [[ "${file%.*}" == "${target%.*}" || "${file}" == *_internal.h ||
         " ${loop_checked} " != *" ${layer} "* ]] ||
        printf '%s %s\n' "${file%.*}" "${target%.*}" >>"${edges}"
      tdir="${target%/*}"
      [[ "${tdir}" == core/*/* ]] && tdir="$(echo "${tdir}" | cut -d/ -f1-2)"
      [[ "${tdir}" == core/* ]] || tdir="${tdir%%/*}"
      ok=0
      for a in ${allowed[${own}]}; do
        if [[ "${tdir}" == "${a}" || "${tdir}" == "${a}"/* ]]; then ok=1; fi
      done
      if [[ ${ok} -eq 0 ]]; then
        echo "${file}:${line}: includes ${target}: ${own} may include only ${allowed[${own}]}"
        bad=1
      fi
      ppat="${forbidden_project[${layer}]:-}"
      if [[ -n "${ppat}" && "${target}" =~ ${ppat} ]]; then
        echo "${file}:${line}: includes ${target}: ${layer} keeps the predictions, the engine computes them (storage/wear_predictor.h)"
        bad=1
      fi
    elif [[ "${inc}" =~ ^\"((tests|bench|fuzz|deploy)/[^\"]*|[^\"]*\.\./[^\"]*)\" ]]; then
      echo "${file}:${line}: includes \"${BASH_REMATCH[1]}\": spell project headers from the root (core/..., storage/..., engine/..., api/..., service/...); tests, bench and fuzz are not libraries"
      bad=1
    elif [[ "${inc}" =~ ^[\"\<]([^\"\>]+)[\"\>] ]]; then
      sys="${BASH_REMATCH[1]}"
      pat="${forbidden[${layer}]:-}"
      if [[ -n "${pat}" && "${sys}" =~ ${pat} ]]; then
        echo "${file}:${line}: includes ${sys}: ${layer} must not use it"
        bad=1
      fi
    fi
  done < <(grep -n -E '^[[:space:]]*#[[:space:]]*include' "${file}" |
           sed -E 's/^([0-9]+):[[:space:]]*#[[:space:]]*include[[:space:]]*/\1:/')
done < <(git ls-files -co --exclude-standard -- core storage engine api service 2>/dev/null |
         grep -E '\.(h|cc)$' || find core storage engine api service -name '*.h' -o -name '*.cc')

# Loops between units: tsort names the units of each cycle it finds.
if ! tsort "${edges}" >/dev/null 2>"${edges}.err"; then
  grep -v 'input contains a loop' "${edges}.err" | sed 's/^tsort: /include loop through: /' 
  bad=1
fi
rm -f "${edges}.err"

if [[ ${bad} -ne 0 ]]; then
  echo "check_layers: wrong-way includes (see docs/architecture.md for the order)" >&2
  exit 1
fi
echo "check_layers: ok"
