#!/usr/bin/env python3
"""Mutation fuzzing of a tool's glTF input (a development aid; tests/cli/test_sanitize.py runs a
short fixed-seed run of it under the sanitizer build).

Each round takes one of the given inputs and mutates it:
- a .glb: 1-3 values of its JSON changed (a number nudged, a value replaced by another type or a
  glTF enum, a key or array element removed), or random bytes of its binary chunk overwritten
  (sometimes truncated);
- a .gltf with external files (.bin, images): its JSON changed structurally (keys deleted, values
  of the wrong type, indices just past or far past their array, huge counts, lengths and offsets,
  bad or hostile URIs), its JSON text cut or damaged, or one external file overwritten, truncated
  or removed.
It then runs the tool on the result and checks the rules every tool keeps on bad input: exit code
0, 2 or 3 (README's table), one error line (warnings aside), an output file only on success (for
a .gltf output, no .bin either), no temporary file left, no hang (TIMEOUT seconds), no
AddressSanitizer/UndefinedBehaviorSanitizer/LeakSanitizer report. A failing input is kept as
DIR/bad-N/ or DIR/hang-N/ (the mutated file and its external files); the exit codes seen are
summarised. `compare` is run as `compare ORIGINAL MUTATED` (no output file).

Usage: scripts/fuzz_inputs.py TOOL_BINARY SEED ROUNDS INPUT.glb|INPUT.gltf... [-- TOOL FLAGS]
  e.g. scripts/fuzz_inputs.py build/bin/simplify 1 300 ../shared/assets/Duck/Duck.glb -- --ratio 0.5,0.1
       scripts/fuzz_inputs.py build/bin/simplify 1 300 --split-glb ../shared/assets/Duck/Duck.glb -- --ratio 0.5
  --split-glb: each .glb input is first rewritten as a .gltf with an external .bin and external
  image files (DIR/src/NAME/), so the .gltf mutations apply to it.
Environment: DIR (work directory, default out/fuzz); JSON_SHARE (share of rounds that mutate the
JSON, default 0.7; 0 mutates only the binary chunk or the external files, e.g. Draco streams);
TIMEOUT (seconds per run, default 60); OUTPUT_EXT (glb or gltf; default: alternate per round).
For a sanitizer build (cmake -DLODBAKE_SANITIZE=ON) the ASAN_OPTIONS and UBSAN_OPTIONS below are
set unless the environment already has them.
"""
import glob
import json
import os
import random
import shutil
import struct
import subprocess
import sys

VALUES = [-1, 0, 1, 2, 3, 7, 65535, 2 ** 31, 2 ** 32 + 5, -2 ** 31, 1e308, -0.5, 0.5, "x", None, [], {}, True,
          5120, 5121, 5122, 5123, 5125, 5126, "VEC3", "MAT4", "SCALAR", 34962, 34963]
# Keys whose value is an index into a top-level array, and those arrays.
INDEX_KEYS = {"bufferView": "bufferViews", "buffer": "buffers", "indices": "accessors", "material": "materials",
              "mesh": "meshes", "source": "images", "sampler": "samplers", "index": "textures",
              "POSITION": "accessors", "NORMAL": "accessors", "TEXCOORD_0": "accessors", "TEXCOORD_1": "accessors",
              "TANGENT": "accessors", "COLOR_0": "accessors", "scene": "scenes", "skin": "skins",
              "input": "accessors", "output": "accessors", "node": "nodes"}
SIZE_KEYS = ("count", "byteLength", "byteOffset", "byteStride")
BAD_URIS = ["", "missing.bin", "../../../../etc/passwd", "/etc/passwd", "/", ".", "http://example.com/x.bin",
            "data:", "data:application/octet-stream;base64,", "data:application/octet-stream;base64,@@@@",
            "data:image/png;base64,iVBORw0KGgo=", "file:///etc/hostname", "a%20b.bin", "%", "\u00e9\u00e9.bin",
            "x" * 5000]

