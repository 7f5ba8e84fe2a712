// Overlapping Allan deviation of series given one sample at a time (allan_deviation.h has the
// maths): the same numbers as OverlappingAllanDeviation, bit for bit, in memory that does not grow
// with the series' length, so that `mavloc imu-noise` reads a log of 1e7 samples without holding
// it.
//
// The sum of cluster size m, sum_{k=0}^{N-2m-1} (S_{k+2m} - 2 S_{k+m} + S_k)^2, gains one term per
// new phase point S_j (k = j - 2m): each series keeps the last 2 m_max + 1 phase points, m_max the
// largest cluster size (AllanOptions::max_cluster_fraction of the series and max_tau_s), plus a
// block of new ones; the terms are added block by block, for each m in order of k, so every sum is
// the batch form's, term for term. Every cluster size is fully overlapping (no stride): the memory
// is (2 m_max + kBlockRows) x series x 8 bytes, 19 MB for six series at 200 Hz and max_tau_s =
// 1000 s (96 MB at 1 kHz).
//
// Exact agreement needs what the batch form takes from the whole series before it starts: the
// count n (the cluster sizes go up to n / 4) and the mean (removed before the cumulative sum, which
// keeps S small: no cancellation of 1e7 * 9.81). ComputeImuAllanDeviationStreaming therefore reads
// the stream twice: a first pass checks the sampling (UniformSamplingCheck, the same refusals as
// CheckUniformSampling) and sums the series, the second accumulates. A single pass with a guessed
// offset (the first sample) would leave S growing like n times the offset's error: a relative
// error near 1e-9 at 1e7 samples instead of none, and "a quarter of the stream" unknown until the
// end.
#pragma once

#include <functional>
#include <vector>

#include "core/imu.h"
#include "evaluation/imu_noise/allan_deviation.h"

namespace mavloc {

// The default longest tau of `mavloc imu-noise` (--max-tau): 1000 s, a decade beyond the
// bias-instability minimum of MEMS IMUs (10..100 s; EuRoC's ADIS16448 gyro: white noise and random
// walk meet near 15 s) and so into the +1/2 slope on which the random walk is fitted and read out
// at tau = 3 s. Logs shorter than 4000 s are not affected (their curves stop at a quarter of the
// log, as before).
constexpr double kImuNoiseDefaultMaxTau_s = 1000.0;

class StreamingAllanDeviation {
 public:
  // Phase points whose terms are added together (rows of history beyond 2 m_max + 1).
  static constexpr size_t kBlockRows = 4096;

  // `means`: one per series, the mean of its `samples` values as OverlappingAllanDeviation
  // computes it (summed in order, then divided by the count). Fewer than kMinAllanSamples samples
  // or sample_period_s <= 0: the curves will be empty, as the batch form's.
  StreamingAllanDeviation(std::vector<double> means, size_t samples, double sample_period_s,
                          const AllanOptions& options = {});

  // The next sample of every series: values[c] for series c.
  void Add(const double* values);
  size_t added() const { return added_; }

  // One curve per series, once exactly `samples` samples have been added (else empty curves).
  std::vector<AllanCurve> Finish();

  // Bytes of phase history held (the memory that max_tau_s bounds).
  size_t history_bytes() const { return ring_.size() * sizeof(double); }

 private:
  void AccumulatePending();

  AllanOptions options_;
  std::vector<double> means_;
  size_t series_ = 0, samples_ = 0;
  double sample_period_s_ = 0.0;
  std::vector<long> cluster_sizes_;
  bool cut_at_max_tau_ = false;
  size_t added_ = 0;
  // Phase point S_j of series c at ring_[(j % rows_) * series_ + c]; S_0 = 0.
  size_t rows_ = 0;
  std::vector<double> ring_;
  std::vector<double> phase_;  // S_added_ per series
  size_t next_term_ = 1;       // phase points j < next_term_ have had their terms added
  std::vector<double> sums_;   // [i * series_ + c]: the sum of cluster_sizes_[i], series c
};

// One pass over an IMU stream: calls `visit` for each sample in order. A pass given to
// ComputeImuAllanDeviationStreaming runs twice and must give the same samples both times.
using ImuSamplePass = std::function<void(const std::function<void(const ImuSample&)>& visit)>;

// ComputeImuAllanDeviation of the samples a pass gives, in two passes (see above): the curves
// and sampling verdict of the samples as a vector, without the vector. A pass that gives another
// count the second time makes sampling.ok false (a file that changed while it was read).
ImuAllanDeviation ComputeImuAllanDeviationStreaming(const ImuSamplePass& pass,
                                                    const AllanOptions& options = {});

}  // namespace mavloc
