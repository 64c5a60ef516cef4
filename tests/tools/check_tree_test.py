#!/usr/bin/env python3
"""Tests of .ci/check_tree.py on small trees this test writes itself.

    python3 tests/tools/check_tree_test.py

Each case builds a miniature repository (a folder table in
docs/architecture.md, a layer map in .ci/check_layers.sh, an allow-list)
and runs the checker as CI does, asserting its exit code and what it names.
"""
import os
import subprocess
import sys
import tempfile
import unittest

CHECKER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".ci",
                       "check_tree.py")

LAYERS = """declare -A allowed=(
  [core/base]="core/base"
  [core/model]="core/base core/model"
  [storage]="core storage"
)
"""


def function(name, body_lines):
    body = "".join(f"  x += {i};\n" for i in range(body_lines))
    return f"int {name}(int x) {{\n{body}  return x;\n}}\n"


class CheckTreeTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = self.tmp.name
        self.write(".ci/check_layers.sh", LAYERS)
        self.write(".ci/size_allowlist.txt", "# none\n")
        self.write("core/base/a.h", "#pragma once\nint A();\n")
        self.write("core/base/a.cc", function("A", 3))
        self.write("core/model/m.h", "int M();\n")
        self.write("storage/s.cc", function("S", 2))
        self.write_doc("| `core/base` | 2 | 8 | — | `a.h` |\n"
                       "| `core/model` | 1 | 1 | base | `m.h` |\n"
                       "| `storage` | 1 | 5 | core | the store |\n")

    def tearDown(self):
        self.tmp.cleanup()

    def write(self, rel, text):
        path = os.path.join(self.root, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)

    def write_doc(self, rows):
        self.write("docs/architecture.md",
                   "# A\n\n| folder | files | lines | may include | what it holds |\n"
                   "|---|---|---|---|---|\n" + rows + "\nText.\n")

    def run_checker(self, *args):
        p = subprocess.run([sys.executable, CHECKER, *args, self.root],
                           capture_output=True, text=True, check=False)
        return p.returncode, p.stdout

    def test_a_true_tree_passes(self):
        rc, out = self.run_checker()
        self.assertEqual(rc, 0, out)
        self.assertIn("check_tree: ok", out)

    def test_a_layer_folder_without_a_row_fails(self):
        self.write("engine/e.cc", function("E", 1))
        rc, out = self.run_checker()
        self.assertEqual(rc, 1)
        self.assertIn("the folder table has no row for `engine`", out)

    def test_a_drifted_table_fails_and_write_mends_it(self):
        self.write("core/base/b.cc", function("B", 1))
        rc, out = self.run_checker()
        self.assertEqual(rc, 1)
        self.assertIn("`core/base` says files 2, lines 8", out)
        self.assertIn("the tree has 3, 12", out)
        rc, out = self.run_checker("--write")
        self.assertEqual(rc, 0, out)
        with open(os.path.join(self.root, "docs/architecture.md"), encoding="utf-8") as f:
            self.assertIn("| `core/base` | 3 | 12 | — | `a.h` |", f.read())
        self.assertEqual(self.run_checker()[0], 0)

    def test_a_wrong_may_include_cell_fails(self):
        self.write_doc("| `core/base` | 2 | 8 | — | `a.h` |\n"
                       "| `core/model` | 1 | 1 | — | `m.h` |\n"
                       "| `storage` | 1 | 5 | core | the store |\n")
        rc, out = self.run_checker()
        self.assertEqual(rc, 1)
        self.assertIn("may include '—'", out)
        self.assertIn("'base'", out)

    def test_an_unnamed_core_header_fails(self):
        self.write("core/model/n.h", "int N();\n")
        self.run_checker("--write")
        rc, out = self.run_checker()
        self.assertEqual(rc, 1)
        self.assertIn("`core/model` does not name its header `n.h`", out)

    def test_a_row_for_a_missing_folder_fails(self):
        self.write_doc("| `core/base` | 2 | 8 | — | `a.h` |\n"
                       "| `core/gone` | 1 | 1 | base | x |\n")
        rc, out = self.run_checker()
        self.assertEqual(rc, 1)
        self.assertIn("`core/gone` is not a folder of the tree", out)

    def test_a_long_function_fails_unless_allowed_within_its_bound(self):
        self.write("storage/s.cc", function("S", 79))
        self.run_checker("--write")
        rc, out = self.run_checker()
        self.assertEqual(rc, 1)
        self.assertIn("storage/s.cc:1: S() is 82 lines (limit 80)", out)
        self.write(".ci/size_allowlist.txt", "storage/s.cc:S 82  # table\n")
        self.assertEqual(self.run_checker()[0], 0)
        self.write(".ci/size_allowlist.txt", "storage/s.cc:S 81  # table\n")
        rc, out = self.run_checker()
        self.assertEqual(rc, 1)
        self.assertIn("above its allow-list bound 81", out)

    def test_an_eighty_line_function_and_class_members_pass(self):
        self.write("storage/s.cc", function("S", 77) +
                   "struct T {\n  int F() {\n" + "    ;\n" * 100 + "  }\n};\n")
        self.run_checker("--write")
        self.assertEqual(self.run_checker()[0], 0)

    def test_a_long_file_fails(self):
        self.write("core/model/m.cc", "// x\n" * 601)
        self.run_checker("--write")
        rc, out = self.run_checker()
        self.assertEqual(rc, 1)
        self.assertIn("core/model/m.cc: the file is 601 lines (limit 600)", out)

    def test_a_stale_allow_list_entry_fails(self):
        self.write(".ci/size_allowlist.txt", "storage/s.cc:S 90  # was long\n")
        rc, out = self.run_checker()
        self.assertEqual(rc, 1)
        self.assertIn("storage/s.cc:S is within the limit now (or gone): remove the entry", out)

    def test_tests_are_not_measured(self):
        self.write("tests/core/t.cc", function("T", 200))
        self.assertEqual(self.run_checker()[0], 0)


if __name__ == "__main__":
    unittest.main(verbosity=2)
