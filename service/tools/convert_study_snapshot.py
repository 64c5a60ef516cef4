#!/usr/bin/python3
"""Converts the public snapshot of the F6/F7 wear study into a rollwear dataset.

Usage:
  /usr/bin/python3 service/tools/convert_study_snapshot.py \
      --snapshot DIR --out DIR --utc-offset +HH:MM [--strict]

--snapshot  the folder holding Data/RawData (Data itself or RawData's parent
            are accepted too).
--out       output folder; must be missing or empty.
--utc-offset the mill's UTC offset. REQUIRED: the workbooks hold the mill's
            local clock without a zone and the snapshot does not record it.
--strict    every row-level drop or substitution (a cell that cannot be used
            as read, a pass rolled on a roll other than the campaign's, an
            empty grade) stops the conversion with an error naming the file,
            sheet, row and column, instead of a report line. Structural
            handling (lock files, duplicate workbooks, missing workbooks or
            sheets) is the same in both modes and always reported.

Writes campaigns.csv, mounts.csv, coils.csv, measurements.csv, profiles.csv
(docs/data-format.md), split_authors.csv, split_time_forward.csv,
authors_ann_predictions.csv and conversion_report.md. Needs only the standard
library and Debian's python3-openpyxl.

The snapshot has no licence: nothing of it is copied into this repository.
The evidence below is recomputed from the data on every run and printed in
conversion_report.md; the figures quoted here are those of the full snapshot
(395 campaigns, 2017-03-08 .. 2017-05-28).

UNIT AND MAPPING DECISIONS (sheet "Camp Data", one row per coil)
-----------------------------------------------------------------
Thickness. ga1..ga8 are the strip thickness (mm) ahead of stand k: ga1 equals
  Transfer_bar_thkness (the bar entering F1), ga6 equals
  InterstandThickness_massFlow_5 (F5 -> F6), ga7 equals
  InterstandThickness_massFlow_6 (F6 -> F7) and ga8 equals ExtGA_thkness (the
  exit gauge after F7), all to <= 0.05 mm; ga8 is within 0.04 mm of
  AimHotVernThk on 90 % of the coils and ord_ga (hundredths of mm) / 100 is
  ga8 within ~1 %; ga6 > ga7 > ga8 on every coil with a reading. So
  F6: entry = ga6, exit = ga7; F7: entry = ga7, exit = ga8.
Force. FbkStandForce6/7 are tonnes-force: kN = t x 9.80665. Read as t the
  specific force is ~9.9 (F6) and ~9.0 kN/mm (F7) at the median, the usual
  range of the last finishing stands, and the mean pressure over the
  undeformed contact arc F / (w sqrt(R dh)) is ~470 / ~600 MPa, a plausible
  hot-rolling roll pressure (flow stress 150-300 MPa x Sims factor x roll
  flattening). Read as kN it would be ~1 kN/mm and ~50-60 MPa, below the
  flow stress of any steel at 900 C.
Length. stripLength is the length leaving F7 (m): CoilWt (kg) /
  (7850 kg/m3 x ord_Wdt x ga8) / stripLength is 0.996 at the median (with
  ga7 instead of ga8 it is 0.85). The length leaving F6 follows by
  mass flow: L6 = stripLength x ga8 / ga7.
Speed. LEADSPD_Fk / TRAILSPD_Fk (head / tail speed) are m/min:
  stripLength / LOADDUR_Sec x 60 divided by the mean of LEADSPD_F7 and
  TRAILSPD_F7 is 0.985 at the median (the same check at F6 with the
  mass-flow length gives 0.999). speed_mps = (LEAD + TRAIL) / 2 / 60; the
  two speeds are also kept, in m/s. F6 and F7 speeds satisfy mass flow
  (v6 h7 / v7 h8 = 0.987 at the median).
Temperature. There are 8 FBKTemp values for 7 stands and they fall strictly
  from F1 to F8 on every coil; FBKTemp_F8 is the closest to MeasuredFMXT
  (the finishing-mill exit pyrometer, median difference ~10 C, F7 ~25 C)
  and FBKTemp_F1 is within ~8 C of meas_FMETemp (entry pyrometer). So
  FBKTemp_Fk is the strip temperature at the entry of stand k:
  temperature_c = FBKTemp_F6 / FBKTemp_F7, and FBKTemp_F7 / FBKTemp_F8 are
  kept as exit_temperature_c. A reading of 0 is no reading.
Width ord_Wdt (mm). Grade: Grade (trimmed); an empty grade is written
  "unknown" and reported. Shift: WROLL_SHIFT_POS6 / 7 (mm, as recorded: the
  snapshot does not say which roll or sign it refers to).
Lubrication. F6: 1 when F6OilFlowRate_Ml_min > 0 (it agrees with
  Oil_ON___F6 > 0 on 99.8 % of coils; Oil_ON___F6 is used only when the
  flow cell is empty). F7 has no oil sensor: the cell is left EMPTY.
Time. Date_St1PU_... is the coil's time at the first stand, local clock;
  written with the --utc-offset. seq orders the coils of a workbook by that
  time (then by row). started_at = the first coil's time; ended_at = the
  last coil's time + its LOADDUR_Sec.
coil_id = Serial; a Serial seen before in the dataset gets "~c<campaign>"
  appended (reported).
Extra columns (recorded process quantities, units in the names where known):
  coil_weight_kg, strip_length_f7_exit_m, load_time_s, idle_time_s,
  strip_hardness_index (NormHard), water_temperature_c, order_thickness_mm,
  fm_entry_temperature_c, fm_exit_temperature_c, exit_temperature_c,
  lead_speed_mps, trail_speed_mps, roll_bending_force (RollBendingForceK,
  unit not recorded), and on F6 rows only oil_flow_ml_min, oil_on_f6 (unit
  not recorded) and backup_roll_water_flow_l_min.
  The mill Level 2's own model outputs (CALC_*, LEARN_*, WRCrown*,
  WRThermal*, WRMechanicalCrown*, BURThermalWear*, CM_i__*, STAMP_RATIO*,
  WEARKm*, *_COEFF*, TOP_WROLL_CRWN*, RollShiftPosition*, RollBending1..7,
  aimCr, LdCr, CYLSCALEPRED*, AimHotVernThk) are never offered as columns.

Mounts. roll_id = TOPIDF6 / BOTIDF6 / TOPIDF7 / BOTIDF7. When an id changes
  within a campaign (a mid-campaign roll change at F7 in the snapshot), the
  mount is the roll in the stand at the campaign's end (the roll the
  measurement after the campaign is about) and the passes rolled on another
  roll at that stand are dropped (reported). diameter_mm = F6TWRDia /
  F6BWRDia / F7TWRDia / F7BWRDia of the first coil on the mounted roll.
  roll_type and hardness_hb are EMPTY (the snapshot has no roll table).

MEASUREMENTS: RawData/WearCentres.xlsx (mm), wear_center_um = value x 1000.
  The f6/f7 sheets hold "Real Profile" roll DIAMETERS (~748 mm at F6, ~778 mm
  at F7 when fresh; F6TWRDia agrees) before (FIRST FRESH GROUND) and after
  (WORN) the campaign. WearCentres equals the mean of (fresh - worn) over the
  barrel centre (|x| <= 375 mm) within 20 um on 70 % of the rolls (ratio 1.000
  at the median; half of it, i.e. a radius loss, disagrees by ~120 um) and
  equals to 1e-6 mm the mean of the sheet's "Top/Bottom Wear, mm" column
  over its 31 central rows. So WearCentres is a DIAMETER loss, twice the
  radius loss that docs/data-format.md names. The study's published figures
  were computed on WearCentres x 1000 as is, so the converter keeps it as is:
  wear_center_um here is the diameter loss at the barrel centre in um.
  measured_at is EMPTY: the grinder's time is not recorded.

PROFILES: sheets f6 / f7, top block from column A (fresh X, profile in B, C;
  worn X, profile in F, G; the sheet's "Top Wear, mm" in M), bottom block
  from column U (V, W; Z, AA; "Bottom Wear, mm" in AG). wear_um = the sheet's
  "Wear, mm" column x 1000 at the worn point's X: the column is (fresh -
  worn), row by row, i.e. a diameter loss like wear_center_um, and it is the
  column WearCentres was computed from, so the profile near x = 0 matches
  the centre reading (mean over |x| <= 375 mm within 20 um on 1315 of 1394
  rolls, against 977 for the plain fresh - worn). On 819 rolls the column
  equals fresh - worn; on 422 it adds a constant and on 213 a linear
  (level + tilt) correction, the sheet's alignment of the two gauge
  readings (without it a few profiles show negative wear at the centre);
  on 3 it holds diameters. The plain difference, each worn point paired
  with the fresh point of nearest X within 12.5 mm (half the 25 mm step),
  is kept as the extra column fresh_minus_worn_um. A roll whose sheet has no
  wear column falls back to that difference (reported). Bad files are not
  fixed: what the rule gives is written and listed in the report.
  x_mm = X - 910: X is measured from one barrel end; 910 mm is the middle of
  the gauge's standard 65-point traverse 110..1710 mm, and the left-right
  symmetry of the wear profiles, pooled per gauge grid, puts the centre at
  900-905 mm on every grid (110..1710, 120..1720, 107.5..1732.5), within
  10 mm of 910, less than half a step. Which end is the drive side is not
  recorded: the sign of x_mm is the sheet's direction. measured_at EMPTY.
"""

import argparse
import bisect
import csv
import datetime as dt
import math
import multiprocessing
import os
import re
import shutil
import statistics
import sys
import time

try:
    import openpyxl
except ImportError:  # a clear message instead of a traceback
    sys.stderr.write("convert_study_snapshot: python3-openpyxl is required "
                     "(apt-get install python3-openpyxl)\n")
    raise SystemExit(2)

TONNE_FORCE_KN = 9.80665
STEEL_DENSITY_KG_M3 = 7850.0
BARREL_CENTRE_X_MM = 910.0
PAIR_TOLERANCE_MM = 12.5
CENTRE_HALF_WIDTH_MM = 375.0
TIME_FORWARD_LAST_TRAIN = 263
CAMP_SHEET = "Camp Data"

