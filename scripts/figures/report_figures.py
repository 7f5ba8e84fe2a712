#!/usr/bin/python3
"""Figures of a mavloc report folder, drawn with Debian's python3-matplotlib.

The kind of folder is detected from its files (or given with --kind). Every figure of a folder
gives each estimator (estimate label) the same color; the truth is black and dashed, drawn on top
of the estimates; lines are broken where consecutive stamps are more than 5 median intervals apart
(no line across a gap); legends sit outside the axes; a panel whose estimators' typical errors
differ by more than 30x has a logarithmic y axis, said in its label.
  eval     `mavloc eval --out DIR`: truth.tum, estimate_<label>[_run<k>].tum, errors_over_time.csv,
           relative_errors.csv ->
           trajectory.png (top x-y and side x-z views, truth on top, equal axes (a flat side
             view's z stretched, said in its title); the estimates over the truth's time span;
             clipped to the truth's area when an estimate runs far away, said in its legend),
           trajectory_ape.png (top view of each estimate colored by its translation error (APE)
             per pose, colorbar in m, truth as a thin gray line),
           trajectory_xyz_rpy.png (x, y, z and roll, pitch, yaw over time, estimates and truth),
           errors_over_time.png (translation and rotation APE over time of every estimate;
             Monte-Carlo mean +- std and min/max bands where a label has several runs),
           ape_over_time.png (per estimate, translation and rotation APE over time with horizontal
             rmse / mean / median lines, values in the legend),
           relative_errors.png (boxplots per sub-trajectory length, grouped by estimate).
  compare  `mavloc compare --report DIR`: errors.csv, report.json (and truth.tum,
           estimate_<name>.tum) ->
           errors_over_time.png (one panel per quantity group, all estimators in it: position
             error |e_xyz|, roll-pitch error, yaw error, velocity error |e_v|, then every other
             quantity's |error|),
           error_boxplots.png (the same groups, one box per estimator),
           trajectory.png, trajectory_ape.png, ape_over_time.png (statistics lines from
             report.json where it has them), trajectory_xyz_rpy.png (estimates from errors.csv, so
             attitude-only estimators appear too), as for eval. Quantities the report leaves
             out for an estimator (report.json metrics) are left out of the error figures too;
             against a reference (compare --reference) the figures show differences to it.
  repro    `mavloc repro NAME --report DIR`: every CSV (time series, with envelopes for mean/max
           columns, bands and runs; boxplots over seeds; bar charts of tables) and the report.json
           tables with per-estimator statistics (bars, the paper's value as a marker, boxplots over
           runs where per-run values are given); trajectory.png when the folder has trajectories.
  matrix   `mavloc matrix ROOT --out DIR`: relative_errors.csv -> relative_error_boxplots.png (one panel
           per sequence, one box per estimator and length).
  sweep, obstacles: no figures.

Usage: /usr/bin/python3 scripts/figures/report_figures.py REPORT_DIR [--kind KIND]
           [--out-dir DIR] [--input NAME]...
The mavloc binary embeds this file and runs it after writing a report, then writes report.html;
run by hand, it writes the PNG files only. Prints one line per figure:
"figure<TAB>file<TAB>caption".
Files: with --input, only REPORT_DIR/NAME of the names given is read (mavloc passes the folder's
regular files); an input that is not a regular file (a named pipe, a device) is never opened.
Each figure is written to a temporary file in the output folder (--out-dir, else REPORT_DIR) and
renamed over its name (os.replace), so an existing name, a symbolic link included, is replaced,
never written through. A failure names the file being read: "report_figures: FILE: ERROR".
Exit code 3 when matplotlib or numpy is missing (Debian: apt-get install python3-matplotlib).
"""
import argparse
import csv
import json
import math
import os
import re
import stat
import sys
import tempfile
import warnings
from collections import OrderedDict, defaultdict

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.collections import LineCollection
    from matplotlib.colors import LogNorm, Normalize
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
except ImportError as error:  # the C++ side turns exit code 3 into "install python3-matplotlib"
    print(f"report_figures: {error}", file=sys.stderr)
    sys.exit(3)

DPI = 100
plt.rcParams["figure.constrained_layout.use"] = True  # makes room for suptitles and legends
plt.rcParams["axes.titlesize"] = "medium"
plt.rcParams["figure.titlesize"] = "large"
MAX_REPRO_FIGURES = 16
ENVELOPE_SAMPLES = 400
GAP_FACTOR = 5.0  # a step longer than this many median intervals is a gap: the line is broken
LOG_RATIO = 30.0  # typical errors in one panel differing by more than this: logarithmic y axis
MAX_PANELS = 12
TRUTH = {"color": "black", "linestyle": "--", "linewidth": 1.1, "zorder": 10}
REFERENCE = {"color": "dimgray", "linestyle": "-.", "linewidth": 1.1, "zorder": 9}
STAT_STYLES = (("rmse", "-", "black"), ("mean", "--", "#555555"), ("median", ":", "black"))


INPUTS = None  # the file names --input allows (None: every file of the folder, run by hand)
READING = []  # the input files opened so far, the last one named when a figure fails
UMASK = os.umask(0)
os.umask(UMASK)


def input_allowed(path):
    return INPUTS is None or os.path.basename(path) in INPUTS


def open_input(path, mode="r", **kwargs):
    """open() for reading an input: only the names given, only a regular file (a named pipe is
    opened without blocking and refused)."""
    if not input_allowed(path):
        raise FileNotFoundError(f"{path}: not among the input files")
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise OSError(f"{path}: not a regular file")
        os.set_blocking(fd, True)
        READING.append(os.path.basename(path))
        return os.fdopen(fd, mode, **kwargs)
    except BaseException:
        os.close(fd)
        raise


def input_exists(path):
    if not input_allowed(path):
        return False
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except OSError:
        return False


def input_names(folder):
    """The folder's input file names, sorted."""
    if INPUTS is not None:
        return sorted(INPUTS)
    return sorted(name for name in os.listdir(folder) if input_exists(os.path.join(folder, name)))


class Figures:
    """Saves figures into the output folder and announces each on stdout."""

    def __init__(self, folder):
        self.folder = folder
        self.written = []

    def save(self, fig, name, caption):
        if os.path.basename(name) != name or name.startswith("."):
            raise ValueError(f"figure name {name!r} is not a plain file name")
        # A fresh temporary file (O_EXCL, never through a link) renamed over the name.
        fd, temporary = tempfile.mkstemp(prefix=f".{name}.tmp-", dir=self.folder)
        try:
            os.fchmod(fd, 0o666 & ~UMASK)
            with os.fdopen(fd, "wb") as f:
                fig.savefig(f, format="png", dpi=DPI)
            os.replace(temporary, os.path.join(self.folder, name))
        except BaseException:
            try:
                os.unlink(temporary)
            except OSError:
                pass
            raise
        finally:
            plt.close(fig)
        self.written.append(name)
        caption = " ".join(caption.split())
        print(f"figure\t{name}\t{caption}", flush=True)


def color_map(labels):
    """One color per label, in order; matplotlib's tab10 without its gray (the truth's family)."""
    cycle = [c for c in plt.rcParams["axes.prop_cycle"].by_key()["color"]
             if c.lower() != "#7f7f7f"]
    colors = {}
    for label in labels:
        if label not in colors:
            colors[label] = cycle[len(colors) % len(cycle)]
    return colors


REPORT_COLORS = OrderedDict()  # estimator -> color over all figures of one repro report


def estimator_colors(labels):
    """Colors of estimators kept over every figure of the report (first come, first served)."""
    cycle = list(color_map(range(9)).values())
    for label in labels:
        if label not in REPORT_COLORS:
            REPORT_COLORS[label] = cycle[len(REPORT_COLORS) % len(cycle)]
    return {label: REPORT_COLORS[label] for label in labels}


