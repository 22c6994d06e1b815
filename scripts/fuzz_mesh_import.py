#!/usr/bin/env python3
"""Mutation fuzzing of the mesh importer through `traxer inspect`.

Takes the shipped meshes, damages copies of them (random bytes, truncation,
insertions; for glTF also random values in the JSON: indices, counts, offsets,
component types, accessor types; for OBJ random tokens and faces) and checks that
every file either imports (exit 0) or is refused with a message (exit 2), and that
nothing panics. Files that break the rule are kept in the work folder.

    cargo build --release
    python3 scripts/fuzz_mesh_import.py [--runs 500] [--seed 1] [--keep DIR]

Its first 4 000 mutations found two panics inside the gltf crate
(now contained and tested in tests/it/common.rs::broken_mesh_files).
"""

import argparse
import json
import os
import random
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=500)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--keep", help="folder for the files that break the rule")
    a = ap.parse_args()
    if not os.path.exists(TRAXER):
        sys.exit(f"{TRAXER} not found: run `cargo build --release` first")
    sources = [os.path.join(ROOT, "meshes", f) for f in sorted(os.listdir(os.path.join(ROOT, "meshes")))
               if f.endswith((".gltf", ".glb", ".obj"))]
    rng = random.Random(a.seed)
    work = a.keep or tempfile.mkdtemp(prefix="traxer-fuzz-")
    os.makedirs(work, exist_ok=True)
    codes, bad = {}, 0
    for k in range(a.runs):
        data, ext = one_mutation(rng.choice(sources), rng)
        path = os.path.join(work, f"case{k}{ext}")
        with open(path, "wb") as f:
            f.write(data)
        r = subprocess.run([TRAXER, "inspect", "--json", path], capture_output=True, timeout=120)
        codes[r.returncode] = codes.get(r.returncode, 0) + 1
        if r.returncode not in (0, 2) or b"panicked" in r.stderr:
            bad += 1
            print(f"BROKEN RULE: {path}: exit {r.returncode}\n{r.stderr.decode(errors='replace')[-600:]}")
        else:
            os.remove(path)
    print(f"{a.runs} mutated files: exit codes {dict(sorted(codes.items()))}; {bad} broke the rule")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
