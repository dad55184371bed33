#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-2-Clause
"""Runs `svc bench` on every scene of the development corpus (bench/corpus.json) and
summarises the BD-rates per scene, their mean and the worst scene.

  bench/corpus.py [--quick] [--scenes a,b] [--split tune|report] [--codecs LIST]
                  [--out DIR] [--cache DIR] [--svc PATH] [--scene-tool PATH] [--threads N]
                  [--before DIR] [--render-only]

Scenes are rendered once (svc-scene, textures from scripts/fetch-textures.sh) into
CACHE/scenes, keyed by their settings; the anchors' quality points are kept in
CACHE/anchors (svc bench --anchor-cache), so a second run encodes only svc.
--quick runs the same scenes on their cells x, z = 0..5 (corpus.json "quick_cells"),
without speed and access measurements, for iterating; the full corpus, with svc's
speed beside its figures, is what is reported.
--before DIR compares svc with the svc of an earlier run's output folder (svc bench
--before), per scene: the BD-rate of a change.

Writes OUT/SCENE/ (svc bench's output per scene), OUT/summary.json and OUT/summary.md,
and prints the summary. BD-rates are over PSNR-Y 32-40 dB, negative where svc is smaller.
"""
import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_CODECS = "svc,svc-intra,x265,av1,av1-slow,avif"
# The anchors as the corpus figures name them: what svc and svc-intra are compared with.
COLUMNS = [("svc", "av1", "svc vs SVT-AV1 p6"), ("svc", "av1-slow", "svc vs libaom cpu-used 2"),
           ("svc", "av1-svt-slow", "svc vs SVT-AV1 p2"), ("svc", "x265", "svc vs x265 medium"),
           ("svc", "svc-intra", "svc vs svc intra-only"), ("svc-intra", "avif", "svc-intra vs AV1 intra")]


