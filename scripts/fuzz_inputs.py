#!/usr/bin/env python3
"""Mutation fuzzing of a tool's glTF input (a development aid, not a test).

Each round takes one of the given GLB files, changes 1-3 values of its JSON (a number nudged, a
value replaced by another type or a glTF enum, a key or array element removed) or overwrites
random bytes of its binary chunk (sometimes truncating it), runs the tool on the result and checks
the rules every tool keeps on bad input: exit code 0, 2 or 3 (README's table), one error line
(warnings aside), an output file only on success, no temporary file left, no hang (60 s).
A failing input is kept as DIR/bad-N.glb or DIR/hang-N.glb; the exit codes seen are summarised.

Usage: scripts/fuzz_inputs.py TOOL_BINARY SEED ROUNDS INPUT.glb... [-- TOOL FLAGS]
  e.g. scripts/fuzz_inputs.py build/bin/simplify 1 300 ../shared/assets/Duck/Duck.glb -- --ratio 0.5,0.1
Environment: DIR (work directory, default out/fuzz); JSON_SHARE (share of rounds that mutate the
JSON, default 0.7; 0 mutates only the binary chunk, e.g. Draco streams).
"""
import glob
import json
import os
import random
import struct
import subprocess
import sys

VALUES = [-1, 0, 1, 2, 3, 7, 65535, 2 ** 31, 2 ** 32 + 5, -2 ** 31, 1e308, -0.5, 0.5, "x", None, [], {}, True,
          5120, 5121, 5122, 5123, 5125, 5126, "VEC3", "MAT4", "SCALAR", 34962, 34963]


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


def mutate_binary(binary, rng):
    b = bytearray(binary)
    for _ in range(rng.randint(1, 20) if b else 0):
        b[rng.randrange(len(b))] = rng.randrange(256)
    if b and rng.random() < 0.2:
        b = b[:rng.randrange(len(b))]
    return bytes(b)


def main():
    args = sys.argv[1:]
    flags = args[args.index("--") + 1:] if "--" in args else []
    args = args[:args.index("--")] if "--" in args else args
    if len(args) < 4:
        sys.exit(__doc__)
    tool, seed, rounds, inputs = args[0], int(args[1]), int(args[2]), args[3:]
    work = os.environ.get("DIR", "out/fuzz")
    json_share = float(os.environ.get("JSON_SHARE", "0.7"))
    os.makedirs(work, exist_ok=True)
    rng = random.Random(seed)
    sources = {p: read_glb(p) for p in inputs}
    inp, out = os.path.join(work, "in.glb"), os.path.join(work, "out.glb")
    codes, failures = {}, 0
    for n in range(rounds):
        source = sources[rng.choice(inputs)]
        doc, binary = json.loads(json.dumps(source[0])), source[1]
        if rng.random() < json_share:
            doc = mutate_json(doc, rng)
        else:
            binary = mutate_binary(binary, rng)
        if os.path.exists(out):
            os.remove(out)
        write_glb(inp, doc, binary)
        try:
            p = subprocess.run([tool, "-i", inp, "-o", out, "--quiet"] + flags, capture_output=True, timeout=60)
        except subprocess.TimeoutExpired:
            failures += 1
            os.replace(inp, os.path.join(work, "hang-%d.glb" % n))
            print("hang: round %d" % n)
            continue
        codes[p.returncode] = codes.get(p.returncode, 0) + 1
        errors = [l for l in p.stderr.decode(errors="replace").splitlines() if l and " warning: " not in l]
        ok = p.returncode in (0, 2, 3) and (p.returncode == 0) == os.path.exists(out) and \
            (p.returncode == 0 or len(errors) == 1)
        if not ok:
            failures += 1
            os.replace(inp, os.path.join(work, "bad-%d.glb" % n))
            print("bad: round %d exit %d: %s" % (n, p.returncode, " | ".join(errors)[:300]))
        for leftover in glob.glob(os.path.join(work, "*.tmp-*")):
            print("temporary file left: " + leftover)
            failures += 1
            os.remove(leftover)
    print("%d rounds, %d failures, exit codes %s" % (rounds, failures, dict(sorted(codes.items()))))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