STANDS = (6, 7)
POSITIONS = ("top", "bottom")
ROLL_ID_COL = {(6, "top"): "TOPIDF6", (6, "bottom"): "BOTIDF6",
               (7, "top"): "TOPIDF7", (7, "bottom"): "BOTIDF7"}
DIAMETER_COL = {(6, "top"): "F6TWRDia", (6, "bottom"): "F6BWRDia",
                (7, "top"): "F7TWRDia", (7, "bottom"): "F7BWRDia"}
THICKNESS_COL = {6: ("ga6", "ga7"), 7: ("ga7", "ga8")}
TIME_COL = "Date_St1PU_CampaignStartTimeWasReferencedByUsingThisColumn_"

# Columns read from "Camp Data". Required ones make a pass unusable when
# missing; the rest are optional extras or evidence.
REQUIRED_COLS = [
    "Serial", TIME_COL, "stripLength", "ord_Wdt", "ga6", "ga7", "ga8",
    "FbkStandForce6", "FbkStandForce7", "LEADSPD_F6", "TRAILSPD_F6",
    "LEADSPD_F7", "TRAILSPD_F7", "FBKTemp_F6", "FBKTemp_F7",
    "WROLL_SHIFT_POS6", "WROLL_SHIFT_POS7", "TOPIDF6", "BOTIDF6", "TOPIDF7",
    "BOTIDF7", "F6TWRDia", "F6BWRDia", "F7TWRDia", "F7BWRDia",
]
OPTIONAL_COLS = [
    "CampaingNo_Stand6", "Grade", "NOLOADDUR_Sec", "LOADDUR_Sec", "NormHard",
    "CoilWt", "WaterTemp_OC", "ord_ga", "meas_FMETemp", "MeasuredFMXT",
    "FBKTemp_F1", "FBKTemp_F8", "RollBendingForce6", "RollBendingForce7",
    "F6OilFlowRate_Ml_min", "Oil_ON___F6", "BURWaterFlowL_min_F6",
    "InterstandThickness_massFlow_5", "InterstandThickness_massFlow_6",
    "ExtGA_thkness", "Transfer_bar_thkness", "AimHotVernThk",
]
READ_COLS = REQUIRED_COLS + OPTIONAL_COLS

# Level-2 model outputs: never a column of the dataset (checked on write).
LEVEL2_PATTERNS = [
    r"CALC_", r"LEARN_", r"WRCrown", r"WRThermal", r"WRMechanicalCrown",
    r"BURThermalWear", r"CM_i__", r"STAMP_RATIO", r"WEARKm", r"_COEFF",
    r"TOP_WROLL_CRWN", r"RollShiftPosition", r"^RollBending\d", r"aimCr",
    r"LdCr", r"CYLSCALEPRED", r"AimHotVernThk",
]

COIL_COLUMNS = [
    "campaign_id", "coil_id", "seq", "rolled_at", "grade", "stand",
    "force_kn", "width_mm", "length_m", "entry_thickness_mm",
    "exit_thickness_mm", "temperature_c", "speed_mps", "lubrication",
    "shift_mm",
    # extras
    "coil_weight_kg", "strip_length_f7_exit_m", "load_time_s", "idle_time_s",
    "strip_hardness_index", "water_temperature_c", "order_thickness_mm",
    "fm_entry_temperature_c", "fm_exit_temperature_c", "exit_temperature_c",
    "lead_speed_mps", "trail_speed_mps", "roll_bending_force",
    "oil_flow_ml_min", "oil_on_f6", "backup_roll_water_flow_l_min",
]


class ConversionError(Exception):
    """A problem that stops the conversion (always, or under --strict)."""


# ---------------------------------------------------------------- helpers

def fmt(v):
    """A number for the CSV files (empty for None)."""
    if v is None:
        return ""
    if isinstance(v, bool):
        return "1" if v else "0"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if v == int(v) and abs(v) < 1e15:
            return str(int(v))
        return "%.10g" % v
    return str(v)


def num(v):
    """The cell as a float, or None when it is not a finite number."""
    if isinstance(v, bool) or v is None:
        return None
    if isinstance(v, (int, float)):
        f = float(v)
        return f if math.isfinite(f) else None
    if isinstance(v, str):
        s = v.strip()
        if not s:
            return None
        try:
            f = float(s)
        except ValueError:
            return None
        return f if math.isfinite(f) else None
    return None


def positive_or_none(v):
    """Temperatures and similar: 0 (or less) is no reading."""
    f = num(v)
    return f if f is not None and f > 0 else None


def col_letter(index0):
    """0-based column index -> Excel letters."""
    n = index0 + 1
    s = ""
    while n:
        n, r = divmod(n - 1, 26)
        s = chr(65 + r) + s
    return s


def row_ranges(rownums):
    """[2, 3, 4, 9] -> '2-4, 9'"""
    out = []
    for r in sorted(rownums):
        if out and r == out[-1][1] + 1:
            out[-1][1] = r
        else:
            out.append([r, r])
    return ", ".join("%d" % a if a == b else "%d-%d" % (a, b)
                     for a, b in out)


def roll_id_text(v):
    f = num(v)
    if f is not None and f == int(f):
        return str(int(f))
    if isinstance(v, str) and v.strip():
        return v.strip()
    return None


def quantiles(values, qs=(0.05, 0.25, 0.5, 0.75, 0.95)):
    v = sorted(values)
    if not v:
        return None
    out = []
    for q in qs:
        out.append(v[min(len(v) - 1, int(q * len(v)))])
    return out


def qtext(values, digits=4):
    q = quantiles(values)
    if q is None:
        return "n=0"
    f = "%%.%dg" % digits
    return "n=%d p5=%s p25=%s median=%s p75=%s p95=%s" % (
        (len(values),) + tuple(f % x for x in q))


def parse_offset(text):
    m = re.fullmatch(r"([+-])(\d{2}):(\d{2})", text or "")
    if not m or int(m.group(2)) > 23 or int(m.group(3)) > 59:
        raise ConversionError(
            "--utc-offset must look like +HH:MM or -HH:MM (e.g. +01:00), got "
            "%r" % text)
    return text


def stamp(t, offset):
    """ISO 8601 to the second (Excel times can carry float noise)."""
    if t.microsecond:
        t = (t + dt.timedelta(microseconds=500000)).replace(microsecond=0)
    return t.strftime("%Y-%m-%dT%H:%M:%S") + offset


class Report:
    """Everything skipped, substituted or flagged, with its reason."""

    def __init__(self, strict):
        self.strict = strict
        self.sections = {}
        self.order = []

    def add(self, section, text):
        if section not in self.sections:
            self.sections[section] = []
            self.order.append(section)
        self.sections[section].append(text)

    def row_problem(self, section, text):
        """A row-level drop or substitution: an error under --strict."""
        if self.strict:
            raise ConversionError(text + " (--strict)")
        self.add(section, text)


# ----------------------------------------------------------- the workbooks

def find_dirs(snapshot):
    cands = [os.path.join(snapshot, "Data", "RawData"),
             os.path.join(snapshot, "RawData"), snapshot]
    for raw in cands:
        if os.path.isdir(os.path.join(raw, "Wear_profiles")):
            return os.path.abspath(raw), os.path.dirname(os.path.abspath(raw))
    raise ConversionError(
        "%s: no Wear_profiles folder found in Data/RawData, RawData or the "
        "folder itself" % snapshot)


def norm_title(s):
    return re.sub(r"[^a-z0-9]", "", str(s).lower())


def read_profile_sheet(ws):
    """The sheet's rows (values) as a list of tuples."""
    return [tuple(r) for r in ws.iter_rows(values_only=True)]


def profile_blocks(rows, sheet_name, where):
    """Top/bottom blocks of an f6/f7 sheet.

    Returns ({position: dict(fresh, worn, sheet_wear)}, problems).
    fresh / worn / sheet_wear are lists of (x, value, excel_row).
    """
    out, problems = {}, []
    titles = rows[0] if rows else ()
    for position, base in (("top", 0), ("bottom", 20)):
        seg_titles = [norm_title(titles[c]) if c < len(titles) and
                      titles[c] is not None else "" for c in
                      range(base, base + 8)]
        has_fresh = any("fresh" in t and "2nd" not in t and "second" not in t
                        for t in seg_titles[:4])
        has_worn = any("worn" in t and "adjusted" not in t
                       for t in seg_titles[4:8])

        def col(xc, vc):
            pts = []
            for i, r in enumerate(rows[2:], start=3):
                if len(r) > max(xc, vc):
                    x, v = num(r[xc]), num(r[vc])
                    if x is not None and v is not None:
                        pts.append((x, v, i))
            return pts

        fresh = col(base + 1, base + 2)
        worn = col(base + 5, base + 6)
        sheet_wear = col(base + 5, base + 12)
        if not (fresh or worn):
            problems.append(
                "%s sheet %s: no %s profile (columns %s-%s and %s-%s hold no "
                "numbers)" % (where, sheet_name, position,
                              col_letter(base + 1), col_letter(base + 2),
                              col_letter(base + 5), col_letter(base + 6)))
            continue
        if not has_fresh or not has_worn:
            problems.append(
                "%s sheet %s: %s block titles in row 1 are not the expected "
                "'FIRST FRESH GROUND' / 'WORN' (%s); read by position" %
                (where, sheet_name, position,
                 ", ".join(repr(t) for t in titles[base:base + 8]
                           if t is not None) or "none"))
        if not fresh:
            problems.append("%s sheet %s: %s profile has no fresh-ground "
                            "values (columns %s-%s)" % (
                                where, sheet_name, position,
                                col_letter(base + 1), col_letter(base + 2)))
        if not worn:
            problems.append("%s sheet %s: %s profile has no worn values "
                            "(columns %s-%s)" % (
                                where, sheet_name, position,
                                col_letter(base + 5), col_letter(base + 6)))
        out[position] = {"fresh": fresh, "worn": worn,
                         "sheet_wear": sheet_wear}
    return out, problems


