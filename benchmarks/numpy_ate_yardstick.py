#!/usr/bin/python3
"""The yardstick for benchmarks/trajectory_eval_benchmark.cc (BM_AteCore): a straightforward numpy
implementation of the same computation on the same analytic trajectories -- association of each
estimate stamp with the nearest truth stamp by np.searchsorted (evo's rule: the earlier stamp on a
tie, |dt| <= 10 ms), Umeyama alignment (se3, or posyaw: yaw about z only) and the ATE RMSE.

File mode, the whole-process yardstick for `mavloc eval` (docs/performance.md): `write DIR` writes
the same trajectories as TUM files DIR/truth_1M.txt (1,000,000 poses at 1 kHz) and
DIR/est_500k.txt (500,000 poses at 500 Hz, stamps 0.3 ms after the truth's, the world turned by
0.01 rad and shifted, positions wobbling by about 1 cm); `read GT EST [se3|posyaw]` reads two TUM
files with np.loadtxt, associates, aligns and prints the APE translation RMSE, as
`mavloc eval --gt GT --est EST --align se3` reports it.

Usage: /usr/bin/python3 benchmarks/numpy_ate_yardstick.py [se3|posyaw] [repeats]
       /usr/bin/python3 benchmarks/numpy_ate_yardstick.py write DIR [N_TRUTH (estimate: half)]
       /usr/bin/python3 benchmarks/numpy_ate_yardstick.py read GT EST [se3|posyaw]
Peak memory: /usr/bin/time -v /usr/bin/python3 benchmarks/numpy_ate_yardstick.py se3
Needs Debian's python3-numpy.
"""
import sys
import time

import numpy as np

N_TRUTH = 1_000_000
N_EST = 500_000


def truth_positions(t):
    return np.stack([20.0 * np.cos(0.05 * t), 15.0 * np.sin(0.07 * t), 2.0 + np.sin(0.3 * t)], axis=1)


def make_data(n_truth=N_TRUTH, n_est=N_EST):
    t_gt_ns = np.arange(n_truth, dtype=np.int64) * 1_000_000
    p_gt = truth_positions(t_gt_ns * 1e-9)
    t_est_ns = np.arange(n_est, dtype=np.int64) * 2_000_000 + 300_000
    t = t_est_ns * 1e-9
    wobble = np.stack([0.01 * np.sin(3 * t), 0.01 * np.cos(2 * t), 0.005 * np.sin(5 * t)], axis=1)
    c, s = np.cos(0.01), np.sin(0.01)
    r_world = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    p_est = (truth_positions(t) + wobble) @ r_world.T + np.array([1.0, 2.0, 0.5])
    return t_gt_ns, p_gt, t_est_ns, p_est


def associate(t_gt_ns, t_est_ns, max_dt_ns=10_000_000):
    k = np.searchsorted(t_gt_ns, t_est_ns)  # first truth stamp >= t
    lo = np.clip(k - 1, 0, len(t_gt_ns) - 1)
    hi = np.clip(k, 0, len(t_gt_ns) - 1)
    d_lo = np.abs(t_est_ns - t_gt_ns[lo])
    d_hi = np.abs(t_gt_ns[hi] - t_est_ns)
    nearest = np.where(d_lo <= d_hi, lo, hi)
    dt = np.minimum(d_lo, d_hi)
    keep = dt <= max_dt_ns
    return np.nonzero(keep)[0], nearest[keep]


def umeyama(x, y, mode):
    """R, t with y ~ R x + t (x estimate, y truth), Umeyama 1991 (evo's umeyama_alignment)."""
    mu_x, mu_y = x.mean(axis=0), y.mean(axis=0)
    xc, yc = x - mu_x, y - mu_y
    cov = yc.T @ xc / len(x)
    if mode == "posyaw":
        theta = np.arctan2(cov[1, 0] - cov[0, 1], cov[0, 0] + cov[1, 1])
        c, s = np.cos(theta), np.sin(theta)
        r = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    else:
        u, _, vt = np.linalg.svd(cov)
        d = np.eye(3)
        if np.linalg.det(u) * np.linalg.det(vt) < 0:
            d[2, 2] = -1
        r = u @ d @ vt
    return r, mu_y - r @ mu_x


def ate(t_gt_ns, p_gt, t_est_ns, p_est, mode):
    i_est, i_gt = associate(t_gt_ns, t_est_ns)
    x, y = p_est[i_est], p_gt[i_gt]
    r, t = umeyama(x, y, mode)
    e = np.linalg.norm(x @ r.T + t - y, axis=1)
    return np.sqrt(np.mean(e * e)), len(e)


