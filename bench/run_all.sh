#!/usr/bin/env bash
# Every performance figure of rollwear in one table: runs core_bench,
# diagnosis_bench, ann_bench, ingest_bench, forecast_bench,
# roll_factor_bench and load_bench, and times the whole `rollwear
# calibrate` command beside the fit it runs, from a build directory (a Release build with ROLLWEAR_BUILD_BENCH=ON) and prints
# figure, measured, target, beside the machine's fsync-per-commit and
# loopback limits that load_bench measures in the same run (so each
# throughput reads as a ratio). Takes about 4-6 minutes on 2 cores; run it on a quiet machine.
#
#   bash bench/run_all.sh [BUILD_DIR] [--out FILE]
#
# BUILD_DIR defaults to ./build. The raw outputs of the seven binaries go to
# BUILD_DIR/bench-run/ (never commit them); --out also writes the table as
# Markdown to FILE.
set -euo pipefail

build=build
out=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) build="$1"; shift ;;
  esac
done
bin="$build/bench"
for b in core_bench diagnosis_bench ann_bench ingest_bench forecast_bench roll_factor_bench load_bench; do
  if [[ ! -x "$bin/$b" ]]; then
    echo "run_all.sh: $bin/$b not found: build with -DCMAKE_BUILD_TYPE=Release -DROLLWEAR_BUILD_BENCH=ON" >&2
    exit 2
  fi
done
work="$build/bench-run"
rm -rf "$work"
mkdir -p "$work"
rows="$work/rows.tsv"   # figure <TAB> measured <TAB> target
: > "$rows"
start=$(date +%s)

# Google Benchmark console lines: "<name> <time> <unit> <cpu> <unit> <iter>".
# Prints "<time> <unit>" of the benchmark named exactly $2 in file $1.
bm() {
  awk -v n="$2" '$1 == n { print $2 " " $3; exit }' "$1"
}
row() { printf '%s\t%s\t%s\n' "$1" "$2" "$3" >> "$rows"; }

echo "== core_bench" >&2
"$bin/core_bench" --benchmark_color=false \
  --benchmark_filter='BM_LoadAndAggregate|BM_FitWang/(1|10)/(1|2)/0|BM_FitWang/1/1/1' \
  > "$work/core_bench.txt" 2> "$work/core_bench.err"
row "load + aggregate, paper size" "$(bm "$work/core_bench.txt" BM_LoadAndAggregate/1)" ""
row "load + aggregate, 10x strips" "$(bm "$work/core_bench.txt" BM_LoadAndAggregate/10)" ""
row "Wang option 1 fit, paper size" "$(bm "$work/core_bench.txt" BM_FitWang/1/1/0)" ""
row "Wang option 2 fit, paper size" "$(bm "$work/core_bench.txt" BM_FitWang/1/2/0)" "< 20 ms"
row "Wang option 2 fit, 10x strips" "$(bm "$work/core_bench.txt" BM_FitWang/10/2/0)" "= paper size (sufficient statistics)"

# The whole `rollwear calibrate` process on the paper-size dataset (seed 2,
# as core_bench's), median of 11 runs, beside the fit it runs (Wang option 1
# with standard errors): reading and checking the files is the cost.
echo "== rollwear calibrate, whole command" >&2
rollwear="$build/service/rollwear"
"$rollwear" simulate --out "$work/paper" --seed 2 > /dev/null
"$rollwear" calibrate --data "$work/paper" > /dev/null  # warm the page cache
for _ in $(seq 11); do
  t0=$(date +%s%N)
  "$rollwear" calibrate --data "$work/paper" > /dev/null
  echo $(( ($(date +%s%N) - t0) / 1000 ))
done | sort -n | sed -n 6p > "$work/calibrate_us.txt"
whole_ms=$(awk '{ printf "%.1f", $1 / 1000 }' "$work/calibrate_us.txt")
fit_ms=$(awk '$1 == "BM_FitWang/1/1/1" { print $2; exit }' "$work/core_bench.txt")
row "calibrate, whole command, paper size" "$whole_ms ms" ""
row "Wang option 1 fit with std. errors, paper size" "$fit_ms ms" ""
row "calibrate whole / fit" "$(awk -v w="$whole_ms" -v f="$fit_ms" 'BEGIN { printf "%.1f x", w / f }')" "<= 10 x"

echo "== diagnosis_bench" >&2
"$bin/diagnosis_bench" --benchmark_color=false \
  > "$work/diagnosis_bench.txt" 2> "$work/diagnosis_bench.err"
row "diagnosis, paper size, no effect" "$(bm "$work/diagnosis_bench.txt" BM_Diagnose/0/iterations:1)" "< 10 s"
row "diagnosis, paper size, campaign_growth" "$(bm "$work/diagnosis_bench.txt" BM_Diagnose/1/iterations:1)" "< 10 s"
case=2
for effect in temperature calendar_drift stoppages supplier_change inexpressible_interaction; do
  row "diagnosis, paper size, $effect" "$(bm "$work/diagnosis_bench.txt" BM_Diagnose/$case/iterations:1)" "< 10 s"
  case=$((case + 1))
done

echo "== ann_bench" >&2
"$bin/ann_bench" --benchmark_color=false \
  --benchmark_filter='BM_AnnTable4PaperSize/1/|BM_AnnEpochGradient|BM_AnnAddPass' \
  > "$work/ann_bench.txt" 2> "$work/ann_bench.err"
row "ANN Table 4 (classical + 5-member ensemble), campaign_growth" \
  "$(bm "$work/ann_bench.txt" BM_AnnTable4PaperSize/1/iterations:1/real_time)" "< 60 s"