def read_workbook(path):
    """Everything the converter needs from one workbook (runs in a worker)."""
    name = os.path.basename(path)
    res = {"file": name, "sheets": [], "coils": None, "header_missing": [],
           "profiles": {}, "problems": [], "error": None}
    try:
        wb = openpyxl.load_workbook(path, read_only=True, data_only=True)
    except Exception as e:  # corrupt, not a workbook, ...
        res["error"] = "cannot open workbook: %s" % e
        return res
    try:
        res["sheets"] = list(wb.sheetnames)
        camp = None
        for s in wb.sheetnames:
            if s.strip().lower() == CAMP_SHEET.lower():
                camp = s
                break
        others = [s for s in wb.sheetnames if s != camp and
                  norm_title(s) == norm_title(CAMP_SHEET)]
        for s in others:
            res["problems"].append(
                "%s: sheet %r ignored (a different export; %r is read)" %
                (name, s, camp or CAMP_SHEET))
        if camp is not None:
            rows = wb[camp].iter_rows(values_only=True)
            header = next(rows, None) or ()
            index = {}
            for i, h in enumerate(header):
                if isinstance(h, str) and h.strip() not in index:
                    index[h.strip()] = i
            res["header_missing"] = [c for c in READ_COLS if c not in index]
            take = [(c, index[c]) for c in READ_COLS if c in index]
            coils = []
            for rownum, r in enumerate(rows, start=2):
                if all(v is None for v in r):
                    continue
                coils.append((rownum, {c: (r[i] if i < len(r) else None)
                                       for c, i in take}))
            res["coils"] = coils
            res["camp_sheet"] = camp
        for s in wb.sheetnames:
            key = s.strip().lower()
            if key in ("f6", "f7"):
                rows = read_profile_sheet(wb[s])
                blocks, probs = profile_blocks(rows, s, name)
                res["profiles"][int(key[1])] = blocks
                res["problems"].extend(probs)
    except Exception as e:
        res["error"] = "cannot read workbook: %s" % e
    finally:
        wb.close()
    return res


def read_all(paths, processes):
    if processes <= 1 or len(paths) <= 1:
        return [read_workbook(p) for p in paths]
    with multiprocessing.Pool(processes) as pool:
        return pool.map(read_workbook, paths, chunksize=2)


# ------------------------------------------------------------- conversion

CAMP_NAME_RE = re.compile(r"^\s*camp\s*(\d+)", re.IGNORECASE)


def list_workbooks(wear_dir, rep):
    by_campaign = {}
    for name in sorted(os.listdir(wear_dir)):
        path = os.path.join(wear_dir, name)
        if not os.path.isfile(path):
            continue
        if name.startswith("~$"):
            rep.add("Skipped files",
                    "%s: Excel lock file (name starts with '~$'), skipped" %
                    name)
            continue
        if not name.lower().endswith((".xlsx", ".xlsm")):
            rep.add("Skipped files", "%s: not an .xlsx workbook, skipped" %
                    name)
            continue
        m = CAMP_NAME_RE.match(name)
        if not m:
            rep.add("Skipped files", "%s: no campaign number in the name "
                    "('Camp <n>...'), skipped" % name)
            continue
        by_campaign.setdefault(int(m.group(1)), []).append(path)
    return by_campaign


def workbook_score(res):
    """Duplicate-workbook rule: the most complete workbook wins."""
    has = sum(1 for s in (6, 7) if s in res["profiles"])
    grades = 0
    filled = 0
    for _, row in res["coils"] or []:
        if isinstance(row.get("Grade"), str) and row["Grade"].strip():
            grades += 1
        filled += sum(1 for v in row.values() if v is not None)
    return (res["coils"] is not None and res["error"] is None, has, grades,
            filled, -len(res["file"]), res["file"])


def name_tags(name):
    low = name.lower()
    tags = []
    for tag, text in (("fake", "'fake'"), ("nodata", "'NoData'"),
                      ("no data", "'NO DATA'"), ("rotate", "'To Rotate'"),
                      ("reversed", "'Reversed'"), ("modif", "'modif'"),
                      ("no f6 prof", "'No F6 Prof'"), ("3coils", "'3coils'")):
        if tag in low:
            tags.append(text)
    return tags


def pass_values(row, stand):
    """The pass at `stand` of one coil row: (values, [(column, reason)])."""
    bad = []

    def need(col, positive=True):
        v = num(row.get(col))
        if v is None:
            raw = row.get(col)
            bad.append((col, "empty" if raw is None or (isinstance(raw, str)
                                                        and not raw.strip())
                        else "not a number (%r)" % (raw,)))
            return None
        if positive and v <= 0:
            bad.append((col, "%s <= 0" % fmt(v)))
            return None
        return v

    h_in_col, h_out_col = THICKNESS_COL[stand]
    h_in = need(h_in_col)
    h_out = need(h_out_col)
    l7 = need("stripLength")
    h8 = need("ga8") if stand == 6 else h_out
    force_t = need("FbkStandForce%d" % stand)
    width = need("ord_Wdt")
    lead = need("LEADSPD_F%d" % stand)
    trail = need("TRAILSPD_F%d" % stand)
    temp = need("FBKTemp_F%d" % stand)
    shift = need("WROLL_SHIFT_POS%d" % stand, positive=False)
    if h_in is not None and h_out is not None and h_out >= h_in:
        bad.append((h_out_col, "exit thickness %s >= entry %s (%s)" % (
            fmt(h_out), fmt(h_in), h_in_col)))
    if bad:
        return None, bad
    length = l7 if stand == 7 else l7 * h8 / h_out
    v = {
        "force_kn": force_t * TONNE_FORCE_KN,
        "width_mm": width,
        "length_m": length,
        "entry_thickness_mm": h_in,
        "exit_thickness_mm": h_out,
        "temperature_c": temp,
        "speed_mps": (lead + trail) / 2.0 / 60.0,
        "shift_mm": shift,
        "exit_temperature_c": positive_or_none(row.get("FBKTemp_F%d" %
                                                       (stand + 1))),
        "lead_speed_mps": lead / 60.0,
        "trail_speed_mps": trail / 60.0,
        "roll_bending_force": num(row.get("RollBendingForce%d" % stand)),
    }
    if stand == 6:
        flow = num(row.get("F6OilFlowRate_Ml_min"))
        on = num(row.get("Oil_ON___F6"))
        v["lubrication"] = (1 if flow > 0 else 0) if flow is not None else (
            (1 if on > 0 else 0) if on is not None else None)
        v["oil_flow_ml_min"] = flow
        v["oil_on_f6"] = on
        v["backup_roll_water_flow_l_min"] = num(row.get(
            "BURWaterFlowL_min_F6"))
    else:
        v["lubrication"] = None  # no sensor at F7: EMPTY
        v["oil_flow_ml_min"] = None
        v["oil_on_f6"] = None
        v["backup_roll_water_flow_l_min"] = None
    return v, []


def coil_extras(row):
    ord_ga = num(row.get("ord_ga"))
    return {
        "coil_weight_kg": num(row.get("CoilWt")),
        "strip_length_f7_exit_m": num(row.get("stripLength")),
        "load_time_s": num(row.get("LOADDUR_Sec")),
        "idle_time_s": num(row.get("NOLOADDUR_Sec")),
        "strip_hardness_index": num(row.get("NormHard")),
        "water_temperature_c": num(row.get("WaterTemp_OC")),
        "order_thickness_mm": ord_ga / 100.0 if ord_ga is not None else None,
        "fm_entry_temperature_c": positive_or_none(row.get("meas_FMETemp")),
        "fm_exit_temperature_c": positive_or_none(row.get("MeasuredFMXT")),
    }


