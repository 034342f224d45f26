"""pipelines/Snakefile: builds two generated samples through simplify -> parameterize ->
texture-refine -> pack with --cores 2; a second run has nothing to do (also with another thread
count); changing one stage's flag plans only that stage and the ones after it, and running it
rewrites only their outputs; the agsphere target plans agsphere-build and the stages after it; golden_update then golden_check passes, and a missing golden file
fails it. The cluster path (Snakemake's generic --cluster submission through
pipelines/cluster/local-submit.sh and its status script) builds the same bytes, and a failing job
fails the run."""
import json
import os
import re
import shutil
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

NAMES = ["colors", "seamball"]
SUFFIXES = ["mr", "uv", "tex", "lod"]
# Fast flags: two levels, small atlases and pages.
CONFIG = {
    "ratios": "0.5,0.1",
    "parameterize_flags": "--size 128",
    "refine_flags": "--sizes 64,128",
    "pack_flags": "--max-size 128",
    "threads": "2",
    "compare_flags": "--views 4 --resolution 64 --samples 10000",
}
SNAKEFILE = os.path.join(lt.SOURCE, "pipelines/Snakefile")
LOCAL_PROFILE = os.path.join(lt.SOURCE, "pipelines/cluster/local")


def snakemake(workdir, out, *extra, profile=None, **config):
    """Runs snakemake in workdir on the samples of setUpClass, writing into out; config overrides
    CONFIG (a None value drops the key). Returns the CompletedProcess (stdout and stderr together)."""
    settings = dict(CONFIG, **{"in": Snakemake.inputs, "out": out, "bin": lt.BIN})
    settings.update(config)
    settings = {k: v for k, v in settings.items() if v is not None}
    cmd = ["snakemake", "-s", SNAKEFILE, "-d", workdir]
    cmd += ["--profile", profile] if profile else ["--cores", "2"]
    # --config takes every word after it, so targets and flags come first.
    cmd += list(extra) + ["--config"] + ["%s=%s" % kv for kv in sorted(settings.items())]
    # Snakemake 7 polls cluster jobs every 10 s, every second when CI=true.
    env = dict(os.environ, CI="true")
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=900, env=env)


def planned_jobs(p):
    """{rule: count} from a dry run's "Job stats" table; {} when there is nothing to be done."""
    if "Nothing to be done" in p.stdout:
        return {}
    table = p.stdout.split("Job stats:", 1)[1]
    jobs = {}
    for line in table.splitlines()[3:]:
        m = re.match(r"(\w+)\s+(\d+)", line)
        if not m or m.group(1) == "total":
            break
        jobs[m.group(1)] = int(m.group(2))
    return jobs


def outputs(out, suffixes=SUFFIXES):
    return [os.path.join(out, "%s.%s.%s" % (n, s, ext)) for s in suffixes for n in NAMES for ext in ("glb", "json")]


def mtimes(files):
    return [os.stat(f).st_mtime_ns for f in files]


