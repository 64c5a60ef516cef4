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
# Prints one line per target with executions and corpus size; exits 1 when
# any target failed.
set -euo pipefail

if [[ $# -lt 2 ]]; then
  sed -n '2,21s/^# \{0,1\}//p' "${BASH_SOURCE[0]}" >&2
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

failed=()
for t in "${targets[@]}"; do
  bin="${build_dir}/fuzz/fuzz_${t}"
  seeds="${fuzz_dir}/corpus/${t}"
  [[ -x "${bin}" ]] || { echo "fuzz/run.sh: ${bin} not built" >&2; exit 2; }
  [[ -d "${seeds}" ]] || { echo "fuzz/run.sh: no seed corpus ${seeds}" >&2; exit 2; }
  work="${build_dir}/fuzz-work/${t}"
  mkdir -p "${work}/corpus"
  log="${work}/fuzz.log"
  echo "::: fuzz_${t}: ${seconds} s (log ${log})"
  rc=0
  # -timeout: one input taking > 10 s is a hang; -rss_limit_mb: > 2 GiB is
  # an OOM. Both count as failures.
  "${bin}" "${work}/corpus" "${seeds}" \
    -max_total_time="${seconds}" -timeout=10 -rss_limit_mb=2048 \
    -max_len=8192 -print_final_stats=1 \
    -artifact_prefix="${work}/" >"${log}" 2>&1 || rc=$?
  execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "${log}" | tail -1)"
  units="$(find "${work}/corpus" -type f | wc -l)"
  if [[ ${rc} -ne 0 ]] || grep -qE '^==[0-9]+==ERROR|runtime error:|^SUMMARY: ' "${log}"; then
    echo "::: fuzz_${t}: FAILED (exit ${rc}); report:"
    grep -E -A30 '^==[0-9]+==ERROR|runtime error:|deadly signal|Test unit written' "${log}" | head -60 || tail -40 "${log}"
    failed+=("${t}")
  else
    echo "::: fuzz_${t}: ok, ${execs:-?} executions, corpus ${units} inputs"
  fi
done
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "::: fuzz failures: ${failed[*]}" >&2
  exit 1
fi
echo "::: fuzz: all ${#targets[@]} targets clean"
