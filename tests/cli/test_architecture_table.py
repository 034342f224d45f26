"""docs/architecture.md's concept -> file table names files that exist: every `lib/...` path of
its file column (braces expanded: `collapse_state.{h,cpp}`), and every bare file name beside one
(`ceres_energy.cpp` after `lib/src/param/chart_energy_terms.h` is lib/src/param/ceres_energy.cpp).
Paths with a placeholder (`<tool>`) are checked up to it."""
import glob
import os
import re
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from lodbake_test import SOURCE  # noqa: E402

DOC = os.path.join(SOURCE, "docs/architecture.md")


def table_rows():
    """The file cells of the concept -> file table."""
    with open(DOC, encoding="utf-8") as f:
        text = f.read()
    section = text.split("## Concept → file", 1)[1].split("\n## ", 1)[0]
    cells = []
    for line in section.splitlines():
        if not line.startswith("|") or set(line) <= set("|- "):
            continue
        columns = [c.strip() for c in line.strip().strip("|").split("|")]
        if columns[0] == "concept (DESIGN.md)":
            continue
        cells.append(columns[-1])
    return cells


def expand(path):
    """`a.{h,cpp}` -> [a.h, a.cpp]."""
    m = re.match(r"^(.*)\{([^}]*)\}(.*)$", path)
    if not m:
        return [path]
    return [p for alt in m.group(2).split(",") for p in expand(m.group(1) + alt + m.group(3))]


def cell_paths(cell):
    """The lib/ paths a file cell names: `lib/...` tokens, and bare file names (with an extension)
    in the folder of the lib/ path before them."""
    paths, folder = [], None
    for token in re.findall(r"`([^`]+)`", cell):
        if token.startswith("lib/"):
            paths.extend(expand(token))
            folder = os.path.dirname(token.split("<", 1)[0].rstrip("/") + "/x") if token.endswith("/") else os.path.dirname(token)
        elif folder and "/" not in token and re.search(r"\.[a-z{]", token):
            paths.extend(os.path.join(folder, p) for p in expand(token))
    return paths


def exists(path):
    full = os.path.join(SOURCE, path)
    if "<" in path:  # a placeholder: some file matches the pattern
        return bool(glob.glob(re.sub(r"<[^>]*>", "*", full)))
    return os.path.exists(full)


class ArchitectureTable(unittest.TestCase):
    def test_table_is_found(self):
        rows = table_rows()
        self.assertGreater(len(rows), 50)
        self.assertGreater(sum(len(cell_paths(c)) for c in rows), 100)

    def test_every_lib_path_exists(self):
        missing = [p for c in table_rows() for p in cell_paths(c) if not exists(p)]
        self.assertEqual(missing, [], "paths in docs/architecture.md's concept -> file table that do not exist")

    def test_expansion(self):
        self.assertEqual(cell_paths("`lib/src/a/b.{h,cpp}`, `c.cpp` (`d`)"), ["lib/src/a/b.h", "lib/src/a/b.cpp", "lib/src/a/c.cpp"])
        self.assertEqual(cell_paths("`lib/src/metrics/`"), ["lib/src/metrics/"])


if __name__ == "__main__":
    unittest.main()
