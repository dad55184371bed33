#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-2-Clause
"""bench/rd_compare.py's BD-rate agrees with bench/bd_rate.h on the published example
data (tests/bench_bd_rate_test.cc) and is exact on a uniform scale."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench"))
import rd_compare  # noqa: E402


def check(name, got, expected, tolerance):
    if abs(got - expected) > tolerance:
        sys.exit(f"{name}: {got} is not {expected} (within {tolerance})")


anchor = [(40.037, 9487.76), (38.615, 4593.60), (36.845, 2486.44), (34.851, 1358.24)]
test = [(40.121, 9787.80), (38.651, 4469.00), (36.970, 2451.52), (34.987, 1356.24)]
bd = rd_compare.bd_rate(anchor, test, -1e9, 1e9)
check("example 1", 100 * bd[0], -4.4174853506, 1e-5)
check("example 1 low end", bd[1], 34.987, 0)
check("example 1 high end", bd[2], 40.037, 0)
anchor = [(43.825, 82472.76), (41.404, 26875.24), (40.037, 9487.76), (38.615, 4593.6)]
test = [(44.731, 99896.96), (41.875, 33952.04), (40.121, 9787.8), (38.651, 4469.0)]
check("example 2", 100 * rd_compare.bd_rate(anchor, test, -1e9, 1e9)[0], -4.4721820028, 1e-5)
scaled = [(psnr, 0.75 * rate) for psnr, rate in anchor]
check("uniform scale", rd_compare.bd_rate(anchor, scaled, -1e9, 1e9)[0], -0.25, 1e-12)
check("window", rd_compare.bd_rate(anchor, scaled, 39, 42)[1], 39, 0)
if rd_compare.bd_rate(anchor, [(30, 1), (31, 2)], -1e9, 1e9) is not None:
    sys.exit("curves without a common range gave a BD-rate")
print("ok")
