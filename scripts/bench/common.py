"""What every suite shares: the builds under test, the peers, the inputs, timed runs and the results
file. Python 3 stdlib only (the inputs made by scripts/subdivide_textured.py need Debian's
/usr/bin/python3 with numpy, which that script asks for itself)."""
import datetime
import hashlib
import json
import os
import platform
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time

SOURCE = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "../.."))
SHARED = os.path.normpath(os.environ.get("LODBAKE_SHARED", os.path.join(SOURCE, "../shared")))
ASSETS = os.path.join(SHARED, "assets")
NODE_BIN = os.path.join(SOURCE, "scripts/node/node_modules/.bin")
SYSTEM_PYTHON = "/usr/bin/python3"
SCHEMA = "lodbake-bench/1"

sys.path.insert(0, os.path.join(SOURCE, "tests/cli"))
from lodbake_test import Gltf  # noqa: E402

# Named inputs made on demand (cached in the work dir): a shared asset subdivided N times, each
# triangle into 4. Textured sources keep their UVs, normals, material and images
# (subdivide_textured.py); sources without TEXCOORD_0 are subdivided by positions only
# (subdivide_glb.py), as the simplify benchmark always did. Any NAME-xN works; these are aliases.
ALIASES = {
    "duck-1M": "Duck-x4",          # 1,078,272 triangles, one texture
    "duck-4M": "Duck-x5",          # 4.3M
    "avocado-3M": "Avocado-x6",    # 2.8M, three 2048^2 maps
    "avocado-11M": "Avocado-x7",   # 11.2M: the ten-million input
    "bunny-1M": "StanfordBunny-x2",  # 1.1M, geometry only
    "bunny-4M": "StanfordBunny-x3",  # 4.4M
}
SAMPLES = ("hemisphere9", "wall5", "colors", "seamball", "pbrscene", "walker", "drum", "critter", "materials", "facets",
           "variants")


def log(msg):
    print(msg, file=sys.stderr, flush=True)


# ---- the machine and the builds -------------------------------------------------------------------

def loadavg():
    with open("/proc/loadavg") as f:
        return [float(x) for x in f.read().split()[:3]]


def busy_cpu_seconds():
    """CPU seconds the whole machine has spent busy since boot (every core; /proc/stat)."""
    with open("/proc/stat") as f:
        fields = [int(x) for x in f.readline().split()[1:]]
    idle = fields[3] + (fields[4] if len(fields) > 4 else 0)  # idle + iowait
    return (sum(fields[:8]) - idle) / os.sysconf("SC_CLK_TCK")


