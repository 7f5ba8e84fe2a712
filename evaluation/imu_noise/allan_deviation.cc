#include "evaluation/imu_noise/allan_deviation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/imu_gaps.h"
#include "evaluation/imu_noise/allan_streaming.h"

namespace mavloc {
namespace {

// Regularized lower incomplete gamma function P(a, x) (series for x < a + 1, Lentz's continued
// fraction for Q = 1 - P otherwise; Numerical Recipes 3rd ed., sec. 6.2).
double AllanRegularizedGammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefactor = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 10000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return std::min(1.0, sum * std::exp(log_prefactor));
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return std::max(0.0, 1.0 - std::exp(log_prefactor) * h);
}

// White PM is never chosen from the slope: at long tau the slope of a white-FM curve wanders below
// -3/4 by chance, and white PM's edf (about N/2 at every m) would then claim a far too narrow
// interval. White FM's edf, used instead, is the smaller (conservative) one.
AllanNoiseType AllanNoiseFromSlope(double slope) {
  if (slope < -0.25) return AllanNoiseType::kWhiteRate;
  if (slope < 0.25) return AllanNoiseType::kFlickerRate;
  return AllanNoiseType::kRandomWalkRate;
}

}  // namespace

const char* AllanNoiseTypeName(AllanNoiseType type) {
  switch (type) {
    case AllanNoiseType::kWhitePhase:
      return "white PM (angle/velocity white noise, quantization)";
    case AllanNoiseType::kWhiteRate:
      return "white FM (rate white noise)";
    case AllanNoiseType::kFlickerRate:
      return "flicker FM (bias instability)";
    case AllanNoiseType::kRandomWalkRate:
      return "random walk FM (rate random walk)";
  }
  return "";
}

double ChiSquareQuantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0) || !(dof > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  // P(dof/2, x/2) increases in x: bracket, then bisect (to the last bit of a double).
  const double a = 0.5 * dof;
  double lo = 0.0, hi = std::max(1.0, dof);
  while (AllanRegularizedGammaP(a, 0.5 * hi) < p) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (AllanRegularizedGammaP(a, 0.5 * mid) < p)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

double AllanEquivalentDof(AllanNoiseType noise, double phase_points, double cluster_size) {
  // NIST SP 1065 (Riley 2008) Table 5: simple approximations of the edf of the overlapping Allan
  // variance (Howe, Allan, Barnes 1981).
  const double N = phase_points, m = cluster_size;
  double edf = 1.0;
  switch (noise) {
    case AllanNoiseType::kWhitePhase:
      edf = (N + 1.0) * (N - 2.0 * m) / (2.0 * (N - m));
      break;
    case AllanNoiseType::kWhiteRate:
      edf = (3.0 * (N - 1.0) / (2.0 * m) - 2.0 * (N - 2.0) / N) * 4.0 * m * m / (4.0 * m * m + 5.0);
      break;
    case AllanNoiseType::kFlickerRate:
      // The table's m = 1 entry, 2(N-2)/(2.3N-4.9), is below 1 for every N (an interval wider than
      // that of one sample pair for a curve point of 1e6 samples): the m >= 2 formula is used at
      // m = 1 too.
      edf = 5.0 * N * N / (4.0 * m * (N + 3.0 * m));
      break;
    case AllanNoiseType::kRandomWalkRate:
      edf = (N - 2.0) / m * ((N - 1.0) * (N - 1.0) - 3.0 * m * (N - 1.0) + 4.0 * m * m) /
            ((N - 3.0) * (N - 3.0));
      break;
  }
  return std::max(1.0, edf);
}

std::vector<long> AllanClusterSizes(size_t samples, double sample_period_s,
                                    const AllanOptions& options, bool* cut) {
  const double max_m = options.max_cluster_fraction * static_cast<double>(samples);
  // m tau0 <= max_tau_s, with a margin for the rounding of the division (1000 s / 0.005 s).
  const double max_tau_m = options.max_tau_s / sample_period_s * (1.0 + 1e-9);
  std::vector<long> sizes;
  bool tau_cut = false;
  for (int j = 0;; ++j) {
    const long m = std::lround(std::pow(10.0, j / options.clusters_per_decade));
    if (static_cast<double>(m) > max_m) break;
    if (static_cast<double>(m) > max_tau_m) {
      tau_cut = true;
      break;
    }
    if (sizes.empty() || m > sizes.back()) sizes.push_back(m);
  }
  if (cut != nullptr) *cut = tau_cut;
  return sizes;
}

double AllanLocalSlope(const std::vector<AllanPoint>& points, size_t i, double half_width_decades) {
  if (points.size() < 2 || i >= points.size()) return 0.0;
  const double center = std::log10(points[i].tau_s);
  size_t from = i, to = i;  // inclusive
  while (from > 0 && center - std::log10(points[from - 1].tau_s) <= half_width_decades) --from;
  while (to + 1 < points.size() && std::log10(points[to + 1].tau_s) - center <= half_width_decades)
    ++to;
  // At the short-tau end the cluster sizes 1, 2, 3 are more than 0.2 decade apart: widen to three
  // points (two for a two-point curve).
  while (to - from + 1 < std::min<size_t>(3, points.size())) {
    if (from == 0)
      ++to;
    else if (to + 1 == points.size())
      --from;
    else if (center - std::log10(points[from - 1].tau_s) <
             std::log10(points[to + 1].tau_s) - center)
      --from;
    else
      ++to;
  }
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(to - from + 1);
  for (size_t j = from; j <= to; ++j) {
    const double x = std::log(points[j].tau_s), y = std::log(points[j].adev);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double denominator = n * sxx - sx * sx;
  return denominator > 0 ? (n * sxy - sx * sy) / denominator : 0.0;
}

AllanCurve OverlappingAllanDeviation(const std::vector<double>& samples, double sample_period_s,
                                     const AllanOptions& options) {
  AllanCurve curve;
  curve.sample_period_s = sample_period_s;
  curve.samples = samples.size();
  curve.max_tau_s = options.max_tau_s;
  if (samples.size() < kMinAllanSamples || !(sample_period_s > 0.0)) return curve;
  const size_t n = samples.size();
  // Phase in sample units: S_k = sum_{i<k} (y_i - mean), k = 0..n. The mean does not change the
  // second differences, and removing it keeps S small (no cancellation of 1e7 * 9.81).
  double mean = 0.0;
  for (const double y : samples) mean += y;
  mean /= static_cast<double>(n);
  std::vector<double> phase(n + 1, 0.0);
  for (size_t k = 0; k < n; ++k) phase[k + 1] = phase[k] + (samples[k] - mean);

  for (const long m : AllanClusterSizes(n, sample_period_s, options, &curve.cut_at_max_tau)) {
    // sigma^2(m tau0) = 1/(2 (N - 2m)) sum_k ((S_{k+2m} - 2 S_{k+m} + S_k) / m)^2 over the
    // N - 2m = n + 1 - 2m start samples k (the phase form of the overlapping
    // Allan variance in NIST SP 1065, with x = tau0 S).
    const size_t span = static_cast<size_t>(m);
    const size_t terms = n + 1 - 2 * span;
    double sum = 0.0;
    for (size_t k = 0; k < terms; ++k) {
      const double d = phase[k + 2 * span] - 2.0 * phase[k + span] + phase[k];
      sum += d * d;
    }
    AllanPoint point;
    point.cluster_size = m;
    point.tau_s = static_cast<double>(m) * sample_period_s;
    point.adev = std::sqrt(sum / (2.0 * static_cast<double>(terms))) / static_cast<double>(m);
    curve.points.push_back(point);
  }
  SetAllanConfidence(&curve, options);
  return curve;
}

void SetAllanConfidence(AllanCurve* curve, const AllanOptions& options) {
  // The confidence intervals need the noise type, identified from the local slope (a constant
  // series has adev 0 everywhere: no slope, no interval).
  const double phase_points = static_cast<double>(curve->samples + 1);
  const double tail = 0.5 * (1.0 - options.confidence);
  for (size_t i = 0; i < curve->points.size(); ++i) {
    AllanPoint& p = curve->points[i];
    if (!(p.adev > 0.0)) continue;
    p.slope = AllanLocalSlope(curve->points, i);
    p.noise = AllanNoiseFromSlope(p.slope);
    p.edf = AllanEquivalentDof(p.noise, phase_points, static_cast<double>(p.cluster_size));
    p.adev_low = p.adev * std::sqrt(p.edf / ChiSquareQuantile(1.0 - tail, p.edf));
    p.adev_high = p.adev * std::sqrt(p.edf / ChiSquareQuantile(tail, p.edf));
  }
}

UniformSampling CheckUniformSampling(const std::vector<ImuSample>& samples) {
  UniformSamplingCheck check;
  for (const ImuSample& s : samples) check.Add(s.t_ns);
  return check.Finish();
}

void UniformSamplingCheck::Add(TimeNs t_ns) {
  const size_t index = samples_++;
  if (index == 0) {
    first_ns_ = last_ns_ = t_ns;
    return;
  }
  if (!not_increasing_.empty()) return;  // the verdict is known
  if (t_ns <= last_ns_) {
    not_increasing_ = fmt::format(
        "sample {} (t = {} ns) does not come after the one before ({} ns)", index, t_ns, last_ns_);
    return;
  }
  AddInterval(t_ns - last_ns_, last_ns_, t_ns);
  last_ns_ = t_ns;
}

void UniformSamplingCheck::AddInterval(TimeNs interval_ns, TimeNs from_ns, TimeNs to_ns) {
  // A gap is longer than kImuGapMinSeconds (and 10 median intervals, FindImuGaps): only those
  // intervals are kept exactly, and the ones among them that exceed every interval before.
  const bool longest_yet = interval_ns > longest_ns_;
  longest_ns_ = std::max(longest_ns_, interval_ns);
  if (static_cast<double>(interval_ns) > kImuGapMinSeconds * 1e9) {
    ++long_intervals_[interval_ns];
    if (longest_yet) records_.push_back({from_ns, to_ns});
    return;
  }
  const TimeNs bin = interval_ns >> shift_;
  if (bin == last_bin_) {  // most intervals repeat the one before
    ++*last_count_;
    return;
  }
  last_count_ = &short_bins_[bin];  // pointers to elements survive rehashing
  last_bin_ = bin;
  ++*last_count_;
  if (short_bins_.size() <= kMaxExactIntervals) return;
  // Too many distinct intervals (stamps with nanosecond jitter): halve the resolution until the
  // histogram is small again.
  while (short_bins_.size() > kMaxExactIntervals / 2) {
    ++shift_;
    std::unordered_map<TimeNs, uint64_t> wider;
    for (const auto& [key, count] : short_bins_) wider[key >> 1] += count;
    short_bins_.swap(wider);
  }
  last_bin_ = -1;
  last_count_ = nullptr;
}

UniformSampling UniformSamplingCheck::Finish() const {
  UniformSampling s;
  s.samples = samples_;
  if (samples_ < kMinAllanSamples) {
    s.reason = fmt::format(
        "{} samples: Allan deviation needs at least {} (and a static log of minutes to hours to "
        "show more than the white noise)",
        samples_, kMinAllanSamples);
    return s;
  }
  if (!not_increasing_.empty()) {
    s.reason = not_increasing_;
    return s;
  }
  // The median interval: the one of rank (n - 1) / 2 among the n - 1 sorted intervals (as
  // std::nth_element picks it); the short bins (at their middle when widened) come first, each
  // shorter than every long interval.
  std::vector<std::pair<TimeNs, uint64_t>> counts;  // (interval, count), increasing
  for (const auto& [bin, count] : short_bins_)
    counts.push_back({shift_ == 0 ? bin : (bin << shift_) + (TimeNs{1} << (shift_ - 1)), count});
  std::sort(counts.begin(), counts.end());
  counts.insert(counts.end(), long_intervals_.begin(), long_intervals_.end());
  const uint64_t rank = (samples_ - 1) / 2;
  uint64_t below = 0;
  TimeNs median = 0;
  for (const auto& [interval, count] : counts) {
    if (below + count > rank) {
      median = interval;
      break;
    }
    below += count;
  }
  const double median_ns = static_cast<double>(median);
  s.median_resolution_ns = TimeNs{1} << shift_;
  s.rate_hz = 1e9 / median_ns;
  const TimeNs span_ns = last_ns_ - first_ns_;
  s.duration_s = NsToSeconds(span_ns);
  const double expected = std::round(static_cast<double>(span_ns) / median_ns) + 1.0;
  s.missing_samples = expected > static_cast<double>(samples_)
                          ? static_cast<size_t>(expected - static_cast<double>(samples_))
                          : 0;
  // Gaps as FindImuGaps finds them: longer than 10 median intervals and kImuGapMinSeconds.
  const double threshold_ns = std::max(kImuGapMedianIntervals * median_ns, kImuGapMinSeconds * 1e9);
  size_t gap_count = 0;
  for (const auto& [interval, count] : long_intervals_)
    if (static_cast<double>(interval) > threshold_ns) gap_count += count;
  if (gap_count > 0) {
    // DescribeImuGaps reads the count, the first gap and the longest (the last record).
    const auto first = std::find_if(records_.begin(), records_.end(), [&](const ImuGap& g) {
      return static_cast<double>(g.to_ns - g.from_ns) > threshold_ns;
    });
    std::vector<ImuGap> gaps(gap_count, *first);
    gaps.back() = records_.back();
    s.reason = "the stream has " + DescribeImuGaps(gaps, first_ns_) +
               ": Allan deviation needs one uninterrupted, uniformly sampled series";
    return s;
  }
  if (static_cast<double>(s.missing_samples) >
      kMaxAllanMissingFraction * static_cast<double>(expected)) {
    s.reason = fmt::format(
        "{} of the {:.0f} samples that {:.3f} s at the median rate {:.3f} Hz should hold are "
        "missing ({:.2f} %, more than {:g} %): Allan deviation needs a uniformly sampled series",
        s.missing_samples, expected, s.duration_s, s.rate_hz,
        100.0 * static_cast<double>(s.missing_samples) / expected,
        100.0 * kMaxAllanMissingFraction);
    return s;
  }
  s.ok = true;
  return s;
}

ImuAllanDeviation ComputeImuAllanDeviation(const std::vector<ImuSample>& samples,
                                           const AllanOptions& options) {
  return ComputeImuAllanDeviationStreaming(
      [&samples](const std::function<void(const ImuSample&)>& visit) {
        for (const ImuSample& s : samples) visit(s);
      },
      options);
}

}  // namespace mavloc
