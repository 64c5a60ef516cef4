#!/usr/bin/env python3
"""Keeps docs/architecture.md's folder table true and the code's sizes in bounds.

    python3 .ci/check_tree.py [--write] [REPO_ROOT]

Two checks; exit 1 with one line per finding when either fails (CTest
runs this as `tools.check_tree`, so CI's readme and asan phases fail on it):

1. The folder table of docs/architecture.md (the rows whose first cell is a
   `folder` in backticks): its `files` and `lines` columns must be the
   `.h` and `.cc` files directly in that folder and their `wc -l` total,
   and its `may include` column the folders .ci/check_layers.sh allows that
   folder (itself left out). For core/ folders, every header of the folder
   must be named (in backticks) in the row's last column. `--write`
   rewrites the three generated columns in place (the text column is
   yours); the naming check cannot be written, only fixed by hand.

2. Sizes, in the product's code (core/, storage/, engine/, api/, service/; tests,
   benchmarks and fuzz targets are not checked): a file of more than 600
   lines, or a function defined at namespace scope whose definition spans
   more than 80 lines, fails unless .ci/size_allowlist.txt lists it with a
   bound it stays within. An allow-list entry that no longer matches an
   over-long file or function fails too (the list only shrinks).

   A function is found by the Google style this code follows: a definition
   at namespace scope starts at column 0 (namespaces do not indent) and
   its body closes with a `}` at column 0. Functions defined inside a class
   body are not measured. Python 3 standard library only.
"""
import os
import re
import sys

FILE_LIMIT = 600
FUNCTION_LIMIT = 80
PRODUCT_DIRS = ("core", "storage", "engine", "api", "service")
DOC = "docs/architecture.md"
ALLOWLIST = ".ci/size_allowlist.txt"
LAYERS = ".ci/check_layers.sh"
NOT_A_FUNCTION = ("namespace", "}", "#", "//", "/*", "class ", "struct ",
                  "enum ", "union ", "using ", "extern ", "typedef",
                  "static_assert")


