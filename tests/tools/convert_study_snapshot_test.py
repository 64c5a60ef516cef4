#!/usr/bin/python3
"""Tests service/tools/convert_study_snapshot.py on a small synthetic snapshot.

The workbooks are built here with openpyxl in a temporary folder (three
campaigns, a handful of coils, only the columns the converter reads plus one
Level-2 model column that must not reach the dataset); no real data is used.
Run by ctest as `tools.convert_study_snapshot` (tests/CMakeLists.txt) with
Debian's /usr/bin/python3 and python3-openpyxl.
"""
import csv
import datetime as dt
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

try:
    import openpyxl
except ImportError:
    raise SystemExit("FAIL: python3-openpyxl is required by "
                     "tests/tools/convert_study_snapshot_test.py "
                     "(apt-get install python3-openpyxl)")

HERE = os.path.dirname(os.path.abspath(__file__))
CONVERTER = os.path.join(HERE, "..", "..", "service", "tools",
                         "convert_study_snapshot.py")

TIME_COL = "Date_St1PU_CampaignStartTimeWasReferencedByUsingThisColumn_"
CAMP_COLUMNS = [
    "CampaingNo_Stand6", "Serial", TIME_COL, "NOLOADDUR_Sec", "LOADDUR_Sec",
    "NormHard", "stripLength", "CoilWt", "WaterTemp_OC", "TOPIDF6",
    "BOTIDF6", "TOPIDF7", "BOTIDF7", "meas_FMETemp", "MeasuredFMXT",
    "FBKTemp_F1", "FBKTemp_F6", "FBKTemp_F7", "FBKTemp_F8", "ga6", "ga7",
    "ga8", "LEADSPD_F6", "TRAILSPD_F6", "LEADSPD_F7", "TRAILSPD_F7",
    "F6OilFlowRate_Ml_min", "BURWaterFlowL_min_F6", "Oil_ON___F6", "Grade",
    "ord_ga", "ord_Wdt", "FbkStandForce6", "FbkStandForce7",
    "RollBendingForce6", "RollBendingForce7", "WROLL_SHIFT_POS6",
    "WROLL_SHIFT_POS7", "F6TWRDia", "F6BWRDia", "F7TWRDia", "F7BWRDia",
    # A Level-2 model output: must never become a dataset column.
    "CALC_WROLL_WEAR_CRWN6",
]


def coil(camp, serial, t, force6=1000.0, ga=(5.0, 4.0, 3.2), oil=50.0,
         ids=(101, 102, 201, 202), grade="CC040", length=500.0):
    """One 'Camp Data' row as a dict."""
    return {
        "CampaingNo_Stand6": camp, "Serial": serial, TIME_COL: t,
        "NOLOADDUR_Sec": 30, "LOADDUR_Sec": 45, "NormHard": 1.2,
        "stripLength": length, "CoilWt": 15000, "WaterTemp_OC": 30,
        "TOPIDF6": ids[0], "BOTIDF6": ids[1], "TOPIDF7": ids[2],
        "BOTIDF7": ids[3], "meas_FMETemp": 1050.0, "MeasuredFMXT": 900.0,
        "FBKTemp_F1": 1040.0, "FBKTemp_F6": 940.0, "FBKTemp_F7": 925.0,
        "FBKTemp_F8": 910.0, "ga6": ga[0], "ga7": ga[1], "ga8": ga[2],
        "LEADSPD_F6": 480.0, "TRAILSPD_F6": 600.0, "LEADSPD_F7": 600.0,
        "TRAILSPD_F7": 720.0, "F6OilFlowRate_Ml_min": oil,
        "BURWaterFlowL_min_F6": 45.0, "Oil_ON___F6": 30.0 if oil else 0.0,
        "Grade": grade, "ord_ga": 320, "ord_Wdt": 1200.0,
        "FbkStandForce6": force6, "FbkStandForce7": 900.0,
        "RollBendingForce6": 60.0, "RollBendingForce7": 50.0,
        "WROLL_SHIFT_POS6": 20, "WROLL_SHIFT_POS7": -20,
        "F6TWRDia": 748.0, "F6BWRDia": 748.2, "F7TWRDia": 778.0,
        "F7BWRDia": 778.1, "CALC_WROLL_WEAR_CRWN6": 0.123,
    }


