#!/usr/bin/env python3
"""Mutation fuzzing of traxer's inputs: mesh files and scene files.

`meshes`: damages copies of the shipped meshes (random bytes, truncation,
insertions; for glTF random values in the JSON: indices, counts, offsets, component
and accessor types; for OBJ random tokens and faces) and runs `traxer inspect`.
`scenes`: damages copies of the shipped scenes (numbers and strings replaced by
0, -1, 1e300, nan, inf, wrong types, unknown variables; lines deleted) and runs
`traxer trace` (or `traxer render` for a scene without sources) on a few photons
or pixels. Every run must end with exit code 0, 1 or 2 and never panic, abort or
hang. Cases that break the rule are kept in the work folder.

    cargo build --release
    python3 scripts/fuzz_inputs.py meshes|scenes [--runs 500] [--seed 1] [--keep DIR]

Its first runs found two panics inside the gltf crate, an Embree abort on a source
at 1e300 mm, a hang at --threads 100000 and an out-of-memory tessellation; all are
now refused with messages and tested (tests/it/errors.rs, tests/it/common.rs).
"""

import argparse
import json
import os
import random
import re
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TRAXER = os.path.join(ROOT, "target", "release", "traxer")
VALUES = [0, 1, 2, 3, 4, 5, 7, 12, 13, 36, 48, 96, 100, 1000, -1, 2**31, 2**32 + 1,
          5120, 5121, 5122, 5123, 5125, 5126, 0.5, 1e300, "SCALAR", "VEC2", "VEC4",
          "MAT4", None, [], {}, "x"]
OBJ_TOKENS = ["-1", "0", "1e400", "nan", "inf", "-999999", "2147483648", "4294967296",
              "x", "//", "/", "1/2/3", "f", "v", "vn", "vt", "o", "g", "l 1 2", "p 1",
              "s off", "usemtl m", "mtllib nothere.mtl", ""]


def leaves(o, path=()):
    if isinstance(o, dict):
        for k, v in o.items():
            yield from leaves(v, path + (k,))
    elif isinstance(o, list):
        for i, v in enumerate(o):
            yield from leaves(v, path + (i,))
    else:
        yield path, o


def mutate_json(doc, rng):
    d = json.loads(json.dumps(doc))
    spots = [p for p, v in leaves(d) if not isinstance(v, bool)]
    for _ in range(rng.randint(1, 3)):
        p = rng.choice(spots)
        o = d
        for key in p[:-1]:
            o = o[key]
        o[p[-1]] = rng.choice(VALUES)
    return d


def mutate_bytes(data, rng):
    data = bytearray(data)
    mode = rng.choice(["flip", "truncate", "insert"])
    if mode == "flip":
        for _ in range(rng.randint(1, 20)):
            data[rng.randrange(len(data))] = rng.randrange(256)
    elif mode == "truncate":
        data = data[: rng.randrange(len(data))]
    else:
        i = rng.randrange(len(data))
        data[i:i] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 50)))
    return bytes(data)


def mutate_obj(text, rng):
    lines = text.split("\n")
    for _ in range(rng.randint(1, 4)):
        i = rng.randrange(len(lines))
        parts = lines[i].split(" ")
        if parts and rng.random() < 0.7:
            parts[rng.randrange(len(parts))] = rng.choice(OBJ_TOKENS)
            lines[i] = " ".join(parts)
        else:
            lines.insert(i, rng.choice(["f 1 2 99999", "f 0 1 2", "f -1 -2 -99999",
                                        "v 1 2", "vn 0 0", "f 1", "f 1 2 3 4 5 6 7 8"]))
    return "\n".join(lines).encode()


NUMBER = re.compile(r'(?<![\w.$"])-?\d+(\.\d+)?([eE]-?\d+)?(?![\w"])')
STRING = re.compile(r'"[^"\n]*"')
SCENE_TOKENS = ["0", "-1", "1e300", "-1e300", "nan", "inf", "-inf", "0.0", "1e-300",
                "4294967296", "-4294967297", '"x"', "true", "[]", "{}", "[1, 2]", '""',
                '"$nope"', '"${x}"']