def source_lines(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    return lines


def folder_sources(root, folder):
    d = os.path.join(root, folder)
    return sorted(f for f in os.listdir(d)
                  if f.endswith((".h", ".cc")) and os.path.isfile(os.path.join(d, f)))


def allowed_includes(root):
    """folder -> the folders it may include, from check_layers.sh's map."""
    text = open(os.path.join(root, LAYERS), encoding="utf-8").read()
    out = {}
    for m in re.finditer(r'^\s*\[([a-z/]+)\]="([^"]*)"', text, re.M):
        out[m.group(1)] = m.group(2).split()
    return out


def short(folder):
    return folder.split("/", 1)[1] if folder.startswith("core/") else folder


def may_include_cell(folder, allowed):
    layer = folder if folder in allowed else folder.split("/")[0]
    name = short if folder.startswith("core/") else (lambda f: f)
    others = [name(f) for f in allowed.get(layer, []) if f != layer]
    return ", ".join(others) if others else "—"


def check_table(root, write):
    path = os.path.join(root, DOC)
    lines = open(path, encoding="utf-8").read().split("\n")
    allowed = allowed_includes(root)
    findings, rows = [], 0
    row = re.compile(r"^\| `([a-z_/]+)` \| ([0-9,]+) \| ([0-9,]+) \| ([^|]*) \| (.*) \|$")
    for i, line in enumerate(lines):
        m = row.match(line)
        if not m:
            continue
        rows += 1
        folder, text = m.group(1), m.group(5)
        if not os.path.isdir(os.path.join(root, folder)):
            findings.append(f"{DOC}:{i + 1}: `{folder}` is not a folder of the tree")
            continue
        files = folder_sources(root, folder)
        total = sum(len(source_lines(os.path.join(root, folder, f))) for f in files)
        want = (f"{len(files)}", f"{total:,}", may_include_cell(folder, allowed))
        have = (m.group(2), m.group(3), m.group(4).strip())
        if want != have:
            if write:
                lines[i] = f"| `{folder}` | {want[0]} | {want[1]} | {want[2]} | {text} |"
            else:
                findings.append(
                    f"{DOC}:{i + 1}: `{folder}` says files {have[0]}, lines {have[1]}, "
                    f"may include '{have[2]}'; the tree has {want[0]}, {want[1]}, "
                    f"'{want[2]}' (python3 .ci/check_tree.py --write)")
        if folder.startswith("core/"):
            for h in (f for f in files if f.endswith(".h")):
                if f"`{h}`" not in text:
                    findings.append(f"{DOC}:{i + 1}: `{folder}` does not name its header `{h}`")
    if rows == 0:
        findings.append(f"{DOC}: no folder table found")
    named = {m.group(1) for m in map(row.match, lines) if m}
    for layer in PRODUCT_DIRS[1:]:
        if os.path.isdir(os.path.join(root, layer)) and layer not in named:
            findings.append(f"{DOC}: the folder table has no row for `{layer}`")
    if write:
        with open(path, "w", encoding="utf-8") as f:
            f.write("\n".join(lines))
    return findings


def functions(lines):
    """(first line number, name, length in lines) of each namespace-scope definition."""
    out, i = [], 0
    while i < len(lines):
        line = lines[i]
        if line and not line[0].isspace() and "(" in line and not line.startswith(NOT_A_FUNCTION):
            j = i
            while j < len(lines) and j - i < 12 and not lines[j].rstrip().endswith(("{", ";")):
                j += 1
            if j < len(lines) and lines[j].rstrip().endswith("{"):
                k = j + 1
                while k < len(lines) and not lines[k].startswith("}"):
                    k += 1
                name = re.sub(r"\s+", " ", line.split("(")[0]).strip().split(" ")[-1]
                out.append((i + 1, name.lstrip("*&"), k - i + 1))
                i = k + 1
                continue
        i += 1
    return out


def read_allowlist(root):
    entries, findings = {}, []
    path = os.path.join(root, ALLOWLIST)
    for n, raw in enumerate(open(path, encoding="utf-8"), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        parts = line.split()
        if len(parts) != 2 or not parts[1].isdigit():
            findings.append(f"{ALLOWLIST}:{n}: want 'path[:function] max_lines  # why'")
            continue
        entries[parts[0]] = (int(parts[1]), n)
    return entries, findings


def check_sizes(root):
    allow, findings = read_allowlist(root)
    used = set()

    def over(key, size, limit, where, what):
        if key in allow:
            used.add(key)
            bound = allow[key][0]
            if size > bound:
                findings.append(f"{where}: {what} is {size} lines, above its allow-list "
                                f"bound {bound} ({ALLOWLIST}:{allow[key][1]})")
        else:
            findings.append(f"{where}: {what} is {size} lines (limit {limit}): split it")

    for top in PRODUCT_DIRS:
        for dirpath, _, names in os.walk(os.path.join(root, top)):
            for name in sorted(names):
                if not name.endswith((".h", ".cc")):
                    continue
                full = os.path.join(dirpath, name)
                rel = os.path.relpath(full, root)
                lines = source_lines(full)
                if len(lines) > FILE_LIMIT:
                    over(rel, len(lines), FILE_LIMIT, rel, "the file")
                for first, fn, size in functions(lines):
                    if size > FUNCTION_LIMIT:
                        over(f"{rel}:{fn}", size, FUNCTION_LIMIT, f"{rel}:{first}", f"{fn}()")
    for key, (_, n) in allow.items():
        if key not in used:
            findings.append(f"{ALLOWLIST}:{n}: {key} is within the limit now (or gone): "
                            "remove the entry")
    return findings


def main(argv):
    write = "--write" in argv
    rest = [a for a in argv if a != "--write"]
    root = rest[0] if rest else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    findings = check_table(root, write) + check_sizes(root)
    for f in findings:
        print(f)
    if findings:
        print(f"check_tree: {len(findings)} finding(s)")
        return 1
    print("check_tree: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
