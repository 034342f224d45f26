"""docs/lodbake.1, the hand-written man page: it names every flag `lodbake --help` lists and no
flag lodbake does not have, and groff formats it without a warning. (test_install checks that
`cmake --install` puts it in share/man/man1.)"""
import os
import re
import shutil
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from lodbake_test import SOURCE, run, skip, tool  # noqa: E402

MAN = os.path.join(SOURCE, "docs/lodbake.1")


def help_flags():
    """Every flag name of `lodbake --help`: the names at the start of its option lines."""
    flags = set()
    for line in run([tool("lodbake"), "--help"]).stdout.splitlines():
        m = re.match(r"^  (-[^ ].*?)(?:  |$)", line)
        if m:
            for part in m.group(1).split(", "):
                flags.add(part.split(" ")[0])
    return flags


def man_flags():
    """The flags the man page lists as options: the bold names on the line after each .TP."""
    with open(MAN) as f:
        lines = f.read().splitlines()
    flags = set()
    for i, line in enumerate(lines[:-1]):
        if line == ".TP" and lines[i + 1].startswith("\\fB\\-"):
            for name in re.findall(r"\\fB(\\-[^\\ ]*(?:\\-[^\\ ]*)*)\\fR", lines[i + 1]):
                flags.add(name.replace("\\-", "-"))
    return flags


class ManPage(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.exists(tool("lodbake")):
            skip("lodbake is not built")

    def test_every_flag_and_no_other(self):
        in_help, in_man = help_flags(), man_flags()
        self.assertGreater(len(in_help), 60)
        self.assertEqual(sorted(in_help - in_man), [], "flags of --help missing from docs/lodbake.1")
        self.assertEqual(sorted(in_man - in_help), [], "flags in docs/lodbake.1 that lodbake does not have")

    def test_groff_formats_it_cleanly(self):
        if shutil.which("groff") is None:
            self.skipTest("groff is missing")
        p = subprocess.run(["groff", "-man", "-Tutf8", "-ww", "-z", MAN], capture_output=True, text=True)
        self.assertEqual((p.returncode, p.stderr), (0, ""))


if __name__ == "__main__":
    unittest.main()
