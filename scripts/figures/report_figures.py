#!/usr/bin/python3
"""Figures of a mavloc report folder, drawn with Debian's python3-matplotlib.

The kind of folder is detected from its files (or given with --kind):
  eval     `mavloc eval --out DIR`: truth.tum, estimate_<label>[_run<k>].tum, errors_over_time.csv,
           relative_errors.csv -> trajectory.png (top x-y and side x-z views), errors_over_time.png
           (Monte-Carlo mean +- std and min/max bands where a label has several runs),
           relative_errors.png (boxplots per sub-trajectory length, grouped by estimate).
  compare  `mavloc compare --report DIR`: errors.csv (and truth.tum, estimate_<name>.tum) ->
           errors_over_time.png, error_boxplots.png, trajectory.png.
  repro    `mavloc repro NAME --report DIR`: every CSV (time series, with envelopes for mean/max
           columns, bands and runs; boxplots over seeds; bar charts of tables) and the report.json
           tables with per-estimator statistics (bars, the paper's value as a marker, boxplots over
           runs where per-run values are given).

Usage: /usr/bin/python3 scripts/figures/report_figures.py REPORT_DIR [--kind eval|compare|repro]
The mavloc binary embeds this file and runs it after writing a report, then writes report.html;
run by hand, it writes the PNG files only. Prints one line per figure:
"figure<TAB>file<TAB>caption".
Exit code 3 when matplotlib or numpy is missing (Debian: apt-get install python3-matplotlib).
"""
import argparse
import csv
import json
import math
import os
import re
import sys
import warnings
from collections import OrderedDict, defaultdict

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
except ImportError as error:  # the C++ side turns exit code 3 into "install python3-matplotlib"
    print(f"report_figures: {error}", file=sys.stderr)
    sys.exit(3)

DPI = 100
plt.rcParams["figure.constrained_layout.use"] = True  # makes room for suptitles and legends
MAX_REPRO_FIGURES = 16
ENVELOPE_SAMPLES = 400


class Figures:
    """Saves figures into the report folder and announces each on stdout."""

    def __init__(self, folder):
        self.folder = folder
        self.written = []

    def save(self, fig, name, caption):
        path = os.path.join(self.folder, name)
        fig.savefig(path, dpi=DPI)
        plt.close(fig)
        self.written.append(name)
        caption = " ".join(caption.split())
        print(f"figure\t{name}\t{caption}", flush=True)


def color_map(labels):
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    return {label: cycle[i % len(cycle)] for i, label in enumerate(labels)}


def to_float(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def read_csv(path):
    with open(path, newline="", encoding="utf-8-sig") as f:
        rows = list(csv.reader(f))
    if not rows:
        return [], []
    return [h.strip() for h in rows[0]], [r for r in rows[1:] if r]


def read_trajectory(path):
    """t x y z from a TUM file (blank and '#' lines skipped; spaces, tabs or commas)."""
    rows = []
    with open(path, encoding="utf-8-sig") as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            fields = re.split(r"[\s,]+", line)
            if len(fields) >= 4:
                values = [to_float(x) for x in fields[:4]]
                if all(math.isfinite(v) for v in values):
                    rows.append(values)
    return np.array(rows) if rows else None


def estimate_files(folder):
    """label -> [(run, path)] for estimate_<label>[_run<k>].tum, runs in order."""
    found = defaultdict(list)
    for name in sorted(os.listdir(folder)):
        m = re.fullmatch(r"estimate_(.+?)(?:_run(\d+))?\.tum", name)
        if m:
            found[m.group(1)].append((int(m.group(2) or 0), os.path.join(folder, name)))
    return OrderedDict((label, sorted(runs)) for label, runs in found.items())


def envelope(runs):
    """runs: [(t, e)]; one run -> (t, e, None); several -> mean, std, min, max on a common grid
    over the time span every run covers (mean +- std is the usual Monte-Carlo envelope)."""
    runs = [(t, e) for t, e in runs if len(t) > 0]
    if len(runs) == 1:
        return runs[0][0], runs[0][1], None
    lo = max(t[0] for t, _ in runs)
    hi = min(t[-1] for t, _ in runs)
    if not hi > lo:
        lo = min(t[0] for t, _ in runs)
        hi = max(t[-1] for t, _ in runs)
    grid = np.linspace(lo, hi, ENVELOPE_SAMPLES)
    stack = np.array([np.interp(grid, t, e, left=np.nan, right=np.nan) for t, e in runs])
    with np.errstate(all="ignore"):
        with warnings.catch_warnings():  # all-NaN columns outside a run's span
            warnings.simplefilter("ignore", category=RuntimeWarning)
            stats = {
                "mean": np.nanmean(stack, axis=0),
                "std": np.nanstd(stack, axis=0),
                "min": np.nanmin(stack, axis=0),
                "max": np.nanmax(stack, axis=0),
                "runs": len(runs),
            }
    return grid, stats["mean"], stats


def plot_series(ax, label, color, runs):
    """One line for one run; mean line with mean +- std and min/max bands for several."""
    t, e, stats = envelope(runs)
    if stats is None:
        ax.plot(t, e, color=color, linewidth=0.9, label=label)
        return
    ax.fill_between(t, stats["min"], stats["max"], color=color, alpha=0.12, linewidth=0)
    ax.fill_between(t, stats["mean"] - stats["std"], stats["mean"] + stats["std"], color=color,
                    alpha=0.3, linewidth=0)
    ax.plot(t, e, color=color, linewidth=1.0,
            label=f"{label}: mean, ±1 std, min-max over {stats['runs']} runs")


def sorted_time_series(pairs):
    pairs = sorted((t, e) for t, e in pairs if math.isfinite(t))
    return np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])