def mutate_scene(text, rng):
    for _ in range(rng.randint(1, 3)):
        r = rng.random()
        spots = list((NUMBER if r < 0.5 else STRING).finditer(text)) if r < 0.75 else None
        if spots:
            m = rng.choice(spots)
            text = text[:m.start()] + rng.choice(SCENE_TOKENS) + text[m.end():]
        elif spots is None:
            lines = text.split("\n")
            del lines[rng.randrange(len(lines))]
            text = "\n".join(lines)
    return text


def glb_parts(raw):
    n = struct.unpack("<I", raw[12:16])[0]
    return json.loads(raw[20:20 + n]), raw[20 + n:]


def glb_pack(doc, rest):
    j = json.dumps(doc).encode()
    j += b" " * ((4 - len(j) % 4) % 4)
    body = struct.pack("<I", len(j)) + b"JSON" + j + rest
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def one_mutation(src, rng):
    raw = open(src, "rb").read()
    ext = os.path.splitext(src)[1]
    if rng.random() < 0.3:
        return mutate_bytes(raw, rng), ext
    if ext == ".gltf":
        return json.dumps(mutate_json(json.loads(raw), rng)).encode(), ext
    if ext == ".glb":
        doc, rest = glb_parts(raw)
        return glb_pack(mutate_json(doc, rng), rest), ext
    return mutate_obj(raw.decode(), rng), ext


def run(cmd):
    """(exit code or 'timeout', stderr) of one traxer run."""
    try:
        r = subprocess.run(cmd, capture_output=True, timeout=120)
        return r.returncode, r.stderr
    except subprocess.TimeoutExpired:
        return "timeout", b""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("target", choices=["meshes", "scenes"])
    ap.add_argument("--runs", type=int, default=500)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--keep", help="folder for the cases that break the rule")
    a = ap.parse_args()
    if not os.path.exists(TRAXER):
        sys.exit(f"{TRAXER} not found: run `cargo build --release` first")
    rng = random.Random(a.seed)
    work = a.keep or tempfile.mkdtemp(prefix="traxer-fuzz-")
    os.makedirs(work, exist_ok=True)
    if a.target == "meshes":
        folder = os.path.join(ROOT, "meshes")
        sources = [os.path.join(folder, f) for f in sorted(os.listdir(folder))
                   if f.endswith((".gltf", ".glb", ".obj"))]
        allowed = (0, 2)
    else:
        # Mutated scenes live in work/scenes/, next to links to meshes/ and data/,
        # so that their relative paths resolve as in the repository.
        folder = os.path.join(ROOT, "scenes")
        sources = [os.path.join(folder, f) for f in sorted(os.listdir(folder)) if f.endswith(".toml")]
        os.makedirs(os.path.join(work, "scenes"), exist_ok=True)
        for d in ("meshes", "data"):
            if not os.path.exists(os.path.join(work, d)):
                os.symlink(os.path.join(ROOT, d), os.path.join(work, d))
        allowed = (0, 1, 2)
    codes, bad = {}, 0
    for k in range(a.runs):
        src = rng.choice(sources)
        if a.target == "meshes":
            data, ext = one_mutation(src, rng)
            path = os.path.join(work, f"case{k}{ext}")
            with open(path, "wb") as f:
                f.write(data)
            cmd = [TRAXER, "inspect", "--json", path]
        else:
            text = open(src).read()
            path = os.path.join(work, "scenes", f"case{k}.toml")
            with open(path, "w") as f:
                f.write(mutate_scene(text, rng))
            out = os.path.join(work, f"out{k}")
            if "[[sources]]" in text:
                cmd = [TRAXER, "trace", path, "-n", "300", "-q", "--out", out]
            else:
                cmd = [TRAXER, "render", path, "--width", "24", "--height", "16", "--spp", "2",
                       "--out", out + ".png"]
        code, err = run(cmd)
        codes[code] = codes.get(code, 0) + 1
        if code not in allowed or b"panicked" in err:
            bad += 1
            print(f"BROKEN RULE: {path}: exit {code}\n{err.decode(errors='replace')[-600:]}")
        else:
            os.remove(path)
        if a.target == "scenes":
            subprocess.run(["rm", "-rf", out, out + ".png"])
    print(f"{a.runs} mutated {a.target}: exit codes {codes}; {bad} broke the rule")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