def cache_root():
    return os.path.join(os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")), "svc", "corpus")


def fetch_textures(texture_set):
    out = subprocess.run([os.path.join(ROOT, "scripts", "fetch-textures.sh"), "--set", texture_set],
                         check=True, capture_output=True, text=True).stdout
    return out.strip().splitlines()[-1]


def scene_arguments(scene):
    args = ["--kind", scene["kind"], "--grid", ",".join(str(v) for v in scene["grid"]),
            "--spacing", str(scene["spacing"]), "--face-size", str(scene.get("face_size", 256)),
            "--seed", str(scene.get("seed", 1))]
    if scene.get("supersample", 1) != 1:
        args += ["--supersample", str(scene["supersample"])]
    if scene.get("exposure", 0) != 0:
        args += ["--exposure", str(scene["exposure"])]
    if scene.get("anisotropic"):
        args += ["--anisotropic"]
    if scene.get("texture_scale", 1) != 1:
        args += ["--texture-scale", str(scene["texture_scale"])]
    return args


def render(scene, corpus_version, cache, scene_tool, threads):
    """The scene's database folder, rendered on first use."""
    args = scene_arguments(scene)
    key = hashlib.sha256(json.dumps([corpus_version, scene["textures"], args]).encode()).hexdigest()[:12]
    folder = os.path.join(cache, "scenes", "%s-%s" % (scene["name"], key))
    if os.path.exists(os.path.join(folder, "manifest.json")):
        return folder
    textures = fetch_textures(scene["textures"])
    print("rendering %s into %s" % (scene["name"], folder), file=sys.stderr)
    subprocess.run([scene_tool, folder] + args + ["--textures", textures, "--threads", str(threads), "--quiet",
                                                 "-y"], check=True)
    return folder


def quick_subset(full, cells, cache, name):
    """A database of the cells [lo, hi] along x and z of `full`, re-indexed from 0, its
    images hard-linked (or copied) from the full scene."""
    lo, hi = cells
    folder = os.path.join(cache, "quick", "%s-%s-%d-%d" % (name, os.path.basename(full), lo, hi))
    if os.path.exists(os.path.join(folder, "manifest.json")):
        return folder
    manifest = json.load(open(os.path.join(full, "manifest.json")))
    staging = folder + ".tmp-%d" % os.getpid()
    shutil.rmtree(staging, ignore_errors=True)
    kept = []
    for cell in manifest["cells"]:
        x, y, z = cell["index"]
        if not (lo <= x <= hi and lo <= z <= hi):
            continue
        index = [x - lo, y, z - lo]
        directory = "cells/%d_%d_%d" % tuple(index)
        os.makedirs(os.path.join(staging, directory))
        for face in cell["faces"].values():
            for kind in ("color", "depth"):
                target = os.path.join(directory, os.path.basename(face[kind]))
                source = os.path.join(full, face[kind])
                try:
                    os.link(source, os.path.join(staging, target))
                except OSError:
                    shutil.copyfile(source, os.path.join(staging, target))
                face[kind] = target
        cell["index"] = index
        kept.append(cell)
    first = next(c for c in kept if c["index"] == [0, 0, 0])
    manifest["grid"]["origin"] = first["position"]
    manifest["grid"]["dims"] = [hi - lo + 1, manifest["grid"]["dims"][1], hi - lo + 1]
    manifest["cells"] = kept
    with open(os.path.join(staging, "manifest.json"), "w") as out:
        json.dump(manifest, out, indent=2)
    os.rename(staging, folder)
    return folder


def run_bench(svc, database, out, codecs, cache, threads, before, speed):
    command = [svc, "bench", database, "--codecs", codecs, "--no-experiments", "--out", out, "-y", "--quiet",
               "--anchor-cache", os.path.join(cache, "anchors"), "--anchor-preset", "avif=4",
               "--threads", str(threads)]
    if not speed:
        command.append("--no-speed")
    if before:
        command += ["--before", before]
    subprocess.run(command, check=True)
    return json.load(open(os.path.join(out, "results.json")))


def bd_between(results, test, anchor):
    """BD-rate of `test` against `anchor` over 32-40 dB from a results.json, or None."""
    codecs = {c["name"]: c for c in results["codecs"] if not c.get("skipped")}
    if test not in codecs or anchor not in codecs:
        return None
    if test == results.get("bd_reference"):
        return codecs[anchor].get("bd_rate_svc_target")
    if test == "svc-intra":
        return codecs[anchor].get("bd_rate_svc_intra_target")
    return None


def summarise(rows, columns):
    lines = ["| scene | split | mean luma | contrast | gradient | sky % | " +
             " | ".join(label for _, _, label in columns) + " |",
             "|---|---|---:|---:|---:|---:|" + "---:|" * len(columns)]

    def cell(v):
        return "n/a" if v is None else "%+.1f %%" % (100 * v)

    for row in rows:
        c = row["content"]
        lines.append("| %s | %s | %.0f | %.0f | %.1f | %.0f | " % (row["scene"], row["split"], c["mean_luma"],
                                                                 c["luma_contrast"], c["mean_gradient"],
                                                                 100 * c["background_share"]) +
                     " | ".join(cell(row["bd"].get(label)) for _, _, label in columns) + " |")
    for name, pick in (("mean", lambda v: sum(v) / len(v)), ("worst", max)):
        values = []
        for _, _, label in columns:
            got = [r["bd"][label] for r in rows if r["bd"].get(label) is not None]
            values.append(cell(pick(got)) if got else "n/a")
        lines.append("| **%s** | | | | | | " % name + " | ".join(values) + " |")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--scenes", default="")
    parser.add_argument("--split", choices=["tune", "report"])
    parser.add_argument("--codecs", default=DEFAULT_CODECS)
    parser.add_argument("--out", default="corpus-results")
    parser.add_argument("--cache", default=cache_root())
    parser.add_argument("--svc", default=os.path.join(ROOT, "build", "bin", "svc"))
    parser.add_argument("--scene-tool", default=os.path.join(ROOT, "build", "bin", "svc-scene"))
    parser.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--before", default="")
    parser.add_argument("--render-only", action="store_true")
    options = parser.parse_args()

    corpus = json.load(open(os.path.join(ROOT, "bench", "corpus.json")))
    wanted = set(filter(None, options.scenes.split(",")))
    scenes = [s for s in corpus["scenes"] if (not wanted or s["name"] in wanted) and
              (not options.split or s["split"] == options.split)]
    unknown = wanted - {s["name"] for s in corpus["scenes"]}
    if unknown:
        sys.exit("corpus: no scene named %s" % ", ".join(sorted(unknown)))
    rows = []
    for scene in scenes:
        database = render(scene, corpus["version"], options.cache, options.scene_tool, options.threads)
        if options.quick:
            database = quick_subset(database, corpus["quick_cells"], options.cache, scene["name"])
        if options.render_only:
            print("%s: %s" % (scene["name"], database))
            continue
        out = os.path.join(options.out, scene["name"])
        before = os.path.join(options.before, scene["name"], "results.json") if options.before else ""
        print("%s: svc bench %s" % (scene["name"], database), file=sys.stderr)
        results = run_bench(options.svc, database, out, options.codecs, options.cache, options.threads, before,
                            not options.quick)
        bd = {label: bd_between(results, test, anchor) for test, anchor, label in COLUMNS}
        if results.get("before"):
            bd["svc vs before"] = results["before"].get("bd_rate_psnr_y")
        rows.append({"scene": scene["name"], "split": scene["split"], "database": database,
                     "content": results["content"], "bd": bd})
    if options.render_only:
        return
    columns = [c for c in COLUMNS if any(r["bd"].get(c[2]) is not None for r in rows)]
    if any("svc vs before" in r["bd"] for r in rows):
        columns.append(("svc", "before", "svc vs before"))
    table = summarise(rows, columns)
    os.makedirs(options.out, exist_ok=True)
    json.dump({"format": "svc-corpus-summary", "corpus_version": corpus["version"], "quick": options.quick,
               "codecs": options.codecs, "scenes": rows}, open(os.path.join(options.out, "summary.json"), "w"),
              indent=2)
    with open(os.path.join(options.out, "summary.md"), "w") as out:
        out.write(table + "\n")
    print(table)


if __name__ == "__main__":
    main()