# ---------------------------------------------------------------------------------------------
# Trajectories (eval and compare)


def trajectory_figure(out, folder, title, order=()):
    """order: labels in the order (and so the colors) of the folder's other figures."""
    truth_path = os.path.join(folder, "truth.tum")
    truth = read_trajectory(truth_path) if os.path.exists(truth_path) else None
    # compare --reference: the reference, an estimate the others were compared with.
    reference_path = os.path.join(folder, "reference.tum")
    reference = read_trajectory(reference_path) if os.path.exists(reference_path) else None
    estimates = OrderedDict()
    for label, runs in estimate_files(folder).items():
        arrays = [a for a in (read_trajectory(p) for _, p in runs) if a is not None]
        if arrays:
            estimates[label] = arrays
    if truth is None and reference is None and not estimates:
        return
    labels = [x for x in order if x in estimates] + [x for x in estimates if x not in order]
    estimates = OrderedDict((x, estimates[x]) for x in labels)
    colors = color_map(list(order) + [x for x in labels if x not in order])
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.8))
    for ax, (i, j, view) in zip(axes, [(1, 2, "top view (x-y)"), (1, 3, "side view (x-z)")]):
        if truth is not None:
            # Drawn last (on top), thin and dashed, so that the estimates under it stay visible.
            ax.plot(truth[:, i], truth[:, j], color="black", linewidth=1.0, linestyle="--",
                    label="truth", zorder=5)
            ax.plot(truth[0, i], truth[0, j], "o", color="black", markersize=4, zorder=5)
        if reference is not None:
            ax.plot(reference[:, i], reference[:, j], color="dimgray", linewidth=1.0,
                    linestyle="-.", label="reference (an estimate)", zorder=4)
        for label, arrays in estimates.items():
            many = len(arrays) > 1
            for k, a in enumerate(arrays):
                name = (f"{label} ({len(arrays)} runs)" if many else label) if k == 0 else None
                ax.plot(a[:, i], a[:, j], color=colors[label], linewidth=0.6 if many else 0.9,
                        alpha=0.45 if many else 0.95, label=name)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]" if j == 2 else "z [m]")
        ax.set_title(view)
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize="small", loc="best")
    fig.suptitle(title)
    out.save(fig, "trajectory.png",
             "Trajectories, top (x-y) and side (x-z) views: " +
             ("truth in black (dot: start) and " if truth is not None
              else "no truth.tum in this folder; ") + "each estimate as written in this folder" +
             (" (aligned as the report states)." if os.path.exists(os.path.join(folder, "report.md"))
              else "."))


# ---------------------------------------------------------------------------------------------
# eval


def csv_labels(path, column):
    """The values of one column in order of first appearance (empty when the file is absent)."""
    labels = []
    if os.path.exists(path):
        header, rows = read_csv(path)
        if column in header:
            i = header.index(column)
            for r in rows:
                if i < len(r) and r[i] not in labels:
                    labels.append(r[i])
    return labels