def convert_campaign(camp, res, offset, rep, serials_seen):
    """Coils, passes and mounts of one campaign workbook."""
    fname = res["file"]
    sheet = res.get("camp_sheet", CAMP_SHEET)
    where = "%s sheet %r" % (fname, sheet)
    missing_required = [c for c in res["header_missing"]
                        if c in REQUIRED_COLS]
    if missing_required:
        rep.row_problem("Skipped campaigns",
                        "%s row 1: header lacks column(s) %s; campaign %d "
                        "skipped" % (where, ", ".join(missing_required), camp))
        return None
    rows = []
    for rownum, row in res["coils"]:
        t = row.get(TIME_COL)
        serial = row.get("Serial")
        if not isinstance(t, dt.datetime):
            rep.row_problem("Skipped coils", "%s row %d column %s: time %r "
                            "is not a date-time; coil skipped" % (
                                where, rownum, TIME_COL, t))
            continue
        if serial is None or not str(serial).strip():
            rep.row_problem("Skipped coils", "%s row %d column Serial: empty; "
                            "coil skipped" % (where, rownum))
            continue
        cn = num(row.get("CampaingNo_Stand6"))
        if cn is not None and int(cn) != camp:
            rep.add("Flagged",
                    "%s row %d column CampaingNo_Stand6: %s, but the file "
                    "name says campaign %d; the file name is used" % (
                        where, rownum, fmt(cn), camp))
        rows.append((t, rownum, row))
    rows.sort(key=lambda x: (x[0], x[1]))
    if not rows:
        rep.add("Skipped campaigns", "campaign %d (%s): no usable coil row" %
                (camp, fname))
        return None

    # Mounts: the roll in the stand at the end of the campaign.
    mounts = {}
    for key, col in ROLL_ID_COL.items():
        ids = [(roll_id_text(r[2].get(col)), r) for r in rows]
        known = [i for i, _ in ids if i is not None]
        if not known:
            rep.add("Skipped mounts", "%s column %s: no roll id on any row; "
                    "no mount for F%d %s" % (where, col, key[0], key[1]))
            continue
        final = known[-1]
        distinct = []
        for i in known:
            if not distinct or distinct[-1][0] != i:
                distinct.append([i, 0])
            distinct[-1][1] += 1
        if len(distinct) > 1:
            rep.add("Roll ids not constant within a campaign",
                    "campaign %d %s column %s: %s (coils per run, in time "
                    "order); mounted = %s, the roll at the campaign's end" % (
                        camp, fname, col,
                        " -> ".join("%s x%d" % (i, n) for i, n in distinct),
                        final))
        first_on = next(r for i, r in ids if i == final)
        dia = num(first_on[2].get(DIAMETER_COL[key]))
        if dia is None or dia <= 0:
            rep.add("Skipped mounts", "%s row %d column %s: diameter %r not "
                    "usable; no mount for F%d %s" % (
                        where, first_on[1], DIAMETER_COL[key],
                        first_on[2].get(DIAMETER_COL[key]), key[0], key[1]))
            continue
        mounts[key] = {"roll_id": final, "diameter_mm": dia,
                       "column": col}

    unmounted = [st for st in STANDS if (st, "top") not in mounts or
                 (st, "bottom") not in mounts]
    for stand in unmounted:
        rep.row_problem("Skipped passes",
                        "%s rows %d-%d: every F%d pass skipped, the campaign "
                        "has no mounted roll pair at F%d" % (
                            where, min(r[1] for r in rows),
                            max(r[1] for r in rows), stand, stand))
    coils = []
    seq = 0
    dropped = {}
    for t, rownum, row in rows:
        passes = []
        for stand in STANDS:
            if stand in unmounted:
                continue
            other = []
            for pos in POSITIONS:
                rid = roll_id_text(row.get(ROLL_ID_COL[(stand, pos)]))
                if rid != mounts[(stand, pos)]["roll_id"]:
                    other.append("%s=%s" % (ROLL_ID_COL[(stand, pos)], rid))
            if other:
                if rep.strict:
                    rep.row_problem(
                        "Passes rolled on another roll (dropped)",
                        "%s row %d column %s: F%d pass rolled on another "
                        "roll than the campaign's mounted one (%s)" % (
                            where, rownum, other[0].split("=")[0], stand,
                            ", ".join(other)))
                dropped.setdefault((stand, ", ".join(other)), []).append(
                    rownum)
                continue
            v, bad = pass_values(row, stand)
            if bad:
                rep.row_problem(
                    "Skipped passes",
                    "%s row %d: F%d pass skipped: %s" % (
                        where, rownum, stand, "; ".join(
                            "column %s %s" % (c, why) for c, why in bad)))
                continue
            passes.append((stand, v))
        if not passes:
            continue
        seq += 1
        serial = roll_id_text(row.get("Serial")) or str(row.get("Serial"))
        coil_id = serial
        if coil_id in serials_seen:
            coil_id = "%s~c%d" % (serial, camp)
            n = 2
            while coil_id in serials_seen:
                coil_id = "%s~c%d~%d" % (serial, camp, n)
                n += 1
            rep.row_problem("Renamed coil ids",
                            "%s row %d column Serial: %s already used (%s); "
                            "written as %s" % (where, rownum, serial,
                                               serials_seen[serial], coil_id))
        serials_seen[coil_id] = "campaign %d row %d" % (camp, rownum)
        grade = row.get("Grade")
        grade = str(grade).strip() if grade is not None else ""
        if not grade:
            grade = "unknown"
        coils.append({"coil_id": coil_id, "seq": seq, "t": t,
                      "rownum": rownum, "grade": grade, "row": row,
                      "passes": passes})
    for (stand, other), rownums in sorted(dropped.items()):
        rep.add("Passes rolled on another roll (dropped)",
                "campaign %d %s row(s) %s: %d F%d pass(es) dropped, rolled on "
                "%s, not on the mounted roll" % (
                    camp, where, row_ranges(rownums), len(rownums), stand,
                    other))
    empty_grades = sum(1 for c in coils if c["grade"] == "unknown")
    if empty_grades:
        rep.row_problem("Empty grades",
                        "%s column Grade: empty on %d of %d coils, written "
                        "'unknown'" % (where, empty_grades, len(coils)))
    if not coils:
        rep.add("Skipped campaigns", "campaign %d (%s): no usable pass" %
                (camp, fname))
        return None
    last = coils[-1]
    load = num(last["row"].get("LOADDUR_Sec"))
    ended = last["t"] + dt.timedelta(seconds=load if load and load > 0
                                     else 0)
    return {"campaign": camp, "file": fname, "coils": coils,
            "mounts": mounts, "started": coils[0]["t"], "ended": ended}


def read_wear_centres(path, rep):
    """{(campaign, stand, position): mm}, header facts."""
    if not os.path.isfile(path):
        raise ConversionError("%s: file not found" % path)
    wb = openpyxl.load_workbook(path, read_only=True, data_only=True)
    ws = wb.worksheets[0]
    rows = [tuple(r) for r in ws.iter_rows(values_only=True)]
    wb.close()
    name = "%s sheet %r" % (os.path.basename(path), ws.title)
    hdr = None
    for i, r in enumerate(rows):
        if r and isinstance(r[0], str) and "camp" in r[0].lower():
            hdr = i
            break
    if hdr is None:
        raise ConversionError("%s: no header row whose column A names the "
                              "campaign ('Num Campagne')" % name)
    cols = {}
    for j, h in enumerate(rows[hdr]):
        m = re.search(r"F\s*([67])\s*(TOP|BOT)", str(h or ""), re.I)
        if m:
            cols[j] = (int(m.group(1)), "top" if m.group(2).upper() == "TOP"
                       else "bottom")
    if len(cols) != 4:
        raise ConversionError("%s row %d: expected 4 columns 'Usure F6 TOP' "
                              ".. 'Usure F7 BOT', found %d" % (
                                  name, hdr + 1, len(cols)))
    units = rows[hdr + 1] if hdr + 1 < len(rows) else ()
    unit_ok = all(j < len(units) and str(units[j] or "").strip().lower() ==
                  "mm" for j in cols)
    start = hdr + 2 if unit_ok else hdr + 1
    if not unit_ok:
        raise ConversionError("%s row %d: the unit row does not say 'mm' "
                              "under every wear column" % (name, hdr + 2))
    counts = {}
    if rows and rows[0] and isinstance(rows[0][0], str) and \
            "nb" in rows[0][0].lower():
        for j in cols:
            counts[cols[j]] = rows[0][j] if j < len(rows[0]) else None
    out = {}
    for i in range(start, len(rows)):
        r = rows[i]
        if not r or r[0] is None:
            continue
        c = num(r[0])
        if c is None or c != int(c):
            rep.row_problem("Skipped measurements",
                            "%s row %d column A: campaign %r is not a "
                            "number; row skipped" % (name, i + 1, r[0]))
            continue
        for j, key in cols.items():
            v = r[j] if j < len(r) else None
            if v is None or (isinstance(v, str) and not v.strip()):
                continue
            f = num(v)
            if f is None:
                rep.row_problem("Skipped measurements",
                                "%s row %d column %s: %r is not a number; "
                                "skipped" % (name, i + 1, col_letter(j), v))
                continue
            out[(int(c),) + key] = f
    return out, counts


def read_split(path, rep):
    """{(campaign, stand, position): 'train'|'validation'}"""
    text = open(path, encoding="utf-8-sig", errors="replace").read()
    out = {}
    labels = []
    name = os.path.basename(path)
    for m in re.finditer(r"([A-Za-z0-9_ ]*?)\s*,\s*([A-Za-z]+)\s*:\s*\[([^\]]*)"
                         r"\]", text):
        label, kind, body = m.group(1).strip(), m.group(2).lower(), m.group(3)
        line = text.count("\n", 0, m.start()) + 1
        lm = re.fullmatch(r"[fF]?\s*([67])\s*_?\s*([tTbB])[a-zA-Z]*", label)
        if not lm:
            rep.add("Split file", "%s line %d: label %r names no roll "
                    "(f6t, f6b, f7t, f7b); list ignored" % (name, line, label))
            continue
        stand = int(lm.group(1))
        pos = "top" if lm.group(2).lower() == "t" else "bottom"
        if kind.startswith("train"):
            s = "train"
        elif kind.startswith("dev") or kind.startswith("val"):
            s = "validation"
        else:
            rep.add("Split file", "%s line %d: list kind %r is neither Train "
                    "nor Dev; list ignored" % (name, line, kind))
            continue
        if not label.lower().startswith("f"):
            rep.add("Split file", "%s line %d: label %r read as F%d %s %s" % (
                name, line, label + "," + m.group(2), stand, pos, s))
        labels.append((stand, pos, s))
        for tok in body.split(","):
            tok = tok.strip()
            if not tok:
                continue
            if not tok.isdigit():
                rep.add("Split file", "%s line %d: %r is not a campaign "
                        "number; ignored" % (name, line, tok))
                continue
            key = (tok, stand, pos)
            if key in out and out[key] != s:
                rep.add("Split file", "%s: campaign %s F%d %s listed in both "
                        "train and validation; kept %s" % (
                            name, tok, stand, pos, out[key]))
                continue
            out[key] = s
    return out, labels


def read_authors_results(models_dir, rep):
    rows = []
    found = []
    for folder, key in (("f6_top", (6, "top")), ("f6_bot", (6, "bottom")),
                        ("f7_top", (7, "top")), ("f7_bot", (7, "bottom"))):
        for fname, s in (("results_train.csv", "train"),
                         ("results_val.csv", "validation")):
            p = os.path.join(models_dir, folder, fname)
            if not os.path.isfile(p):
                if s == "validation":
                    rep.add("Authors' predictions",
                            "%s: missing" % os.path.join(folder, fname))
                continue
            found.append(os.path.join(folder, fname))
            with open(p, encoding="utf-8-sig", errors="replace",
                      newline="") as f:
                data = list(csv.reader(f))
            if not data:
                continue
            hdr = [h.lower() for h in data[0]]

            def find(word):
                for j, h in enumerate(hdr):
                    if word in h:
                        return j
                raise ConversionError("%s line 1: no column containing %r" %
                                      (p, word))
            jc, jp, jg = find("campaign"), find("prediction"), find("truth")
            for ln, r in enumerate(data[1:], start=2):
                if not r or all(not x.strip() for x in r):
                    continue
                try:
                    c = int(float(r[jc]))
                    pr = float(r[jp])
                    gt = float(r[jg])
                except (ValueError, IndexError):
                    rep.row_problem("Authors' predictions",
                                    "%s line %d: not numbers (%s); skipped" %
                                    (os.path.join(folder, fname), ln,
                                     ",".join(r)))
                    continue
                rows.append((c, key[0], key[1], s, gt, pr))
    return rows, found