class Snakemake(unittest.TestCase):
    inputs = ""

    @classmethod
    def setUpClass(cls):
        cls.work = lt.work_dir()
        samples = lt.make_samples(os.path.join(cls.work, "samples"))
        Snakemake.inputs = os.path.join(cls.work, "in")
        os.makedirs(Snakemake.inputs)
        for n in NAMES:
            shutil.copy(os.path.join(samples, n + ".glb"), Snakemake.inputs)
        # The reference build, kept as bytes: the other tests compare with it.
        cls.local = os.path.join(cls.work, "local")
        cls.out = os.path.join(cls.local, "out")
        os.makedirs(cls.local)
        cls.first = snakemake(cls.local, cls.out)
        cls.reference = {}
        if cls.first.returncode == 0:
            for f in outputs(cls.out, ["mr", "uv", "tex", "lod"]):
                if f.endswith(".glb"):
                    with open(f, "rb") as fh:
                        cls.reference[os.path.basename(f)] = fh.read()

    def assertBuilt(self, p, out):
        self.assertEqual(p.returncode, 0, p.stdout[-3000:])
        for f in outputs(out):
            self.assertGreater(os.path.getsize(f), 0, f)
        for n in NAMES:
            with open(os.path.join(out, n + ".lod.json")) as r:
                report = json.load(r)
            self.assertEqual(report["tool"], "pack")
            self.assertEqual(len(report["levels"]), 3, n)  # LOD0 + the two ratios

    def test_local_incremental(self):
        self.assertBuilt(self.first, self.out)

        # A second run has nothing to do, whatever the thread count.
        for threads in ("2", "1"):
            p = snakemake(self.local, self.out, "-n", threads=threads)
            self.assertEqual(p.returncode, 0, p.stdout[-3000:])
            self.assertEqual(planned_jobs(p), {}, p.stdout[-3000:])

        # A flag plans only its stage and the stages after it.
        p = snakemake(self.local, self.out, "-n", pack_flags="--max-size 64")
        self.assertEqual(planned_jobs(p), {"pack": 2, "all": 1}, p.stdout[-3000:])
        p = snakemake(self.local, self.out, "-n", parameterize_flags="--size 64")
        self.assertEqual(planned_jobs(p), {"parameterize": 2, "refine": 2, "pack": 2, "all": 1}, p.stdout[-3000:])
        p = snakemake(self.local, self.out, "-n", ratios="0.5,0.2")
        self.assertEqual(planned_jobs(p), {"simplify": 2, "parameterize": 2, "refine": 2, "pack": 2, "all": 1})

        # The agsphere front end replaces simplify with agsphere-build and reuses the other stages.
        p = snakemake(self.local, self.out, "-n", "agsphere")
        self.assertEqual(planned_jobs(p), {"agsphere_build": 2, "parameterize": 2, "refine": 2, "pack": 2,
                                           "agsphere": 1}, p.stdout[-3000:])

        # Without `in`, make-samples writes the Makefile's four samples first.
        p = snakemake(self.local, os.path.join(self.work, "from-samples"), "-n", **{"in": None})
        self.assertEqual(planned_jobs(p), {"samples": 1, "simplify": 4, "parameterize": 4, "refine": 4, "pack": 4,
                                           "all": 1}, p.stdout[-3000:])

        # Running the pack change rewrites pack's outputs only; going back restores the same bytes.
        upstream = outputs(self.out, ["mr", "uv", "tex"])
        before = mtimes(upstream)
        lod = os.path.join(self.out, "colors.lod.glb")
        lod_before = os.stat(lod).st_mtime_ns
        p = snakemake(self.local, self.out, pack_flags="--max-size 64")
        self.assertEqual(p.returncode, 0, p.stdout[-3000:])
        self.assertEqual(before, mtimes(upstream))
        self.assertNotEqual(lod_before, os.stat(lod).st_mtime_ns)
        self.assertEqual(planned_jobs(snakemake(self.local, self.out, "-n", pack_flags="--max-size 64")), {})
        p = snakemake(self.local, self.out)
        self.assertEqual(p.returncode, 0, p.stdout[-3000:])
        self.assertEqual(before, mtimes(upstream))
        with open(lod, "rb") as f:
            self.assertEqual(f.read(), self.reference["colors.lod.glb"])

        # Golden files: update, then the check passes level by level; a missing one fails it.
        golden = os.path.join(self.work, "golden")
        p = snakemake(self.local, self.out, "golden_update", golden=golden)
        self.assertEqual(p.returncode, 0, p.stdout[-3000:])
        p = snakemake(self.local, self.out, "golden_check", golden=golden)
        self.assertEqual(p.returncode, 0, p.stdout[-3000:])
        self.assertEqual(len(re.findall(r"golden-check: \S+ lod \d ok", p.stdout)), 3 * len(NAMES), p.stdout)
        os.remove(os.path.join(golden, "seamball.lod.glb"))
        p = snakemake(self.local, self.out, "golden_check", golden=golden)
        self.assertNotEqual(p.returncode, 0, p.stdout[-3000:])
        self.assertIn("seamball.lod.glb missing (run golden_update)", p.stdout)

    def test_cluster_submission(self):
        self.assertEqual(self.first.returncode, 0, "the local build failed: " + self.first.stdout[-3000:])
        workdir = os.path.join(self.work, "cluster")
        out = os.path.join(workdir, "out")
        os.makedirs(workdir)
        p = snakemake(workdir, out, profile=LOCAL_PROFILE)
        self.assertBuilt(p, out)
        # Every stage job went through local-submit.sh (the local rules did not).
        submitted = re.findall(r"Submitted job \d+ with external jobid '(job\.\w+)'", p.stdout)
        self.assertEqual(len(submitted), len(NAMES) * len(SUFFIXES), p.stdout[-3000:])
        for job in submitted:
            with open(os.path.join(workdir, ".snakemake/local-cluster", job, "rc")) as f:
                self.assertEqual(f.read().strip(), "0", job)
        for name, data in sorted(self.reference.items()):
            with open(os.path.join(out, name), "rb") as f:
                self.assertEqual(f.read(), data, name + " differs from the local build")
        self.assertEqual(planned_jobs(snakemake(workdir, out, "-n", profile=LOCAL_PROFILE)), {})

        # A job that fails on the "cluster" fails the run, and its stderr says why.
        p = snakemake(workdir, out, profile=LOCAL_PROFILE, pack_flags="--no-such-flag")
        self.assertNotEqual(p.returncode, 0, p.stdout[-3000:])
        failed = re.findall(r"Submitted job \d+ with external jobid '(job\.\w+)'", p.stdout)
        self.assertTrue(failed, p.stdout[-3000:])
        with open(os.path.join(workdir, ".snakemake/local-cluster", failed[0], "stderr")) as f:
            self.assertIn("--no-such-flag", f.read())

    def test_local_scheduler_scripts(self):
        """local-submit.sh, local-status.sh and local-cancel.sh as a scheduler: a job id, running
        until the job ends, success or failed from its exit code, cancel ends the whole job."""
        cluster = os.path.join(lt.SOURCE, "pipelines/cluster")
        workdir = lt.work_dir("scheduler")

        def script(name, *args):
            return subprocess.run([os.path.join(cluster, name)] + list(args), cwd=workdir, stdout=subprocess.PIPE,
                                  text=True, check=True, timeout=60).stdout.strip()

        def wait(job):
            for _ in range(100):
                status = script("local-status.sh", job)
                if status != "running":
                    return status
                time.sleep(0.1)
            return status

        for body, expected in (("exit 0", "success"), ("exit 3", "failed")):
            path = os.path.join(workdir, "job.sh")
            with open(path, "w") as f:
                f.write("#!/bin/sh\necho out; %s\n" % body)
            job = script("local-submit.sh", path)
            self.assertEqual(wait(job), expected)
            with open(os.path.join(workdir, ".snakemake/local-cluster", job, "stdout")) as f:
                self.assertEqual(f.read(), "out\n")

        # A job that would run for a minute, with a child: cancel ends both.
        with open(path, "w") as f:
            f.write("#!/bin/sh\nsleep 60 & sleep 61\n")
        job = script("local-submit.sh", path)
        self.assertEqual(script("local-status.sh", job), "running")
        with open(os.path.join(workdir, ".snakemake/local-cluster", job, "pid")) as f:
            group = int(f.read())
        script("local-cancel.sh", job)
        self.assertEqual(wait(job), "failed")
        for _ in range(50):
            alive = subprocess.run(["pgrep", "-g", str(group)], stdout=subprocess.PIPE, text=True).stdout.split()
            if not alive:
                break
            time.sleep(0.1)
        self.assertEqual(alive, [], "processes of the cancelled job remain")


if __name__ == "__main__":
    tools = ("make-samples", "simplify", "parameterize", "texture-refine", "pack", "compare")
    missing = [t for t in tools if not os.path.exists(lt.tool(t))]
    if missing:
        lt.skip("needs the built tools in LODBAKE_BIN (missing: %s)" % ", ".join(missing))
    if shutil.which("snakemake") is None:
        lt.skip("snakemake is missing (apt-get install snakemake; scripts/setup-debian.sh)")
    if shutil.which("setsid") is None:
        lt.skip("setsid is missing (util-linux), which pipelines/cluster/local-submit.sh needs")
    unittest.main()