# Sanitizer settings for the tools: stop at the first report with a stack trace and a non-zero
# exit; LeakSanitizer on (no suppressions: the leaks found so far were lodbake's or avoidable).
# new_delete_type_mismatch=0: OpenImageIO 2.4's TextureSystem::destroy deletes the object its
# create() made through a pointer of another type (both calls inside libOpenImageIO); ASan cannot
# suppress that check by location, and in lodbake's code -Wdelete-non-virtual-dtor (-Wall, -Werror
# in CI) already rejects the same mistake.
SANITIZER_ENV = {
    "ASAN_OPTIONS": "halt_on_error=1:abort_on_error=1:print_stacktrace=1:detect_leaks=1:new_delete_type_mismatch=0",
    "UBSAN_OPTIONS": "halt_on_error=1:abort_on_error=1:print_stacktrace=1",
}
SANITIZER_MARKERS = ("AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer", "runtime error:")


def sanitizer_environment(env=None):
    """A copy of env (default os.environ) with SANITIZER_ENV's entries added where absent."""
    out = dict(os.environ if env is None else env)
    for k, v in SANITIZER_ENV.items():
        out.setdefault(k, v)
    return out


def sanitizer_report(stderr):
    """The first line of a sanitizer report in stderr, or None."""
    for line in stderr.splitlines():
        if any(m in line for m in SANITIZER_MARKERS):
            return line
    return None


def read_glb(path):
    data = open(path, "rb").read()
    length = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + length])
    rest = data[20 + length:]
    binary = rest[8:8 + struct.unpack_from("<I", rest, 0)[0]] if len(rest) >= 8 else b""
    return doc, binary


def write_glb(path, doc, binary):
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    out = struct.pack("<III", 0x46546C67, 2, 20 + len(text) + (8 + len(binary) if binary else 0))
    out += struct.pack("<II", len(text), 0x4E4F534A) + text
    if binary:
        out += struct.pack("<II", len(binary), 0x004E4942) + binary
    open(path, "wb").write(out)


def external_uris(doc):
    """The relative file URIs of a .gltf's buffers and images."""
    uris = []
    for key in ("buffers", "images"):
        for item in doc.get(key, []) if isinstance(doc.get(key), list) else []:
            uri = item.get("uri") if isinstance(item, dict) else None
            if isinstance(uri, str) and uri and not uri.startswith("data:") and uri not in uris:
                uris.append(uri)
    return uris


def read_gltf(path):
    """A .gltf as (JSON text, {uri: bytes} of its external files)."""
    text = open(path, "rb").read()
    base = os.path.dirname(path)
    files = {}
    for uri in external_uris(json.loads(text)):
        with open(os.path.join(base, uri), "rb") as f:
            files[uri] = f.read()
    return text, files


def split_glb(path, out_dir):
    """Rewrites a GLB as OUT_DIR/NAME.gltf with NAME.bin and one file per image; returns its path.
    Images move out of the binary buffer (their bufferViews are left unused)."""
    doc, binary = read_glb(path)
    name = os.path.splitext(os.path.basename(path))[0]
    os.makedirs(out_dir, exist_ok=True)
    ext = {"image/png": ".png", "image/jpeg": ".jpg"}
    for i, image in enumerate(doc.get("images", [])):
        if "bufferView" in image:
            view = doc["bufferViews"][image.pop("bufferView")]
            start = view.get("byteOffset", 0)
            uri = "%s_image%d%s" % (name, i, ext.get(image.pop("mimeType", ""), ".img"))
            with open(os.path.join(out_dir, uri), "wb") as f:
                f.write(binary[start:start + view["byteLength"]])
            image["uri"] = uri
    if doc.get("buffers"):
        doc["buffers"][0]["uri"] = name + ".bin"
        with open(os.path.join(out_dir, name + ".bin"), "wb") as f:
            f.write(binary)
    out = os.path.join(out_dir, name + ".gltf")
    with open(out, "w") as f:
        json.dump(doc, f, indent=1)
    return out


def walk(x, path=()):
    yield path, x
    items = x.items() if isinstance(x, dict) else enumerate(x) if isinstance(x, list) else ()
    for k, v in items:
        yield from walk(v, path + (k,))