def add_camp_sheet(wb, rows):
    ws = wb.create_sheet("Camp Data")
    ws.append(CAMP_COLUMNS)
    for r in rows:
        ws.append([r[c] for c in CAMP_COLUMNS])


def add_profile_sheet(wb, name, fresh_dia, wear_mm, sheet_wear=None):
    """An f6/f7 sheet: 65 points X = 110..1710 for top and bottom.

    The worn profile is fresh - wear; the sheet's 'Wear, mm' column holds
    sheet_wear (a function of the point index) or fresh - worn.
    """
    ws = wb.create_sheet(name)
    titles = [None] * 35
    for base in (0, 20):
        titles[base] = "Real Profile-FIRST FRESH GROUND "
        titles[base + 4] = "Real Profile-WORN"
        titles[base + 8] = "Real Profile - 2ND FRESH GROUND"
    ws.append(titles)
    head = [None] * 35
    for base, label in ((0, "Top Wear, mm"), (20, "Bottom Wear, mm")):
        for k in (0, 4, 8):
            head[base + k], head[base + k + 1], head[base + k + 2] = (
                "P", "X", "Real Profile")
        head[base + 12] = label
    ws.append(head)
    for i in range(65):
        x = 110 + 25 * i
        row = [None] * 35
        for base in (0, 20):
            w = wear_mm(i)
            row[base], row[base + 1], row[base + 2] = i, x, fresh_dia
            row[base + 4], row[base + 5], row[base + 6] = i, x, fresh_dia - w
            row[base + 8], row[base + 9], row[base + 10] = (
                i, x, fresh_dia - 0.4)
            row[base + 12] = sheet_wear(i) if sheet_wear else w
        ws.append(row)


def hump(i):
    """A wear profile: 0.1 mm over the centre, falling to 0 at the ends."""
    return 0.1 * max(0.0, 1.0 - (abs(i - 32) / 32.0) ** 4)


def write_workbook(path, camp_rows, profile_sheets=("f6", "f7"),
                   f7_sheet_wear=None):
    wb = openpyxl.Workbook()
    wb.remove(wb.active)
    if "f6" in profile_sheets:
        add_profile_sheet(wb, "f6", 748.0, hump)
    if "f7" in profile_sheets:
        add_profile_sheet(wb, "f7", 778.0, hump, f7_sheet_wear)
    if camp_rows is not None:
        add_camp_sheet(wb, camp_rows)
    if not wb.sheetnames:
        wb.create_sheet("Sheet1")
    wb.save(path)


