#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-2-Clause
"""Keeps the normative tables of docs/codec.md equal to the source.

Every table of the bitstream specification that the source spells out as a constant
array sits in docs/codec.md between two markers:

    <!-- spec-table: NAME -->
    ...generated text...
    <!-- /spec-table -->

NAME is a table below; each reads the initializer of one or more constants, found by
identifier anywhere under codec/ (so files may move between folders), and prints it in
the form the document shows.

    scripts/spec-tables.py            check: exit 1 and print a diff when a table drifts
    scripts/spec-tables.py --write    rewrite the marked blocks from the source
"""

import argparse
import difflib
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "codec.md"
SOURCE_DIR = ROOT / "codec"


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return re.sub(r"//[^\n]*", " ", text)


_sources = None


def sources():
    global _sources
    if _sources is None:
        _sources = {}
        for path in sorted(SOURCE_DIR.rglob("*")):
            if path.suffix in (".h", ".cc") and path.is_file():
                _sources[path] = strip_comments(path.read_text())
    return _sources


def initializer(name):
    """The integers of the brace initializer of constant `name`, in order."""
    pattern = re.compile(r"\b" + re.escape(name) + r"\s*(?:\[[^\]]*\]\s*)*=\s*\{")
    hits = []
    for path, text in sources().items():
        for m in pattern.finditer(text):
            depth, i = 0, m.end() - 1
            while True:
                if text[i] == "{":
                    depth += 1
                elif text[i] == "}":
                    depth -= 1
                    if depth == 0:
                        break
                i += 1
            body = text[m.end():i]
            hits.append((path, [int(v) for v in re.findall(r"-?\b\d+\b", body)]))
    if len(hits) != 1:
        where = ", ".join(str(p) for p, _ in hits) or "nowhere"
        sys.exit(f"spec-tables: constant {name} is defined {len(hits)} times under codec/ ({where})")
    return hits[0][1]


def expect(values, count, name):
    if len(values) != count:
        sys.exit(f"spec-tables: {name} has {len(values)} entries, expected {count}")
    return values


def rows(values, per_row, width):
    return [" ".join(f"{v:>{width}}" for v in values[i:i + per_row]) for i in range(0, len(values), per_row)]


def code(lines):
    return "```\n" + "\n".join(line.rstrip() for line in lines) + "\n```"


def angle_table():
    return code([" ".join(str(v) for v in expect(initializer("kAngle"), 33, "kAngle"))])


def inverse_angle_table():
    """The switch of inverse_angle(angle): `case A: return V;` and the default (-32)."""
    hits = []
    for path, text in sources().items():
        m = re.search(r"\binverse_angle\(int \w+\)\s*\{(.*?)\n\}", text, re.S)
        if m:
            hits.append(m.group(1))
    if len(hits) != 1:
        sys.exit(f"spec-tables: inverse_angle is defined {len(hits)} times under codec/")
    pairs = [(int(a), int(v)) for a, v in re.findall(r"case (-?\d+): return (-?\d+);", hits[0])]
    default = re.search(r"default: return (-?\d+);", hits[0])
    if len(pairs) != 7 or not default:
        sys.exit("spec-tables: inverse_angle does not have 7 cases and a default")
    pairs.append((-32, int(default.group(1))))
    return code(["angle: " + " ".join(f"{a:>5}" for a, _ in pairs),
                 "inv:   " + " ".join(f"{v:>5}" for _, v in pairs)])


def intra_matrix():
    return code(rows(expect(initializer("kDefaultIntraMatrix"), 64, "kDefaultIntraMatrix"), 8, 2))


def scale_octave():
    values = expect(initializer("kScaleOctave"), 32, "kScaleOctave")
    return code(["T[0..31], T[k] = round(128 * 2^(k/32)):"] + ["  " + r for r in rows(values, 16, 3)])


def filter_bank(luma, chroma):
    def phases(name, count):
        values = expect(initializer(name), count * 8, name)
        return [values[i * 8:(i + 1) * 8] for i in range(count)]
    lines = []
    for plane, name, count in (("luma", luma, 4), ("chroma", chroma, 8)):
        for phase, taps in enumerate(phases(name, count)):
            label = f"{plane:<6} phase {phase}:" if phase == 0 else f"{'':<6} phase {phase}:"
            lines.append(label + " " + " ".join(f"{t:>3}" for t in taps))
    return code(lines)


def idct_basis():
    values = expect(initializer("kIdctBasis"), 32, "kIdctBasis")
    return code([f"u={u}: " + " ".join(f"{v:>5}" for v in values[4 * u:4 * u + 4]) for u in range(8)])


def hevc_dct_table():
    return code(["T[0..15] = " + " ".join(str(v) for v in expect(initializer("kDctAngleTable"), 16, "kDctAngleTable"))])


def dst_tables():
    lines = []
    for n, name in ((4, "kDst4AngleTable"), (8, "kDst8AngleTable"), (16, "kDst16AngleTable")):
        values = expect(initializer(name), n + 1, name)
        lines.append(f"A_{n:<2} = " + " ".join(str(v) for v in values) + f"   (j = 0..{n})")
    return code(lines)


