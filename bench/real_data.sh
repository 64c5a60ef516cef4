#!/usr/bin/env bash
# The real-data figures (docs/real-data.md): converts a local copy of the
# study's public snapshot (GitHub Muppetwashere/deep_learning, no license:
# nothing it holds, nor anything derived from it, is ever committed), then
# runs the study, calibrations, the diagnosis and the network on the
# authors' split and on the time-forward split (campaigns 1-263 train,
# 264-395 validation), and prints one table: seconds and validation gap
# (mean |measured - predicted| centre wear, µm) of each, beside the study's
# published figures and the authors' own network scored on the same
# readings from its predictions file.
#
#   bash bench/real_data.sh SNAPSHOT_DIR [--build DIR] [--work DIR] [--utc-offset +HH:MM]
#   bash bench/real_data.sh --converted DATASET_DIR [--build DIR] [--work DIR]
#
# SNAPSHOT_DIR holds Data/RawData (see docs/real-data.md for getting it);
# --build defaults to ./build, --work (where the converted dataset and
# every output go; outside the repository) to /tmp/rollwear-real-data.
# The snapshot does not record the mill's time zone: --utc-offset
# (default +00:00) is only used to write the timestamps and changes no
# figure below. --converted skips the conversion (a folder the converter
# wrote earlier). Takes about 4 minutes on 2 cores (the conversion 2.5).
set -euo pipefail

snapshot=""
converted=""
build=build
work=/tmp/rollwear-real-data
offset=+00:00
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --utc-offset) offset="$2"; shift 2 ;;
    --converted) converted="$2"; shift 2 ;;
    -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
    *) snapshot="$1"; shift ;;
  esac
done
[[ -n "${snapshot}${converted}" ]] || { sed -n '2,22p' "$0"; exit 2; }
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
R="${build}/service/rollwear"
[[ -x "${R}" ]] || { echo "real_data.sh: ${R} not found (bash deploy/install.sh)" >&2; exit 2; }
rm -rf "${work}"
mkdir -p "${work}"
ds="${work}/ds"

# now_s: seconds since the epoch with ms; took START: seconds since START.
now_s() { date +%s.%N; }
took() { python3 -c "import sys; print('%.1f' % (float(sys.argv[2]) - float(sys.argv[1])))" "$1" "$(now_s)"; }

if [[ -n "${converted}" ]]; then
  cp -r "${converted}" "${ds}"
else
  t=$(now_s)
  /usr/bin/python3 "${repo}/service/tools/convert_study_snapshot.py" --snapshot "${snapshot}" \
    --out "${ds}" --utc-offset "${offset}" > "${work}/convert.log"
  echo "import (conversion): $(took "$t") s"
fi

# row NAME SPLIT ARGS...: one calibrate run, its validation gap from its
# predictions file.
declare -a rows=()
row() {
  local name="$1" split="$2"; shift 2
  local t0; t0=$(now_s)
  "${R}" calibrate --data "${ds}" --split "${ds}/${split}.csv" \
    --predictions "${work}/${split}.${name}.csv" "$@" > "${work}/${split}.${name}.log" 2>&1 || true
  local s; s=$(took "$t0")
  local ident; ident=$(grep -m1 '^identification:' "${work}/${split}.${name}.log" | cut -c17-60 || true)
  rows+=("${split}|${name}|${s}|${work}/${split}.${name}.csv|${ident}")
}
for split in split_authors split_time_forward; do
  row wang_opt1 "${split}" --option 1
  row wang_opt1_free_grades "${split}" --option 1 --free-grades
  row wang_opt2 "${split}" --option 2
  row wang_opt3 "${split}" --option 3
  row cao_opt1 "${split}" --model cao --option 1
  row wang_opt3_per_roll "${split}" --option 3 --per-roll
  row wang_opt1_per_roll "${split}" --option 1 --per-roll
  t=$(now_s)
  "${R}" diagnose --data "${ds}" --split "${ds}/${split}.csv" --json "${work}/${split}.diagnosis.json" \
    > "${work}/${split}.diagnosis.log" 2>&1 || true
  echo "${split}: diagnosis $(took "$t") s: $(grep -m1 '^verdict' "${work}/${split}.diagnosis.log")"
  grep '^finding' "${work}/${split}.diagnosis.log" | sed "s/^/${split}:   /" || true
  # The issue's chain: the diagnosis's adopted terms refitted by calibrate.
  row wang_opt1_diagnosis_terms "${split}" --terms "${work}/${split}.diagnosis.json"
  ident=$(grep -m1 "^option 1's K on this data" "${work}/${split}.wang_opt1_diagnosis_terms.log" | cut -c47-100 || true)
  rows[-1]="${rows[-1]%|*}|K beneath the terms: ${ident}"
  t=$(now_s)
  "${R}" study --data "${ds}" --split "${ds}/${split}.csv" --out "${work}/${split}.study" \
    > "${work}/${split}.study.log" 2>&1 || true
  echo "${split}: study (Tables 1-3) $(took "$t") s"
  t=$(now_s)
  "${R}" ann --data "${ds}" --split "${ds}/${split}.csv" --json "${work}/${split}.ann.json" \
    --predictions "${work}/${split}.ann.csv" > "${work}/${split}.ann.log" 2>&1 || true
  echo "${split}: ann $(took "$t") s: $(grep -m1 'ANN, ' "${work}/${split}.ann.log" | cut -d'|' -f2,4,5)"
  rows+=("${split}|rollwear_ann|$(took "$t")|${work}/${split}.ann.csv|network (no identification verdict)")
done

# The table: each predictions file's validation gap, and the authors'
# network on exactly the same validation readings where it has them.
python3 - "${ds}/authors_ann_predictions.csv" "${rows[@]}" <<'EOF'
import csv, sys
authors = {}
for r in csv.DictReader(open(sys.argv[1])):
    if r['set'] == 'validation':
        authors[(r['campaign_id'], r['stand'], r['position'])] = float(r['predicted_um'])
print()
print('| split | model | s | validation gap µm (n) | authors\' network on the same readings µm (n) | identification |')
print('|---|---|---|---|---|---|')
for spec in sys.argv[2:]:
    split, name, secs, path, ident = spec.split('|')
    try:
        rows = [r for r in csv.DictReader(open(path)) if r['set'] == 'validation']
    except OSError:
        print(f'| {split} | {name} | {secs} | failed | | |'); continue
    gap = sum(abs(float(r['measured_um']) - float(r['predicted_um'])) for r in rows) / max(1, len(rows))
    same = [r for r in rows if (r['campaign_id'], r['stand'], r['position']) in authors]
    theirs = sum(abs(float(r['measured_um']) - authors[(r['campaign_id'], r['stand'], r['position'])])
                 for r in same) / max(1, len(same))
    print(f'| {split} | {name} | {secs} | {gap:.1f} ({len(rows)}) | {theirs:.1f} ({len(same)}) | {ident} |')
print()
print('The study (Table 1-2, its own split): Wang option 1 45.8 µm, Nikitenko 47.2, Cao 50.9; option 2 45.2, option 3 49.4; its network 42.3 (34.7 training).')
EOF
