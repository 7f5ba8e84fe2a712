#!/usr/bin/python3
"""Compares every number of two mavloc report.json files: did a change of the code (a faster
solver, another memory layout) move any reported number?

Usage: /usr/bin/python3 benchmarks/compare_report_numbers.py OLD.json NEW.json [--rtol 1e-9]

Both files must have the same structure (the same keys, lists and tables of the same lengths);
every number is compared, and every text that differs (a warning, a title) is listed. Left out:
what describes the run rather than its results (provenance; the keys and table columns that time
the run: runtime_s, mean_runtime_s, compute_s, ...) and the sections' markdown, whose numbers are
those of the results rounded for people.

Two relative differences are printed for each number that differs:
- elementwise, |new - old| / |old|;
- within its statistics, |new - old| / max |value| over the statistics object it belongs to
  (rmse, mean, median, std, min, max of one error series): the change measured against the
  scale of the series, as a normwise comparison of vectors does. A minimum of 5e-8 rad in a
  series whose maximum is 1e-3 rad is resolved by double arithmetic to about 1e-16 rad, which
  is 2e-9 of itself: its elementwise difference is not meaningful below that.
Numbers outside a statistics object are their own scale. The exit status is 1 when a difference
within statistics exceeds --rtol (or any elementwise one, with --elementwise), 2 when the
structures differ, 0 otherwise.
"""
import argparse
import json
import math
import sys

SKIPPED_KEYS = {"provenance", "markdown"}
TIMING_WORDS = ("runtime", "elapsed", "compute_s", "wall", "cpu_s")  # keys and columns of timings
STATISTICS_KEYS = {"rmse", "mean", "median", "std", "min", "max"}


def walk(old, new, path, scale, out):
    """Appends (path, old, new, scale) for every number and (path, old, new) for every string that
    differs; raises ValueError where the structures differ."""
    if isinstance(old, dict) and isinstance(new, dict) and "columns" in old and "rows" in old:
        walk_table(old, new, path, out)
    elif isinstance(old, dict) and isinstance(new, dict):
        if old.keys() != new.keys():
            raise ValueError(f"{path}: keys differ: {sorted(old.keys() ^ new.keys())}")
        group_scale = None
        if STATISTICS_KEYS <= old.keys():
            values = [abs(old[k]) for k in STATISTICS_KEYS if isinstance(old[k], (int, float))]
            group_scale = max(values, default=None)
        for key in old:
            if key in SKIPPED_KEYS or any(word in key.lower() for word in TIMING_WORDS):
                continue
            inner = group_scale if key in STATISTICS_KEYS else None
            walk(old[key], new[key], f"{path}.{key}", inner, out)
    elif isinstance(old, list) and isinstance(new, list) and all(
            isinstance(x, str) for x in old + new):
        if old != new:  # warnings, events: listed, not a difference of structure
            out.append((path, old, new))
    elif isinstance(old, list) and isinstance(new, list):
        if len(old) != len(new):
            raise ValueError(f"{path}: {len(old)} entries against {len(new)}")
        for i, (a, b) in enumerate(zip(old, new)):
            walk(a, b, f"{path}[{i}]", None, out)
    elif isinstance(old, str) and isinstance(new, str):
        if old != new:
            out.append((path, old, new))
    elif isinstance(old, bool) or isinstance(new, bool) or old is None or new is None:
        if old != new:
            raise ValueError(f"{path}: {old!r} against {new!r}")
    elif isinstance(old, (int, float)) and isinstance(new, (int, float)):
        out.append((path, float(old), float(new), scale))
    else:
        raise ValueError(f"{path}: {old!r} against {new!r}")


def walk_table(old, new, path, out):
    """A report table: its columns compared whole, its rows without the columns that time the
    run."""
    walk(old["columns"], new["columns"], f"{path}.columns", None, out)
    timing = {i for i, c in enumerate(old["columns"])
              if any(word in c["name"].lower() for word in TIMING_WORDS)}
    for key in old.keys() - {"columns", "rows"}:
        walk(old[key], new[key], f"{path}.{key}", None, out)
    if len(old["rows"]) != len(new["rows"]):
        raise ValueError(f"{path}.rows: {len(old['rows'])} rows against {len(new['rows'])}")
    for r, (row_old, row_new) in enumerate(zip(old["rows"], new["rows"])):
        kept = [i for i in range(len(row_old)) if i not in timing]
        walk([row_old[i] for i in kept], [row_new[i] for i in kept], f"{path}.rows[{r}]", None,
             out)


def relative(a, b, scale):
    if a == b:
        return 0.0
    if not (math.isfinite(a) and math.isfinite(b)):
        return math.inf
    return abs(b - a) / max(abs(scale), sys.float_info.min)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--rtol", type=float, default=1e-9)
    parser.add_argument("--elementwise", action="store_true",
                        help="fail on an elementwise difference beyond --rtol too")
    args = parser.parse_args()
    try:
        old, new = (json.loads(open(path).read()) for path in (args.old, args.new))
    except (OSError, ValueError) as error:
        print(f"compare_report_numbers: {error}", file=sys.stderr)
        return 2
    numbers = []
    try:
        walk(old, new, "", None, numbers)
    except ValueError as error:
        print(f"structures differ at {error}")
        return 2
    texts = [entry for entry in numbers if len(entry) == 3]
    numbers = [entry for entry in numbers if len(entry) == 4]
    for path, a, b in texts:
        print(f"text {path}: {a!r} -> {b!r}")
    failed = False
    worst_element, worst_group = 0.0, 0.0
    for path, a, b, scale in numbers:
        element = relative(a, b, a)
        group = relative(a, b, scale if scale is not None else a)
        worst_element, worst_group = max(worst_element, element), max(worst_group, group)
        over = group > args.rtol or (args.elementwise and element > args.rtol)
        failed |= over
        if element > args.rtol:
            print(f"{'OVER ' if over else 'ok   '}{path}: {a!r} -> {b!r} "
                  f"(elementwise {element:.2g}, within its statistics {group:.2g})")
    print(f"{len(numbers)} numbers, {len(texts)} texts differ; largest relative difference "
          f"elementwise {worst_element:.2g}, "
          f"within statistics {worst_group:.2g} (rtol {args.rtol:g})")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