def deblock_tables():
    beta = expect(initializer("kBeta"), 52, "kBeta")
    tc = expect(initializer("kTc"), 54, "kTc")
    return code(["B[0..51]:"] + ["  " + r for r in rows(beta, 26, 2)] +
                ["C[0..53]:"] + ["  " + r for r in rows(tc, 27, 2)])


def cdef_tables():
    d = expect(initializer("kCdefDirections"), 32, "kCdefDirections")
    lines = []
    for direction in range(8):
        k0 = d[direction * 4:direction * 4 + 2]
        k1 = d[direction * 4 + 2:direction * 4 + 4]
        lines.append(f"O[{direction}] = ({k0[0]:>2},{k0[1]:>2}) ({k1[0]:>2},{k1[1]:>2})")
    primary = expect(initializer("kCdefPrimaryTaps"), 4, "kCdefPrimaryTaps")
    secondary = expect(initializer("kCdefSecondaryTaps"), 2, "kCdefSecondaryTaps")
    divisors = expect(initializer("kDivTable"), 9, "kDivTable")
    lines.append(f"Wp = ({primary[0]}, {primary[1]}) for even p, ({primary[2]}, {primary[3]}) for odd p")
    lines.append(f"Ws = ({secondary[0]}, {secondary[1]})")
    lines.append("D = {" + ", ".join(str(v) for v in divisors) + "}")
    return code(lines)


def face_frames():
    values = expect(initializer("kFrames"), 54, "kFrames")
    names = ["px", "nx", "py", "ny", "pz", "nz"]

    def axis(v):
        (i,) = [k for k in range(3) if v[k] != 0]
        return ("+" if v[i] > 0 else "-") + "xyz"[i]
    lines = ["| face | R | D | F |", "|---|---|---|---|"]
    for f, name in enumerate(names):
        v = values[f * 9:(f + 1) * 9]
        lines.append(f"| {name} | {axis(v[0:3])} | {axis(v[3:6])} | {axis(v[6:9])} |")
    return "\n".join(lines)


def priors(name):
    def render():
        values = initializer(name)
        return code([f"{i:>4}: " + " ".join(f"{v:>5}" for v in values[i:i + 12]) for i in range(0, len(values), 12)])
    return render


TABLES = {
    "kAngle": angle_table,
    "inverse-angle": inverse_angle_table,
    "kDefaultIntraMatrix": intra_matrix,
    "kScaleOctave": scale_octave,
    "interpolation-regular": lambda: filter_bank("kLumaTaps", "kChromaTaps"),
    "interpolation-smooth": lambda: filter_bank("kSmoothLumaTaps", "kSmoothChromaTaps"),
    "interpolation-bilinear": lambda: filter_bank("kBilinearLumaTaps", "kBilinearChromaTaps"),
    "kIdctBasis": idct_basis,
    "kDctAngleTable": hevc_dct_table,
    "dst-angle-tables": dst_tables,
    "deblocking": deblock_tables,
    "cdef": cdef_tables,
    "face-frames": face_frames,
    "kIntraFrameTable": priors("kIntraFrameTable"),
    "kBFrameTable": priors("kBFrameTable"),
}

BLOCK = re.compile(r"(<!-- spec-table: (\S+) -->\n)(.*?)(<!-- /spec-table -->)", re.S)


def main():
    global SOURCE_DIR
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--write", action="store_true", help="rewrite the marked blocks of docs/codec.md")
    parser.add_argument("--doc", type=pathlib.Path, default=DOC, help="the document (default docs/codec.md)")
    parser.add_argument("--source", type=pathlib.Path, default=SOURCE_DIR,
                        help="the folder whose .h and .cc files define the tables (default codec/)")
    args = parser.parse_args()
    SOURCE_DIR = args.source

    text = args.doc.read_text()
    seen = set()

    def replace(m):
        name = m.group(2)
        if name not in TABLES:
            sys.exit(f"spec-tables: {args.doc}: unknown table {name}")
        if name in seen:
            sys.exit(f"spec-tables: {args.doc}: table {name} appears twice")
        seen.add(name)
        return m.group(1) + TABLES[name]() + "\n" + m.group(4)

    expected = BLOCK.sub(replace, text)
    missing = sorted(set(TABLES) - seen)
    if missing:
        sys.exit(f"spec-tables: {args.doc} lacks the tables {', '.join(missing)}")
    if args.write:
        if expected != text:
            args.doc.write_text(expected)
        return 0
    if expected != text:
        diff = difflib.unified_diff(text.splitlines(), expected.splitlines(), "docs/codec.md", "from the source",
                                    lineterm="", n=1)
        print("\n".join(diff))
        print("spec-tables: docs/codec.md differs from the source; run scripts/spec-tables.py --write "
              "after checking that the change to the bitstream is intended", file=sys.stderr)
        return 1
    print(f"spec-tables: {len(seen)} tables of docs/codec.md match the source")
    return 0


if __name__ == "__main__":
    sys.exit(main())