def build_snapshot(root, bad_thickness=False, roll_change=True):
    raw = os.path.join(root, "Data", "RawData")
    wp = os.path.join(raw, "Wear_profiles")
    os.makedirs(wp)
    t0 = dt.datetime(2017, 3, 8, 16, 15, 27)
    m = dt.timedelta(minutes=2)
    # Campaign 1: complete; the f7 sheet's wear column holds diameters.
    write_workbook(
        os.path.join(wp, "Camp 1-March 8 2017-4.15pm_OK.xlsx"),
        [coil(1, "A1", t0), coil(1, "A2", t0 + m, force6=1100.0, oil=0.0),
         coil(1, "A3", t0 + 2 * m)],
        f7_sheet_wear=lambda i: 777.9)
    # Campaign 264: rows out of time order, no f7 sheet, a mid-campaign
    # F7 roll change, (optionally) a coil with a zero thickness.
    t1 = dt.datetime(2017, 5, 4, 7, 45, 36)
    rows = [coil(264, "B2", t1 + m, ids=(111, 112, 211, 212)),
            coil(264, "B1", t1, ids=(111, 112, 299, 298) if roll_change
                 else (111, 112, 211, 212)),
            coil(264, "B3", t1 + 2 * m, ids=(111, 112, 211, 212))]
    if bad_thickness:
        rows.append(coil(264, "B4", t1 + 3 * m, ga=(0, 0, 0),
                         ids=(111, 112, 211, 212)))
    write_workbook(os.path.join(wp, "Camp 264-May 4 2017-7.45amOK.xlsx"),
                   rows, profile_sheets=("f6",))
    # Campaign 300: two workbooks; the one without profile sheets and
    # without grades must lose.
    t2 = dt.datetime(2017, 5, 11, 2, 18, 0)
    write_workbook(os.path.join(wp, "Camp 300-May 11 2017-2.18am.xlsx"),
                   [coil(300, "C1", t2, grade=None)], profile_sheets=())
    write_workbook(os.path.join(wp, "Camp 300-May 11 2017-2.18amOK.xlsx"),
                   [coil(300, "C1", t2, grade="EA061")])
    # An Excel lock file.
    with open(os.path.join(wp, "~$Camp 1-March 8 2017-4.15pm_OK.xlsx"),
              "wb") as f:
        f.write(b"\x00" * 165)
    # Centre readings (mm).
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Feuil1"
    ws.append(["nb_valeurs", 4, 4, 3, 3])
    ws.append([None] * 5)
    ws.append(["Num Campagne", "Usure F6 TOP", "Usure F6 BOT",
               "Usure F7 TOP", "Usure F7 BOT"])
    ws.append([None, "mm", "mm", "mm", "mm"])
    ws.append([1, 0.25, 0.2, 0.15, 0.1])
    ws.append([264, 0.3, -0.01, 0.12, None])
    ws.append([300, 0.2, 0.2, 0.2, 0.2])
    ws.append([9, 0.2, 0.2, None, None])  # no workbook
    wb.save(os.path.join(raw, "WearCentres.xlsx"))
    # The authors' split (with the snapshot's typo'd label) and results.
    db = os.path.join(root, "Data", "DataBases")
    os.makedirs(db)
    with open(os.path.join(db, "campaign_split.txt"), "w") as f:
        f.write("f6t,Train:\r\n[1,300]\r\n\r\n6t,Dev:\r\n[264]\r\n\r\n"
                "f6b,Train:\r\n[1]\r\n\r\nf6b,Dev:\r\n[264,300]\r\n\r\n"
                "f7t,Train:\r\n[1,264]\r\n\r\nf7t,Dev:\r\n[300]\r\n\r\n"
                "f7b,Train:\r\n[1]\r\n\r\nf7b,Dev:\r\n[300]\r\n")
    mdir = os.path.join(root, "Data", "Outputs", "Models", "f6_top")
    os.makedirs(mdir)
    with open(os.path.join(mdir, "results_val.csv"), "w",
              encoding="utf-8") as f:
        f.write("N\u00b0 CAMPAIGN,Prediction (\u00b5m),Ground Truth "
                "(\u00b5m)\r\n264,280.5,300\r\n")
    return root


def read_csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def run(args):
    return subprocess.run([sys.executable, CONVERTER] + args,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, timeout=300)


class ConvertTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="convert_snapshot_test_")
        cls.snap = build_snapshot(os.path.join(cls.tmp, "snap"))
        cls.out = os.path.join(cls.tmp, "out")
        cls.result = run(["--snapshot", cls.snap, "--out", cls.out,
                          "--utc-offset", "+02:00"])
        if cls.result.returncode != 0:
            raise AssertionError("conversion failed: " + cls.result.stderr)
        with open(os.path.join(cls.out, "conversion_report.md"),
                  encoding="utf-8") as f:
            cls.report = f.read()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def coils(self):
        return read_csv(os.path.join(self.out, "coils.csv"))

    def pass_of(self, coil_id, stand):
        rows = [r for r in self.coils()
                if r["coil_id"] == coil_id and r["stand"] == stand]
        self.assertEqual(len(rows), 1, (coil_id, stand))
        return rows[0]

    def test_writes_every_file(self):
        for name in ("campaigns.csv", "mounts.csv", "coils.csv",
                     "measurements.csv", "profiles.csv", "split_authors.csv",
                     "split_time_forward.csv", "authors_ann_predictions.csv",
                     "conversion_report.md"):
            self.assertTrue(os.path.isfile(os.path.join(self.out, name)),
                            name)

    def test_force_is_tonnes_force(self):
        self.assertAlmostEqual(float(self.pass_of("A1", "F6")["force_kn"]),
                               9806.65, places=6)
        self.assertAlmostEqual(float(self.pass_of("A2", "F6")["force_kn"]),
                               1100 * 9.80665, places=6)
        self.assertAlmostEqual(float(self.pass_of("A1", "F7")["force_kn"]),
                               900 * 9.80665, places=6)

    def test_speed_is_m_per_min(self):
        # (600 + 720) / 2 m/min = 11 m/s at F7, (480 + 600) / 2 = 9 at F6.
        self.assertAlmostEqual(float(self.pass_of("A1", "F7")["speed_mps"]),
                               11.0)
        self.assertAlmostEqual(float(self.pass_of("A1", "F6")["speed_mps"]),
                               9.0)
        self.assertAlmostEqual(
            float(self.pass_of("A1", "F7")["lead_speed_mps"]), 10.0)

    def test_lengths_and_thicknesses(self):
        f6, f7 = self.pass_of("A1", "F6"), self.pass_of("A1", "F7")
        self.assertAlmostEqual(float(f7["length_m"]), 500.0)
        # Mass flow: 500 m x 3.2 / 4.0 leaving F6.
        self.assertAlmostEqual(float(f6["length_m"]), 400.0)
        self.assertEqual((f6["entry_thickness_mm"], f6["exit_thickness_mm"]),
                         ("5", "4"))
        self.assertEqual((f7["entry_thickness_mm"], f7["exit_thickness_mm"]),
                         ("4", "3.2"))
        self.assertEqual(f6["temperature_c"], "940")
        self.assertEqual(f7["temperature_c"], "925")
        self.assertEqual(f7["exit_temperature_c"], "910")

    def test_lubrication(self):
        self.assertEqual(self.pass_of("A1", "F6")["lubrication"], "1")
        self.assertEqual(self.pass_of("A2", "F6")["lubrication"], "0")
        for r in self.coils():
            if r["stand"] == "F7":
                self.assertEqual(r["lubrication"], "", r)

    def test_no_level2_column(self):
        with open(os.path.join(self.out, "coils.csv"), encoding="utf-8") as f:
            header = f.readline().strip().split(",")
        for h in header:
            for bad in ("CALC_", "LEARN_", "WRCrown", "COEFF", "WEARKm"):
                self.assertNotIn(bad, h)
        with open(os.path.join(self.out, "coils.csv"), encoding="utf-8") as f:
            self.assertNotIn("0.123", f.read())
        for extra in ("coil_weight_kg", "roll_bending_force", "load_time_s",
                      "idle_time_s", "strip_hardness_index",
                      "water_temperature_c"):
            self.assertIn(extra, header)

    def test_offsets_written_on_every_timestamp(self):
        for r in self.coils():
            self.assertTrue(r["rolled_at"].endswith("+02:00"), r)
        self.assertEqual(self.pass_of("A1", "F6")["rolled_at"],
                         "2017-03-08T16:15:27+02:00")
        for r in read_csv(os.path.join(self.out, "campaigns.csv")):
            self.assertTrue(r["started_at"].endswith("+02:00"))
            self.assertTrue(r["ended_at"].endswith("+02:00"))
        camp1 = [r for r in read_csv(os.path.join(self.out, "campaigns.csv"))
                 if r["campaign_id"] == "1"][0]
        # The last coil at 16:19:27 plus its 45 s load time.
        self.assertEqual(camp1["ended_at"], "2017-03-08T16:20:12+02:00")

    def test_utc_offset_is_required(self):
        r = run(["--snapshot", self.snap, "--out",
                 os.path.join(self.tmp, "no_offset")])
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--utc-offset is required", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "no_offset")))
        r = run(["--snapshot", self.snap, "--out",
                 os.path.join(self.tmp, "bad_offset"), "--utc-offset", "2"])
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("+HH:MM", r.stderr)

    def test_negative_offset(self):
        out = os.path.join(self.tmp, "negative_offset")
        r = run(["--snapshot", os.path.join(self.snap, "Data"), "--out", out,
                 "--utc-offset", "-05:30"])
        self.assertEqual(r.returncode, 0, r.stderr)
        for row in read_csv(os.path.join(out, "campaigns.csv")):
            self.assertTrue(row["started_at"].endswith("-05:30"), row)

    def test_output_must_be_empty(self):
        busy = os.path.join(self.tmp, "busy")
        os.makedirs(busy)
        open(os.path.join(busy, "x"), "w").close()
        r = run(["--snapshot", self.snap, "--out", busy, "--utc-offset",
                 "+00:00"])
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("missing or empty", r.stderr)

    def test_measurements_mm_to_um(self):
        rows = {(r["campaign_id"], r["stand"], r["position"]): r
                for r in read_csv(os.path.join(self.out,
                                               "measurements.csv"))}
        self.assertAlmostEqual(float(rows[("1", "F6", "top")]
                                     ["wear_center_um"]), 250.0)
        self.assertAlmostEqual(float(rows[("264", "F6", "bottom")]
                                     ["wear_center_um"]), -10.0)
        self.assertEqual(rows[("1", "F6", "top")]["roll_id"], "101")
        self.assertEqual(rows[("1", "F6", "top")]["measured_at"], "")
        self.assertNotIn(("264", "F7", "bottom"), rows)
        self.assertNotIn(("9", "F6", "top"), rows)
        self.assertIn("campaign 9 F6 top", self.report)
        self.assertIn("negative", self.report)

    def test_profiles(self):
        rows = [r for r in read_csv(os.path.join(self.out, "profiles.csv"))
                if (r["campaign_id"], r["stand"], r["position"]) ==
                ("1", "F6", "top")]
        self.assertEqual(len(rows), 65)
        centre = [r for r in rows if float(r["x_mm"]) == 0.0]
        self.assertEqual(len(centre), 1)
        # 0.1 mm at the centre -> 100 um, same convention as the reading.
        self.assertAlmostEqual(float(centre[0]["wear_um"]), 100.0, places=3)
        self.assertEqual(float(rows[0]["x_mm"]), 110 - 910)

    def test_profile_holding_diameters_is_listed(self):
        rows = [r for r in read_csv(os.path.join(self.out, "profiles.csv"))
                if (r["campaign_id"], r["stand"]) == ("1", "F7")]
        self.assertTrue(rows)  # written, not fixed
        self.assertAlmostEqual(float(rows[0]["wear_um"]), 777900.0)
        self.assertIn("Profiles whose values are not plausible wear",
                      self.report)
        self.assertIn("Camp 1-March 8 2017-4.15pm_OK.xlsx sheet f7 top",
                      self.report)

    def test_missing_sheet_reported_not_fatal(self):
        self.assertIn("Camp 264-May 4 2017-7.45amOK.xlsx: no sheet f7",
                      self.report)
        camp264 = [r for r in self.coils() if r["campaign_id"] == "264"]
        self.assertTrue(camp264)
        self.assertFalse([r for r in read_csv(os.path.join(
            self.out, "profiles.csv")) if r["campaign_id"] == "264" and
            r["stand"] == "F7"])

    def test_lock_file_skipped(self):
        self.assertIn("~$Camp 1-March 8 2017-4.15pm_OK.xlsx: Excel lock file",
                      self.report)

    def test_seq_by_time_and_roll_change(self):
        seq = {r["coil_id"]: r["seq"] for r in self.coils()
               if r["campaign_id"] == "264"}
        self.assertEqual(seq, {"B1": "1", "B2": "2", "B3": "3"})
        # B1 ran on F7 rolls 299/298, not the campaign's final 211/212.
        stands = sorted(r["stand"] for r in self.coils()
                        if r["coil_id"] == "B1")
        self.assertEqual(stands, ["F6"])
        mounts = {(r["campaign_id"], r["stand"], r["position"]): r
                  for r in read_csv(os.path.join(self.out, "mounts.csv"))}
        self.assertEqual(mounts[("264", "F7", "top")]["roll_id"], "211")
        self.assertEqual(mounts[("264", "F7", "top")]["roll_type"], "")
        self.assertEqual(mounts[("264", "F7", "top")]["hardness_hb"], "")
        self.assertEqual(mounts[("1", "F6", "top")]["diameter_mm"], "748")
        self.assertIn("TOPIDF7: 299 x1 -> 211 x2", self.report)

    def test_duplicate_workbook_rule(self):
        self.assertIn("campaign 300: 'Camp 300-May 11 2017-2.18amOK.xlsx' "
                      "used, 'Camp 300-May 11 2017-2.18am.xlsx' not used",
                      self.report)
        c1 = self.pass_of("C1", "F6")
        self.assertEqual(c1["grade"], "EA061")

    def test_splits(self):
        auth = {(r["campaign_id"], r["stand"], r["position"]): r["set"]
                for r in read_csv(os.path.join(self.out,
                                               "split_authors.csv"))}
        self.assertEqual(auth[("264", "F6", "top")], "validation")  # "6t,Dev"
        self.assertEqual(auth[("1", "F6", "top")], "train")
        self.assertEqual(auth[("300", "F7", "bottom")], "validation")
        tf = {(r["campaign_id"], r["stand"], r["position"]): r["set"]
              for r in read_csv(os.path.join(self.out,
                                             "split_time_forward.csv"))}
        self.assertEqual(tf[("1", "F6", "top")], "train")
        self.assertEqual(tf[("264", "F6", "top")], "validation")
        meas = read_csv(os.path.join(self.out, "measurements.csv"))
        self.assertEqual(len(tf), len(meas))
        self.assertIn("'6t,Dev' read as F6 top validation", self.report)

    def test_authors_predictions(self):
        rows = read_csv(os.path.join(self.out,
                                     "authors_ann_predictions.csv"))
        self.assertEqual(len(rows), 1)
        r = rows[0]
        self.assertEqual((r["campaign_id"], r["stand"], r["position"],
                          r["roll_id"], r["set"]),
                         ("264", "F6", "top", "111", "validation"))
        self.assertEqual((r["measured_um"], r["predicted_um"]),
                         ("300", "280.5"))
        self.assertEqual((r["lo_um"], r["hi_um"]), ("", ""))

    def test_bad_row_skipped_or_refused_under_strict(self):
        snap = build_snapshot(os.path.join(self.tmp, "snap_bad"),
                              bad_thickness=True, roll_change=False)
        out = os.path.join(self.tmp, "out_bad")
        r = run(["--snapshot", snap, "--out", out, "--utc-offset", "+00:00"])
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "conversion_report.md"),
                  encoding="utf-8") as f:
            report = f.read()
        self.assertIn("Camp 264-May 4 2017-7.45amOK.xlsx sheet 'Camp Data' "
                      "row 5: F6 pass skipped: column ga6 0 <= 0", report)
        self.assertFalse([c for c in read_csv(os.path.join(out, "coils.csv"))
                          if c["coil_id"] == "B4"])
        r = run(["--snapshot", snap, "--out",
                 os.path.join(self.tmp, "out_strict"), "--utc-offset",
                 "+00:00", "--strict"])
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("Camp 264-May 4 2017-7.45amOK.xlsx sheet 'Camp Data' "
                      "row 5: F6 pass skipped: column ga6 0 <= 0", r.stderr)
        self.assertIn("--strict", r.stderr)


if __name__ == "__main__":
    unittest.main()