def own_cpu_seconds():
    """CPU seconds of this harness and every child it has waited for."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def machine():
    info = {"host": socket.gethostname(), "os": platform.platform(), "cores": os.cpu_count(),
            "python": platform.python_version(), "loadAverageStart": loadavg(),
            "busyCpuStart": busy_cpu_seconds(), "ownCpuStart": own_cpu_seconds()}
    try:
        with open("/proc/cpuinfo") as f:
            info["cpu"] = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), None)
        with open("/proc/meminfo") as f:
            info["memoryGiB"] = round(int(f.readline().split()[1]) / 2 ** 20, 1)
    except OSError:
        pass
    return info


def git(args, cwd):
    p = subprocess.run(["git"] + args, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    return p.stdout.strip() if p.returncode == 0 else None


def commit_of(directory):
    """HEAD of the git checkout `directory` lies in, '+dirty' when it has uncommitted changes."""
    head = git(["rev-parse", "HEAD"], directory) if os.path.isdir(directory) else None
    if head and git(["status", "--porcelain", "--untracked-files=no"], directory):
        head += "+dirty"
    return head


class Build:
    """A bin dir of lodbake's tools. Its source commit is read from the CMake cache beside it
    (the checkout's HEAD now, which is the built commit unless the checkout moved since)."""

    def __init__(self, label, bin_dir):
        self.label, self.bin = label, os.path.abspath(bin_dir)
        if not os.path.isfile(self.tool("lodbake")):
            raise SystemExit("bench: %s has no lodbake executable" % self.bin)
        self.source = None
        cache = os.path.join(os.path.dirname(self.bin), "CMakeCache.txt")
        if os.path.isfile(cache):
            with open(cache) as f:
                self.source = next((l.split("=", 1)[1].strip() for l in f if l.startswith("CMAKE_HOME_DIRECTORY")), None)

    def tool(self, name):
        return os.path.join(self.bin, name)

    def describe(self):
        p = subprocess.run([self.tool("lodbake"), "--version"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        built = datetime.datetime.fromtimestamp(os.path.getmtime(self.tool("lodbake")), datetime.timezone.utc)
        return {"label": self.label, "bin": self.bin, "version": p.stdout.strip(), "source": self.source,
                "commit": commit_of(self.source) if self.source else None, "built": built.isoformat(timespec="seconds")}


def builds(args):
    out = [Build("bin", args.bin)]
    if args.against:
        out.append(Build("against", args.against))
    return out


# ---- peers ------------------------------------------------------------------------------------------

def blender():
    return shutil.which("blender")


def peers_available():
    """Peer name -> command maker (src, out, ratio, extra flags) for the peers installed here."""
    found = {}
    if shutil.which("gltfpack"):
        found["gltfpack-debian"] = lambda src, out, r, extra=(): ["gltfpack", "-i", src, "-o", out, "-si", str(r)] + list(extra)
    npm = os.path.join(NODE_BIN, "gltfpack")
    if os.path.exists(npm):
        found["gltfpack-npm"] = lambda src, out, r, extra=(): [npm, "-i", src, "-o", out, "-si", str(r)] + list(extra)
    b = blender()
    if b:
        # Blender's embedded Python takes its library from the first python3 on PATH: a pyenv (or
        # virtualenv) one ahead of Debian's hides Debian's numpy, and the scripts die on import
        # while Blender still exits 0. Blender runs with those directories left out of PATH, and
        # --python-exit-code makes a failing script a failed run.
        path = os.pathsep.join(d for d in os.environ.get("PATH", "").split(os.pathsep)
                               if d and ".pyenv" not in d and "virtualenv" not in d)
        run = ["env", "PATH=" + path, b, "-b", "--factory-startup", "--python-exit-code", "3", "--python"]
        decimate = os.path.join(SOURCE, "scripts/blender_decimate.py")
        found["blender-decimate"] = lambda src, out, r, extra=(): run + [decimate, "--", src, out, str(r)]
        bake = os.path.join(SHARED, "peers/blender_bake.py")
        if os.path.exists(bake):
            found["blender-bake"] = lambda src, out, r, extra=(): run + [bake, "--", src, out, str(r)]
    return found


def peer_versions():
    v = {}
    if shutil.which("gltfpack"):
        p = subprocess.run(["gltfpack"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        v["gltfpack-debian"] = p.stdout.splitlines()[0] if p.stdout else None
    npm = os.path.join(NODE_BIN, "gltfpack")
    if os.path.exists(npm):
        p = subprocess.run([npm], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        v["gltfpack-npm"] = p.stdout.splitlines()[0] if p.stdout else None
    if blender():
        p = subprocess.run([blender(), "--version"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        v["blender"] = p.stdout.splitlines()[0] if p.stdout else None
    return v


# ---- inputs -----------------------------------------------------------------------------------------

def shared_asset_file(name):
    d = os.path.join(ASSETS, name)
    if not os.path.isdir(d):
        return None
    files = sorted(f for f in os.listdir(d) if f.endswith((".glb", ".gltf")))
    return os.path.join(d, files[0]) if files else None


def shared_asset_names():
    if not os.path.isdir(ASSETS):
        return []
    return sorted(n for n in os.listdir(ASSETS) if shared_asset_file(n))


def triangles(path):
    g = Gltf(path)
    return sum(g.mesh_triangle_count(i) for i in range(len(g.json.get("meshes", []))))


def has_texcoords(path):
    g = Gltf(path)
    return any("TEXCOORD_0" in p.get("attributes", {}) for m in g.json.get("meshes", []) for p in m["primitives"])


class Inputs:
    """Resolves input names: a file path, a shared asset (Duck), a generated sample (walker, made by
    --bin's make-samples once per run) or a subdivided asset (Duck-x4, aliases in ALIASES), made once
    and cached in work/inputs."""

    def __init__(self, work, build):
        self.dir = os.path.join(work, "inputs")
        self.build = build
        self.samples_made = False
        os.makedirs(self.dir, exist_ok=True)

    def resolve(self, name):
        """-> (label, path). Raises SystemExit for a name that is none of the above."""
        if os.path.isfile(name):
            return os.path.splitext(os.path.basename(name))[0], os.path.abspath(name)
        if shared_asset_file(name):
            return name, shared_asset_file(name)
        if name in SAMPLES:
            samples = os.path.join(self.dir, "samples")
            if not self.samples_made:  # once per run, by this run's build
                run_checked([self.build.tool("make-samples"), samples])
                self.samples_made = True
            return name, os.path.join(samples, name + ".glb")
        base, _, n = ALIASES.get(name, name).rpartition("-x")
        if base and n.isdigit() and shared_asset_file(base):
            out = os.path.join(self.dir, "%s-x%s.glb" % (base, n))
            if not os.path.exists(out):
                src = shared_asset_file(base)
                script = "subdivide_textured.py" if has_texcoords(src) else "subdivide_glb.py"
                log("bench: making %s (%s %s %s)" % (out, script, os.path.basename(src), n))
                run_checked([SYSTEM_PYTHON, os.path.join(SOURCE, "scripts", script), src, out + ".tmp", n])
                os.rename(out + ".tmp", out)
            return name, out
        raise SystemExit("bench: unknown input %r (a file, a folder of %s, a sample %s, or NAME-xN)"
                         % (name, ASSETS, ", ".join(SAMPLES)))


# ---- running and timing -----------------------------------------------------------------------------

def run_checked(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise SystemExit("bench: %s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr.strip()[-500:]))
    return p.stdout


def timed(cmd):
    """Runs cmd once; -> {"wall", "cpu" (user + sys s), "peakMB" (the child's max RSS), "rc"[, "error"]}.
    The child's own rusage comes from wait4, so nothing else on the machine is counted."""
    with tempfile.TemporaryFile("w+") as err:
        start = time.monotonic()
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err)
        _, status, ru = os.wait4(p.pid, 0)
        wall = time.monotonic() - start
        p.returncode = rc = os.waitstatus_to_exitcode(status)
        r = {"wall": round(wall, 3), "cpu": round(ru.ru_utime + ru.ru_stime, 3),
             "peakMB": round(ru.ru_maxrss / 1024.0, 1), "rc": rc}
        if rc != 0:
            err.seek(0)
            r["error"] = err.read().strip()[-400:] or "exit %d" % rc
    return r


def timed_reps(cmds, reps):
    """Runs the command list (one job, e.g. a peer's three levels) `reps` times; -> the median
    run's figures (wall, cpu and peak summed / maxed over the list) plus every rep's wall. A failed
    command ends the job with its error."""
    runs = []
    for _ in range(reps):
        total = {"wall": 0.0, "cpu": 0.0, "peakMB": 0.0}
        for cmd in cmds:
            r = timed(cmd)
            if r["rc"] != 0:
                return {"error": r["error"], "command": " ".join(cmd)}
            total = {"wall": total["wall"] + r["wall"], "cpu": total["cpu"] + r["cpu"],
                     "peakMB": max(total["peakMB"], r["peakMB"])}
        runs.append(total)
    walls = [r["wall"] for r in runs]
    med = sorted(runs, key=lambda r: r["wall"])[(len(runs) - 1) // 2]
    return {"wall": round(med["wall"], 3), "cpu": round(med["cpu"], 3), "peakMB": med["peakMB"],
            "walls": [round(w, 3) for w in walls]}


def median(values):
    return statistics.median(values) if values else None


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def read_json(path):
    with open(path) as f:
        return json.load(f)


# ---- the results file -------------------------------------------------------------------------------

def start_results(suite, args, build_list):
    return {"schema": SCHEMA, "suite": suite, "command": [os.path.relpath(sys.argv[0], SOURCE)] + sys.argv[1:],
            "started": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
            "harness": commit_of(SOURCE), "machine": machine(),
            "builds": [b.describe() for b in build_list], "peers": peer_versions(), "settings": {}, "assets": []}


def finish_results(results, path, started):
    m = results["machine"]
    m["loadAverageEnd"] = loadavg()
    results["seconds"] = round(time.monotonic() - started, 1)
    # The load average counts the harness's own runs; what other processes took is the machine's
    # busy time less the harness's, as a share of one core over the run.
    other = (busy_cpu_seconds() - m.pop("busyCpuStart")) - (own_cpu_seconds() - m.pop("ownCpuStart"))
    m["otherCpuShare"] = round(max(0.0, other) / max(results["seconds"], 1e-9), 3)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as f:
        json.dump(results, f, indent=1, sort_keys=False)
        f.write("\n")
    log("bench: results in %s" % path)