def yaw_quaternions_xyzw(yaw):
    """TUM's (qx, qy, qz, qw) of rotations by yaw about z."""
    zero = np.zeros_like(yaw)
    return np.stack([zero, zero, np.sin(0.5 * yaw), np.cos(0.5 * yaw)], axis=1)


def write_tum(path, t_ns, p, q_xyzw):
    """A TUM file: header comment, then "timestamp tx ty tz qx qy qz qw" with the stamp in seconds
    (9 decimals, written from the integer nanoseconds) and the rest with 9 decimals."""
    seconds = [f"{s}.{f:09d}" for s, f in zip(t_ns // 1_000_000_000, t_ns % 1_000_000_000)]
    values = np.char.mod("%.9f", np.concatenate([p, q_xyzw], axis=1))
    rows = [" ".join([stamp, *row]) for stamp, row in zip(seconds, values)]
    with open(path, "w") as out:
        out.write("# timestamp tx ty tz qx qy qz qw\n")
        out.write("\n".join(rows))
        out.write("\n")


def count_label(n):
    """1000000 -> "1M", 500000 -> "500k", 1234 -> "1234"."""
    if n % 1_000_000 == 0:
        return f"{n // 1_000_000}M"
    return f"{n // 1000}k" if n % 1000 == 0 else str(n)


def write_files(folder, n_truth=N_TRUTH):
    """Writes DIR/truth_<n>.txt and DIR/est_<n/2>.txt (truth_1M.txt and est_500k.txt by default) and
    prints their paths."""
    n_est = n_truth // 2
    t_gt_ns, p_gt, t_est_ns, p_est = make_data(n_truth, n_est)
    gt_path = f"{folder}/truth_{count_label(n_truth)}.txt"
    est_path = f"{folder}/est_{count_label(n_est)}.txt"
    write_tum(gt_path, t_gt_ns, p_gt, yaw_quaternions_xyzw(0.05 * t_gt_ns * 1e-9))
    write_tum(est_path, t_est_ns, p_est, yaw_quaternions_xyzw(0.05 * t_est_ns * 1e-9 + 0.01))
    print(gt_path)
    print(est_path)


def read_and_evaluate(gt_path, est_path, mode):
    """The whole yardstick: np.loadtxt, association within 0.01 s (evo: nearest, earlier on a tie),
    Umeyama, APE translation RMSE."""
    start = time.perf_counter()
    gt = np.loadtxt(gt_path, comments="#")
    est = np.loadtxt(est_path, comments="#")
    read_s = time.perf_counter() - start
    i_est, i_gt = associate_seconds(gt[:, 0], est[:, 0], 0.01)
    x, y = est[i_est, 1:4], gt[i_gt, 1:4]
    r, t = umeyama(x, y, mode)
    e = np.linalg.norm(x @ r.T + t - y, axis=1)
    rmse = np.sqrt(np.mean(e * e))
    print(f"numpy {np.__version__} {mode}: {len(e)} of {len(est)} poses associated, APE translation "
          f"rmse {rmse:.17g} m (read {read_s:.2f} s, total {time.perf_counter() - start:.2f} s)")


def associate_seconds(t_gt_s, t_est_s, max_dt_s):
    """associate() on stamps in seconds as read from the files."""
    k = np.searchsorted(t_gt_s, t_est_s)
    lo = np.clip(k - 1, 0, len(t_gt_s) - 1)
    hi = np.clip(k, 0, len(t_gt_s) - 1)
    d_lo = np.abs(t_est_s - t_gt_s[lo])
    d_hi = np.abs(t_gt_s[hi] - t_est_s)
    nearest = np.where(d_lo <= d_hi, lo, hi)
    keep = np.minimum(d_lo, d_hi) <= max_dt_s
    return np.nonzero(keep)[0], nearest[keep]


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "write":
        write_files(sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else N_TRUTH)
        return
    if len(sys.argv) > 3 and sys.argv[1] == "read":
        read_and_evaluate(sys.argv[2], sys.argv[3], sys.argv[4] if len(sys.argv) > 4 else "se3")
        return
    mode = sys.argv[1] if len(sys.argv) > 1 else "se3"
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    data = make_data()
    wall, cpu = [], []
    for _ in range(repeats):
        start, start_cpu = time.perf_counter(), time.process_time()
        rmse, pairs = ate(*data, mode)
        wall.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    print(f"numpy {np.__version__} {mode}: {pairs} pairs, ATE rmse {rmse:.6f} m, "
          f"wall median {1e3 * np.median(wall):.1f} ms, CPU median {1e3 * np.median(cpu):.1f} ms "
          f"over {repeats} runs")


if __name__ == "__main__":
    main()