def to_float(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def read_csv(path):
    with open_input(path, newline="", encoding="utf-8-sig") as f:
        rows = list(csv.reader(f))
    if not rows:
        return [], []
    return [h.strip() for h in rows[0]], [r for r in rows[1:] if r]


def read_json(path):
    try:
        with open_input(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def read_trajectory(path):
    """[t x y z qx qy qz qw] rows of a TUM file (blank and '#' lines skipped; spaces, tabs or
    commas; the quaternion NaN when a line has only t x y z), sorted by time."""
    rows = []
    with open_input(path, encoding="utf-8-sig") as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            fields = re.split(r"[\s,]+", line)
            if len(fields) >= 4:
                values = [to_float(x) for x in fields[:8]]
                if all(math.isfinite(v) for v in values[:4]):
                    rows.append(values + [math.nan] * (8 - len(values)))
    if not rows:
        return None
    a = np.array(rows)
    return a[np.argsort(a[:, 0], kind="stable")]


def estimate_files(folder):
    """label -> [(run, path)] for estimate_<label>[_run<k>].tum, runs in order."""
    found = defaultdict(list)
    for name in input_names(folder):
        m = re.fullmatch(r"estimate_(.+?)(?:_run(\d+))?\.tum", name)
        if m:
            found[m.group(1)].append((int(m.group(2) or 0), os.path.join(folder, name)))
    return OrderedDict((label, sorted(runs)) for label, runs in found.items())


def read_estimates(folder, order=()):
    """label -> [array per run], labels in `order` first."""
    estimates = OrderedDict()
    for label, runs in estimate_files(folder).items():
        arrays = [a for a in (read_trajectory(p) for _, p in runs) if a is not None]
        if arrays:
            estimates[label] = arrays
    labels = [x for x in order if x in estimates] + [x for x in estimates if x not in order]
    return OrderedDict((x, estimates[x]) for x in labels)


def read_truth(folder, name="truth.tum"):
    path = os.path.join(folder, name)
    return read_trajectory(path) if input_exists(path) else None


# ---------------------------------------------------------------------------------------------
# Small numerical helpers


def median_step(t):
    dt = np.diff(np.asarray(t, dtype=float))
    dt = dt[np.isfinite(dt) & (dt > 0)]
    return float(np.median(dt)) if len(dt) else math.nan


def gap_indices(t):
    """Indices i where the step t[i-1] -> t[i] is a gap (> GAP_FACTOR median steps)."""
    t = np.asarray(t, dtype=float)
    step = median_step(t)
    if len(t) < 3 or not math.isfinite(step):
        return np.array([], dtype=int)
    return np.nonzero(np.diff(t) > GAP_FACTOR * step)[0] + 1


def break_gaps(t, *columns):
    """(t, columns...) with a NaN row inserted at every gap, so that a line stops there."""
    t = np.asarray(t, dtype=float)
    columns = [np.asarray(c, dtype=float) for c in columns]
    at = gap_indices(t)
    if len(at) == 0:
        return (t, *columns)
    return (np.insert(t, at, np.nan), *[np.insert(c, at, np.nan) for c in columns])


def break_wraps(t, angle_deg):
    """Angles in (-180, 180]: a NaN where consecutive values jump by more than 180 deg (a wrap),
    on top of the gaps."""
    t, a = break_gaps(t, angle_deg)
    jumps = np.nonzero(np.abs(np.diff(a)) > 180.0)[0] + 1
    if len(jumps):
        t, a = np.insert(t, jumps, np.nan), np.insert(a, jumps, np.nan)
    return t, a


def interp_no_gaps(grid, t, e):
    """np.interp on the grid, NaN outside [t0, t1] and inside the gaps of t."""
    v = np.interp(grid, t, e, left=np.nan, right=np.nan)
    for i in gap_indices(t):
        v[(grid > t[i - 1]) & (grid < t[i])] = np.nan
    return v


def statistics(values):
    v = np.asarray([x for x in values if math.isfinite(x)], dtype=float)
    if not len(v):
        return None
    return {"rmse": float(np.sqrt(np.mean(v * v))), "mean": float(np.mean(v)),
            "median": float(np.median(v)), "count": len(v)}


def statistics_over_runs(runs):
    """rmse, mean, median of each run, averaged over the runs (the report's "mean over runs")."""
    per_run = [x for x in (statistics(e) for e in runs) if x is not None]
    if not per_run:
        return None
    stats = {k: float(np.mean([x[k] for x in per_run])) for k in ("rmse", "mean", "median")}
    stats["runs"] = len(per_run)
    return stats


def typical(values):
    """The median of the finite nonzero magnitudes (a panel's log-scale decision)."""
    v = np.abs(np.asarray([x for x in values if math.isfinite(x) and x != 0], dtype=float))
    return float(np.median(v)) if len(v) else math.nan


def use_log_scale(groups):
    """Whether the typical magnitudes of the series (one value list each) differ by > LOG_RATIO."""
    ts = [typical(v) for v in groups]
    ts = [x for x in ts if math.isfinite(x) and x > 0]
    return len(ts) >= 2 and max(ts) / min(ts) > LOG_RATIO


def set_log_if_spread(ax, groups, ylabel):
    """Log y axis when the groups' typical values differ by more than LOG_RATIO; the label says it.
    The axis starts at half the 1st percentile of the positive values, so that a series starting
    at zero error does not stretch it over decades nobody reads."""
    log = use_log_scale(groups)
    if log:
        positive = np.concatenate([np.asarray(v, dtype=float) for v in groups] or [np.array([])])
        positive = positive[np.isfinite(positive) & (positive > 0)]
        ax.set_yscale("log")
        if len(positive):
            ax.set_ylim(bottom=0.5 * float(np.percentile(positive, 1)))
    ax.set_ylabel(f"{ylabel}, log scale" if log else ylabel)
    return log


def with_unit(value, unit):
    """"0.000914 m" -> "0.914 mm": legend values in a readable unit (3 significant digits)."""
    if unit == "m" and abs(value) < 0.01:
        return f"{value * 1e3:.3g} mm"
    return f"{value:.3g} {unit}"


def legend_outside(ax, handles=None, title=None, fontsize="small"):
    """The legend right of the axes, top-aligned (never over the data)."""
    kwargs = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "borderaxespad": 0.0,
              "fontsize": fontsize, "frameon": False}
    if title:
        kwargs["title"] = title
        kwargs["title_fontsize"] = fontsize
    return ax.legend(handles=handles, **kwargs) if handles else ax.legend(**kwargs)


def euler_zyx_deg(q):
    """roll, pitch, yaw [deg] (R = Rz(yaw) Ry(pitch) Rx(roll), as mavloc's quantities) of [qx qy qz
    qw] rows."""
    x, y, z, w = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.degrees(roll), np.degrees(pitch), np.degrees(yaw)


def ape_along(estimate, truth):
    """Per estimate pose: (translation error [m], rotation error [deg]) to the truth interpolated
    at its stamp (linear in position, normalised linear in the quaternion); NaN outside the truth's
    time span and inside its gaps."""
    n = len(estimate)
    et, er = np.full(n, np.nan), np.full(n, np.nan)
    if truth is None or len(truth) < 2:
        return et, er
    tt, t = truth[:, 0], estimate[:, 0]
    i = np.clip(np.searchsorted(tt, t), 1, len(tt) - 1)
    t0, t1 = tt[i - 1], tt[i]
    ok = (t >= tt[0]) & (t <= tt[-1]) & ((t1 - t0) <= GAP_FACTOR * median_step(tt))
    w = np.where(t1 > t0, (t - t0) / np.where(t1 > t0, t1 - t0, 1.0), 0.0)[:, None]
    p = truth[i - 1, 1:4] + w * (truth[i, 1:4] - truth[i - 1, 1:4])
    et[ok] = np.linalg.norm(estimate[:, 1:4] - p, axis=1)[ok]
    q0, q1 = truth[i - 1, 4:8], truth[i, 4:8]
    q1 = q1 * np.where(np.sum(q0 * q1, axis=1) < 0, -1.0, 1.0)[:, None]
    q = q0 + w * (q1 - q0)
    with np.errstate(all="ignore"):
        q = q / np.linalg.norm(q, axis=1)[:, None]
        qe = estimate[:, 4:8] / np.linalg.norm(estimate[:, 4:8], axis=1)[:, None]
        angle = np.degrees(2 * np.arccos(np.clip(np.abs(np.sum(q * qe, axis=1)), 0.0, 1.0)))
    okr = ok & np.isfinite(angle)
    er[okr] = angle[okr]
    return et, er


def envelope(runs):
    """runs: [(t, e)]; one run -> (t, e, None); several -> mean, std, min, max on a common grid
    over the time span every run covers (mean +- std is the usual Monte-Carlo envelope); grid
    points inside a run's gap do not count for that run."""
    runs = [(t, e) for t, e in runs if len(t) > 0]
    if len(runs) == 1:
        return runs[0][0], runs[0][1], None
    lo = max(t[0] for t, _ in runs)
    hi = min(t[-1] for t, _ in runs)
    if not hi > lo:
        lo = min(t[0] for t, _ in runs)
        hi = max(t[-1] for t, _ in runs)
    grid = np.linspace(lo, hi, ENVELOPE_SAMPLES)
    stack = np.array([interp_no_gaps(grid, t, e) for t, e in runs])
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


def plot_series(ax, label, color, runs, linewidth=0.9):
    """One line for one run; mean line with mean +- std and min/max bands for several."""
    t, e, stats = envelope(runs)
    if stats is None:
        t, e = break_gaps(t, e)
        ax.plot(t, e, color=color, linewidth=linewidth, label=label)
        return
    ax.fill_between(t, stats["min"], stats["max"], color=color, alpha=0.12, linewidth=0)
    ax.fill_between(t, stats["mean"] - stats["std"], stats["mean"] + stats["std"], color=color,
                    alpha=0.3, linewidth=0)
    ax.plot(t, e, color=color, linewidth=linewidth + 0.1,
            label=f"{label}: mean, ±1 std, min-max over {stats['runs']} runs")


def sorted_time_series(pairs):
    pairs = sorted((t, e) for t, e in pairs if math.isfinite(t))
    return np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])


