#include "evaluation/imu_noise/allan_streaming.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace mavloc {

StreamingAllanDeviation::StreamingAllanDeviation(std::vector<double> means, size_t samples,
                                                 double sample_period_s,
                                                 const AllanOptions& options)
    : options_(options),
      means_(std::move(means)),
      series_(means_.size()),
      samples_(samples),
      sample_period_s_(sample_period_s) {
  if (samples < kMinAllanSamples || !(sample_period_s > 0.0)) return;
  cluster_sizes_ = AllanClusterSizes(samples, sample_period_s, options, &cut_at_max_tau_);
  if (cluster_sizes_.empty()) return;
  // Terms of the phase points [next_term_, added_] need S back to 2 m_max before the first.
  rows_ = std::min(samples + 1, 2 * static_cast<size_t>(cluster_sizes_.back()) + kBlockRows);
  ring_.assign(rows_ * series_, 0.0);  // row 0: S_0 = 0
  phase_.assign(series_, 0.0);
  sums_.assign(cluster_sizes_.size() * series_, 0.0);
}

void StreamingAllanDeviation::Add(const double* values) {
  ++added_;
  if (rows_ == 0 || added_ > samples_) return;
  // S_{k+1} = S_k + (y_k - mean), as the batch form accumulates it.
  double* row = &ring_[(added_ % rows_) * series_];
  for (size_t c = 0; c < series_; ++c) row[c] = phase_[c] += values[c] - means_[c];
  if (added_ + 1 - next_term_ == kBlockRows) AccumulatePending();
}

void StreamingAllanDeviation::AccumulatePending() {
  const size_t last = added_;  // the terms of phase points next_term_..last
  for (size_t i = 0; i < cluster_sizes_.size(); ++i) {
    const size_t m = static_cast<size_t>(cluster_sizes_[i]);
    const size_t first = std::max(next_term_, 2 * m);  // the first term of m is at j = 2m
    if (first > last) break;                           // so are those of the larger m
    // Rows of S_j, S_{j-m}, S_{j-2m}, stepped together with wrap-around.
    size_t r0 = first % rows_, r1 = (first - m) % rows_, r2 = (first - 2 * m) % rows_;
    double* sum = &sums_[i * series_];
    for (size_t j = first; j <= last; ++j) {
      const double* s0 = &ring_[r0 * series_];
      const double* s1 = &ring_[r1 * series_];
      const double* s2 = &ring_[r2 * series_];
      for (size_t c = 0; c < series_; ++c) {
        const double d = s0[c] - 2.0 * s1[c] + s2[c];  // the batch form's expression
        sum[c] += d * d;
      }
      if (++r0 == rows_) r0 = 0;
      if (++r1 == rows_) r1 = 0;
      if (++r2 == rows_) r2 = 0;
    }
  }
  next_term_ = last + 1;
}

std::vector<AllanCurve> StreamingAllanDeviation::Finish() {
  std::vector<AllanCurve> curves(series_);
  for (AllanCurve& curve : curves) {
    curve.sample_period_s = sample_period_s_;
    curve.samples = samples_;
    curve.max_tau_s = options_.max_tau_s;
    curve.cut_at_max_tau = cut_at_max_tau_;
  }
  if (rows_ == 0 || added_ != samples_) return curves;
  AccumulatePending();
  for (size_t c = 0; c < series_; ++c) {
    AllanCurve& curve = curves[c];
    for (size_t i = 0; i < cluster_sizes_.size(); ++i) {
      const long m = cluster_sizes_[i];
      const size_t terms = samples_ + 1 - 2 * static_cast<size_t>(m);
      AllanPoint point;
      point.cluster_size = m;
      point.tau_s = static_cast<double>(m) * sample_period_s_;
      point.adev = std::sqrt(sums_[i * series_ + c] / (2.0 * static_cast<double>(terms))) /
                   static_cast<double>(m);
      curve.points.push_back(point);
    }
    SetAllanConfidence(&curve, options_);
  }
  return curves;
}

namespace {

// An IMU sample as the six series of ImuAllanDeviation: gyro x y z, accel x y z.
void ImuSeries(const ImuSample& s, double* values) {
  for (int axis = 0; axis < 3; ++axis) {
    values[axis] = s.gyro_rad_s[axis];
    values[3 + axis] = s.accel_m_s2[axis];
  }
}

}  // namespace

ImuAllanDeviation ComputeImuAllanDeviationStreaming(const ImuSamplePass& pass,
                                                    const AllanOptions& options) {
  ImuAllanDeviation result;
  // Pass 1: the sampling check and the sums behind the means.
  UniformSamplingCheck check;
  std::vector<double> means(6, 0.0);
  size_t samples = 0;
  pass([&](const ImuSample& s) {
    check.Add(s.t_ns);
    double values[6];
    ImuSeries(s, values);
    for (int c = 0; c < 6; ++c) means[c] += values[c];
    ++samples;
  });
  result.sampling = check.Finish();
  if (!result.sampling.ok) return result;
  for (double& mean : means) mean /= static_cast<double>(samples);
  // Pass 2: the curves.
  StreamingAllanDeviation allan(means, samples, 1.0 / result.sampling.rate_hz, options);
  pass([&](const ImuSample& s) {
    double values[6];
    ImuSeries(s, values);
    allan.Add(values);
  });
  if (allan.added() != samples) {
    result.sampling.ok = false;
    result.sampling.reason = fmt::format(
        "the stream gave {} samples, then {} when read again: it changed while it was read",
        samples, allan.added());
    return result;
  }
  const std::vector<AllanCurve> curves = allan.Finish();
  for (int axis = 0; axis < 3; ++axis) {
    result.gyro[axis] = curves[axis];
    result.accel[axis] = curves[3 + axis];
  }
  return result;
}

}  // namespace mavloc