# ------------------------------------------------------------- evidence

def interp(pts, x):
    for (x0, v0), (x1, v1) in zip(pts, pts[1:]):
        if x0 <= x <= x1:
            return v0 if x1 == x0 else v0 + (v1 - v0) * (x - x0) / (x1 - x0)
    return None


def pair_profile(fresh, worn):
    """[(x_sheet, fresh - worn (mm), excel_row)], unpaired count."""
    fr = sorted((x, v) for x, v, _ in fresh)
    out, unpaired = [], 0
    if not fr:
        return out, len(worn)
    xs = [x for x, _ in fr]
    for x, v, rownum in worn:
        i = bisect.bisect_left(xs, x)
        best = None
        for j in (i - 1, i):
            if 0 <= j < len(fr):
                if best is None or abs(fr[j][0] - x) < abs(fr[best][0] - x):
                    best = j
        if best is not None and abs(fr[best][0] - x) <= PAIR_TOLERANCE_MM:
            out.append((x, fr[best][1] - v, rownum))
        else:
            unpaired += 1
    return out, unpaired


def symmetry_curve(pairs, centres):
    pts = sorted((x, w) for x, w, _ in pairs)
    wr = max(w for _, w in pts) - min(w for _, w in pts)
    if wr <= 0 or wr > 2:
        return None
    curve = []
    for c in centres:
        e = 0.0
        for u in range(25, 651, 25):
            a, b = interp(pts, c - u), interp(pts, c + u)
            if a is None or b is None:
                return None
            e += (a - b) ** 2
        curve.append(e / wr ** 2)
    return curve


# ---------------------------------------------------------------- main

def write_csv(path, header, rows):
    for h in header:
        for pat in LEVEL2_PATTERNS:
            if re.search(pat, h):
                raise ConversionError("internal: column %r looks like a "
                                      "Level-2 output" % h)
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        for r in rows:
            w.writerow([fmt(v) for v in r])


def convert(args):
    t0 = time.time()
    offset = parse_offset(args.utc_offset)
    rep = Report(args.strict)
    raw_dir, data_dir = find_dirs(args.snapshot)
    out = args.out
    if os.path.exists(out):
        if not os.path.isdir(out) or os.listdir(out):
            raise ConversionError("%s: the output folder must be missing or "
                                  "empty" % out)
    wear_dir = os.path.join(raw_dir, "Wear_profiles")
    by_campaign = list_workbooks(wear_dir, rep)
    paths = [p for ps in by_campaign.values() for p in ps]
    results = read_all(sorted(paths), args.processes)
    by_path = {p: r for p, r in zip(sorted(paths), results)}

    # One workbook per campaign.
    chosen = {}
    for camp in sorted(by_campaign):
        cands = [by_path[p] for p in by_campaign[camp]]
        for r in cands:
            if r["error"]:
                rep.add("Skipped files", "%s: %s" % (r["file"], r["error"]))
        ok = [r for r in cands if not r["error"]]
        if not ok:
            continue
        if len(ok) > 1:
            ok.sort(key=workbook_score, reverse=True)
            win = ok[0]
            for r in ok[1:]:
                sw, sl = workbook_score(win), workbook_score(r)
                why = ("has %d profile sheet(s) against %d" % (sw[1], sl[1])
                       if sw[1] != sl[1] else
                       "has %d graded coils against %d" % (sw[2], sl[2])
                       if sw[2] != sl[2] else
                       "has %d filled cells against %d" % (sw[3], sl[3])
                       if sw[3] != sl[3] else "has the shorter file name")
                rep.add("Duplicate workbooks",
                        "campaign %d: %r used, %r not used (rule: a workbook "
                        "with a 'Camp Data' sheet, then the one with more of "
                        "the f6/f7 profile sheets, then more "
                        "non-empty Grade cells, then more filled cells in "
                        "the columns read; here the used one %s)" % (
                            camp, win["file"], r["file"], why))
        chosen[camp] = ok[0]

    for camp, r in sorted(chosen.items()):
        for p in r["problems"]:
            rep.add("Missing or odd sheets", p)
        if r["coils"] is None:
            rep.add("Missing or odd sheets", "%s: no %r sheet (sheets: %s); "
                    "campaign %d has no coils and is not written" % (
                        r["file"], CAMP_SHEET, ", ".join(r["sheets"]), camp))
        for s in (6, 7):
            if s not in r["profiles"]:
                rep.add("Missing or odd sheets", "%s: no sheet f%d (sheets: "
                        "%s); no F%d profiles for campaign %d" % (
                            r["file"], s, ", ".join(r["sheets"]), s, camp))
        tags = name_tags(r["file"])
        if tags:
            rep.add("File names with a status tag",
                    "%s: the name says %s; converted as any other workbook" %
                    (r["file"], " and ".join(tags)))
    missing = [c for c in range(1, max(list(chosen) + [0]) + 1)
               if c not in chosen]
    if missing:
        rep.add("Missing workbooks", "no workbook for campaign(s) %s" %
                row_ranges(missing))

    # Coils and mounts.
    campaigns = {}
    serials_seen = {}
    for camp, r in sorted(chosen.items()):
        if r["coils"] is None:
            continue
        c = convert_campaign(camp, r, offset, rep, serials_seen)
        if c:
            campaigns[camp] = c

    # Measurements.
    wc, wc_counts = read_wear_centres(os.path.join(raw_dir,
                                                   "WearCentres.xlsx"), rep)
    meas = {}
    for key in sorted(wc):
        camp, stand, pos = key
        c = campaigns.get(camp)
        if c is None or (stand, pos) not in c["mounts"]:
            rep.add("Skipped measurements",
                    "WearCentres.xlsx campaign %d F%d %s (%s mm): campaign %s"
                    "; reading not written" % (
                        camp, stand, pos, fmt(round(wc[key], 6)),
                        "has no workbook / coils" if c is None else
                        "has no mount there"))
            continue
        meas[key] = wc[key] * 1000.0
        if wc[key] < 0:
            rep.add("Negative or near-zero readings",
                    "campaign %d F%d %s: %.1f um (negative; written as is)" %
                    (camp, stand, pos, wc[key] * 1000))
        elif wc[key] * 1000 < 20:
            rep.add("Negative or near-zero readings",
                    "campaign %d F%d %s: %.1f um (below 20 um; written as is)"
                    % (camp, stand, pos, wc[key] * 1000))

    # Profiles: the sheet's own "Top/Bottom Wear, mm" column, at the worn
    # profile's X (see the comment at the top).
    prof_rows = []
    prof_by_roll = {}  # written wear: [(x_sheet, wear_mm, excel_row)]
    raw_by_roll = {}  # fresh - worn paired by X: [(x_sheet, mm, excel_row)]
    sheet_kinds = {"equal": 0, "const": 0, "linear": 0, "diameters": 0,
                   "other": 0}
    sheet_kind_list = {"const": [], "linear": [], "diameters": [],
                       "other": []}
    fallback, no_wear, unpaired_total = [], [], [0, 0]
    grid_curves = {}
    centres = [860 + 2.5 * i for i in range(41)]
    window_match = [0, 0]
    for camp, c in sorted(campaigns.items()):
        r = chosen[camp]
        for stand in STANDS:
            for pos in POSITIONS:
                blk = r["profiles"].get(stand, {}).get(pos)
                if not blk or not blk["worn"]:
                    continue
                key = (camp, stand, pos)
                label = "%d F%d %s" % key
                where = "%s sheet f%d %s" % (r["file"], stand, pos)
                if (stand, pos) not in c["mounts"]:
                    rep.add("Skipped profiles", "%s: no mount; profile not "
                            "written" % where)
                    continue
                pairs, unpaired = pair_profile(blk["fresh"], blk["worn"])
                if pairs:
                    raw_by_roll[key] = pairs
                    unpaired_total[0] += unpaired
                    unpaired_total[1] += 1 if unpaired else 0
                raw_at_row = {rn: w for _, w, rn in pairs}
                if blk["sheet_wear"]:
                    written = blk["sheet_wear"]
                elif pairs:
                    written = pairs
                    fallback.append(label)
                else:
                    no_wear.append(label)
                    continue
                vals = [v for _, v, _ in blk["fresh"]] + \
                    [v for _, v, _ in blk["worn"]]
                notes = []
                if min(vals) < 600 or max(vals) > 900:
                    notes.append("its fresh/worn profile columns hold "
                                 "%s..%s, not roll diameters" % (
                                     fmt(round(min(vals), 3)),
                                     fmt(round(max(vals), 3))))
                if not blk["fresh"]:
                    notes.append("no fresh-ground profile")
                wmin = min(w for _, w, _ in written) * 1000
                wmax = max(w for _, w, _ in written) * 1000
                if wmax > 2000 or wmin < -500:
                    notes.append("wear written %.0f..%.0f um%s" % (
                        wmin, wmax, " (the sheet's wear column holds "
                        "diameters)" if max(abs(wmin), abs(wmax)) > 1e5
                        else ""))
                if notes:
                    rep.add("Profiles whose values are not plausible wear "
                            "(written by the rule, not fixed)",
                            "%s: %s" % (where, "; ".join(notes)))
                for x, w, rn in written:
                    raw = raw_at_row.get(rn)
                    prof_rows.append((
                        str(camp), "F%d" % stand, pos,
                        c["mounts"][(stand, pos)]["roll_id"], None,
                        round(x - BARREL_CENTRE_X_MM, 3),
                        round(w * 1000.0, 3),
                        round(raw * 1000.0, 3) if raw is not None else None))
                prof_by_roll[key] = written
                # The sheet's wear column against (fresh - worn), row by row.
                fr_by_row = {rn: v for _, v, rn in blk["fresh"]}
                wo_by_row = {rn: v for _, v, rn in blk["worn"]}
                d = [(x, sw - (fr_by_row[rn] - wo_by_row[rn]))
                     for x, sw, rn in blk["sheet_wear"]
                     if rn in fr_by_row and rn in wo_by_row]
                if d:
                    m = statistics.mean(b for _, b in d)
                    sd = statistics.pstdev([b for _, b in d])
                    if max(abs(v) for _, v, _ in blk["sheet_wear"]) > 100:
                        k = "diameters"
                    elif abs(m) < 1e-6 and sd < 1e-6:
                        k = "equal"
                    elif sd < 1e-4:
                        k = "const"
                    else:
                        xs = [a for a, _ in d]
                        mx = statistics.mean(xs)
                        sxx = sum((a - mx) ** 2 for a in xs)
                        sl = sum((a - mx) * (b - m) for a, b in d) / sxx \
                            if sxx else 0
                        res_sd = statistics.pstdev(
                            [b - (m + sl * (a - mx)) for a, b in d])
                        k = "linear" if res_sd < 1e-4 else "other"
                    sheet_kinds[k] += 1
                    if k != "equal":
                        sheet_kind_list[k].append(label)
                # WearCentres against the sheet column's 31 central rows.
                sw = [v for _, v, _ in sorted(blk["sheet_wear"],
                                              key=lambda t: t[2])]
                if key in wc and len(sw) >= 63:
                    window_match[1] += 1
                    if abs(statistics.mean(sw[17:48]) - wc[key]) < 1e-6:
                        window_match[0] += 1
                # Symmetry of the wear profile, pooled per gauge grid.
                grid = "%d points %s..%s" % (
                    len(blk["worn"]), fmt(min(x for x, _, _ in blk["worn"])),
                    fmt(max(x for x, _, _ in blk["worn"])))
                if len(written) >= 60:
                    cv = symmetry_curve(written, centres)
                    if cv:
                        g = grid_curves.setdefault(grid, [0, [0.0] * len(cv)])
                        g[0] += 1
                        for i, e in enumerate(cv):
                            g[1][i] += e
    if fallback:
        rep.add("Profiles without the sheet's wear column",
                "%d roll(s) written as (fresh - worn) paired by X: %s" % (
                    len(fallback), ", ".join(fallback)))
    if no_wear:
        rep.add("Skipped profiles",
                "%d roll(s) with a worn profile but neither a wear column nor "
                "fresh values; not written: %s" % (len(no_wear),
                                                   ", ".join(no_wear)))
    for k in ("const", "linear", "diameters", "other"):
        if sheet_kind_list[k]:
            rep.add("The sheets' wear column against (fresh - worn)",
                    "%d roll(s), %s: %s" % (
                        len(sheet_kind_list[k]), {
                            "const": "(fresh - worn) + a constant level "
                                     "correction",
                            "linear": "(fresh - worn) + a linear level/tilt "
                                      "correction",
                            "diameters": "the column holds diameters, not "
                                         "wear",
                            "other": "neither"}[k],
                        ", ".join(sheet_kind_list[k])))

    # ------------------------------------------------- write the dataset
    # Into a scratch folder next to --out, renamed at the end: a failed run
    # leaves no half-written dataset.
    final_out = os.path.abspath(out)
    out = final_out + ".converting-%d" % os.getpid()
    os.makedirs(out)
    try:
        summary = write_outputs(out, final_out, args, offset, rep, t0,
                                campaigns, chosen, by_campaign, meas, wc,
                                wc_counts, prof_rows, prof_by_roll,
                                raw_by_roll, sheet_kinds, window_match,
                                grid_curves, centres, unpaired_total,
                                data_dir, raw_dir)
    except BaseException:
        shutil.rmtree(out, ignore_errors=True)
        raise
    if os.path.isdir(final_out):
        os.rmdir(final_out)  # checked empty above
    os.rename(out, final_out)
    return summary