def eval_figures(out, folder):
    # One color per estimate in every figure: the order of errors_over_time.csv, then the others.
    order = csv_labels(os.path.join(folder, "errors_over_time.csv"), "label")
    order += [x for x in csv_labels(os.path.join(folder, "relative_errors.csv"), "label")
              if x not in order]
    order += [x for x in estimate_files(folder) if x not in order]
    colors = color_map(order)
    trajectory_figure(out, folder, "trajectories", order)
    path = os.path.join(folder, "errors_over_time.csv")
    if os.path.exists(path):
        header, rows = read_csv(path)
        col = {h: i for i, h in enumerate(header)}
        needed = ["label", "t_s", "translation_error_m", "rotation_error_deg"]
        if rows and all(h in col for h in needed):
            series = OrderedDict()  # label -> run -> [(t, et, er)]
            for r in rows:
                run = r[col["run"]] if "run" in col and col["run"] < len(r) else ""
                series.setdefault(r[col["label"]], OrderedDict()).setdefault(run, []).append(
                    (to_float(r[col["t_s"]]), to_float(r[col["translation_error_m"]]),
                     to_float(r[col["rotation_error_deg"]])))
            t0 = min(v[0] for runs in series.values() for rs in runs.values() for v in rs
                     if math.isfinite(v[0]))
            fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
            any_runs = False
            for label, runs in series.items():
                any_runs |= len(runs) > 1
                for k, (ax, unit) in enumerate(zip(axes, ["m", "deg"])):
                    plot_series(ax, label, colors[label],
                                [sorted_time_series((v[0] - t0, v[1 + k]) for v in rs)
                                 for rs in runs.values()])
            axes[0].set_ylabel("translation error [m]")
            axes[1].set_ylabel("rotation error [deg]")
            axes[1].set_xlabel("time [s]")
            for ax in axes:
                ax.grid(True, alpha=0.3)
            axes[0].legend(fontsize="small", loc="upper left")
            fig.suptitle("absolute error over time (after alignment)")
            out.save(fig, "errors_over_time.png",
                     "Translation and rotation error over time after alignment, per estimate" +
                     ("; where an estimate has several runs, a Monte-Carlo envelope: the line is "
                      "the mean over runs, the dark band ±1 standard deviation and the light band "
                      "min to max." if any_runs else "."))
    path = os.path.join(folder, "relative_errors.csv")
    if os.path.exists(path):
        header, rows = read_csv(path)
        col = {h: i for i, h in enumerate(header)}
        needed = ["label", "length_m", "translation_error_pct", "rotation_error_deg_per_m"]
        if rows and all(h in col for h in needed):
            data = defaultdict(lambda: ([], []))  # (label, length) -> (pct, deg/m)
            labels, lengths = [], []
            for r in rows:
                label, length = r[col["label"]], to_float(r[col["length_m"]])
                if label not in labels:
                    labels.append(label)
                if length not in lengths:
                    lengths.append(length)
                data[(label, length)][0].append(to_float(r[col["translation_error_pct"]]))
                data[(label, length)][1].append(to_float(r[col["rotation_error_deg_per_m"]]))
            lengths.sort()
            labels = [x for x in order if x in labels]
            grouped_boxplots(out, labels, colors, lengths, data,
                             ["translation error [%]", "rotation error [deg/m]"],
                             "relative_errors.png", "relative error per sub-trajectory length",
                             "Relative errors over sub-trajectories of each length (KITTI / "
                             "rpg_trajectory_evaluation definition): translation in % of the "
                             "length, rotation in deg/m; one box per estimate (all runs pooled), "
                             "box = quartiles, whiskers = 1.5 IQR.",
                             [f"{x:g} m" for x in lengths])


def grouped_boxplots(out, labels, colors, groups, data, ylabels, name, title, caption,
                     group_names):
    width_in = max(7.0, 4.0 + 1.2 * len(groups) * math.sqrt(max(1, len(labels))))
    fig, axes = plt.subplots(len(ylabels), 1, figsize=(width_in, 3.0 * len(ylabels)), squeeze=False)
    width = 0.8 / max(1, len(labels))
    for k, ax in enumerate(axes[:, 0]):
        for i, label in enumerate(labels):
            positions, values = [], []
            for g, group in enumerate(groups):
                v = [x for x in data.get((label, group), ([], []))[k] if math.isfinite(x)]
                if v:
                    positions.append(g - 0.4 + width * (i + 0.5))
                    values.append(v)
            if not values:
                continue
            box = ax.boxplot(values, positions=positions, widths=width * 0.85, patch_artist=True,
                             flierprops={"markersize": 2})
            for patch in box["boxes"]:
                patch.set_facecolor(colors[label])
                patch.set_alpha(0.6)
            for median in box["medians"]:
                median.set_color("black")
        ax.set_xticks(range(len(groups)))
        ax.set_xticklabels(group_names)
        ax.set_xlim(-0.6, len(groups) - 0.4)
        ax.set_ylabel(ylabels[k])
        ax.grid(True, axis="y", alpha=0.3)
    axes[-1, 0].set_xlabel("sub-trajectory length")
    axes[0, 0].legend(handles=[Patch(facecolor=colors[x], alpha=0.6, label=x) for x in labels],
                      fontsize="small", loc="upper left")
    fig.suptitle(title)
    out.save(fig, name, caption)


# ---------------------------------------------------------------------------------------------
# compare


def report_reference(folder):
    """protocol.reference of the folder's report.json: "truth", "estimate" or None."""
    try:
        with open(os.path.join(folder, "report.json"), encoding="utf-8") as f:
            protocol = json.load(f).get("protocol") or {}
        return protocol.get("reference")
    except (OSError, ValueError, AttributeError):
        return None


