#!/usr/bin/env python3
"""How far EuRoC V1_01_easy's real gyro and its ground truth disagree about the rotation.

euroc-vision renders its images at the ground truth's poses and keeps the real IMU: whatever the
two disagree about, a visual-inertial estimator must absorb. This script (Python standard library
only) integrates the gyro over windows of 1, 5 and 10 s and compares the rotation with the ground
truth's over the same window, three ways: with the gyro's mean bias removed; with the ground
truth's body frame turned by the small rotation theta of the fit gyro - w_gt = b - [w]x theta;
and with a full 3 x 3 gyro calibration M, gyro = M w_gt + b, fitted by least squares. It also
scans a time offset between the two streams.

Usage: benchmarks/euroc_imu_truth_consistency.py [EUROC_FOLDER]  (default ../shared/data/euroc_v1_01_easy)
"""
import bisect
import math
import statistics
import sys


def qmul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


def qconj(a):
    return (-a[0], -a[1], -a[2], a[3])


def expq(v):
    angle = math.sqrt(sum(x * x for x in v))
    if angle < 1e-12:
        return (v[0] / 2, v[1] / 2, v[2] / 2, 1.0)
    s = math.sin(angle / 2) / angle
    return (v[0] * s, v[1] * s, v[2] * s, math.cos(angle / 2))


def angle_deg(q):
    return 2 * math.degrees(math.atan2(math.sqrt(q[0] ** 2 + q[1] ** 2 + q[2] ** 2), abs(q[3])))


def solve(a, y):
    n = len(y)
    m = [a[i][:] + [y[i]] for i in range(n)]
    for i in range(n):
        p = max(range(i, n), key=lambda r: abs(m[r][i]))
        m[i], m[p] = m[p], m[i]
        for r in range(n):
            if r != i:
                f = m[r][i] / m[i][i]
                for c in range(n + 1):
                    m[r][c] -= f * m[i][c]
    return [m[i][n] / m[i][i] for i in range(n)]


def least_squares(rows):
    """rows: (regressors, value) pairs; returns the coefficients."""
    n = len(rows[0][0])
    a = [[0.0] * n for _ in range(n)]
    y = [0.0] * n
    for x, v in rows:
        for i in range(n):
            y[i] += x[i] * v
            for j in range(n):
                a[i][j] += x[i] * x[j]
    return solve(a, y)


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "../shared/data/euroc_v1_01_easy"
    gt = [list(map(float, line.split())) for line in open(folder + "/groundtruth_full_tum.txt")
          if not line.startswith("#")]
    imu = []
    for line in open(folder + "/mav0/imu0/data.csv"):
        if not line.startswith("#"):
            r = [float(x) for x in line.strip().split(",")]
            imu.append((r[0] * 1e-9, r[1:4]))
    gt_t = [g[0] for g in gt]

    def gt_q(t):  # the nearest row
        i = bisect.bisect_left(gt_t, t)
        if i > 0 and (i == len(gt) or abs(gt_t[i - 1] - t) < abs(gt_t[i] - t)):
            i -= 1
        return tuple(gt[i][4:8])

    rates = []  # the ground truth's body rate at the midpoint of consecutive rows
    for a, b in zip(gt, gt[1:]):
        dq = qmul(qconj(tuple(a[4:8])), tuple(b[4:8]))
        s = 1 if dq[3] >= 0 else -1
        rates.append(((a[0] + b[0]) / 2, [2 * s * dq[k] / (b[0] - a[0]) for k in range(3)]))
    rate_t = [r[0] for r in rates]

    def rate_at(t):
        i = bisect.bisect_left(rate_t, t)
        if i <= 0 or i >= len(rates):
            return None
        (t0, w0), (t1, w1) = rates[i - 1], rates[i]
        f = (t - t0) / (t1 - t0)
        return [w0[k] + f * (w1[k] - w0[k]) for k in range(3)]

    print("time offset scan: rms of gyro - ground-truth rate (mean removed)")
    for offset_ms in (-10, -5, -2.5, 0, 2.5, 5, 10):
        d = [[w[k] - g[k] for k in range(3)] for t, w in imu[::2]
             if (g := rate_at(t + offset_ms * 1e-3)) is not None]
        mean = [statistics.fmean(x[k] for x in d) for k in range(3)]
        rms = math.sqrt(statistics.fmean(sum((x[k] - mean[k]) ** 2 for k in range(3)) for x in d))
        print(f"  {offset_ms:+5.1f} ms: {rms:.4f} rad/s")

    pairs = [(w, g) for t, w in imu if (g := rate_at(t)) is not None]
    # gyro - w_gt = b - [w]x theta (6 unknowns, three rows per sample)
    rows = []
    for w, g in pairs:
        skew = [[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]
        for r in range(3):
            rows.append(([1.0 if c == r else 0.0 for c in range(3)] + [-skew[r][c] for c in range(3)],
                         w[r] - g[r]))
    x = least_squares(rows)
    bias, theta = x[:3], x[3:]
    print("bias [rad/s] " + " ".join(f"{v:.5f}" for v in bias) +
          ", frame rotation theta [deg] " + " ".join(f"{math.degrees(v):.3f}" for v in theta))
    # gyro = M w_gt + b (12 unknowns)
    m, b = [], []
    for r in range(3):
        c = least_squares([([g[0], g[1], g[2], 1.0], w[r]) for w, g in pairs])
        m.append(c[:3])
        b.append(c[3])
    print("gyro calibration M " + "; ".join(" ".join(f"{v:.4f}" for v in row) for row in m))
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    m_inv = [[(m[(j + 1) % 3][(i + 1) % 3] * m[(j + 2) % 3][(i + 2) % 3] -
               m[(j + 1) % 3][(i + 2) % 3] * m[(j + 2) % 3][(i + 1) % 3]) / det
              for j in range(3)] for i in range(3)]

    def corrected(way, w):
        if way == "calibrated":
            u = [w[k] - b[k] for k in range(3)]
            return [sum(m_inv[r][k] * u[k] for k in range(3)) for r in range(3)]
        return [w[k] - bias[k] for k in range(3)]

    q_off = expq([-v for v in theta])
    print("rotation of the integrated gyro against the ground truth's over each window [deg]")
    for way in ("bias removed", "frame turned", "calibrated"):
        for window_s in (1, 5, 10):
            errors = []
            t_start = gt_t[0] + 1
            while t_start + window_s < gt_t[-1] - 1:
                samples = [s for s in imu if t_start <= s[0] < t_start + window_s]
                q = (0.0, 0.0, 0.0, 1.0)
                for (t, w), (t2, _) in zip(samples, samples[1:]):
                    q = qmul(q, expq([v * (t2 - t) for v in corrected(way, w)]))
                qa, qb = gt_q(samples[0][0]), gt_q(samples[-1][0])
                if way == "frame turned":
                    qa, qb = qmul(qa, q_off), qmul(qb, q_off)
                errors.append(angle_deg(qmul(qconj(qmul(qconj(qa), qb)), q)))
                t_start += window_s
            errors.sort()
            print(f"  {way:13s} {window_s:2d} s: median {errors[len(errors) // 2]:.3f}, "
                  f"max {errors[-1]:.3f} over {len(errors)} windows")


if __name__ == "__main__":
    main()