row "ANN one training epoch, one member" "$(bm "$work/ann_bench.txt" BM_AnnEpochGradient)" ""
row "ANN coil-by-coil prediction, one pass" "$(bm "$work/ann_bench.txt" BM_AnnAddPass)" "microseconds"

echo "== ingest_bench" >&2
"$bin/ingest_bench" --benchmark_color=false --benchmark_min_time=2 \
  --benchmark_filter='BM_DecodeCoil|BM_EncodeCoilAnswer|BM_StoreAddCoil/real_time/threads:16' \
  > "$work/ingest_bench.txt" 2> "$work/ingest_bench.err"
# items_per_second of the benchmark named exactly $2 in file $1, as "N coils/s".
ips() {
  awk -v n="$2" '$1 == n { for (i = 1; i <= NF; ++i) if ($i ~ /^items_per_second=/) {
    v = $i; sub(/^items_per_second=/, "", v); sub(/\/s$/, "", v)
    m = 1; if (v ~ /k$/) m = 1e3; if (v ~ /M$/) m = 1e6; sub(/[kM]$/, "", v)
    printf "%.0f coils/s\n", v * m; exit } }' "$1"
}
row "coil request decode (482 B, 2 passes)" "$(bm "$work/ingest_bench.txt" BM_DecodeCoil)" ""
row "coil answer encode (527 B)" "$(bm "$work/ingest_bench.txt" BM_EncodeCoilAnswer)" ""
row "MillStore::AddCoil, 16 threads, no HTTP (durable)" "$(ips "$work/ingest_bench.txt" BM_StoreAddCoil/real_time/threads:16)" ""

echo "== forecast_bench" >&2
"$bin/forecast_bench" --benchmark_color=false \
  > "$work/forecast_bench.txt" 2> "$work/forecast_bench.err"
row "POST /v1/forecast, 200 coils, 4 rolls, no HTTP" "$(bm "$work/forecast_bench.txt" BM_ForecastRequest/200)" "milliseconds"
row "engine::MountedRolls::ForecastCoils, 200 coils, 4 rolls" "$(bm "$work/forecast_bench.txt" BM_ForecastStore/200)" ""
row "GET /v1/wear/{stand}/{position}/profile, 201 slices, no HTTP (see p99_us)" "$(bm "$work/forecast_bench.txt" BM_WearProfileGet)" "p99 < 1 ms"
row "one pass added to a roll tracking its profile" "$(bm "$work/forecast_bench.txt" BM_ProfilePassUpdate)" "microseconds"

echo "== roll_factor_bench" >&2
"$bin/roll_factor_bench" --campaigns 395 \
  > "$work/roll_factor_bench.txt" 2> "$work/roll_factor_bench.err"
# column c of the row whose store column matches s (| campaigns | passes |
# store | reopen ms | measurement ms | promotion ms |)
rf() { awk -F'|' -v s="$1" -v c="$2" '$4 ~ s { gsub(/ /, "", $c); print $c }' "$work/roll_factor_bench.txt"; }
row "store reopen, 395 campaigns: prior / roll_effect term (factors re-estimated)" "$(rf plain 5) / $(rf roll_effect 5) ms" ""
row "AddMeasurement, 395 campaigns: prior / roll_effect term" "$(rf plain 6) / $(rf roll_effect 6) ms" ""
row "promotion of a roll_effect model, 395 campaigns" "$(rf roll_effect 7) ms" ""

echo "== load_bench" >&2
"$bin/load_bench" --tsv "$work/load.tsv" \
  > "$work/load_bench.txt" 2>&1 || { cat "$work/load_bench.txt" >&2; exit 1; }
grep -v '^#' "$work/load.tsv" >> "$rows"
fsync=$(awk -F'\t' '$1 == "#fsync_limit" { print $2 }' "$work/load.tsv")
loopback=$(awk -F'\t' '$1 == "#loopback_limit" { print $2 }' "$work/load.tsv")

elapsed=$(( $(date +%s) - start ))
commit=$(git -C "$(dirname "$0")/.." rev-parse --short HEAD 2>/dev/null || echo unknown)
{
  echo "rollwear performance figures - $(date -u +%Y-%m-%dT%H:%M:%SZ), commit $commit (plus working tree), $(nproc) cores, $build"
  echo "machine limits measured in this run: fsync-per-commit ${fsync} commits/s (WAL, synchronous=FULL), loopback ${loopback} req/s (GET /healthz, 16 clients)"
  echo
  awk -F'\t' -v fsync="$fsync" -v loop="$loopback" '
    function ratio(m, lim,   v) {
      # a rate ("N coils/s", "N req/s", "(N coils/s)") as a multiple of lim
      if (m !~ /achieved/ && match(m, /[0-9.]+ (coils|req|commits)\/s/)) {
        v = substr(m, RSTART, RLENGTH); sub(/ .*/, "", v)
        if (lim > 0) return sprintf("%.2f", v / lim)
      }
      return ""
    }
    BEGIN {
      printf "| %-62s | %-34s | %-22s | %-7s | %-9s |\n", "figure", "measured", "target", "/fsync", "/loopback"
      printf "|%s|%s|%s|%s|%s|\n", "----------------------------------------------------------------",
        "------------------------------------", "------------------------", "---------", "-----------"
    }
    { printf "| %-62s | %-34s | %-22s | %-7s | %-9s |\n", $1, $2, $3, ratio($2, fsync), ratio($2, loop) }
  ' "$rows"
  echo
  echo "(/fsync, /loopback: a rate over the machine's fsync-per-commit and loopback limits above; whole run ${elapsed} s)"
} | tee "$work/table.md"
if [[ -n "$out" ]]; then cp "$work/table.md" "$out"; fi