def mutate_json(doc, rng):
    for _ in range(rng.randint(1, 3)):
        path, value = rng.choice(list(walk(doc)))
        if not path:
            continue
        parent = doc
        for k in path[:-1]:
            parent = parent[k]
        r = rng.random()
        if r < 0.2 and isinstance(parent, dict):
            del parent[path[-1]]
        elif r < 0.3 and isinstance(parent, list):
            parent.pop(path[-1])
        elif isinstance(value, (int, float)) and not isinstance(value, bool) and r < 0.8:
            half = value // 2 if isinstance(value, int) else value / 2
            parent[path[-1]] = rng.choice([value + 1, value - 1, value * 2, half, -value, 0, value + 4, value * 1000])
        else:
            parent[path[-1]] = rng.choice(VALUES)
    return doc


def mutate_structure(doc, rng):
    """Structural mutations of a glTF document: indices past their arrays, huge sizes, bad URIs,
    whole objects removed or of the wrong type."""
    for _ in range(rng.randint(1, 3)):
        nodes = list(walk(doc))
        r = rng.random()
        if r < 0.3:
            refs = [(p, v) for p, v in nodes if p and p[-1] in INDEX_KEYS and isinstance(v, int)]
            if refs:
                path, _ = rng.choice(refs)
                target = doc.get(INDEX_KEYS[path[-1]])
                size = len(target) if isinstance(target, list) else 0
                value = rng.choice([size, size + 1, -1, 2 ** 31 - 1, 2 ** 32, 2 ** 63])
                set_path(doc, path, value)
                continue
        if r < 0.5:
            sizes = [p for p, v in nodes if p and p[-1] in SIZE_KEYS and isinstance(v, int)]
            if sizes:
                set_path(doc, rng.choice(sizes), rng.choice([0, 1, 3, 2 ** 31 - 1, 2 ** 31, 2 ** 32 + 4, 2 ** 62, -4]))
                continue
        if r < 0.7:
            holders = [item for key in ("buffers", "images") for item in doc.get(key, []) or []
                       if isinstance(item, dict)]
            if holders:
                rng.choice(holders)["uri"] = rng.choice(BAD_URIS)
                continue
        if r < 0.85:
            keys = [k for k in doc if k != "asset"]
            if keys:
                k = rng.choice(keys)
                repeated = [doc[k][:1] * 3] if isinstance(doc[k], list) else []
                doc[k] = rng.choice([None, {}, [], 0, "x", [None], [[]], [{}]] + repeated)
                continue
        mutate_json(doc, rng)
    return doc


def set_path(doc, path, value):
    parent = doc
    for k in path[:-1]:
        parent = parent[k]
    parent[path[-1]] = value


def mutate_text(text, rng):
    """Byte-level damage to JSON text: cut short, a byte changed, a span deleted or duplicated."""
    b = bytearray(text)
    r = rng.random()
    if r < 0.3:
        return bytes(b[:rng.randrange(len(b))])
    for _ in range(rng.randint(1, 4)):
        i = rng.randrange(len(b))
        if r < 0.6:
            b[i] = rng.choice(b'{}[]",:0-9eE.\\ \x00\xff')
        elif r < 0.8:
            del b[i:i + rng.randint(1, 40)]
        else:
            b[i:i] = b[i:i + rng.randint(1, 200)]
    return bytes(b)


def mutate_binary(binary, rng):
    b = bytearray(binary)
    for _ in range(rng.randint(1, 20) if b else 0):
        b[rng.randrange(len(b))] = rng.randrange(256)
    if b and rng.random() < 0.2:
        b = b[:rng.randrange(len(b))]
    return bytes(b)


def mutate_gltf(text, files, rng, json_share):
    """One mutated .gltf: (JSON text, {uri: bytes or None to leave the file out})."""
    files = dict(files)
    if rng.random() < json_share or not files:
        if rng.random() < 0.2:
            text = mutate_text(text, rng)
        else:
            doc = json.loads(text)
            doc = mutate_structure(doc, rng) if rng.random() < 0.6 else mutate_json(doc, rng)
            text = json.dumps(doc).encode()
    else:
        uri = rng.choice(sorted(files))
        files[uri] = None if rng.random() < 0.1 else mutate_binary(files[uri], rng)
    return text, files