def grid_of(n, ncols_max=3):
    ncols = max(1, min(ncols_max, n))
    return ncols, (n + ncols - 1) // ncols


def humanise(name):
    """"hover_envelope" -> "Hover envelope" (figure titles are sentences, not file names)."""
    text = re.sub(r"[_/]+", " ", os.path.splitext(name)[0]).strip()
    return text[:1].upper() + text[1:] if text else name


# ---------------------------------------------------------------------------------------------
# Trajectories (eval, compare, repro)


def view_limits(truth_xy, others_xy):
    """(xlim, ylim, clipped) of a 2-D view: everything, or the truth's area (+50 %) when an estimate
    runs more than 3x as far; clipped: the labels that leave that area."""
    def box(a):
        a = a[np.all(np.isfinite(a), axis=1)]
        return (a.min(axis=0), a.max(axis=0)) if len(a) else None

    boxes = {k: box(v) for k, v in others_xy.items()}
    boxes = {k: b for k, b in boxes.items() if b is not None}
    tb = box(truth_xy) if truth_xy is not None else None
    if tb is None:
        return None, None, []
    span = max(float(np.max(tb[1] - tb[0])), 0.5)
    lo = np.minimum.reduce([tb[0]] + [b[0] for b in boxes.values()])
    hi = np.maximum.reduce([tb[1]] + [b[1] for b in boxes.values()])
    if float(np.max(hi - lo)) <= 3.0 * span:
        return None, None, []
    margin = 0.5 * span
    lo, hi = tb[0] - margin, tb[1] + margin
    clipped = [k for k, b in boxes.items() if np.any(b[0] < lo) or np.any(b[1] > hi)]
    return (lo[0], hi[0]), (lo[1], hi[1]), clipped


def trajectory_figure(out, folder, title, order=(), colors=None):
    """Top (x-y) and side (x-z) views: every estimate in its color, the truth black and dashed on
    top (dot: start). order: labels in the order (and so the colors) of the folder's other
    figures."""
    truth = read_truth(folder)
    # compare --reference: the reference, an estimate the others were compared with.
    reference = read_truth(folder, "reference.tum")
    estimates = read_estimates(folder, order)
    if truth is None and reference is None and not estimates:
        return
    colors = colors or color_map(list(order) + list(estimates))
    anchor = truth if truth is not None else reference
    # As evo draws the associated poses: only the part of an estimate within the truth's time
    # span (the part the errors describe).
    cut = []
    if anchor is not None and len(anchor) > 1:
        tol = GAP_FACTOR * median_step(anchor[:, 0])
        tol = tol if math.isfinite(tol) else 0.0
        lo, hi = anchor[0, 0] - tol, anchor[-1, 0] + tol
        for label in list(estimates):
            kept = [a[(a[:, 0] >= lo) & (a[:, 0] <= hi)] for a in estimates[label]]
            if sum(len(a) for a in kept) < sum(len(a) for a in estimates[label]):
                cut.append(label)
            kept = [a for a in kept if len(a)]
            if kept:
                estimates[label] = kept
            else:
                del estimates[label]
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.0))
    all_clipped = set()
    stretched = False
    for ax, (i, j, view) in zip(axes, [(1, 2, "Top view (x-y)"), (1, 3, "Side view (x-z)")]):
        lines = {label: np.vstack([a[:, [i, j]] for a in arrays])
                 for label, arrays in estimates.items()}
        xlim, ylim, clipped = view_limits(anchor[:, [i, j]] if anchor is not None else None,
                                          lines)
        all_clipped |= set(clipped)
        if truth is not None:
            _, x, y = break_gaps(truth[:, 0], truth[:, i], truth[:, j])
            ax.plot(x, y, label="truth", **TRUTH)
            ax.plot(truth[0, i], truth[0, j], "o", color="black", markersize=4, zorder=11)
        if reference is not None:
            _, x, y = break_gaps(reference[:, 0], reference[:, i], reference[:, j])
            ax.plot(x, y, label="reference (an estimate)", **REFERENCE)
        for label, arrays in estimates.items():
            many = len(arrays) > 1
            for k, a in enumerate(arrays):
                name = None
                if k == 0:
                    name = f"{label} ({len(arrays)} runs)" if many else label
                    if label in clipped:
                        name += " (leaves the plot)"
                _, x, y = break_gaps(a[:, 0], a[:, i], a[:, j])
                ax.plot(x, y, color=colors[label], linewidth=0.7 if many else 1.3,
                        alpha=0.5 if many else 0.9, label=name, zorder=3)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]" if j == 2 else "z [m]")
        # The side view of a flight that keeps its height would be a flat line at equal scales:
        # there z is stretched, and the title says so.
        spans = np.ptp((anchor if anchor is not None else
                        np.vstack([a for arrays in estimates.values() for a in arrays]))[:, [i, j]],
                       axis=0)
        if j == 3 and spans[1] < 0.25 * spans[0]:
            stretched = True
            ax.set_title(f"{view}, z axis stretched")
        else:
            ax.set_title(view)
            ax.set_aspect("equal", adjustable="datalim")
        if xlim is not None:
            ax.set_xlim(*xlim)
            ax.set_ylim(*ylim)
        ax.grid(True, alpha=0.3)
    legend_outside(axes[1])
    fig.suptitle(title)
    aligned = input_exists(os.path.join(folder, "report.md"))
    out.save(fig, "trajectory.png",
             "Trajectories, top (x-y) and side (x-z) views, equal axes" +
             (" (but the side view's z axis, stretched: the height varies little)" if stretched
              else "") + ": " +
             ("the truth black and dashed, drawn on top (dot: start), and " if truth is not None
              else "no truth.tum in this folder; ") +
             "each estimate in its color" +
             (" as written in this folder (aligned as the report states)" if aligned else "") +
             (f"; the view is limited to the truth's area: {', '.join(sorted(all_clipped))} "
              "leave(s) it" if all_clipped else "") +
             (f"; only the part within the {'truth' if truth is not None else 'reference'}'s "
              f"time span is drawn (longer: {', '.join(cut)})" if cut else "") + ".")