def write_outputs(out, final_out, args, offset, rep, t0, campaigns, chosen,
                  by_campaign, meas, wc, wc_counts, prof_rows, prof_by_roll,
                  raw_by_roll, sheet_kinds, window_match, grid_curves,
                  centres, unpaired_total, data_dir, raw_dir):
    """Writes every output file into `out` (renamed to final_out later)."""
    camp_rows, mount_rows, coil_rows = [], [], []
    for camp, c in sorted(campaigns.items()):
        cid = str(camp)
        camp_rows.append((cid, stamp(c["started"], offset),
                          stamp(c["ended"], offset)))
        for stand in STANDS:
            for pos in POSITIONS:
                m = c["mounts"].get((stand, pos))
                if m:
                    mount_rows.append((cid, "F%d" % stand, pos, m["roll_id"],
                                       None, m["diameter_mm"], None))
        for coil in c["coils"]:
            ex = coil_extras(coil["row"])
            for stand, v in coil["passes"]:
                row = [cid, coil["coil_id"], coil["seq"],
                       stamp(coil["t"], offset), coil["grade"], "F%d" % stand]
                allv = dict(ex)
                allv.update(v)
                for col in COIL_COLUMNS[6:]:
                    row.append(allv.get(col))
                coil_rows.append(row)
    write_csv(os.path.join(out, "campaigns.csv"),
              ["campaign_id", "started_at", "ended_at"], camp_rows)
    write_csv(os.path.join(out, "mounts.csv"),
              ["campaign_id", "stand", "position", "roll_id", "roll_type",
               "diameter_mm", "hardness_hb"], mount_rows)
    write_csv(os.path.join(out, "coils.csv"), COIL_COLUMNS, coil_rows)
    meas_rows = []
    for (camp, stand, pos), um in sorted(meas.items()):
        meas_rows.append((str(camp), "F%d" % stand, pos,
                          campaigns[camp]["mounts"][(stand, pos)]["roll_id"],
                          None, round(um, 6)))
    write_csv(os.path.join(out, "measurements.csv"),
              ["campaign_id", "stand", "position", "roll_id", "measured_at",
               "wear_center_um"], meas_rows)
    write_csv(os.path.join(out, "profiles.csv"),
              ["campaign_id", "stand", "position", "roll_id", "measured_at",
               "x_mm", "wear_um", "fresh_minus_worn_um"], prof_rows)

    # Splits.
    split_path = os.path.join(data_dir, "DataBases", "campaign_split.txt")
    authors_rows = []
    split_labels = []
    if os.path.isfile(split_path):
        split, split_labels = read_split(split_path, rep)
        not_measured = []
        for (cid, stand, pos), s in sorted(
                split.items(), key=lambda kv: (int(kv[0][0]), kv[0][1],
                                               kv[0][2])):
            if (int(cid), stand, pos) in meas:
                authors_rows.append((cid, "F%d" % stand, pos, s))
            else:
                not_measured.append("%s F%d %s" % (cid, stand, pos))
        if not_measured:
            rep.add("Split file", "%d listed reading(s) not in "
                    "measurements.csv, not written: %s" % (
                        len(not_measured), ", ".join(not_measured)))
        unlisted = [k for k in meas if (str(k[0]), k[1], k[2]) not in split]
        if unlisted:
            rep.add("Split file", "%d measured reading(s) in neither list "
                    "of the authors' split: %s" % (
                        len(unlisted), ", ".join("%d F%d %s" % k for k in
                                                 sorted(unlisted))))
    else:
        rep.add("Split file", "%s: missing; split_authors.csv has no rows" %
                split_path)
    write_csv(os.path.join(out, "split_authors.csv"),
              ["campaign_id", "stand", "position", "set"], authors_rows)
    tf_rows = [(str(c), "F%d" % s, p,
                "train" if c <= TIME_FORWARD_LAST_TRAIN else "validation")
               for (c, s, p) in sorted(meas)]
    write_csv(os.path.join(out, "split_time_forward.csv"),
              ["campaign_id", "stand", "position", "set"], tf_rows)

    # Authors' network predictions.
    models_dir = os.path.join(data_dir, "Outputs", "Models")
    pred_rows = []
    gt_diffs = []
    mae = {}
    found = []
    if os.path.isdir(models_dir):
        preds, found = read_authors_results(models_dir, rep)
        for camp, stand, pos, s, gt, pr in preds:
            c = campaigns.get(camp)
            rid = c["mounts"][(stand, pos)]["roll_id"] if c and \
                (stand, pos) in c["mounts"] else None
            if rid is None:
                rep.add("Authors' predictions",
                        "campaign %d F%d %s (%s): no mounted roll in the "
                        "dataset; roll_id left empty" % (camp, stand, pos, s))
            if (camp, stand, pos) in meas:
                gt_diffs.append(abs(gt - meas[(camp, stand, pos)]))
            pred_rows.append((str(camp), "F%d" % stand, pos, rid, s, gt, pr,
                              None, None))
            mae.setdefault(s, []).append(abs(pr - gt))
    else:
        rep.add("Authors' predictions", "%s: missing" % models_dir)
    write_csv(os.path.join(out, "authors_ann_predictions.csv"),
              ["campaign_id", "stand", "position", "roll_id", "set",
               "measured_um", "predicted_um", "lo_um", "hi_um"], pred_rows)

    # --------------------------------------------------- evidence figures
    ev = []
    passes = [(c, coil, stand, v) for c in campaigns.values()
              for coil in c["coils"] for stand, v in coil["passes"]]
    coil_rows_raw = [coil["row"] for c in campaigns.values()
                     for coil in c["coils"]]

    def g(row, col):
        return num(row.get(col))

    for stand in STANDS:
        sf_t, sf_k, p_t, p_k = [], [], [], []
        for c, coil, s, v in passes:
            if s != stand:
                continue
            sf = v["force_kn"] / v["width_mm"]
            sf_t.append(sf)
            sf_k.append(sf / TONNE_FORCE_KN)
            dia = c["mounts"][(stand, "top")]["diameter_mm"]
            lc = math.sqrt(dia / 2 * (v["entry_thickness_mm"] -
                                      v["exit_thickness_mm"]))
            p = v["force_kn"] * 1000 / (v["width_mm"] * lc)
            p_t.append(p)
            p_k.append(p / TONNE_FORCE_KN)
        ev.append("Force F%d read as tonnes-force, specific force kN/mm: %s" %
                  (stand, qtext(sf_t)))
        ev.append("Force F%d read as kN, specific force kN/mm: %s" %
                  (stand, qtext(sf_k)))
        ev.append("Force F%d read as tonnes-force, mean pressure F/(w "
                  "sqrt(R dh)) MPa: %s" % (stand, qtext(p_t)))
        ev.append("Force F%d read as kN, mean pressure MPa: %s" %
                  (stand, qtext(p_k)))
    sp7, sp6, mf, lw8, lw7 = [], [], [], [], []
    th = {k: [] for k in ("ga1", "ga6", "ga7", "ga8")}
    aim, ordr, t8, t7, t1 = [], [], [], [], []
    mono = [0, 0]
    lub = {}
    for row in coil_rows_raw:
        l7, ld = g(row, "stripLength"), g(row, "LOADDUR_Sec")
        h6, h7, h8 = g(row, "ga6"), g(row, "ga7"), g(row, "ga8")
        w = g(row, "ord_Wdt")
        s7 = [g(row, "LEADSPD_F7"), g(row, "TRAILSPD_F7")]
        s6 = [g(row, "LEADSPD_F6"), g(row, "TRAILSPD_F6")]
        ok = None not in (l7, h6, h7, h8, w) and h7 and h8
        if ok and ld and None not in s7 and sum(s7) > 0:
            sp7.append(l7 / ld * 60 / (sum(s7) / 2))
            if None not in s6 and sum(s6) > 0:
                sp6.append(l7 * h8 / h7 / ld * 60 / (sum(s6) / 2))
                mf.append(sum(s6) * h7 / (sum(s7) * h8))
        cw = g(row, "CoilWt")
        if ok and cw and l7:
            lw8.append(cw / (STEEL_DENSITY_KG_M3 * w / 1000 * h8 / 1000) / l7)
            lw7.append(cw / (STEEL_DENSITY_KG_M3 * w / 1000 * h7 / 1000) / l7)
        for a, b in (("ga1", "Transfer_bar_thkness"),
                     ("ga6", "InterstandThickness_massFlow_5"),
                     ("ga7", "InterstandThickness_massFlow_6"),
                     ("ga8", "ExtGA_thkness")):
            x, y = g(row, a), g(row, b)
            if x is not None and y is not None and x > 0:
                th[a].append(abs(x - y))
        a = g(row, "AimHotVernThk")
        if h8 and a:
            aim.append(h8 - a)
        o = g(row, "ord_ga")
        if h8 and o:
            ordr.append(h8 / (o / 100))
        fx = positive_or_none(row.get("MeasuredFMXT"))
        f8, f7 = positive_or_none(row.get("FBKTemp_F8")), positive_or_none(
            row.get("FBKTemp_F7"))
        if fx and f8 and f7:
            t8.append(f8 - fx)
            t7.append(f7 - fx)
        fe, f1 = positive_or_none(row.get("meas_FMETemp")), positive_or_none(
            row.get("FBKTemp_F1"))
        if fe and f1:
            t1.append(f1 - fe)
        seqt = [positive_or_none(row.get("FBKTemp_F%d" % k)) for k in
                (1, 6, 7, 8)]
        if None not in seqt:
            mono[1] += 1
            if seqt[0] > seqt[1] > seqt[2] > seqt[3]:
                mono[0] += 1
        fl, on = g(row, "F6OilFlowRate_Ml_min"), g(row, "Oil_ON___F6")
        if fl is not None and on is not None:
            k = (fl > 0, on > 0)
            lub[k] = lub.get(k, 0) + 1
    ev.append("Speed: stripLength / LOADDUR_Sec x 60 / mean(LEADSPD_F7, "
              "TRAILSPD_F7): %s (1 if the speeds are m/min)" % qtext(sp7))
    ev.append("Speed: (stripLength x ga8/ga7) / LOADDUR_Sec x 60 / "
              "mean(LEADSPD_F6, TRAILSPD_F6): %s" % qtext(sp6))
    ev.append("Mass flow: v6 x ga7 / (v7 x ga8) with v = mean(lead, trail): "
              "%s" % qtext(mf))
    ev.append("Length: CoilWt / (7850 x ord_Wdt x ga8) / stripLength: %s "
              "(1 if stripLength is the length leaving F7 and CoilWt is kg)" %
              qtext(lw8))
    ev.append("Length: the same with ga7 instead of ga8: %s" % qtext(lw7))
    for a, b in (("ga1", "Transfer_bar_thkness"),
                 ("ga6", "InterstandThickness_massFlow_5"),
                 ("ga7", "InterstandThickness_massFlow_6"),
                 ("ga8", "ExtGA_thkness")):
        if th[a]:
            ev.append("Thickness: |%s - %s| max %.4f mm over %d coils" % (
                a, b, max(th[a]), len(th[a])))
    ev.append("Thickness: ga8 - AimHotVernThk mm: %s" % qtext(aim))
    ev.append("Thickness: ga8 / (ord_ga / 100): %s" % qtext(ordr))
    ev.append("Temperature: FBKTemp_F8 - MeasuredFMXT C: %s" % qtext(t8))
    ev.append("Temperature: FBKTemp_F7 - MeasuredFMXT C: %s" % qtext(t7))
    ev.append("Temperature: FBKTemp_F1 - meas_FMETemp C: %s" % qtext(t1))
    if mono[1]:
        ev.append("Temperature: FBKTemp_F1 > F6 > F7 > F8 on %d of %d coils" %
                  (mono[0], mono[1]))
    ev.append("Lubrication: (F6OilFlowRate_Ml_min > 0, Oil_ON___F6 > 0) "
              "counts: %s" % ", ".join("%s: %d" % (k, n) for k, n in
                                       sorted(lub.items())))

    # Radius or diameter.
    rd = []
    for key, pairs in raw_by_roll.items():
        if key not in wc:
            continue
        cen = [w for x, w, _ in pairs
               if abs(x - BARREL_CENTRE_X_MM) <= CENTRE_HALF_WIDTH_MM]
        if cen:
            rd.append((wc[key], statistics.mean(cen)))
    dia_ev = []
    if rd:
        d1 = [a - b for a, b in rd]
        d2 = [a - b / 2 for a, b in rd]
        ratio = [a / b for a, b in rd if a > 0.05 and b > 0.05]
        dia_ev.append("Rolls with both a centre reading and fresh and worn "
                      "profiles: %d" % len(rd))
        dia_ev.append("WearCentres - mean(fresh - worn) over |x| <= %g mm, "
                      "um: %s" % (CENTRE_HALF_WIDTH_MM,
                                  qtext([x * 1000 for x in d1])))
        dia_ev.append("WearCentres - mean(fresh - worn)/2 (a radius loss), "
                      "um: %s" % qtext([x * 1000 for x in d2]))
        dia_ev.append("Ratio WearCentres / mean(fresh - worn) (both > 50 um): "
                      "%s" % qtext(ratio))
        dia_ev.append("Within 20 um: of (fresh - worn) %d, of (fresh - "
                      "worn)/2 %d, of %d" % (
                          sum(1 for x in d1 if abs(x) <= 0.02),
                          sum(1 for x in d2 if abs(x) <= 0.02), len(rd)))
        big = []
        for k, p in sorted(prof_by_roll.items()):
            cen = [w for x, w, _ in p
                   if abs(x - BARREL_CENTRE_X_MM) <= CENTRE_HALF_WIDTH_MM]
            if k in wc and cen and abs(wc[k] - statistics.mean(cen)) > 0.05:
                big.append("%d F%d %s (%.0f vs %.0f um)" % (
                    k + (wc[k] * 1000, statistics.mean(cen) * 1000)))
        if big:
            rep.add("Profiles whose centre differs from the centre reading "
                    "by more than 50 um",
                    "%d roll(s) (reading vs mean of the written profile over "
                    "|x| <= %g mm): %s" % (len(big), CENTRE_HALF_WIDTH_MM,
                                           ", ".join(big)))
    if unpaired_total[0]:
        dia_ev.append("Worn points with no fresh point within %g mm "
                      "(fresh_minus_worn_um left empty): %d, on %d rolls (the "
                      "worn traverse reaching past the fresh one)" % (
                          PAIR_TOLERANCE_MM, unpaired_total[0],
                          unpaired_total[1]))
    fresh_dia = []
    for camp, c in campaigns.items():
        for (stand, pos), m in c["mounts"].items():
            blk = chosen[camp]["profiles"].get(stand, {}).get(pos)
            if blk and blk["fresh"]:
                vals = [v for _, v, _ in blk["fresh"] if 600 < v < 900]
                if vals:
                    fresh_dia.append(statistics.median(vals) -
                                     m["diameter_mm"])
    if fresh_dia:
        dia_ev.append("Fresh-ground 'Real Profile' median minus the "
                      "recorded diameter F<k><T|B>WRDia, mm: %s (the "
                      "profiles are diameters)" % qtext(fresh_dia))
    if window_match[1]:
        dia_ev.append("WearCentres equals the mean of the sheet's 'Wear, mm' "
                      "column over its 31 central rows (to 1e-6 mm) on %d of "
                      "%d rolls" % tuple(window_match))
    dia_ev.append("Sheet 'Wear, mm' column vs (fresh - worn), rolls: equal "
                  "%d, + constant %d, + linear correction %d, holds "
                  "diameters %d, other %d" % (
                      sheet_kinds["equal"], sheet_kinds["const"],
                      sheet_kinds["linear"], sheet_kinds["diameters"],
                      sheet_kinds["other"]))
    centre_ev = []
    for grid, (n, curve) in sorted(grid_curves.items(),
                                   key=lambda kv: -kv[1][0]):
        i = min(range(len(curve)), key=lambda i: curve[i])
        at910 = curve[centres.index(BARREL_CENTRE_X_MM)]
        centre_ev.append("worn grid %s: %d profiles, pooled symmetry centre "
                         "X = %s mm (asymmetry at the minimum %.0f, at X=%g "
                         "%.0f)" % (grid, n, fmt(centres[i]), curve[i],
                                    BARREL_CENTRE_X_MM, at910))
        if n >= 20 and abs(centres[i] - BARREL_CENTRE_X_MM) > 15:
            rep.add("Flagged", "worn grid %s: symmetry centre %s mm is more "
                    "than 15 mm from the X = %g mm used" % (
                        grid, fmt(centres[i]), BARREL_CENTRE_X_MM))

    # Profile at x ~ 0 vs reading.
    agree = [0, 0]
    for key, pairs in prof_by_roll.items():
        if key in meas:
            cen = [w for x, w, _ in pairs
                   if abs(x - BARREL_CENTRE_X_MM) <= CENTRE_HALF_WIDTH_MM]
            if cen:
                agree[1] += 1
                if abs(statistics.mean(cen) * 1000 - meas[key]) <= 20:
                    agree[0] += 1

    # ------------------------------------------------------------- report
    elapsed = time.time() - t0
    n_coils = sum(len(c["coils"]) for c in campaigns.values())
    rolls = set(r[3] for r in mount_rows)
    grades = set(coil["grade"] for c in campaigns.values()
                 for coil in c["coils"])
    lines = []
    lines.append("# Conversion report: study snapshot -> rollwear dataset")
    lines.append("")
    lines.append("Snapshot: `%s`  " % raw_dir)
    lines.append("Output: `%s`  " % os.path.abspath(final_out))
    lines.append("UTC offset written on every timestamp: `%s` (given with "
                 "--utc-offset; the snapshot does not record the zone)  " %
                 offset)
    lines.append("Mode: %s  " % ("strict" if args.strict else "default"))
    lines.append("Run time: %.1f s" % elapsed)
    lines.append("")
    lines.append("## Counts")
    lines.append("")
    wb_total = sum(len(v) for v in by_campaign.values())
    lines.append("- workbooks read: %d (campaign numbers: %d)" % (
        wb_total, len(by_campaign)))
    lines.append("- campaigns: %d" % len(campaigns))
    lines.append("- mounts: %d" % len(mount_rows))
    lines.append("- coils: %d" % n_coils)
    lines.append("- passes (coils.csv rows): %d (F6 %d, F7 %d)" % (
        len(coil_rows), sum(1 for r in coil_rows if r[5] == "F6"),
        sum(1 for r in coil_rows if r[5] == "F7")))
    lines.append("- measurements: %d (WearCentres.xlsx holds %d readings%s)"
                 % (len(meas_rows), len(wc), "; its own count row says %s" %
                    ", ".join("F%d %s %s" % (k[0], k[1], fmt(v)) for k, v in
                              sorted(wc_counts.items())) if wc_counts else ""))
    lines.append("- profiles: %d rolls, %d points" % (len(prof_by_roll),
                                                     len(prof_rows)))
    lines.append("- distinct rolls: %d; distinct grades: %d%s" % (
        len(rolls), len(grades), " (including 'unknown')" if "unknown" in
        grades else ""))
    lines.append("- split_authors.csv: %d rows (%d train, %d validation); "
                 "labels read: %s" % (
                     len(authors_rows),
                     sum(1 for r in authors_rows if r[3] == "train"),
                     sum(1 for r in authors_rows if r[3] == "validation"),
                     ", ".join("F%d %s %s" % x for x in split_labels)))
    lines.append("- split_time_forward.csv: %d rows (campaigns 1-%d train: "
                 "%d, later validation: %d)" % (
                     len(tf_rows), TIME_FORWARD_LAST_TRAIN,
                     sum(1 for r in tf_rows if r[3] == "train"),
                     sum(1 for r in tf_rows if r[3] == "validation")))
    lines.append("- authors_ann_predictions.csv: %d rows from %s" % (
        len(pred_rows), ", ".join(found) if found else "nothing"))
    for s in sorted(mae):
        lines.append("  - authors' network, %s: mean |predicted - measured| "
                     "= %.2f um over %d readings" % (
                         s, statistics.mean(mae[s]), len(mae[s])))
    if gt_diffs:
        lines.append("  - their 'Ground Truth' vs wear_center_um: max "
                     "|difference| %.4f um over %d readings (their ground "
                     "truth is WearCentres x 1000)" % (max(gt_diffs),
                                                       len(gt_diffs)))
    lines.append("")
    lines.append("## Unit and mapping decisions")
    lines.append("")
    lines.append(
        "- force_kn = FbkStandForce6/7 x 9.80665 (tonnes-force -> kN).\n"
        "- speed_mps = (LEADSPD_Fk + TRAILSPD_Fk) / 2 / 60 (m/min -> m/s); "
        "lead_speed_mps and trail_speed_mps kept.\n"
        "- length_m: F7 = stripLength (length leaving F7); F6 = stripLength "
        "x ga8 / ga7 (mass flow).\n"
        "- thickness: F6 entry ga6, exit ga7; F7 entry ga7, exit ga8 (mm).\n"
        "- temperature_c: FBKTemp_F6 / FBKTemp_F7 (entry of the stand); "
        "exit_temperature_c: FBKTemp_F7 / FBKTemp_F8.\n"
        "- width_mm = ord_Wdt; grade = Grade; shift_mm = WROLL_SHIFT_POS6/7 "
        "as recorded.\n"
        "- lubrication: F6 = 1 if F6OilFlowRate_Ml_min > 0 (Oil_ON___F6 > 0 "
        "when the flow is empty); F7 EMPTY (no sensor).\n"
        "- rolled_at = Date_St1PU_... + offset; seq = order by that time; "
        "started_at = first coil; ended_at = last coil + its LOADDUR_Sec.\n"
        "- mounts: roll_id TOP/BOTIDF6/7 (the roll at the campaign's end); "
        "diameter_mm = F6TWRDia.. of the first coil on it; roll_type and "
        "hardness_hb EMPTY.\n"
        "- wear_center_um = WearCentres (mm) x 1000. **It is a DIAMETER "
        "loss** (fresh minus worn roll diameter at the barrel centre), twice "
        "the radius loss named by docs/data-format.md; kept as is because "
        "the study's published figures were computed on it. measured_at is "
        "EMPTY (the grinder's time is not recorded).\n"
        "- profiles: wear_um = the sheet's 'Top/Bottom Wear, mm' column x "
        "1000 (fresh - worn diameter, with the sheet's own level "
        "correction on some rolls; the column WearCentres was computed "
        "from), the same diameter convention; fresh_minus_worn_um = the "
        "plain difference paired by X; x_mm = X - %g (X from one barrel "
        "end; which end is the drive side is not recorded); measured_at "
        "EMPTY.\n"
        "- extra columns in coils.csv: %s. No Level-2 model output is a "
        "column." % (BARREL_CENTRE_X_MM, ", ".join(COIL_COLUMNS[15:])))
    lines.append("")
    lines.append("## Evidence for the units (computed from this snapshot)")
    lines.append("")
    for e in ev:
        lines.append("- " + e)
    lines.append("")
    lines.append("## Radius or diameter: WearCentres against the profiles")
    lines.append("")
    for e in dia_ev:
        lines.append("- " + e)
    lines.append("- Profiles as written: mean wear_um over |x| <= %g mm "
                 "within 20 um of wear_center_um on %d of %d rolls" % (
                     CENTRE_HALF_WIDTH_MM, agree[0], agree[1]))
    lines.append("")
    lines.append("## Barrel centre of the profiles")
    lines.append("")
    lines.append("- x_mm = X - %g mm for every grid. Left-right asymmetry "
                 "sum((w(c-u) - w(c+u))^2)/range^2 for u = 25..650 mm, "
                 "pooled over the profiles of each worn-profile grid:" %
                 BARREL_CENTRE_X_MM)
    for e in centre_ev:
        lines.append("  - " + e)
    lines.append("")
    lines.append("## Skipped, substituted and flagged items")
    lines.append("")
    if not rep.order:
        lines.append("None.")
    for sec in rep.order:
        items = rep.sections[sec]
        lines.append("### %s (%d)" % (sec, len(items)))
        lines.append("")
        for it in items:
            lines.append("- " + it)
        lines.append("")
    with open(os.path.join(out, "conversion_report.md"), "w",
              encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    return {"campaigns": len(campaigns), "coils": n_coils,
            "passes": len(coil_rows), "measurements": len(meas_rows),
            "profile_points": len(prof_rows), "rolls": len(rolls),
            "grades": len(grades), "seconds": elapsed}


def main(argv=None):
    ap = argparse.ArgumentParser(
        description="Convert the F6/F7 wear study's snapshot to the rollwear "
                    "dataset format (docs/data-format.md).")
    ap.add_argument("--snapshot", required=True,
                    help="folder holding Data/RawData (or Data, or RawData's "
                         "parent)")
    ap.add_argument("--out", required=True,
                    help="output folder (missing or empty)")
    ap.add_argument("--utc-offset", dest="utc_offset", default=None,
                    help="the mill's UTC offset, +HH:MM or -HH:MM (required)")
    ap.add_argument("--strict", action="store_true",
                    help="a row-level drop or substitution is an error")
    ap.add_argument("--processes", type=int, default=2,
                    help=argparse.SUPPRESS)
    # "--utc-offset -05:00" would read the value as an option.
    argv = list(sys.argv[1:] if argv is None else argv)
    for i in range(len(argv) - 1):
        if argv[i] == "--utc-offset" and re.match(r"-\d", argv[i + 1]):
            argv[i:i + 2] = ["--utc-offset=" + argv[i + 1]]
            break
    args = ap.parse_args(argv)
    if args.utc_offset is None:
        sys.stderr.write(
            "convert_study_snapshot: --utc-offset is required: the workbooks "
            "hold the mill's local clock without a time zone and the snapshot "
            "does not record it; give the mill's offset, e.g. --utc-offset "
            "+01:00\n")
        return 2
    try:
        s = convert(args)
    except ConversionError as e:
        sys.stderr.write("convert_study_snapshot: %s\n" % e)
        return 1
    print("campaigns %d, coils %d, passes %d, measurements %d, profile points "
          "%d, rolls %d, grades %d, %.1f s; report: %s" % (
              s["campaigns"], s["coils"], s["passes"], s["measurements"],
              s["profile_points"], s["rolls"], s["grades"], s["seconds"],
              os.path.join(args.out, "conversion_report.md")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
