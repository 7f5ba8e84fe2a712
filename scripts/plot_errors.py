#!/usr/bin/python3
"""Plots the errors of a mavloc report folder: one panel per quantity, error over time, one line
per estimator. Reads <report>/errors.csv (written by `mavloc compare`) and writes
<report>/errors.png.

`mavloc compare` already draws every quantity into errors_over_time.png (and report.html) with
scripts/figures/report_figures.py; this script draws a chosen subset of quantities.

Usage: /usr/bin/python3 scripts/plot_errors.py REPORT_DIR [--quantities x,y,z,roll,pitch,yaw]
(Debian's python3-matplotlib, installed by scripts/setup; call /usr/bin/python3 explicitly.)
"""
import argparse
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("report_dir")
    parser.add_argument("--quantities", default="", help="comma-separated subset")
    args = parser.parse_args()
    path = os.path.join(args.report_dir, "errors.csv")
    if not os.path.exists(path):
        sys.exit(f"plot_errors: {path}: file does not exist")
    series = defaultdict(lambda: ([], []))  # (quantity, estimator) -> (t, error)
    units = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            key = (row["quantity"], row["estimator"])
            series[key][0].append(float(row["t_s"]))
            series[key][1].append(float(row["error"]))
            units[row["quantity"]] = row["unit"]
    wanted = [q for q in args.quantities.split(",") if q] or sorted(units, key=list(units).index)
    if not wanted:
        sys.exit(f"plot_errors: {path}: no error rows")
    fig, axes = plt.subplots(len(wanted), 1, figsize=(9, 2.2 * len(wanted)), sharex=True, squeeze=False)
    t0 = min(t[0] for t, _ in series.values() if t)
    for ax, quantity in zip(axes[:, 0], wanted):
        for (q, estimator), (t, e) in sorted(series.items()):
            if q == quantity:
                ax.plot([x - t0 for x in t], e, label=estimator, linewidth=0.8)
        ax.set_ylabel(f"{quantity} [{units.get(quantity, '')}]")
        ax.grid(True, alpha=0.3)
    axes[0, 0].legend(fontsize="small", loc="upper left")
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle("estimate - truth")
    fig.tight_layout()
    out = os.path.join(args.report_dir, "errors.png")
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
