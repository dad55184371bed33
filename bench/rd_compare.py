#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-2-Clause
"""BD-rate of svc encoder settings against each other on one database.

    bench/rd_compare.py DB --config base= --config offset34="--b-qindex-offset 34"

Encodes DB (`svc encode DB -q Q --psnr --json`) at each quality of --qualities with every
--config (NAME=ARGUMENTS, the arguments added to the encode command; NAME:SVC=ARGUMENTS
runs the svc binary SVC instead of --svc, to compare two builds), then prints the
BD-rate of every config against the first: bytes of the whole file against PSNR-Y of all
faces, log-rate as a PCHIP of PSNR (as bench/bd_rate.h), over the PSNR range both curves
cover within --window (32-40 dB). The tuning loop of docs/bench.md for encoder-only
choices: `svc bench` measures svc against the anchors, this measures svc against itself.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile


def pchip_slopes(x, y):
    """Fritsch-Carlson monotone slopes at the points (x strictly increasing)."""
    n = len(x)
    h = [x[i + 1] - x[i] for i in range(n - 1)]
    delta = [(y[i + 1] - y[i]) / h[i] for i in range(n - 1)]
    if n == 2:
        return [delta[0], delta[0]]
    d = [0.0] * n
    for i in range(1, n - 1):
        if delta[i - 1] * delta[i] > 0:
            w1, w2 = 2 * h[i] + h[i - 1], h[i] + 2 * h[i - 1]
            d[i] = (w1 + w2) / (w1 / delta[i - 1] + w2 / delta[i])
    for end, (h0, h1, d0, d1) in ((0, (h[0], h[1], delta[0], delta[1])),
                                  (n - 1, (h[-1], h[-2], delta[-1], delta[-2]))):
        s = ((2 * h0 + h1) * d0 - h0 * d1) / (h0 + h1)
        if s * d0 <= 0:
            s = 0.0
        elif d0 * d1 < 0 and abs(s) > 3 * abs(d0):
            s = 3 * d0
        d[end] = s
    return d


def pchip_integral(x, y, d, a, b):
    """Integral from a to b (x[0] <= a <= b <= x[-1]) of the cubic Hermite through the points."""
    def from_start(i, s):  # integral over segment i from its start to fraction s of it
        h = x[i + 1] - x[i]
        return h * (y[i] * (s**4 / 2 - s**3 + s) + h * d[i] * (s**4 / 4 - 2 * s**3 / 3 + s**2 / 2) +
                    y[i + 1] * (s**3 - s**4 / 2) + h * d[i + 1] * (s**4 / 4 - s**3 / 3))

    total = 0.0
    for i in range(len(x) - 1):
        lo, hi = max(a, x[i]), min(b, x[i + 1])
        if lo < hi:
            h = x[i + 1] - x[i]
            total += from_start(i, (hi - x[i]) / h) - from_start(i, (lo - x[i]) / h)
    return total


def curve(points):
    """(PSNR, log bytes) sorted by PSNR, the smallest rate kept at equal PSNR."""
    best = {}
    for psnr, rate in points:
        best[psnr] = min(rate, best.get(psnr, rate))
    x = sorted(best)
    return x, [math.log(best[p]) for p in x]


def bd_rate(anchor, test, low, high):
    ax, ay = curve(anchor)
    tx, ty = curve(test)
    lo, hi = max(ax[0], tx[0], low), min(ax[-1], tx[-1], high)
    if len(ax) < 2 or len(tx) < 2 or hi <= lo:
        return None
    area = pchip_integral(tx, ty, pchip_slopes(tx, ty), lo, hi) - pchip_integral(ax, ay, pchip_slopes(ax, ay), lo, hi)
    mean = area / (hi - lo)
    return math.exp(mean) - 1, lo, hi


def encode(svc, db, quality, arguments, work, threads):
    out = os.path.join(work, "out.svc")
    command = [svc, "encode", db, "-o", out, "-y", "-q", str(quality), "--psnr", "--json",
               "--threads", str(threads)] + arguments
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{run.stderr}")
    result = json.loads(run.stdout)
    os.unlink(out)
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("db")
    parser.add_argument("--config", action="append", required=True, help="NAME=ARGUMENTS (the first is the anchor)")
    parser.add_argument("--qualities", default="28,38,48,58,66")
    parser.add_argument("--svc", default=os.path.join(os.path.dirname(__file__), "..", "build", "bin", "svc"))
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--window", default="32,40", help="PSNR-Y range in dB")
    options = parser.parse_args()
    low, high = (float(v) for v in options.window.split(","))
    configs = [c.split("=", 1) if "=" in c else (c, "") for c in options.config]
    binaries = {}
    for k, (name, arguments) in enumerate(configs):
        name, _, binary = name.partition(":")
        configs[k] = (name, arguments)
        binaries[name] = binary or options.svc
    curves = {}
    with tempfile.TemporaryDirectory(prefix="svc-rd-compare-") as work:
        for name, arguments in configs:
            points = []
            for quality in (int(q) for q in options.qualities.split(",")):
                result = encode(binaries[name], options.db, quality, arguments.split(), work, options.threads)
                psnr = result["quality"]["psnr_y"]
                points.append((psnr, result["file_bytes"]))
                print(f"{name} q{quality}: {result['file_bytes']} bytes, {psnr:.3f} dB, B-face qindex "
                      f"{result.get('b_qindex', -1)}", file=sys.stderr, flush=True)
            curves[name] = points
    anchor = configs[0][0]
    for name, _ in configs[1:]:
        bd = bd_rate(curves[anchor], curves[name], low, high)
        text = "no common PSNR range" if bd is None else f"{100 * bd[0]:+.2f} % ({bd[1]:.1f}-{bd[2]:.1f} dB)"
        print(f"{os.path.basename(os.path.normpath(options.db))} {name} against {anchor}: {text}", flush=True)


if __name__ == "__main__":
    main()