def write_gltf(work, text, files):
    path = os.path.join(work, "in.gltf")
    with open(path, "wb") as f:
        f.write(text)
    for uri, data in files.items():
        target = os.path.join(work, uri)
        if os.path.exists(target):
            os.remove(target)
        if data is not None:
            with open(target, "wb") as f:
                f.write(data)
    return path


def keep(work, n, kind, inp, files):
    """Moves a failing input (and its external files) to WORK/KIND-N/."""
    d = os.path.join(work, "%s-%d" % (kind, n))
    os.makedirs(d, exist_ok=True)
    shutil.copy(inp, d)
    for uri in files:
        if os.path.exists(os.path.join(work, uri)):
            shutil.copy(os.path.join(work, uri), d)
    return d


def output_files(out):
    files = [out]
    if out.endswith(".gltf"):
        files.append(out[:-5] + ".bin")
    return [f for f in files if os.path.exists(f)]


def main():
    args = sys.argv[1:]
    flags = args[args.index("--") + 1:] if "--" in args else []
    args = args[:args.index("--")] if "--" in args else args
    split = "--split-glb" in args
    args = [a for a in args if a != "--split-glb"]
    if len(args) < 4:
        sys.exit(__doc__)
    tool, seed, rounds, inputs = args[0], int(args[1]), int(args[2]), args[3:]
    work = os.environ.get("DIR", "out/fuzz")
    json_share = float(os.environ.get("JSON_SHARE", "0.7"))
    timeout = float(os.environ.get("TIMEOUT", "60"))
    out_ext = os.environ.get("OUTPUT_EXT", "")
    env = sanitizer_environment()
    is_compare = os.path.basename(tool) == "compare"
    os.makedirs(work, exist_ok=True)
    if split:
        inputs = [split_glb(p, os.path.join(work, "src", os.path.basename(p)[:-4])) if p.endswith(".glb") else p
                  for p in inputs]
    rng = random.Random(seed)
    sources = {p: read_gltf(p) if p.endswith(".gltf") else read_glb(p) for p in inputs}
    codes, failures = {}, 0
    for n in range(rounds):
        source_path = rng.choice(inputs)
        source = sources[source_path]
        files = {}
        if source_path.endswith(".gltf"):
            text, files = mutate_gltf(source[0], source[1], rng, json_share)
            inp = write_gltf(work, text, files)
        else:
            doc, binary = json.loads(json.dumps(source[0])), source[1]
            if rng.random() < json_share:
                doc = mutate_json(doc, rng)
            else:
                binary = mutate_binary(binary, rng)
            inp = os.path.join(work, "in.glb")
            write_glb(inp, doc, binary)
        out = os.path.join(work, "out." + (out_ext or ("glb" if n % 2 == 0 else "gltf")))
        for f in glob.glob(os.path.join(work, "out.*")):
            os.remove(f)
        cmd = [tool, source_path, inp] if is_compare else [tool, "-i", inp, "-o", out, "--quiet"]
        try:
            p = subprocess.run(cmd + flags, capture_output=True, timeout=timeout, env=env)
        except subprocess.TimeoutExpired:
            failures += 1
            print("hang: round %d, kept in %s" % (n, keep(work, n, "hang", inp, files)))
            continue
        codes[p.returncode] = codes.get(p.returncode, 0) + 1
        stderr = p.stderr.decode(errors="replace")
        errors = [l for l in stderr.splitlines() if l and " warning: " not in l]
        written = [] if is_compare else output_files(out)
        report = sanitizer_report(stderr)
        ok = p.returncode in (0, 2, 3) and report is None and (p.returncode == 0 or len(errors) == 1) and \
            (is_compare or (p.returncode == 0) == (out in written)) and (p.returncode == 0 or not written)
        if not ok:
            failures += 1
            print("bad: round %d exit %d, kept in %s: %s" % (n, p.returncode, keep(work, n, "bad", inp, files),
                                                             (report or " | ".join(errors))[:300]))
        for leftover in glob.glob(os.path.join(work, "*.tmp*")):
            print("temporary file left: " + leftover)
            failures += 1
            os.remove(leftover)
    print("%s: %d rounds, %d failures, exit codes %s" % (os.path.basename(tool), rounds, failures,
                                                        dict(sorted(codes.items()))))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