def compare_figures(out, folder):
    header, rows = read_csv(os.path.join(folder, "errors.csv"))
    col = {h: i for i, h in enumerate(header)}
    needed = ["estimator", "quantity", "unit", "t_s", "error"]
    if rows and all(h in col for h in needed):
        series = OrderedDict()  # quantity -> estimator -> [(t, e)]
        units = {}
        estimators = []  # in the order of the report's table
        for r in rows:
            if r[col["estimator"]] not in estimators:
                estimators.append(r[col["estimator"]])
            q = r[col["quantity"]]
            units[q] = r[col["unit"]]
            series.setdefault(q, OrderedDict()).setdefault(r[col["estimator"]], []).append(
                (to_float(r[col["t_s"]]), to_float(r[col["error"]])))
        colors = color_map(estimators)
        t0 = min(t for per in series.values() for v in per.values() for t, _ in v
                 if math.isfinite(t))
        quantities = list(series)
        fig, axes = plt.subplots(len(quantities), 1, figsize=(10, 1.9 * len(quantities) + 1),
                                 sharex=True, squeeze=False)
        for ax, q in zip(axes[:, 0], quantities):
            for estimator, values in series[q].items():
                t, e = sorted_time_series((t - t0, e) for t, e in values)
                ax.plot(t, e, color=colors[estimator], linewidth=0.8, label=estimator)
            ax.set_ylabel(f"{q} [{units[q]}]")
            ax.grid(True, alpha=0.3)
        axes[0, 0].legend(handles=[Line2D([], [], color=colors[e], label=e) for e in estimators],
                          fontsize="small", loc="upper left", ncol=max(1, min(4, len(estimators))))
        axes[-1, 0].set_xlabel("time [s]")
        against = "reference" if report_reference(folder) == "estimate" else "truth"
        fig.suptitle(f"Error over time (estimate - {against}) of each quantity")
        out.save(fig, "errors_over_time.png",
                 "Error (estimate - truth; against a reference: estimate - reference) of every "
                 "quantity over time, one line per estimator, as in errors.csv.")

        ncols = min(3, len(quantities))
        nrows = (len(quantities) + ncols - 1) // ncols
        fig, axes = plt.subplots(nrows, ncols, figsize=(4.2 * ncols, max(3.6, 2.9 * nrows)),
                                 squeeze=False)
        for k, q in enumerate(quantities):
            ax = axes[k // ncols, k % ncols]
            names = [e for e in estimators if e in series[q]]
            values = [[abs(v) for _, v in series[q][e] if math.isfinite(v)] for e in names]
            keep = [i for i, v in enumerate(values) if v]
            if keep:
                box = ax.boxplot([values[i] for i in keep], patch_artist=True,
                                 flierprops={"markersize": 2})
                for patch, i in zip(box["boxes"], keep):
                    patch.set_facecolor(colors[names[i]])
                    patch.set_alpha(0.6)
                for median in box["medians"]:
                    median.set_color("black")
                ax.set_xticks(range(1, len(keep) + 1))
                ax.set_xticklabels([names[i] for i in keep], rotation=30, ha="right",
                                   fontsize="small")
            ax.set_title(f"|{q}| [{units[q]}]", fontsize="medium")
            ax.grid(True, axis="y", alpha=0.3)
        for k in range(len(quantities), nrows * ncols):
            axes[k // ncols, k % ncols].axis("off")
        fig.suptitle("absolute error per quantity and estimator")
        out.save(fig, "error_boxplots.png",
                 "Distribution of the absolute error of each quantity over all frames, one box per "
                 "estimator (quartiles; whiskers 1.5 IQR).")
    trajectory_figure(out, folder, "trajectories (truth and estimates after the ATE alignment)",
                      csv_labels(os.path.join(folder, "errors.csv"), "estimator"))


# ---------------------------------------------------------------------------------------------
# repro: generic plots of the CSV files and of the report.json tables

TIME_COLUMN = re.compile(r"^t(_s| \[s\]|ime( \[s\]|_s)?)?$")
RUN_COLUMN = re.compile(r"^(run|seed)$")


def is_numeric_column(rows, i):
    values = [r[i] for r in rows if i < len(r) and r[i] != ""]
    missing = ("nan", "-", "inf", "-inf")
    return bool(values) and all(math.isfinite(to_float(v)) or v.lower() in missing for v in values)


def repro_csv_figure(out, folder, name):
    header, rows = read_csv(os.path.join(folder, name))
    if not rows or len(header) < 2:
        return
    base = os.path.splitext(name)[0]
    numeric = [i for i in range(len(header)) if is_numeric_column(rows, i)]
    text = [i for i in range(len(header)) if i not in numeric]
    time = next((i for i in numeric if TIME_COLUMN.match(header[i])), None)
    run = next((i for i in range(len(header)) if RUN_COLUMN.match(header[i])), None)

    def group_of(r):
        return " / ".join(r[i] for i in text if i < len(r) and i != run) or base

    if time is not None:
        values = [i for i in numeric if i not in (time, run)]
        # "<x>_mean [u]" with "<x>_max [u]": one panel with the mean and a band up to the max.
        pairs, used = [], set()
        for i in values:
            m = re.match(r"^(.*)_mean(.*)$", header[i])
            if m:
                j = next((j for j in values if header[j] == f"{m.group(1)}_max{m.group(2)}"), None)
                if j is not None:
                    pairs.append((f"{m.group(1)}{m.group(2)}", i, j))
                    used |= {i, j}
        band = [i for i in values if header[i] in ("band_low", "band_high")]
        used |= set(band)
        singles = [i for i in values if i not in used][:9]
        panels = [("pair", p) for p in pairs] + [("single", i) for i in singles]
        if not panels:
            return
        groups = OrderedDict()
        for r in rows:
            groups.setdefault(group_of(r), OrderedDict()).setdefault(
                r[run] if run is not None else "", []).append(r)
        colors = color_map(list(groups))
        fig, axes = plt.subplots(len(panels), 1, figsize=(10, 1.8 * len(panels) + 1.2),
                                 sharex=True, squeeze=False)
        for ax, (kind, p) in zip(axes[:, 0], panels):
            for g, runs in groups.items():
                if kind == "pair":
                    label, i, j = p
                    r0 = next(iter(runs.values()))
                    t = np.array([to_float(r[time]) for r in r0])
                    ax.fill_between(t, [to_float(r[i]) for r in r0], [to_float(r[j]) for r in r0],
                                    color=colors[g], alpha=0.2, linewidth=0)
                    ax.plot(t, [to_float(r[i]) for r in r0], color=colors[g], linewidth=0.9,
                            label=f"{g}: mean (line) to max (band)" if len(groups) > 1
                            else "mean (line) to max (band) over runs")
                    ax.set_ylabel(label, fontsize="small")
                else:
                    plot_series(ax, g, colors[g],
                                [sorted_time_series((to_float(r[time]), to_float(r[p]))
                                                    for r in rs) for rs in runs.values()])
                    ax.set_ylabel(header[p], fontsize="small")
            if band and len(band) == 2 and kind == "single":
                r0 = rows
                t = np.array([to_float(r[time]) for r in r0])
                ax.fill_between(t, [to_float(r[band[0]]) for r in r0],
                                [to_float(r[band[1]]) for r in r0], color="gray", alpha=0.2,
                                linewidth=0, label="95% band")
            ax.grid(True, alpha=0.3)
        handles, _ = axes[0, 0].get_legend_handles_labels()
        if handles:
            axes[0, 0].legend(fontsize="x-small", loc="upper right")
        axes[-1, 0].set_xlabel(header[time])
        fig.suptitle(name)
        out.save(fig, f"{base}.png",
                 f"{name} over time" +
                 (" (Monte-Carlo: mean line, ±1 std and min-max bands over runs)"
                  if run is not None else "")
                 + ("; Monte-Carlo envelope: line = mean over runs, band up to the max over runs"
                    if pairs else "")
                 + (", gray: the consistency band" if band else "") + ".")
        return

    if run is not None:
        # One value per run: boxplots over runs, one panel per quantity (when named).
        metric_names = [header[i] for i in numeric if i != run]
        preferred = next((i for key in ("mae", "rmse", "error") for i in numeric
                          if i != run and key in header[i]), None)
        metric = preferred if preferred is not None else next(
            (i for i in numeric if i != run), None)
        if metric is None:
            return
        qcol = next((i for i in text if header[i] == "quantity"), None)
        ucol = next((i for i in text if header[i] == "unit"), None)
        others = [i for i in text if i not in (qcol, ucol)]
        panels = OrderedDict()
        for r in rows:
            q = r[qcol] if qcol is not None else header[metric]
            g = " / ".join(r[i] for i in others) or base
            panels.setdefault(q, OrderedDict()).setdefault(g, []).append(to_float(r[metric]))
        units = {r[qcol]: r[ucol] for r in rows} if qcol is not None and ucol is not None else {}
        keys = list(panels)[:12]
        group_colors = color_map(list(OrderedDict.fromkeys(g for q in keys for g in panels[q])))
        ncols = min(3, len(keys))
        nrows = (len(keys) + ncols - 1) // ncols
        fig, axes = plt.subplots(nrows, ncols, figsize=(4.3 * ncols, max(3.6, 3.0 * nrows)),
                                 squeeze=False)
        for k, q in enumerate(keys):
            ax = axes[k // ncols, k % ncols]
            names = [g for g, v in panels[q].items() if any(math.isfinite(x) for x in v)]
            if names:
                box = ax.boxplot([[x for x in panels[q][g] if math.isfinite(x)] for g in names],
                                 patch_artist=True, flierprops={"markersize": 2})
                for patch, g in zip(box["boxes"], names):
                    patch.set_facecolor(group_colors[g])
                    patch.set_alpha(0.6)
                for median in box["medians"]:
                    median.set_color("black")
                ax.set_xticks(range(1, len(names) + 1))
                ax.set_xticklabels(names, rotation=25, ha="right", fontsize="x-small")
            unit = f" [{units[q]}]" if q in units else ""
            ax.set_title(f"{q}: {header[metric]}{unit}" if qcol is not None else q,
                         fontsize="small")
            ax.grid(True, axis="y", alpha=0.3)
        for k in range(len(keys), nrows * ncols):
            axes[k // ncols, k % ncols].axis("off")
        fig.suptitle(f"{name}: {header[metric]} over {header[run]}s")
        out.save(fig, f"{base}.png",
                 f"{name}: distribution of {header[metric]} over the Monte-Carlo "
                 f"{header[run]}s (boxes: quartiles; whiskers 1.5 IQR)"
                 + (f"; other columns: {', '.join(m for m in metric_names if m != header[metric])}"
                    if len(metric_names) > 1 else "") + ".")
        return

    # A table: one row per line, one panel of bars per metric column. The key columns (the row's
    # label) are the leading ones up to the first numeric column with a unit ("[cm]", "/run", "%")
    # that follows a text column; e.g. "factor,value,pnp RMSE [cm],..." -> keys factor, value.
    seen_text, first_metric = False, None
    for i, h in enumerate(header):
        if i in numeric and seen_text and re.search(r"\[|/|%", h):
            first_metric = i
            break
        seen_text |= i not in numeric
    if first_metric is None or not text:
        return
    keys = list(range(first_metric))
    columns = [i for i in numeric if i >= first_metric][:8]
    labels = [" / ".join(r[i] for i in keys if i < len(r)) for r in rows]
    # Colors by the text key with the fewest distinct values (above one): the estimator or factor.
    distinct = {i: len(set(r[i] for r in rows if i < len(r))) for i in keys if i not in numeric}
    color_key = min(distinct, key=lambda i: (distinct[i] < 2, distinct[i], -i))
    bar_colors = color_map(list(OrderedDict.fromkeys(r[color_key] for r in rows)))
    ncols = min(2, len(columns))
    nrows = (len(columns) + ncols - 1) // ncols
    height = 0.28 * len(labels) + 1.2
    fig, axes = plt.subplots(nrows, ncols, figsize=(6.5 * ncols, height * nrows + 0.6),
                             squeeze=False)
    for k, i in enumerate(columns):
        ax = axes[k // ncols, k % ncols]
        v = [to_float(r[i]) if i < len(r) else math.nan for r in rows]
        y = np.arange(len(labels))
        ax.barh(y, [x if math.isfinite(x) else 0 for x in v], alpha=0.8,
                color=[bar_colors[r[color_key]] for r in rows])
        ax.set_yticks(y)
        ax.set_yticklabels(labels if k % ncols == 0 else [""] * len(labels), fontsize="x-small")
        ax.invert_yaxis()
        ax.set_title(header[i], fontsize="small")
        ax.grid(True, axis="x", alpha=0.3)
    for k in range(len(columns), nrows * ncols):
        axes[k // ncols, k % ncols].axis("off")
    fig.suptitle(name)
    out.save(fig, f"{base}.png",
             f"{name}: one panel per column, one bar per line (labelled by "
             f"{', '.join(header[i] for i in keys)}; colored by {header[color_key]}); "
             "missing values are drawn as empty bars.")


def find_estimator_tables(node, path, found):
    """Every object with an "estimators" object (report.json of repro: per-estimator objects as in
    compare's report.json)."""
    if not isinstance(node, dict):
        return
    if isinstance(node.get("estimators"), dict) and node["estimators"]:
        found.append((path, node["estimators"]))
    for key, value in node.items():
        if key != "estimators":
            find_estimator_tables(value, f"{path}/{key}" if path else key, found)


def quantity_stats(entry):
    """quantity -> (unit, statistic name, value, paper value or None, per-run list or None)."""
    result = OrderedDict()
    for key in ("quantities", "quantity_rmse"):
        quantities = entry.get(key)
        if not isinstance(quantities, dict):
            continue
        for q, s in quantities.items():
            if not isinstance(s, dict):
                continue
            stat = next((k for k in ("mean_abs", "rmse", "mean")
                         if isinstance(s.get(k), (int, float))), None)
            per_run = next((v for k, v in s.items()
                            if k.startswith("per_run") and isinstance(v, list) and v
                            and all(isinstance(x, (int, float)) for x in v)), None)
            if stat is None and per_run is None:
                continue
            result[q] = (s.get("unit", ""), stat, s.get(stat) if stat else None,
                         s.get("paper") if isinstance(s.get("paper"), (int, float)) else None,
                         per_run)
    return result


def repro_json_figure(out, path, estimators, index):
    stats = OrderedDict((name, quantity_stats(e)) for name, e in estimators.items()
                        if isinstance(e, dict))
    stats = OrderedDict((n, s) for n, s in stats.items() if s)
    if not stats:
        return False
    quantities = []
    for s in stats.values():
        quantities += [q for q in s if q not in quantities]
    quantities = quantities[:12]
    names = list(stats)
    colors = color_map(names)
    ncols = min(3, len(quantities))
    nrows = (len(quantities) + ncols - 1) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.4 * ncols, max(3.6, 3.1 * nrows)),
                             squeeze=False)
    has_paper = has_runs = False
    stat_names = set()
    for k, q in enumerate(quantities):
        ax = axes[k // ncols, k % ncols]
        unit = ""
        for i, n in enumerate(names):
            if q not in stats[n]:
                continue
            unit, stat, value, paper, per_run = stats[n][q]
            if per_run is not None:
                has_runs = True
                v = [x for x in per_run if isinstance(x, (int, float)) and math.isfinite(x)]
                if v:
                    box = ax.boxplot([v], positions=[i], widths=0.6, patch_artist=True,
                                     flierprops={"markersize": 2})
                    box["boxes"][0].set_facecolor(colors[n])
                    box["boxes"][0].set_alpha(0.6)
                    box["medians"][0].set_color("black")
            elif value is not None and math.isfinite(value):
                stat_names.add(stat)
                ax.bar(i, value, color=colors[n], alpha=0.8, width=0.6)
            if paper is not None:
                has_paper = True
                ax.plot(i, paper, marker="D", color="black", markersize=5, linestyle="none")
        ax.set_xticks(range(len(names)))
        ax.set_xticklabels(names, rotation=30, ha="right", fontsize="x-small")
        ax.set_xlim(-0.6, len(names) - 0.4)
        ax.set_title(f"{q} [{unit}]" if unit else q, fontsize="small")
        ax.grid(True, axis="y", alpha=0.3)
    for k in range(len(quantities), nrows * ncols):
        axes[k // ncols, k % ncols].axis("off")
    fig.suptitle(f"report.json: {path}")
    safe = re.sub(r"[^A-Za-z0-9]+", "_", path).strip("_") or "table"
    caption = f"report.json table {path}: per quantity and estimator, "
    caption += ("boxplots over the Monte-Carlo runs" if has_runs else "")
    if stat_names:
        caption += (" and " if has_runs else "") + "bars of " + ", ".join(sorted(stat_names))
    caption += "; black diamonds: the paper's value." if has_paper else "."
    out.save(fig, f"table_{index:02d}_{safe}.png", caption)
    return True


def crlb_csv_figure(out, folder, name):
    """crlb_<scenario>.csv (`mavloc repro smoother`): per estimator the RMS over runs of
    its position and attitude errors (solid) against the RMS of its Cramér–Rao bound (dashed, same
    color), on a logarithmic axis: the errors span orders of magnitude between estimators."""
    header, rows = read_csv(os.path.join(folder, name))
    need = ("estimator", "curve", "t [s]", "position [m]", "attitude [rad]")
    if not rows or any(h not in header for h in need):
        return repro_csv_figure(out, folder, name)
    ie, ic, it, ip, ia = (header.index(h) for h in need)
    series = OrderedDict()
    for r in rows:
        series.setdefault(r[ie], OrderedDict()).setdefault(r[ic], []).append(r)
    colors = color_map(list(series))
    fig, axes = plt.subplots(2, 1, figsize=(10, 6.2), sharex=True, squeeze=False)
    panels = ((ip, 1e3, "position error RMS [mm]"), (ia, 180.0 / math.pi,
                                                        "attitude error RMS [deg]"))
    for ax, (col, scale, ylabel) in zip(axes[:, 0], panels):
        for estimator, curves in series.items():
            for curve, rs in curves.items():
                pts = sorted((to_float(r[it]), scale * to_float(r[col])) for r in rs)
                pts = [(t, v) for t, v in pts if math.isfinite(t) and math.isfinite(v) and v > 0]
                if not pts:
                    continue
                bound = curve != "RMSE"
                ax.plot([t for t, _ in pts], [v for _, v in pts], color=colors[estimator],
                        linewidth=1.1 if bound else 0.8, linestyle="--" if bound else "-",
                        label=f"{estimator} / {curve}")
        ax.set_yscale("log")
        ax.set_ylabel(ylabel, fontsize="small")
        ax.grid(True, which="both", alpha=0.3)
    handles, _ = axes[0, 0].get_legend_handles_labels()
    if handles:
        axes[0, 0].legend(fontsize="x-small", loc="upper right", ncol=2)
    axes[-1, 0].set_xlabel("t [s]")
    fig.suptitle(name)
    out.save(fig, os.path.splitext(name)[0] + ".png",
             f"{name}: error RMS over the Monte-Carlo runs (solid) against the Cramér–Rao bound "
             "(dashed, same color: the smoothing bound for the smoother, the filtering bound for "
             "the causal estimators), logarithmic scale.")


def repro_figures(out, folder):
    for name in sorted(os.listdir(folder)):
        if name.endswith(".csv") and len(out.written) < MAX_REPRO_FIGURES:
            try:
                if name.startswith("crlb_"):
                    crlb_csv_figure(out, folder, name)
                else:
                    repro_csv_figure(out, folder, name)
            except (ValueError, IndexError, KeyError) as error:
                print(f"report_figures: {name}: skipped ({error})", file=sys.stderr)
    path = os.path.join(folder, "report.json")
    if os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            report = json.load(f)
        # A reproduction's own tables are the details of the one report schema.
        if isinstance(report, dict) and isinstance(report.get("details"), dict):
            report = report["details"]
        tables = []
        find_estimator_tables(report.get("tables", report), "", tables)
        index = 0
        for table_path, estimators in tables:
            if len(out.written) >= MAX_REPRO_FIGURES:
                print(f"report_figures: figure limit {MAX_REPRO_FIGURES} reached; "
                      f"{table_path} and later tables not drawn", file=sys.stderr)
                break
            if repro_json_figure(out, table_path, estimators, index + 1):
                index += 1
    trajectory_figure(out, folder, "trajectories")


def matrix_figures(out, folder):
    """Grouped boxplots of the relative error per length (estimators side by side, one color per
    estimator in every panel), one panel per sequence; the mean APE RMSE per sequence with its
    bootstrap interval."""
    header, rows = read_csv(os.path.join(folder, "relative_errors.csv"))
    col = {h: i for i, h in enumerate(header)}
    if rows and all(h in col for h in ("estimator", "sequence", "length_m", "translation_error_pct")):
        data = OrderedDict()  # sequence -> length -> estimator -> [pct]
        estimators = sorted({r[col["estimator"]] for r in rows})
        for r in rows:
            data.setdefault(r[col["sequence"]], OrderedDict()).setdefault(
                to_float(r[col["length_m"]]), OrderedDict()).setdefault(
                r[col["estimator"]], []).append(to_float(r[col["translation_error_pct"]]))
        colors = color_map(estimators)
        sequences = sorted(data)
        fig, axes = plt.subplots(len(sequences), 1, figsize=(10, 3.2 * len(sequences) + 0.8),
                                 squeeze=False)
        width = 0.8 / max(1, len(estimators))
        for ax, sequence in zip(axes[:, 0], sequences):
            lengths = sorted(data[sequence])
            for k, estimator in enumerate(estimators):
                values = [[v for v in data[sequence][length].get(estimator, []) if math.isfinite(v)]
                          for length in lengths]
                positions = [i + (k - (len(estimators) - 1) / 2) * width for i in range(len(lengths))]
                keep = [i for i, v in enumerate(values) if v]
                if not keep:
                    continue
                box = ax.boxplot([values[i] for i in keep], positions=[positions[i] for i in keep],
                                 widths=width * 0.9, patch_artist=True, manage_ticks=False,
                                 flierprops={"markersize": 2})
                for patch in box["boxes"]:
                    patch.set_facecolor(colors[estimator])
                    patch.set_alpha(0.7)
                for median in box["medians"]:
                    median.set_color("black")
            ax.set_xticks(range(len(lengths)))
            ax.set_xticklabels([f"{length:g}" for length in lengths])
            ax.set_ylabel("translation error [%]")
            ax.set_title(f"{sequence}", fontsize="medium")
            ax.grid(True, axis="y", alpha=0.3)
        axes[-1, 0].set_xlabel("sub-trajectory length [m]")
        fig.legend(handles=[Line2D([], [], color=colors[e], linewidth=6, label=e)
                            for e in estimators],
                   loc="upper right", fontsize="small", ncol=max(1, min(4, len(estimators))))
        fig.suptitle("Relative translation error per sub-trajectory length, estimators side by side")
        out.save(fig, "relative_error_boxplots.png",
                 "Relative translation error (rpg's definition, % of the length) per sequence and "
                 "sub-trajectory length, one box per estimator, pooled over runs.")


def detect_kind(folder):
    """The report_kind its report.json (or eval.json) declares; "unknown" otherwise."""
    for name in ("report.json", "eval.json"):
        path = os.path.join(folder, name)
        try:
            with open(path, encoding="utf-8") as f:
                kind = json.load(f).get("report_kind")
        except (OSError, ValueError, AttributeError):
            continue
        if isinstance(kind, str):
            return kind
    return "unknown"


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("report_dir")
    parser.add_argument("--kind",
                        choices=["eval", "compare", "repro", "sweep", "obstacles", "matrix"],
                        default=None)
    args = parser.parse_args()
    if not os.path.isdir(args.report_dir):
        sys.exit(f"report_figures: {args.report_dir}: not a folder")
    kind = args.kind or detect_kind(args.report_dir)
    out = Figures(args.report_dir)
    {"eval": eval_figures, "compare": compare_figures, "repro": repro_figures,
     "matrix": matrix_figures}.get(
        kind, lambda *_: None)(out, args.report_dir)
    if not out.written:
        print(f"report_figures: {args.report_dir} ({kind}): nothing to plot", file=sys.stderr)


if __name__ == "__main__":
    main()
