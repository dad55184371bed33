#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-2-Clause
"""Re-encodes a database with the ffmpeg command lines of docs/bench.md, at every setting
`svc bench` recorded in results.json, and compares the bytes with the bench's.

  bench/check-anchor-cli.py DB_DIR RESULTS_JSON [CODEC ...]   (default: x264 x265 x265-ra av1)

Each face sequence is fed in row-major cell order (layer, then z, then x), as the bench
codes it. Equal bytes mean the same bitstream, so the same decoded pixels and PSNR.
Prints one line per setting; exits 1 if any differs by 1 % or more.
"""
import json
import os
import subprocess
import sys
import tempfile

FACES = ["px", "nx", "py", "ny", "pz", "nz"]
X265 = "-c:v libx265 -pix_fmt yuv420p -threads 1 -g {gop} -bf {bf} -crf {s} -preset medium -forced-idr 1 " \
       "-x265-params open-gop={open}:log-level=error:pools=none:frame-threads=1{extra} -f hevc"
COMMANDS = {
    "x264": "-c:v libx264 -pix_fmt yuv420p -threads 1 -g 9 -bf 2 -crf {s} -preset medium -forced-idr 1 -f h264",
    "x265": X265.replace("{gop}", "9").replace("{bf}", "2").replace("{open}", "1").replace("{extra}", ""),
    "x265-ra": X265.replace("{gop}", "3").replace("{bf}", "2").replace("{open}", "1")
                   .replace("{extra}", ":b-adapt=0:b-pyramid=0"),
    "x265-intra": X265.replace("{gop}", "1").replace("{bf}", "0").replace("{open}", "0").replace("{extra}", ""),
    "av1": "-c:v libsvtav1 -pix_fmt yuv420p -threads 1 -g 9 -bf 0 -flags +cgop -crf {s} -preset 6 -f obu",
    "av1-svt-slow": "-c:v libsvtav1 -pix_fmt yuv420p -threads 1 -g 9 -bf 0 -flags +cgop -crf {s} -preset 2 -f obu",
    "av1-slow": "-c:v libaom-av1 -pix_fmt yuv420p -threads 1 -g 9 -bf 0 -flags +cgop -crf {s} -cpu-used 2 -f obu",
}


def face_sequences(db, work):
    manifest = json.load(open(os.path.join(db, "manifest.json")))
    cells = sorted(manifest["cells"], key=lambda c: (c["index"][1], c["index"][2], c["index"][0]))
    for face in FACES:
        folder = os.path.join(work, face)
        os.makedirs(folder)
        for k, cell in enumerate(cells):
            os.symlink(os.path.abspath(os.path.join(db, cell["faces"][face]["color"])),
                       os.path.join(folder, "%04d.png" % k))


def encoded_bytes(work, arguments):
    total = 0
    out = os.path.join(work, "out.bin")
    for face in FACES:
        subprocess.run("ffmpeg -v error -y -framerate 25 -i '%s/%s/%%04d.png' %s '%s'" %
                       (work, face, arguments, out), shell=True, check=True)
        total += os.path.getsize(out)
    return total


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    db, results = sys.argv[1], json.load(open(sys.argv[2]))
    codecs = sys.argv[3:] or ["x264", "x265", "x265-ra", "av1"]
    worst = 0.0
    with tempfile.TemporaryDirectory() as work:
        face_sequences(db, work)
        for name in codecs:
            codec = next(c for c in results["codecs"] if c["name"] == name)
            for point in sorted(codec["points"], key=lambda p: p["setting"]):
                ffmpeg = encoded_bytes(work, COMMANDS[name].format(s=point["setting"]))
                diff = 100.0 * (ffmpeg - point["bytes"]) / point["bytes"]
                worst = max(worst, abs(diff))
                print("%s crf %d: bench %d bytes, ffmpeg %d bytes, %+.3f %%" %
                      (name, point["setting"], point["bytes"], ffmpeg, diff), flush=True)
    sys.exit(1 if worst >= 1.0 else 0)


if __name__ == "__main__":
    main()
