#!/usr/bin/env bash
# fuzz/run.sh: runs every libFuzzer target of a ROLLWEAR_FUZZ build for a
# bounded time and fails on any crash, leak, timeout, OOM or sanitizer
# report.
#
#   bash fuzz/run.sh BUILD_DIR SECONDS [TARGET...]
#
#   BUILD_DIR  a build configured with -DROLLWEAR_FUZZ=ON (clang), targets
#              built (cmake --build BUILD_DIR --target fuzz_all)
#   SECONDS    fuzzing time per target (-max_total_time)
#   TARGET     names without the fuzz_ prefix (default: all of them:
#              dataset_csv api_decode config http_parser)
#
# Each target starts from its committed seed corpus fuzz/corpus/<target>/,
# which is only read; the inputs libFuzzer finds go to
# BUILD_DIR/fuzz-work/<target>/corpus and crash/leak/timeout reproducers to
# BUILD_DIR/fuzz-work/<target>/ (never into the source tree). Reproduce one
# with: BUILD_DIR/fuzz/fuzz_<target> BUILD_DIR/fuzz-work/<target>/crash-...
# Targets run one per core at a time (ROLLWEAR_FUZZ_JOBS, default nproc).
# Prints one line per target with executions and corpus size; exits 1 when
# any target failed.
set -euo pipefail

if [[ $# -lt 2 ]]; then
  sed -n '2,22s/^# \{0,1\}//p' "${BASH_SOURCE[0]}" >&2
  exit 2
fi
build_dir="$(cd "$1" && pwd)"
seconds="$2"
shift 2
[[ "${seconds}" =~ ^[0-9]+$ && "${seconds}" -ge 1 ]] ||
  { echo "fuzz/run.sh: SECONDS must be a positive integer" >&2; exit 2; }
fuzz_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then targets=(dataset_csv api_decode config http_parser); fi

# Leaks are failures; UBSan stops at the first report (the build also uses
# -fno-sanitize-recover=undefined).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:symbolize=1${ASAN_OPTIONS:+:${ASAN_OPTIONS}}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:${UBSAN_OPTIONS}}"

# run_target T: fuzzes one target; prints its result lines; exit 1 on a
# failure. Runs in the background, one per core (below).
run_target() {
  local t="$1"
  local bin="${build_dir}/fuzz/fuzz_${t}"
  local seeds="${fuzz_dir}/corpus/${t}"
  local work="${build_dir}/fuzz-work/${t}"
  mkdir -p "${work}/corpus"
  local log="${work}/fuzz.log"
  local rc=0
  # -timeout: one input taking > 10 s is a hang; -rss_limit_mb: > 2 GiB is
  # an OOM. Both count as failures.
  "${bin}" "${work}/corpus" "${seeds}" \
    -max_total_time="${seconds}" -timeout=10 -rss_limit_mb=2048 \
    -max_len=8192 -print_final_stats=1 \
    -artifact_prefix="${work}/" >"${log}" 2>&1 || rc=$?
  local execs units
  execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "${log}" | tail -1)"
  units="$(find "${work}/corpus" -type f | wc -l)"
  if [[ ${rc} -ne 0 ]] || grep -qE '^==[0-9]+==ERROR|runtime error:|^SUMMARY: ' "${log}"; then
    echo "::: fuzz_${t}: FAILED (exit ${rc}); report:"
    grep -E -A30 '^==[0-9]+==ERROR|runtime error:|deadly signal|Test unit written' "${log}" | head -60 || tail -40 "${log}"
    return 1
  fi
  echo "::: fuzz_${t}: ok, ${execs:-?} executions, corpus ${units} inputs"
}

for t in "${targets[@]}"; do
  [[ -x "${build_dir}/fuzz/fuzz_${t}" ]] || { echo "fuzz/run.sh: ${build_dir}/fuzz/fuzz_${t} not built" >&2; exit 2; }
  [[ -d "${fuzz_dir}/corpus/${t}" ]] || { echo "fuzz/run.sh: no seed corpus ${fuzz_dir}/corpus/${t}" >&2; exit 2; }
done

# libFuzzer is single-threaded: one target per core at a time
# (ROLLWEAR_FUZZ_JOBS, default nproc), each with its whole SECONDS. Each
# target's lines are printed together when it ends.
jobs="${ROLLWEAR_FUZZ_JOBS:-$(nproc)}"
[[ "${jobs}" =~ ^[0-9]+$ && "${jobs}" -ge 1 ]] ||
  { echo "fuzz/run.sh: ROLLWEAR_FUZZ_JOBS must be a positive integer" >&2; exit 2; }
out_dir="${build_dir}/fuzz-work/results"
rm -rf "${out_dir}" && mkdir -p "${out_dir}"
echo "::: fuzz: ${#targets[@]} targets, ${seconds} s each, ${jobs} at a time"
for t in "${targets[@]}"; do
  while [[ $(jobs -rp | wc -l) -ge ${jobs} ]]; do wait -n || true; done
  ( run_target "${t}" >"${out_dir}/${t}.out" 2>&1; echo $? >"${out_dir}/${t}.rc" ) &
done
wait
failed=()
for t in "${targets[@]}"; do
  cat "${out_dir}/${t}.out"
  [[ "$(cat "${out_dir}/${t}.rc" 2>/dev/null)" == 0 ]] || failed+=("${t}")
done
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "::: fuzz failures: ${failed[*]}" >&2
  exit 1
fi
echo "::: fuzz: all ${#targets[@]} targets clean"