def ape_trajectory_figure(out, folder, order, colors, against_reference=False, skip=()):
    """Top view of each estimate colored by its translation error per pose (one panel each; the
    first run of a label with several). against_reference: the error to reference.tum (compare
    --reference) instead of truth.tum; skip: labels not drawn (the reference itself)."""
    truth = read_truth(folder, "reference.tum" if against_reference else "truth.tum")
    estimates = read_estimates(folder, order)
    estimates = OrderedDict((k, v) for k, v in estimates.items() if k not in skip)
    anchor = "reference" if against_reference else "truth"
    if truth is None or not estimates:
        return
    panels = []
    for label, arrays in estimates.items():
        et, _ = ape_along(arrays[0], truth)
        if np.any(np.isfinite(et)):
            panels.append((label, arrays[0], et, len(arrays)))
    panels = panels[:MAX_PANELS]
    if not panels:
        return
    ncols, nrows = grid_of(len(panels))
    fig, axes = plt.subplots(nrows, ncols, figsize=(5.2 * ncols + 1.2, 4.4 * nrows + 0.6),
                             squeeze=False)
    any_log = False
    for k, (label, a, et, runs) in enumerate(panels):
        ax = axes[k // ncols, k % ncols]
        _, tx, ty = break_gaps(truth[:, 0], truth[:, 1], truth[:, 2])
        ax.plot(tx, ty, color="0.55", linewidth=0.8, zorder=1, label=anchor)
        ok = np.isfinite(et)
        breaks = set(gap_indices(a[:, 0]).tolist())
        segments, values = [], []
        for i in range(1, len(a)):
            if i in breaks or not (ok[i - 1] and ok[i]):
                continue
            segments.append(a[i - 1:i + 1, 1:3])
            values.append(0.5 * (et[i - 1] + et[i]))
        values = np.array(values)
        finite = et[ok]
        lo, hi = float(np.percentile(finite, 1)), float(np.max(finite))
        log = lo > 0 and hi / lo > LOG_RATIO
        any_log |= log
        if not hi > lo:
            lo, hi = lo - 1e-9, hi + 1e-9
        norm = LogNorm(vmin=lo, vmax=hi) if log else Normalize(vmin=lo, vmax=hi)
        lc = LineCollection(segments, cmap="viridis", norm=norm, linewidth=2.2, zorder=3)
        lc.set_array(np.clip(values, lo, None))
        ax.add_collection(lc)
        ax.plot(a[0, 1], a[0, 2], "o", color="black", markersize=4, zorder=4)
        bar = fig.colorbar(lc, ax=ax, shrink=0.9)
        bar.set_label(("difference to the reference [m]" if against_reference else
                       "APE (translation) [m]") + (", log scale" if log else ""))
        xs = np.concatenate([a[ok, 1], truth[:, 1]])
        ys = np.concatenate([a[ok, 2], truth[:, 2]])
        ax.update_datalim(np.column_stack([xs, ys]))
        ax.autoscale_view()
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(f"{label}" + (f" (run 1 of {runs})" if runs > 1 else ""),
                     color=colors.get(label, "black"))
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.grid(True, alpha=0.3)
    for k in range(len(panels), nrows * ncols):
        axes[k // ncols, k % ncols].axis("off")
    fig.suptitle("Position difference to the reference along each estimated trajectory (top view)"
                 if against_reference else
                 "Translation error along each estimated trajectory (top view)")
    out.save(fig, "trajectory_ape.png",
             "Top view (x-y, equal axes) of each estimate colored by its " +
             ("position difference to the reference (an estimate, not a truth" if against_reference
              else "absolute position error (APE, translation part") +
             f", in m; the {anchor} interpolated at the estimate's stamps; per-panel "
             "color scale from the smallest (1st percentile) to the largest error" +
             (", logarithmic where the errors span more than 30x" if any_log else "") +
             f"); the {anchor} as a thin gray line, dot: start. A label with several runs shows "
             "its first run.")


def xyz_rpy_figure(out, folder, t0, truth, estimates, colors, note="", reference=None):
    """x, y, z and roll, pitch, yaw over time. estimates: label -> {quantity: (t, v)} in m / deg
    (any subset of the six); truth and reference (compare --reference): trajectory arrays."""
    names = (("x", "m"), ("y", "m"), ("z", "m"), ("roll", "deg"), ("pitch", "deg"), ("yaw", "deg"))
    anchors = [(a, label, style) for a, label, style in
               ((reference, "reference (an estimate)", REFERENCE), (truth, "truth", TRUTH))
               if a is not None]
    present = [n for n, _ in names if any(n in q for q in estimates.values())]
    if not present:
        return
    # The truth and the reference only over the estimates' time span (a truth much longer than
    # the estimates would squeeze them into a corner).
    spans = [(float(np.nanmin(t)), float(np.nanmax(t))) for q in estimates.values()
             for t, _ in q.values() if len(t)]
    lo, hi = min(a for a, _ in spans), max(b for _, b in spans)
    margin = 0.02 * (hi - lo)
    anchors = [(a[(a[:, 0] - t0 >= lo - margin) & (a[:, 0] - t0 <= hi + margin)], label, style)
               for a, label, style in anchors]
    anchors = [(trajectory_quantities(a, t0), label, style) for a, label, style in anchors
               if len(a)]
    fig, axes = plt.subplots(3, 2, figsize=(13, 7.5), sharex=True, squeeze=False)
    for k, (name, unit) in enumerate(names):
        ax = axes[k % 3, k // 3]
        angle = unit == "deg"
        for label, quantities in estimates.items():
            if name in quantities:
                t, v = quantities[name]
                t, v = break_wraps(t, v) if angle else break_gaps(t, v)
                ax.plot(t, v, color=colors[label], linewidth=1.0, alpha=0.9, label=label, zorder=3)
        for quantities, label, style in anchors:
            if name in quantities:
                t, v = quantities[name]
                t, v = break_wraps(t, v) if angle else break_gaps(t, v)
                ax.plot(t, v, label=label, **style)
        ax.set_ylabel(f"{name} [{unit}]")
        ax.grid(True, alpha=0.3)
        if name not in present:
            ax.text(0.5, 0.5, "not estimated", transform=ax.transAxes, ha="center",
                    va="center", color="gray")
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    axes[0, 0].set_title("Position")
    axes[0, 1].set_title("Attitude (Z-Y-X Euler angles)")
    handles = [Line2D([], [], color=colors[x], linewidth=1.5, label=x) for x in estimates]
    handles += [Line2D([], [], label=label, **style) for _, label, style in anchors]
    legend_outside(axes[0, 1], handles=handles)
    fig.suptitle("Position and attitude of each estimate and of the truth over time"
                 if truth is not None else "Position and attitude of each estimate over time")
    out.save(fig, "trajectory_xyz_rpy.png",
             "Position x, y, z [m] and attitude roll, pitch, yaw [deg] over time: each estimate in "
             "its color" + (", the truth black and dashed on top" if truth is not None else "") +
             (", the reference (an estimate) gray and dash-dotted" if reference is not None
              else "") + "; lines are broken at gaps in the stamps and where an angle wraps at "
             "±180 deg" + note + ".")


def stat_lines(ax, stats, unit):
    """Horizontal rmse / mean / median lines, their values in the legend."""
    handles = []
    for key, style, color in STAT_STYLES:
        if stats and math.isfinite(stats.get(key, math.nan)):
            ax.axhline(stats[key], color=color, linestyle=style, linewidth=1.1, zorder=6)
            handles.append(Line2D([], [], color=color, linestyle=style, linewidth=1.1,
                                  label=f"{key} {with_unit(stats[key], unit)}"))
    return handles


def ape_over_time_figure(out, rows, caption_source, against_reference=False):
    """rows: [(label, color, [(t, et)] per run, [(t, er)] per run, stats_t, stats_r)]: per
    estimate a row of two panels (translation [m], rotation [deg]) with rmse/mean/median lines."""
    rows = rows[:MAX_PANELS]
    if not rows:
        return
    has_rotation = any(any(len(t) for t, _ in r[3]) for r in rows)
    ncols = 2 if has_rotation else 1
    fig, axes = plt.subplots(len(rows), ncols, figsize=(7.2 * ncols + 1.8, 2.3 * len(rows) + 1.0),
                             sharex=True, squeeze=False)
    for k, (label, color, trans, rot, st, sr) in enumerate(rows):
        for c, (runs, stats, unit, what) in enumerate(
                [(trans, st, "m", "translation"), (rot, sr, "deg", "rotation")][:ncols]):
            ax = axes[k, c]
            runs = [(t, e) for t, e in runs if len(t)]
            if runs:
                plot_series(ax, label, color, runs, linewidth=1.0)
                handles = [Line2D([], [], color=color, linewidth=1.2,
                                  label=label if len(runs) == 1 else
                                  f"{label}: mean ±1 std, min-max ({len(runs)} runs)")]
                handles += stat_lines(ax, stats, unit)
                legend_outside(ax, handles=handles, fontsize="x-small",
                               title="mean of the runs' statistics" if len(runs) > 1 else None)
                tops = [float(np.nanmax(e)) for _, e in runs if np.any(np.isfinite(e))]
                tops += [stats.get(k, 0.0) for k in ("rmse", "mean", "median")] if stats else []
                top = max(tops, default=0.0)
                ax.set_ylim(0.0, 1.08 * top if top > 0 else 1.0)
            else:
                ax.text(0.5, 0.5, f"no {what} error", transform=ax.transAxes, ha="center",
                        va="center", color="gray")
            ax.set_ylabel(f"{what} difference [{unit}]" if against_reference else
                          f"APE {what} [{unit}]", fontsize="small")
            ax.grid(True, alpha=0.3)
            if k == 0:
                ax.set_title(f"{what.capitalize()} " +
                             ("difference" if against_reference else "error"))
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    fig.suptitle("Pose difference to the reference over time of each estimate, with its statistics"
                 if against_reference else
                 "Absolute pose error over time of each estimate, with its statistics")
    out.save(fig, "ape_over_time.png",
             ("Pose difference to the reference (an estimate, not a truth)" if against_reference
              else "Absolute pose error (APE)") +
             " over time, one row per estimate: translation [m] and "
             "rotation angle [deg]; horizontal lines: rmse (solid), mean (dashed) and median "
             "(dotted), values in the legend (" + caption_source + "); where an estimate has "
             "several runs, the mean over runs with ±1 std and min-max bands, and each statistic "
             "is the mean of the runs' values (as in the report's table).")


# ---------------------------------------------------------------------------------------------
# eval


def csv_labels(path, column):
    """The values of one column in order of first appearance (empty when the file is absent)."""
    labels = []
    if input_exists(path):
        header, rows = read_csv(path)
        if column in header:
            i = header.index(column)
            for r in rows:
                if i < len(r) and r[i] not in labels:
                    labels.append(r[i])
    return labels


def trajectory_quantities(a, t0):
    """{quantity: (t, values)} of a trajectory array, in m and deg."""
    t = a[:, 0] - t0
    q = {"x": (t, a[:, 1]), "y": (t, a[:, 2]), "z": (t, a[:, 3])}
    if np.all(np.isfinite(a[:, 4:8])):
        r, p, y = euler_zyx_deg(a[:, 4:8])
        q.update({"roll": (t, r), "pitch": (t, p), "yaw": (t, y)})
    return q


def eval_figures(out, folder):
    # One color per estimate in every figure: the order of errors_over_time.csv, then the others.
    order = csv_labels(os.path.join(folder, "errors_over_time.csv"), "label")
    order += [x for x in csv_labels(os.path.join(folder, "relative_errors.csv"), "label")
              if x not in order]
    order += [x for x in estimate_files(folder) if x not in order]
    colors = color_map(order)
    trajectory_figure(out, folder, "Estimated trajectories and the ground truth, after alignment",
                      order, colors)
    ape_trajectory_figure(out, folder, order, colors)
    truth = read_truth(folder)
    estimates = read_estimates(folder, order)
    t0 = truth[0, 0] if truth is not None else min(
        (a[0, 0] for arrays in estimates.values() for a in arrays), default=0.0)
    xyz_rpy_figure(out, folder, t0, truth,
                   OrderedDict((x, trajectory_quantities(a[0], t0)) for x, a in estimates.items()),
                   colors, "; a label with several runs shows its first run")
    path = os.path.join(folder, "errors_over_time.csv")
    if input_exists(path):
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
            # t_s counts from the truth's first stamp (older folders: absolute stamps).
            t0 = min(v[0] for runs in series.values() for rs in runs.values() for v in rs
                     if math.isfinite(v[0]))
            if truth is not None and truth[0, 0] - 1.0 <= t0 <= truth[-1, 0] + 1.0:
                t0 = truth[0, 0]
            elif truth is not None:
                t0 = 0.0
            per_label = OrderedDict()  # label -> ([(t, et)] per run, [(t, er)] per run)
            for label, runs in series.items():
                per_label[label] = tuple(
                    [sorted_time_series((v[0] - t0, v[1 + k]) for v in rs) for rs in runs.values()]
                    for k in range(2))
            fig, axes = plt.subplots(2, 1, figsize=(11, 6.4), sharex=True)
            any_runs = False
            logs = []
            for k, (ax, ylabel) in enumerate(zip(axes, ["APE translation [m]",
                                                        "APE rotation [deg]"])):
                for label, both in per_label.items():
                    any_runs |= len(both[k]) > 1
                    plot_series(ax, label, colors[label], both[k])
                logs.append(set_log_if_spread(
                    ax, [np.concatenate([e for _, e in both[k]]) for both in per_label.values()],
                    ylabel))
                ax.grid(True, alpha=0.3)
            axes[1].set_xlabel("time [s]")
            legend_outside(axes[0])
            fig.suptitle("Absolute translation and rotation error over time of each estimate")
            out.save(fig, "errors_over_time.png",
                     "Translation and rotation error (APE) over time after alignment, one line "
                     "per estimate" +
                     (" (logarithmic y axis where said: the estimates' errors differ by more "
                      "than 30x)" if any(logs) else "") +
                     ("; where an estimate has several runs, a Monte-Carlo envelope: the line is "
                      "the mean over runs, the dark band ±1 standard deviation and the light band "
                      "min to max." if any_runs else "."))
            ape_rows = []
            for label, (trans, rot) in per_label.items():
                ape_rows.append((label, colors[label], trans, rot,
                                 statistics_over_runs([e for _, e in trans]),
                                 statistics_over_runs([e for _, e in rot])))
            ape_over_time_figure(out, ape_rows, "computed over the pairs of errors_over_time.csv")
    path = os.path.join(folder, "relative_errors.csv")
    if input_exists(path):
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
                             ["relative translation error [%]", "relative rotation error [deg/m]"],
                             "relative_errors.png",
                             "Relative error over sub-trajectories of each length",
                             "Relative errors over sub-trajectories of each length (KITTI / "
                             "rpg_trajectory_evaluation definition): translation in % of the "
                             "length, rotation in deg/m; one box per estimate (all runs pooled), "
                             "box = quartiles, whiskers = 1.5 IQR.",
                             [f"{x:g}" for x in lengths], "sub-trajectory length [m]")


def grouped_boxplots(out, labels, colors, groups, data, ylabels, name, title, caption,
                     group_names, xlabel):
    if not any(math.isfinite(x) for v in data.values() for series in v for x in series):
        return
    width_in = max(8.0, 5.5 + 1.2 * len(groups) * math.sqrt(max(1, len(labels))))
    fig, axes = plt.subplots(len(ylabels), 1, figsize=(width_in, 3.1 * len(ylabels) + 0.6),
                             squeeze=False, sharex=True)
    width = 0.8 / max(1, len(labels))
    any_log = False
    for k, ax in enumerate(axes[:, 0]):
        spread = []
        for i, label in enumerate(labels):
            positions, values = [], []
            for g, group in enumerate(groups):
                v = [x for x in data.get((label, group), ([], []))[k] if math.isfinite(x)]
                if v:
                    positions.append(g - 0.4 + width * (i + 0.5))
                    values.append(v)
            if not values:
                continue
            spread.append([x for v in values for x in v])
            box = ax.boxplot(values, positions=positions, widths=width * 0.85, patch_artist=True,
                             manage_ticks=False, flierprops={"markersize": 2})
            for patch in box["boxes"]:
                patch.set_facecolor(colors[label])
                patch.set_alpha(0.7)
            for median in box["medians"]:
                median.set_color("black")
        any_log |= set_log_if_spread(ax, spread, ylabels[k])
        ax.set_xticks(range(len(groups)))
        ax.set_xticklabels(group_names)
        ax.set_xlim(-0.6, len(groups) - 0.4)
        ax.grid(True, axis="y", alpha=0.3)
    axes[-1, 0].set_xlabel(xlabel)
    legend_outside(axes[0, 0], handles=[Patch(facecolor=colors[x], alpha=0.7, label=x)
                                        for x in labels])
    fig.suptitle(title)
    out.save(fig, name, caption + (" Logarithmic y axis where said (the estimates differ by "
                                   "more than 30x)." if any_log else ""))


# ---------------------------------------------------------------------------------------------
# compare

# Quantity groups of compare's overview, in this order; each is the norm of the components an
# estimator has. Quantities outside these groups get a panel each (|error|), in errors.csv order.
QUANTITY_GROUPS = (
    ("position error", ("x", "y", "z")),
    ("roll-pitch error", ("roll", "pitch")),
    ("yaw error", ("yaw",)),
    ("velocity error", ("vx", "vy", "vz")),
    ("accelerometer bias error", ("bax", "bay", "baz")),
    ("gyroscope bias error", ("bgx", "bgy", "bgz")),
)


def report_reference(folder):
    """protocol.reference of the folder's report.json: "truth", "estimate" or None."""
    report = read_json(os.path.join(folder, "report.json"))
    if isinstance(report, dict) and isinstance(report.get("protocol"), dict):
        return report["protocol"].get("reference")
    return None


def report_reference_estimators(folder):
    """Names of the estimators report.json marks is_reference (compare --reference ESTIMATOR)."""
    report = read_json(os.path.join(folder, "report.json"))
    entries = report.get("estimators") if isinstance(report, dict) else None
    return {e["name"] for e in entries if isinstance(e, dict) and e.get("is_reference") is True
            and isinstance(e.get("name"), str)} if isinstance(entries, list) else set()


def report_ate_statistics(folder):
    """estimator -> (translation statistics [m], rotation statistics [deg]) from report.json's
    estimators[].metrics.ate_translation / ate_rotation (rad), where present."""
    report = read_json(os.path.join(folder, "report.json"))
    found = {}
    entries = report.get("estimators") if isinstance(report, dict) else None
    if not isinstance(entries, list):
        return found
    for e in entries:
        if not isinstance(e, dict) or not isinstance(e.get("metrics"), dict):
            continue
        pair = []
        for key, scale in (("ate_translation", 1.0), ("ate_rotation", 180.0 / math.pi)):
            s = e["metrics"].get(key, {})
            s = s.get("statistics") if isinstance(s, dict) else None
            if isinstance(s, dict) and all(isinstance(s.get(k), (int, float))
                                           for k in ("rmse", "mean", "median")):
                pair.append({k: scale * s[k] for k in ("rmse", "mean", "median")})
            else:
                pair.append(None)
        if isinstance(e.get("name"), str):
            found[e["name"]] = tuple(pair)
    return found


def report_quantities(folder):
    """estimator -> the quantities its report.json entry has metrics for (the report leaves out
    some, e.g. Euler angles near their singularity); estimators without metrics are absent."""
    report = read_json(os.path.join(folder, "report.json"))
    entries = report.get("estimators") if isinstance(report, dict) else None
    found = {}
    for e in entries if isinstance(entries, list) else []:
        if isinstance(e, dict) and isinstance(e.get("name"), str) and \
                isinstance(e.get("metrics"), dict) and e["metrics"]:
            found[e["name"]] = set(e["metrics"])
    return found


def group_series(per_quantity, components):
    """per_quantity: quantity -> [(t, error)] of one estimator. The norm of the components it has,
    at the stamps where all of them are given: (t, value, components used)."""
    have = [c for c in components if c in per_quantity]
    if not have:
        return None
    by_t = defaultdict(dict)
    for c in have:
        for t, e in per_quantity[c]:
            if math.isfinite(t) and math.isfinite(e):
                by_t[t][c] = e
    pts = sorted((t, math.sqrt(sum(v * v for v in d.values())))
                 for t, d in by_t.items() if len(d) == len(have))
    if not pts:
        return None
    return np.array([p[0] for p in pts]), np.array([p[1] for p in pts]), have


def compare_panels(series, units):
    """[(title, unit, {estimator: (t, |e|, note)})] in the fixed order of QUANTITY_GROUPS, then the
    other quantities."""
    estimators = list(OrderedDict.fromkeys(e for per in series.values() for e in per))
    panels, used = [], set()
    for title, components in QUANTITY_GROUPS:
        present = [c for c in components if c in series]
        group_units = {units[c] for c in present}
        if not present or len(group_units) != 1:
            continue
        used |= set(present)
        lines, notes = OrderedDict(), []
        for e in estimators:
            g = group_series({c: series[c][e] for c in present if e in series[c]}, present)
            if g is not None:
                t, v, have = g
                lines[e] = (t, v, "")
                if len(have) < len(present):
                    notes.append(f"{e}: {', '.join(have)} only")
        if len(present) == 1:
            name = (f"{title[:1].upper()}{title[1:]}" if len(components) == 1 else
                    f"Error of {present[0]}") + f", |e_{present[0]}|"
        else:
            name = (f"{title[:1].upper()}{title[1:]}, ‖(" +
                    ", ".join(f"e_{c}" for c in present) + ")‖")
        panels.append((name + (f" ({'; '.join(notes)})" if notes else ""), group_units.pop(),
                       lines))
    for q in series:
        if q in used:
            continue
        lines = OrderedDict()
        for e, values in series[q].items():
            t, v = sorted_time_series(values)
            lines[e] = (t, np.abs(v), "")
        panels.append((f"Error of {q}, |e_{q}|", units[q], lines))
    return panels


def compare_figures(out, folder):
    header, rows = read_csv(os.path.join(folder, "errors.csv"))
    col = {h: i for i, h in enumerate(header)}
    needed = ["estimator", "quantity", "unit", "t_s", "error"]
    ok = rows and all(h in col for h in needed)
    series = OrderedDict()  # quantity -> estimator -> [(t, e)]
    values = defaultdict(dict)  # estimator -> quantity -> [(t, estimate)]
    units = {}
    estimators = []  # in the order of the report's table
    if ok:
        for r in rows:
            if len(r) < len(header):
                continue
            name, q = r[col["estimator"]], r[col["quantity"]]
            if name not in estimators:
                estimators.append(name)
            units[q] = r[col["unit"]]
            t = to_float(r[col["t_s"]])
            series.setdefault(q, OrderedDict()).setdefault(name, []).append(
                (t, to_float(r[col["error"]])))
            if "estimate" in col:
                values[name].setdefault(q, []).append((t, to_float(r[col["estimate"]])))
    # The error figures show what the report's tables show: quantities the report leaves out
    # for an estimator (its warnings say why) are left out here too.
    reported, left_out = report_quantities(folder), []
    for q in list(series):
        for e in list(series[q]):
            if e in reported and q not in reported[e]:
                del series[q][e]
                left_out.append(f"{q} of {e}")
        if not series[q]:
            del series[q]
    trajectories = read_estimates(folder, estimators)
    colors = color_map(estimators + list(trajectories))
    truth = read_truth(folder)
    against = "reference" if report_reference(folder) == "estimate" else "truth"
    # Time from the first error sample (errors.csv and the trajectories share one clock).
    starts = [t for per in series.values() for v in per.values() for t, _ in v if math.isfinite(t)]
    t0 = min(starts) if starts else (truth[0, 0] if truth is not None else 0.0)
    if series:
        panels = compare_panels(series, units)
        dropped = [p[0] for p in panels[MAX_PANELS:]]
        panels = panels[:MAX_PANELS]
        fig, axes = plt.subplots(len(panels), 1, figsize=(11, 2.0 * len(panels) + 1.2),
                                 sharex=True, squeeze=False)
        logs = []
        for ax, (title, unit, lines) in zip(axes[:, 0], panels):
            for e, (t, v, note) in lines.items():
                t, v = break_gaps(t - t0, v)
                ax.plot(t, v, color=colors[e], linewidth=0.9, label=e + note)
            logs.append(set_log_if_spread(ax, [v for _, v, _ in lines.values()],
                                          f"error [{unit}]" if unit and unit != "1"
                                          else "error [-]"))
            ax.set_title(title, fontsize="small", loc="left")
            ax.grid(True, alpha=0.3)
        legend_outside(axes[0, 0], handles=[Line2D([], [], color=colors[e], linewidth=1.5,
                                                   label=e) for e in estimators],
                       title="estimator")
        axes[-1, 0].set_xlabel("time [s]")
        fig.suptitle(f"Error over time of each estimator against the {against}, per quantity")
        out.save(fig, "errors_over_time.png",
                 f"Absolute error (estimate - {against}) over time, one panel per quantity "
                 "group with every estimator in it (one color per estimator in every figure): "
                 "the norm of the position error (x, y, z), of the roll-pitch error, the yaw "
                 "error, the norms of the velocity, accelerometer-bias and gyroscope-bias errors, "
                 "then each other quantity of errors.csv "
                 "(a panel title names the components an estimator lacks)"
                 + ("; logarithmic y axis where the estimators' errors differ by more than 30x "
                    "(said in the axis label)" if any(logs) else "")
                 + (f"; not drawn: {', '.join(dropped)}" if dropped else "")
                 + (f"; left out as in the report (see its warnings): {', '.join(left_out)}"
                    if left_out else "") + ".")

        fig_panels = panels
        ncols, nrows = grid_of(len(fig_panels))
        fig, axes = plt.subplots(nrows, ncols, figsize=(4.4 * ncols, 3.3 * nrows + 0.6),
                                 squeeze=False)
        logs = []
        for k, (title, unit, lines) in enumerate(fig_panels):
            ax = axes[k // ncols, k % ncols]
            names = [e for e in estimators if e in lines and np.any(np.isfinite(lines[e][1]))]
            data = [lines[e][1][np.isfinite(lines[e][1])] for e in names]
            if names:
                box = ax.boxplot(data, patch_artist=True, flierprops={"markersize": 2})
                for patch, e in zip(box["boxes"], names):
                    patch.set_facecolor(colors[e])
                    patch.set_alpha(0.7)
                for median in box["medians"]:
                    median.set_color("black")
                ax.set_xticks(range(1, len(names) + 1))
                ax.set_xticklabels(names, rotation=30, ha="right", fontsize="small")
            logs.append(set_log_if_spread(ax, data, f"|error| [{unit}]" if unit and unit != "1"
                                          else "|error| [-]"))
            ax.set_title(title, fontsize="small")
            ax.grid(True, axis="y", alpha=0.3)
        for k in range(len(fig_panels), nrows * ncols):
            axes[k // ncols, k % ncols].axis("off")
        fig.suptitle("Distribution of each estimator's error, per quantity")
        out.save(fig, "error_boxplots.png",
                 "Distribution over all frames of the absolute error of each quantity group "
                 "(as in the error-over-time figure), one box per estimator in its color "
                 "(quartiles; whiskers 1.5 IQR; points beyond them)"
                 + ("; logarithmic y axis where the estimators differ by more than 30x"
                    if any(logs) else "") + ".")
    trajectory_figure(out, folder, "Estimated trajectories and the ground truth" +
                      (" after the ATE alignment" if against == "truth" else ""),
                      estimators, colors)
    reference = read_truth(folder, "reference.tum") if against == "reference" else None
    is_reference = report_reference_estimators(folder)
    ape_trajectory_figure(out, folder, estimators, colors, reference is not None, is_reference)
    anchor = reference if reference is not None else truth
    if anchor is not None and trajectories:
        stats = report_ate_statistics(folder)
        ape_rows = []
        for name, arrays in trajectories.items():
            if name in is_reference:
                continue
            et, er = ape_along(arrays[0], anchor)
            t = arrays[0][:, 0] - t0
            st, sr = stats.get(name, (None, None))
            if not np.any(np.isfinite(et)) and not np.any(np.isfinite(er)):
                continue  # no pose within the truth's (reference's) span
            ape_rows.append((name, colors[name], [(t[np.isfinite(et)], et[np.isfinite(et)])],
                             [(t[np.isfinite(er)], er[np.isfinite(er)])],
                             st or statistics(et), sr or statistics(er)))
        ape_over_time_figure(out, ape_rows, "from report.json, as in the report's table, where "
                             "it has them; else over the drawn poses", reference is not None)
    # x, y, z, roll, pitch, yaw: from errors.csv (attitude-only estimators too), else from the
    # trajectory files.
    quantities = OrderedDict()
    for name in estimators + [x for x in trajectories if x not in estimators]:
        if name in is_reference and reference is not None:
            continue  # drawn as the reference
        q = {}
        for k in ("x", "y", "z", "roll", "pitch", "yaw"):
            pts = values.get(name, {}).get(k)
            if pts:
                t, v = sorted_time_series(pts)
                if units.get(k) == "rad":
                    v = np.degrees(v)
                q[k] = (t - t0, v)
        if not q and name in trajectories:
            q = trajectory_quantities(trajectories[name][0], t0)
        if q:
            quantities[name] = q
    if quantities:
        xyz_rpy_figure(out, folder, t0, truth, quantities, colors,
                       "; estimates as in errors.csv (an estimator appears in the panels of the "
                       "quantities it estimates)", reference)


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
            legend_outside(axes[0, 0], fontsize="x-small")
        axes[-1, 0].set_xlabel(header[time])
        fig.suptitle(f"{humanise(name)} over time"
                     + (", over the Monte-Carlo runs" if run is not None or pairs else ""))
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
        fig.suptitle(f"{humanise(name)}: distribution of {header[metric]} over the "
                     f"{header[run]}s")
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
    fig.suptitle(f"{humanise(name)}: one bar per row, one panel per column")
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
            unit, scale = display_unit(s.get("unit", ""))
            value = s.get(stat) if stat else None
            paper = s.get("paper") if isinstance(s.get("paper"), (int, float)) else None
            result[q] = (unit, stat, None if value is None else value * scale,
                         None if paper is None else paper * scale,
                         None if per_run is None else [x * scale for x in per_run])
    return result


def display_unit(unit):
    """report.json holds SI units; angles are drawn in degrees, as the tables show them."""
    if unit == "rad":
        return "deg", 180.0 / math.pi
    if unit == "rad/s":
        return "deg/s", 180.0 / math.pi
    return unit, 1.0


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
    colors = estimator_colors(names)
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
    fig.suptitle(f"{humanise(path)}: each estimator's statistics per quantity")
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
    colors = estimator_colors(list(series))
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
        legend_outside(axes[0, 0], fontsize="x-small")
    axes[-1, 0].set_xlabel("t [s]")
    scenario = os.path.splitext(name)[0][len("crlb_"):]
    fig.suptitle(f"Error RMS of each estimator against its Cramér–Rao bound ({scenario})")
    out.save(fig, os.path.splitext(name)[0] + ".png",
             f"{name}: error RMS over the Monte-Carlo runs (solid) against the Cramér–Rao bound "
             "(dashed, same color: the smoothing bound for the smoother, the filtering bound for "
             "the causal estimators), logarithmic scale.")


def repro_figures(out, folder):
    for name in input_names(folder):
        if name.endswith(".csv") and len(out.written) < MAX_REPRO_FIGURES:
            try:
                if name.startswith("crlb_"):
                    crlb_csv_figure(out, folder, name)
                else:
                    repro_csv_figure(out, folder, name)
            except (ValueError, IndexError, KeyError) as error:
                print(f"report_figures: {name}: skipped ({error})", file=sys.stderr)
    path = os.path.join(folder, "report.json")
    if input_exists(path):
        with open_input(path, encoding="utf-8") as f:
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
    trajectory_figure(out, folder, "Trajectories of the runs and the ground truth")


def matrix_figures(out, folder):
    """Grouped boxplots of the relative error per length (estimators side by side, one color per
    estimator in every panel), one panel per sequence."""
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
        fig, axes = plt.subplots(len(sequences), 1, figsize=(11, 3.2 * len(sequences) + 0.8),
                                 squeeze=False)
        width = 0.8 / max(1, len(estimators))
        any_log = False
        for ax, sequence in zip(axes[:, 0], sequences):
            lengths = sorted(data[sequence])
            spread = []
            for k, estimator in enumerate(estimators):
                values = [[v for v in data[sequence][length].get(estimator, []) if math.isfinite(v)]
                          for length in lengths]
                positions = [i + (k - (len(estimators) - 1) / 2) * width for i in range(len(lengths))]
                keep = [i for i, v in enumerate(values) if v]
                if not keep:
                    continue
                spread.append([x for i in keep for x in values[i]])
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
            ax.set_xlim(-0.6, len(lengths) - 0.4)
            any_log |= set_log_if_spread(ax, spread, "translation error [%]")
            ax.set_title(f"Sequence {sequence}", fontsize="medium", loc="left")
            ax.grid(True, axis="y", alpha=0.3)
        axes[-1, 0].set_xlabel("sub-trajectory length [m]")
        legend_outside(axes[0, 0], handles=[Patch(facecolor=colors[e], alpha=0.7, label=e)
                                            for e in estimators], title="estimator")
        fig.suptitle("Relative translation error per sub-trajectory length, estimators side by side")
        out.save(fig, "relative_error_boxplots.png",
                 "Relative translation error (rpg's definition, % of the length) per sequence and "
                 "sub-trajectory length, one box per estimator (same color in every panel), "
                 "pooled over runs (quartiles; whiskers 1.5 IQR)"
                 + ("; logarithmic y axis where said (the estimators differ by more than 30x)"
                    if any_log else "") + ".")


def sweep_figures(out, folder):
    """A sweep's runs.csv: the ATE translation and rotation RMSE of every seed, one group per
    scenario and settings combination, estimators side by side (boxes over the seeds)."""
    header, rows = read_csv(os.path.join(folder, "runs.csv"))
    col = {h: i for i, h in enumerate(header)}
    if not rows or not all(h in col for h in ("scenario", "settings", "estimator", "metric",
                                               "value")):
        return
    metrics = (("ate_rmse", "ATE RMSE [m]", 1.0),
               ("ate_rotation_rmse", "rotation RMSE [deg]", 180.0 / math.pi))
    labels, groups, data = [], [], {}
    for r in rows:
        metric = r[col["metric"]]
        k = next((i for i, m in enumerate(metrics) if m[0] == metric), None)
        if k is None:
            continue
        label = r[col["estimator"]]
        settings = r[col["settings"]]
        group = r[col["scenario"]] + (f" ({settings})" if settings else "")
        if label not in labels:
            labels.append(label)
        if group not in groups:
            groups.append(group)
        series = data.setdefault((label, group), tuple([] for _ in metrics))
        series[k].append(to_float(r[col["value"]]) * metrics[k][2])
    if not data:
        return
    grouped_boxplots(out, labels, estimator_colors(labels), groups, data,
                     [m[1] for m in metrics], "sweep_ate_boxplots.png",
                     "ATE over the seeds of each scenario and settings combination",
                     "ATE translation RMSE and rotation RMSE (the angle of the rotation error) of "
                     "each seed, one box per estimator (the same color in every group; quartiles, "
                     "whiskers 1.5 IQR), per scenario and settings combination (runs.csv).",
                     groups, "scenario (settings)")


def obstacle_figures(out, folder):
    """An obstacles report's frames.csv: per frame, the nearest measured obstacle distance beside
    the true one with the alerts and the clearance, and the time of each pipeline stage."""
    header, rows = read_csv(os.path.join(folder, "frames.csv"))
    col = {h.lstrip("#").strip(): i for i, h in enumerate(header)}
    needed = ("timestamp [ns]", "alert", "nearest_measured_distance [m]", "true_distance [m]",
              "rectification [ms]", "disparity [ms]", "point_cloud [ms]", "total [ms]")
    if not rows or not all(h in col for h in needed):
        return
    a = np.array([[to_float(r[col[h]]) for h in needed] for r in rows])
    t = (a[:, 0] - a[0, 0]) * 1e-9
    report = read_json(os.path.join(folder, "report.json")) or {}
    clearance = to_float(report.get("details", {}).get("settings", {}).get("clearance_m"))
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(10, 6.5), sharex=True)
    tm, measured = break_gaps(t, a[:, 2])
    top.plot(tm, measured, color="tab:blue", label="nearest measured point")
    if np.isfinite(a[:, 3]).any():
        tt, truth = break_gaps(t, a[:, 3])
        top.plot(tt, truth, color="0.35", linewidth=2.0, label="truth: nearest surface", zorder=3)
    alerts = a[:, 1] > 0.5
    if alerts.any():
        top.plot(t[alerts], np.where(np.isfinite(a[alerts, 2]), a[alerts, 2], 0.0), "v",
                 color="tab:red", markersize=4, linestyle="none", label="alert")
    if math.isfinite(clearance):
        top.axhline(clearance, color="tab:red", linestyle="--", linewidth=1.0,
                    label=f"clearance {clearance:g} m")
    top.set_ylabel("distance [m]")
    top.set_title("Distance to the nearest obstacle per frame")
    legend_outside(top)
    for k, (name, color) in enumerate((("rectification", "tab:green"),
                                       ("disparity", "tab:orange"),
                                       ("point cloud", "tab:purple"),
                                       ("total", "black"))):
        ts, ms = break_gaps(t, a[:, 4 + k])
        bottom.plot(ts, ms, color=color, linewidth=1.0, label=name)
    bottom.set_ylabel("time per frame [ms]")
    bottom.set_xlabel("time since the first frame [s]")
    bottom.set_title("Time of each stage of the pipeline (the paper's Table 1 gives the means)")
    legend_outside(bottom)
    fig.tight_layout()
    out.save(fig, "obstacles_over_time.png",
             "Per frame: the nearest measured obstacle point against the true nearest surface, "
             "alerts and the clearance; below, the time of each pipeline stage (frames.csv).")


def detect_kind(folder):
    """The report_kind its report.json (or eval.json) declares; "unknown" otherwise."""
    for name in ("report.json", "eval.json"):
        path = os.path.join(folder, name)
        try:
            with open_input(path, encoding="utf-8") as f:
                kind = json.load(f).get("report_kind")
        except (OSError, ValueError, AttributeError):
            continue
        if isinstance(kind, str):
            return kind
    return "unknown"


def imu_noise_figures(out, folder):
    """Allan deviation of the six axes (log-log), 68 % confidence bands, and the lines of the
    fitted white noise (slope -1/2) and random walk (slope +1/2) of the value in imu.yaml."""
    header, rows = read_csv(os.path.join(folder, "allan_deviation.csv"))
    col = {h: i for i, h in enumerate(header)}
    if not rows or "tau_s" not in col:
        return
    tau = np.array([to_float(r[col["tau_s"]]) for r in rows])
    report = {}
    try:
        with open_input(os.path.join(folder, "report.json"), encoding="utf-8") as f:
            report = json.load(f)
    except (OSError, ValueError):
        pass
    tables = {t.get("name"): t for t in report.get("tables", []) if isinstance(t, dict)}
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    for ax, sensor, unit, name in ((axes[0], "gyro", "rad_s", "gyroscope"),
                                   (axes[1], "accel", "m_s2", "accelerometer")):
        for axis, color in zip("xyz", ("tab:red", "tab:green", "tab:blue")):
            key = f"{sensor}_{axis}_adev_{unit}"
            if key not in col:
                continue
            adev = np.array([to_float(r[col[key]]) for r in rows])
            low = np.array([to_float(r[col[f"{sensor}_{axis}_low_{unit}"]]) for r in rows])
            high = np.array([to_float(r[col[f"{sensor}_{axis}_high_{unit}"]]) for r in rows])
            ax.loglog(tau, adev, color=color, label=f"{axis}")
            ax.fill_between(tau, low, high, color=color, alpha=0.15, linewidth=0)
        table = tables.get(name)
        if table and len(table.get("rows", [])) >= 4:
            row = table["rows"][3]  # the value written to imu.yaml (largest axis)
            white, white_kind, walk, walk_kind = row[1], row[2], row[5], row[6]
            if isinstance(white, (int, float)) and white > 0:
                ax.loglog(tau, white / np.sqrt(tau), "k--", linewidth=1,
                          label=f"white noise N = {white:.3g} ({white_kind})")
            if isinstance(walk, (int, float)) and walk > 0:
                ax.loglog(tau, walk * np.sqrt(tau / 3.0), "k:", linewidth=1,
                          label=f"random walk K = {walk:.3g} ({walk_kind})")
        shown = "rad/s" if sensor == "gyro" else "m/s^2"
        ax.set_xlabel("cluster time tau [s]")
        ax.set_ylabel(f"Allan deviation [{shown}]")
        ax.set_title(f"The {name}'s Allan deviation per axis", fontsize="medium")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(0.0, -0.15), ncol=2, fontsize="small",
                  frameon=False)
    fig.suptitle("Allan deviation of the IMU with 68 % confidence bands and the fitted noise")
    out.save(fig, "allan_deviation.png",
             "Overlapping Allan deviation of each axis (bands: 68 % confidence from the "
             "equivalent degrees of freedom); dashed: white noise N/sqrt(tau), dotted: random walk "
             "K sqrt(tau/3), for the values written to imu.yaml.")


def main():
    global INPUTS
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("report_dir")
    parser.add_argument("--kind",
                        choices=["eval", "compare", "repro", "sweep", "obstacles", "matrix",
                                 "imu-noise"],
                        default=None)
    parser.add_argument("--out-dir", default=None,
                        help="folder the PNG files are written to (default: REPORT_DIR)")
    parser.add_argument("--input", action="append", default=None, metavar="NAME",
                        help="a file of REPORT_DIR the figures may read (repeated); default: all")
    args = parser.parse_args()
    if not os.path.isdir(args.report_dir):
        sys.exit(f"report_figures: {args.report_dir}: not a folder")
    out_dir = args.out_dir or args.report_dir
    if not os.path.isdir(out_dir):
        sys.exit(f"report_figures: {out_dir}: not a folder")
    if args.input is not None:
        INPUTS = {name for name in args.input if os.path.basename(name) == name}
    kind = args.kind or detect_kind(args.report_dir)
    out = Figures(out_dir)
    draw = {"eval": eval_figures, "compare": compare_figures, "repro": repro_figures,
            "matrix": matrix_figures, "imu-noise": imu_noise_figures, "sweep": sweep_figures,
            "obstacles": obstacle_figures}.get(kind, lambda *_: None)
    try:
        draw(out, args.report_dir)
    except Exception as error:  # one line naming the file, not a traceback
        name = READING[-1] if READING else args.report_dir
        message = " ".join(str(error).split()) or "no message"
        print(f"report_figures: {name}: {type(error).__name__}: {message} "
              f"(while drawing the {kind} figures)", file=sys.stderr)
        sys.exit(1)
    if not out.written:
        print(f"report_figures: {args.report_dir} ({kind}): nothing to plot", file=sys.stderr)


if __name__ == "__main__":
    main()
