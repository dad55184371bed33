#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-2-Clause
"""What each conformance stream reaches of the decoder: reads the per-stream gcovr JSON
reports that scripts/conformance-coverage.sh --per-stream writes (DIR/NAME.json) and
prints, per stream, the decoder lines it executes and those that no other stream
executes, with the functions those lines are in."""
import json
import re
import pathlib
import sys


def reached_lines(report):
    """{(file, line)} executed, and {(file, line): function name} from the report."""
    lines, functions = set(), {}
    for entry in report["files"]:
        name = entry["file"]
        starts = sorted((f["lineno"], f["name"]) for f in entry.get("functions", []))
        for line in entry["lines"]:
            if line.get("gcovr/noncode") or line["count"] == 0:
                continue
            lines.add((name, line["line_number"]))
            owner = [fn for start, fn in starts if start <= line["line_number"]]
            functions[(name, line["line_number"])] = owner[-1] if owner else "?"
    return lines, functions


def short_name(function):
    """The function's own name, without namespaces, template arguments or parameters."""
    name = function.replace("(anonymous namespace)::", "").split("(")[0]
    return re.sub(r"<.*>", "", name).split("::")[-1]


def main(directory):
    reports = {}
    functions = {}
    for path in sorted(pathlib.Path(directory).glob("*.json")):
        lines, owners = reached_lines(json.loads(path.read_text()))
        reports[path.stem] = lines
        functions.update(owners)
    print(f"{'stream':<44} {'lines':>6} {'alone':>6}  functions with lines no other stream reaches")
    for name, lines in reports.items():
        others = set().union(*(l for n, l in reports.items() if n != name))
        alone = lines - others
        owners = sorted({f"{pathlib.Path(f).name}:{short_name(functions[(f, n)])}" for f, n in alone})
        print(f"{name:<44} {len(lines):>6} {len(alone):>6}  {', '.join(owners) if owners else '-'}")


if __name__ == "__main__":
    main(sys.argv[1])
