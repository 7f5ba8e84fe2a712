// The streaming path of `mavloc imu-noise` (evaluation/imu_noise/allan_streaming.h): the
// accumulator against the batch OverlappingAllanDeviation on random series (bit for bit), the
// longest tau (--max-tau) and the memory it bounds, the streaming sampling check against the
// vector-based check it replaced (kept here as the reference), the streaming IMU CSV reader
// (datasets/io/euroc_io.h) and its line reader against the values written, and bad input through
// the CLI: exit code 2, one line naming the file, line and field, nothing left at --out.
#include "evaluation/imu_noise/allan_streaming.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/imu_gaps.h"
#include "core/random.h"
#include "datasets/io/euroc_io.h"
#include "datasets/io/text_table.h"
#include "evaluation/imu_noise/noise_fit.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;

// White noise of per-sample sigma plus a random walk of per-sample step, on top of an offset.
std::vector<double> RandomSeries(size_t n, double sigma, double step, double offset,
                                 uint64_t seed) {
  Rng rng(seed);
  std::vector<double> y(n);
  double walk = 0.0;
  for (double& v : y) {
    walk += step * rng.Gaussian();
    v = offset + walk + sigma * rng.Gaussian();
  }
  return y;
}

// The streaming accumulator over several series at once, with the series' means computed as the
// batch form computes them.
std::vector<AllanCurve> Streamed(const std::vector<std::vector<double>>& series, double tau0_s,
                                 const AllanOptions& options, size_t* history_bytes = nullptr) {
  const size_t n = series.front().size();
  std::vector<double> means(series.size(), 0.0);
  for (size_t c = 0; c < series.size(); ++c) {
    for (const double y : series[c]) means[c] += y;
    means[c] /= static_cast<double>(n);
  }
  StreamingAllanDeviation allan(means, n, tau0_s, options);
  std::vector<double> row(series.size());
  for (size_t k = 0; k < n; ++k) {
    for (size_t c = 0; c < series.size(); ++c) row[c] = series[c][k];
    allan.Add(row.data());
  }
  if (history_bytes != nullptr) *history_bytes = allan.history_bytes();
  return allan.Finish();
}

// Every field of every point equal, bit for bit.
void ExpectSameCurve(const AllanCurve& streamed, const AllanCurve& batch) {
  EXPECT_EQ(streamed.samples, batch.samples);
  EXPECT_EQ(streamed.sample_period_s, batch.sample_period_s);
  EXPECT_EQ(streamed.cut_at_max_tau, batch.cut_at_max_tau);
  ASSERT_EQ(streamed.points.size(), batch.points.size());
  for (size_t i = 0; i < batch.points.size(); ++i) {
    const AllanPoint& s = streamed.points[i];
    const AllanPoint& b = batch.points[i];
    SCOPED_TRACE("m = " + std::to_string(b.cluster_size));
    EXPECT_EQ(s.cluster_size, b.cluster_size);
    EXPECT_EQ(s.tau_s, b.tau_s);
    EXPECT_EQ(s.adev, b.adev);
    EXPECT_EQ(s.slope, b.slope);
    EXPECT_EQ(s.edf, b.edf);
    EXPECT_EQ(s.adev_low, b.adev_low);
    EXPECT_EQ(s.adev_high, b.adev_high);
  }
}

TEST(StreamingAllan, EqualsTheBatchFormBitForBitOnRandomSeries) {
  // Lengths around the ring's size (2 m_max + 4096 rows: the history wraps for n > ~8200 with the
  // quarter rule, at once with a short max tau), offsets up to an accelerometer's 9.81, white
  // noise and random walks, three series at once; other cluster spacings and a tau cap.
  struct Case {
    size_t n;
    double offset, step;
    double per_decade, max_tau_s;
  };
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Case> cases = {
      {1000, 0.0, 0.0, 10, inf},     {1001, 9.81, 1e-4, 10, inf}, {4097, -3.0, 1e-3, 10, inf},
      {8193, 9.81, 0.0, 10, inf},    {20011, 0.5, 1e-3, 10, inf}, {50000, 9.81, 1e-4, 10, 0.5},
      {120000, 9.81, 1e-4, 10, 30.}, {30001, 1.0, 1e-2, 3, inf},  {30001, 1.0, 1e-2, 20, 5.0},
  };
  uint64_t seed = 100;
  for (const Case& c : cases) {
    SCOPED_TRACE("n = " + std::to_string(c.n) + ", max tau " + std::to_string(c.max_tau_s));
    AllanOptions options;
    options.clusters_per_decade = c.per_decade;
    options.max_tau_s = c.max_tau_s;
    const double tau0_s = 0.01;
    std::vector<std::vector<double>> series;
    for (int s = 0; s < 3; ++s)
      series.push_back(RandomSeries(c.n, 1e-2 * (s + 1), c.step, c.offset * s, ++seed));
    const std::vector<AllanCurve> streamed = Streamed(series, tau0_s, options);
    ASSERT_EQ(streamed.size(), 3u);
    for (int s = 0; s < 3; ++s) {
      const AllanCurve batch = OverlappingAllanDeviation(series[s], tau0_s, options);
      ASSERT_GE(batch.points.size(), 5u);
      ExpectSameCurve(streamed[s], batch);
    }
  }
}

TEST(StreamingAllan, TooShortOrWithoutPeriodGivesEmptyCurvesAsTheBatchForm) {
  const std::vector<double> y = RandomSeries(999, 1e-3, 0.0, 0.0, 7);
  ExpectSameCurve(Streamed({y}, 0.01, {}).front(), OverlappingAllanDeviation(y, 0.01));
  const std::vector<double> z = RandomSeries(2000, 1e-3, 0.0, 0.0, 8);
  ExpectSameCurve(Streamed({z}, 0.0, {}).front(), OverlappingAllanDeviation(z, 0.0));
  // A sample too few: no curve rather than a wrong one.
  StreamingAllanDeviation allan({0.0}, 2000, 0.01);
  for (size_t k = 0; k + 1 < z.size(); ++k) allan.Add(&z[k]);
  EXPECT_TRUE(allan.Finish().front().points.empty());
}

// A static 200 Hz IMU with EuRoC-like stamps: white noise and bias random walks.
std::vector<ImuSample> ImuStream(size_t n, uint64_t seed) {
  Rng rng(seed);
  std::vector<ImuSample> samples(n);
  Eigen::Vector3d bias_g = Eigen::Vector3d::Zero(), bias_a = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    bias_g += rng.Gaussian3(1e-6);
    bias_a += rng.Gaussian3(1e-4);
    samples[i].t_ns = 1403715273262142976 + static_cast<TimeNs>(i) * 5000000;
    samples[i].gyro_rad_s = Eigen::Vector3d(0.01, -0.02, 0.005) + bias_g + rng.Gaussian3(2.4e-3);
    samples[i].accel_m_s2 = Eigen::Vector3d(0.1, -0.2, 9.81) + bias_a + rng.Gaussian3(2.8e-2);
  }
  return samples;
}

TEST(StreamingAllan, ImuStreamInTwoPassesEqualsTheBatchFormPerAxis) {
  const std::vector<ImuSample> samples = ImuStream(60000, 3);
  AllanOptions options;
  options.max_tau_s = 20.0;  // a ring much shorter than the stream
  int passes = 0;
  const ImuAllanDeviation streamed = ComputeImuAllanDeviationStreaming(
      [&](const std::function<void(const ImuSample&)>& visit) {
        ++passes;
        for (const ImuSample& s : samples) visit(s);
      },
      options);
  EXPECT_EQ(passes, 2);
  ASSERT_TRUE(streamed.sampling.ok) << streamed.sampling.reason;
  EXPECT_EQ(streamed.sampling.rate_hz, 200.0);
  std::vector<double> series(samples.size());
  for (int axis = 0; axis < 3; ++axis) {
    for (size_t i = 0; i < samples.size(); ++i) series[i] = samples[i].gyro_rad_s[axis];
    ExpectSameCurve(streamed.gyro[axis], OverlappingAllanDeviation(series, 0.005, options));
    for (size_t i = 0; i < samples.size(); ++i) series[i] = samples[i].accel_m_s2[axis];
    ExpectSameCurve(streamed.accel[axis], OverlappingAllanDeviation(series, 0.005, options));
  }
  // The vector form goes the same way.
  const ImuAllanDeviation from_vector = ComputeImuAllanDeviation(samples, options);
  ExpectSameCurve(from_vector.accel[2], streamed.accel[2]);

  // A source that changes between the passes is refused, not averaged.
  int pass = 0;
  const ImuAllanDeviation changed =
      ComputeImuAllanDeviationStreaming([&](const std::function<void(const ImuSample&)>& visit) {
        const size_t count = ++pass == 1 ? samples.size() : samples.size() - 10;
        for (size_t i = 0; i < count; ++i) visit(samples[i]);
      });
  EXPECT_FALSE(changed.sampling.ok);
  EXPECT_NE(changed.sampling.reason.find("changed while it was read"), std::string::npos)
      << changed.sampling.reason;
}

TEST(StreamingAllan, MaxTauBoundsTheCurveAndTheMemory) {
  // 200 Hz: max tau 10 s keeps m <= 2000 (1995 = 10^3.3); the curve is the uncapped one cut
  // there, and the history does not grow with the series (the same bytes for 100 000 and 300 000
  // samples).
  const double tau0_s = 0.005;
  AllanOptions capped;
  capped.max_tau_s = 10.0;
  size_t bytes_short = 0, bytes_long = 0;
  const std::vector<double> y = RandomSeries(300000, 2.4e-3, 1e-5, 9.81, 11);
  const std::vector<double> head(y.begin(), y.begin() + 100000);
  const AllanCurve curve = Streamed({y}, tau0_s, capped, &bytes_long).front();
  Streamed({head}, tau0_s, capped, &bytes_short);
  EXPECT_EQ(bytes_short, bytes_long);
  // (2 m_max + block) rows of one double.
  EXPECT_EQ(bytes_long, (2 * 1995 + StreamingAllanDeviation::kBlockRows) * sizeof(double));
  ASSERT_FALSE(curve.points.empty());
  EXPECT_LE(curve.points.back().tau_s, 10.0);
  EXPECT_GT(curve.points.back().tau_s, 10.0 / std::pow(10.0, 0.1) - 1e-9);
  EXPECT_TRUE(curve.cut_at_max_tau);
  EXPECT_EQ(curve.max_tau_s, 10.0);
  const AllanCurve full = OverlappingAllanDeviation(y, tau0_s);
  EXPECT_FALSE(full.cut_at_max_tau);
  ASSERT_GT(full.points.size(), curve.points.size());
  for (size_t i = 0; i < curve.points.size(); ++i)
    EXPECT_EQ(curve.points[i].adev, full.points[i].adev) << "m = " << curve.points[i].cluster_size;
  // tau exactly at the cap is kept (1000 s / 0.005 s rounds either way in double).
  AllanOptions at_grid;
  at_grid.max_tau_s = 0.05;  // m = 10
  EXPECT_EQ(AllanClusterSizes(100000, tau0_s, at_grid).back(), 10);
  // A cap below the shortest tau leaves no point, and says it was the cap.
  AllanOptions tiny;
  tiny.max_tau_s = 1e-3;
  const AllanCurve none = Streamed({head}, tau0_s, tiny).front();
  EXPECT_TRUE(none.points.empty());
  EXPECT_TRUE(none.cut_at_max_tau);
  // A series shorter than 4 max tau is not cut: its curve is the batch form's, quarter and all.
  AllanOptions long_cap;
  long_cap.max_tau_s = 1000.0;
  EXPECT_FALSE(Streamed({head}, tau0_s, long_cap).front().cut_at_max_tau);
}

TEST(StreamingAllan, CutCurveNotesSayMaxTauNotTheLogLength) {
  // 2000 s of white noise (N = 1e-3) + random walk (K = 1e-5) at 100 Hz, whose slopes meet near
  // 170 s, cut at 5 s: the random walk is not reached, and the note names --max-tau, not a
  // longer log.
  const std::vector<double> y = RandomSeries(200000, 1e-2, 1e-6, 0.0, 12);
  AllanOptions options;
  options.max_tau_s = 5.0;
  const AxisNoiseFit fit = FitAllanNoise(OverlappingAllanDeviation(y, 0.01, options));
  EXPECT_FALSE(fit.random_walk.measured);
  EXPECT_NE(fit.random_walk.note.find("--max-tau (5 s) stops it"), std::string::npos)
      << fit.random_walk.note;
  EXPECT_EQ(fit.random_walk.note.find("times longer"), std::string::npos) << fit.random_walk.note;
}

// CheckUniformSampling as it was before the streaming check (vector of intervals, nth_element,
// FindImuGaps): the reference for UniformSamplingCheck.
UniformSampling ReferenceCheck(const std::vector<ImuSample>& samples) {
  UniformSampling s;
  s.samples = samples.size();
  if (samples.size() < kMinAllanSamples) {
    s.reason = fmt::format(
        "{} samples: Allan deviation needs at least {} (and a static log of minutes to hours to "
        "show more than the white noise)",
        samples.size(), kMinAllanSamples);
    return s;
  }
  for (size_t i = 1; i < samples.size(); ++i) {
    if (samples[i].t_ns <= samples[i - 1].t_ns) {
      s.reason = fmt::format("sample {} (t = {} ns) does not come after the one before ({} ns)", i,
                             samples[i].t_ns, samples[i - 1].t_ns);
      return s;
    }
  }
  std::vector<TimeNs> intervals;
  for (size_t i = 1; i < samples.size(); ++i)
    intervals.push_back(samples[i].t_ns - samples[i - 1].t_ns);
  std::nth_element(intervals.begin(), intervals.begin() + static_cast<long>(intervals.size() / 2),
                   intervals.end());
  const double median_ns = static_cast<double>(intervals[intervals.size() / 2]);
  s.rate_hz = 1e9 / median_ns;
  const TimeNs span_ns = samples.back().t_ns - samples.front().t_ns;
  s.duration_s = NsToSeconds(span_ns);
  const double expected = std::round(static_cast<double>(span_ns) / median_ns) + 1.0;
  s.missing_samples = expected > static_cast<double>(samples.size())
                          ? static_cast<size_t>(expected - static_cast<double>(samples.size()))
                          : 0;
  const std::vector<ImuGap> gaps = FindImuGaps(samples);
  if (!gaps.empty()) {
    s.reason = "the stream has " + DescribeImuGaps(gaps, samples.front().t_ns) +
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

std::vector<ImuSample> Stamped(const std::vector<TimeNs>& t_ns) {
  std::vector<ImuSample> samples(t_ns.size());
  for (size_t i = 0; i < t_ns.size(); ++i) samples[i].t_ns = t_ns[i];
  return samples;
}

TEST(StreamingSamplingCheck, SameVerdictAndMessageAsTheVectorCheck) {
  Rng rng(21);
  const auto uniform = [](size_t n, TimeNs period_ns) {
    std::vector<TimeNs> t(n);
    for (size_t i = 0; i < n; ++i) t[i] = 1000000000 + static_cast<TimeNs>(i) * period_ns;
    return t;
  };
  std::vector<std::pair<std::string, std::vector<TimeNs>>> streams;
  streams.push_back({"uniform 200 Hz", uniform(5000, 5000000)});
  streams.push_back({"too short", uniform(999, 5000000)});
  streams.push_back({"empty", {}});
  {
    auto t = uniform(3000, 5000000);  // EuRoC-like stamps: 4999936 / 5000192 ns intervals
    for (size_t i = 0; i < t.size(); ++i) t[i] += (i * 37) % 5 == 0 ? 256 : -64;
    streams.push_back({"euroc rounding", t});
  }
  {
    auto t = uniform(4000, 5000000);
    for (size_t i = 2000; i < t.size(); ++i) t[i] += 1000000000;
    streams.push_back({"one gap", t});
  }
  {
    auto t = uniform(8000, 4000000);  // three gaps, the longest not the first
    for (size_t i = 1000; i < t.size(); ++i) t[i] += 300000000;
    for (size_t i = 3000; i < t.size(); ++i) t[i] += 2000000000;
    for (size_t i = 6000; i < t.size(); ++i) t[i] += 500000000;
    streams.push_back({"three gaps", t});
  }
  {
    auto t = uniform(4000, 4000000);  // two gaps of the same length: the first is the longest
    for (size_t i = 1000; i < t.size(); ++i) t[i] += 700000000;
    for (size_t i = 3000; i < t.size(); ++i) t[i] += 700000000;
    streams.push_back({"equal gaps", t});
  }
  {
    auto t = uniform(4000, 5000000);  // a 35 ms interval: 7 periods, not a gap
    for (size_t i = 2000; i < t.size(); ++i) t[i] += 30000000;
    streams.push_back({"short pause", t});
  }
  {
    std::vector<TimeNs> thinned;  // every 40th sample dropped: 2.5 % missing
    const auto all = uniform(8000, 5000000);
    for (size_t i = 0; i < all.size(); ++i)
      if (i % 40 != 39) thinned.push_back(all[i]);
    streams.push_back({"2.5 % missing", thinned});
  }
  {
    auto t = uniform(8000, 5000000);  // jitter of +-1 ms and 0.5 % dropped: accepted
    std::vector<TimeNs> jittered;
    for (size_t i = 0; i < t.size(); ++i)
      if (i % 200 != 100) jittered.push_back(t[i] + SecondsToNs(rng.Uniform(-1e-3, 1e-3)));
    streams.push_back({"jitter", jittered});
  }
  {
    auto t = uniform(2000, 5000000);
    std::swap(t[100], t[101]);
    streams.push_back({"backwards", t});
  }
  {
    auto t = uniform(2000, 5000000);
    t[500] = t[499];
    streams.push_back({"repeated", t});
  }
  {
    auto t = uniform(1500, 1000000000);  // 1 Hz: every interval is longer than 0.2 s
    for (size_t i = 700; i < t.size(); ++i) t[i] += 20000000000;  // and one of 21 s, a gap
    streams.push_back({"1 Hz with a gap", t});
    auto u = uniform(1500, 1000000000);
    for (size_t i = 1; i < u.size(); ++i) u[i] += static_cast<TimeNs>(rng.Uniform(-1e6, 1e6));
    streams.push_back({"1 Hz jittered", u});
  }
  {
    auto t = uniform(6000, 2500000);  // two intervals in three longer than 0.2 s: the median too
    for (size_t i = 0; i < t.size(); ++i) t[i] += static_cast<TimeNs>(i - i / 3) * 297000000;
    streams.push_back({"two thirds long", t});
  }
  for (const auto& [name, t] : streams) {
    SCOPED_TRACE(name);
    const std::vector<ImuSample> samples = Stamped(t);
    const UniformSampling reference = ReferenceCheck(samples);
    const UniformSampling streamed = CheckUniformSampling(samples);
    EXPECT_EQ(streamed.ok, reference.ok);
    EXPECT_EQ(streamed.reason, reference.reason);
    EXPECT_EQ(streamed.samples, reference.samples);
    EXPECT_EQ(streamed.rate_hz, reference.rate_hz);
    EXPECT_EQ(streamed.duration_s, reference.duration_s);
    EXPECT_EQ(streamed.missing_samples, reference.missing_samples);
    EXPECT_EQ(streamed.median_resolution_ns, 1);
  }
}

TEST(StreamingSamplingCheck, ManyDistinctIntervalsKeepTheMedianWithinHalfABin) {
  // 300 000 stamps with nanosecond jitter of +-1 ms: about 300 000 distinct intervals, more than
  // the exact histogram holds; the median stays within half a bin of the exact one.
  Rng rng(22);
  std::vector<TimeNs> t(300000);
  for (size_t i = 0; i < t.size(); ++i)
    t[i] =
        1000000000 + static_cast<TimeNs>(i) * 5000000 + static_cast<TimeNs>(rng.Uniform(-1e6, 1e6));
  const std::vector<ImuSample> samples = Stamped(t);
  const UniformSampling reference = ReferenceCheck(samples);
  const UniformSampling streamed = CheckUniformSampling(samples);
  ASSERT_TRUE(reference.ok) << reference.reason;
  ASSERT_TRUE(streamed.ok) << streamed.reason;
  EXPECT_GT(streamed.median_resolution_ns, 1);
  EXPECT_LE(streamed.median_resolution_ns, 256);
  const double median_ns = 1e9 / streamed.rate_hz, reference_ns = 1e9 / reference.rate_hz;
  EXPECT_LE(std::abs(median_ns - reference_ns), 0.5 * streamed.median_resolution_ns + 0.5);
  // The missing count moves with the median: by span / median^2 per ns of the median.
  const double per_ns = 1500.0 / 5e6 * 1e9 / 5e6;
  EXPECT_NEAR(static_cast<double>(streamed.missing_samples),
              static_cast<double>(reference.missing_samples),
              per_ns * 0.5 * streamed.median_resolution_ns + 1.0);
}

// ---- The streaming IMU CSV reader ----

std::string ImuCsvText(const std::vector<ImuSample>& samples, bool euroc_header = true) {
  std::string text = euroc_header ? "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],"
                                    "w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],"
                                    "a_RS_S_z [m s^-2]\n"
                                  : "";
  for (const ImuSample& s : samples)
    text += fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", s.t_ns,
                        s.gyro_rad_s.x(), s.gyro_rad_s.y(), s.gyro_rad_s.z(), s.accel_m_s2.x(),
                        s.accel_m_s2.y(), s.accel_m_s2.z());
  return text;
}

TEST(StreamingImuCsv, ReadsBackEveryValueAcrossBlockBoundaries) {
  // 20 000 rows (2.9 MB: three blocks of the reader, rows cut at every boundary), CRLF line ends,
  // a comment of 3 MB in the middle (longer than a block), no newline after the last row.
  const std::vector<ImuSample> samples = ImuStream(20000, 31);
  std::string text = ImuCsvText(samples);
  const size_t middle = text.find('\n', text.size() / 2) + 1;
  text.insert(middle, "# " + std::string(3 << 20, 'x') + "\n");
  std::string crlf;
  for (const char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  crlf.resize(crlf.size() - 2);
  const std::string path = testing::MakeTempDir() + "/imu.csv";
  testing::WriteFileBytes(path, crlf);
  std::vector<ImuSample> read;
  ForEachImuCsvSample(path, [&](const ImuSample& s) { read.push_back(s); });
  ASSERT_EQ(read.size(), samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    ASSERT_EQ(read[i].t_ns, samples[i].t_ns) << i;
    ASSERT_EQ(read[i].gyro_rad_s, samples[i].gyro_rad_s) << i;
    ASSERT_EQ(read[i].accel_m_s2, samples[i].accel_m_s2) << i;
  }
  EXPECT_EQ(ReadImuCsv(path).size(), samples.size());
}

TEST(StreamingImuCsv, LineReaderSplitsAsTheLineByLineReaderDid) {
  // Fields as std::getline(',') / `stream >> word` split them, trimmed of " \t\r\n" only; the
  // header is the last '#' line before the first row; blank lines skipped; a BOM dropped.
  const std::string path = testing::MakeTempDir() + "/t.txt";
  testing::WriteFileBytes(path,
                          "\xEF\xBB\xBF# a, b ,c\n\n  \t\r\n# x,y\n 1 , 2,\v3 ,\r\n,\n#late\n"
                          "a,,b\n4\t5 \v6\n");
  const TextTable comma = ReadTextTable(path, Separator::kComma);
  EXPECT_EQ(comma.header, (std::vector<std::string>{"x", "y"}));
  ASSERT_EQ(comma.rows.size(), 4u);
  EXPECT_EQ(comma.rows[0].line, 5);
  EXPECT_EQ(comma.rows[0].fields, (std::vector<std::string>{"1", "2", "\v3", ""}));
  EXPECT_EQ(comma.rows[1].fields, (std::vector<std::string>{"", ""}));
  EXPECT_EQ(comma.rows[2].line, 8);
  EXPECT_EQ(comma.rows[2].fields, (std::vector<std::string>{"a", "", "b"}));
  EXPECT_EQ(comma.rows[3].fields, (std::vector<std::string>{"4\t5 \v6"}));
  const TextTable words = ReadTextTable(path, Separator::kWhitespace);
  EXPECT_EQ(words.header, (std::vector<std::string>{"x,y"}));
  EXPECT_EQ(words.rows[0].fields, (std::vector<std::string>{"1", ",", "2,", "3", ","}));
  EXPECT_EQ(words.rows[3].fields, (std::vector<std::string>{"4", "5", "6"}));
}

// ---- Bad input, through the reader and through `mavloc imu-noise` ----

struct BadCsv {
  std::string name;
  std::string text;                   // the CSV (after a valid header and 2000 valid rows when
                                      // `after_rows`)
  bool after_rows;                    // appended to 2000 good rows
  std::vector<std::string> expected;  // substrings of the message, after "<file>"
};

std::vector<BadCsv> BadCsvCases() {
  // Good rows are 1403715273262142976 + i * 5 ms; the header is line 1, good row i is line i + 2.
  const std::string next = "1403715283262142976";  // 10 s after the first: after row 1999
  return {
      {"empty file", "", false, {": file has no data rows"}},
      {"header only",
       "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n",
       false,
       {": file has no data rows"}},
      {"NaN gyro",
       next + ",nan,0,0,0,0,9.81\n",
       true,
       {":2002: field 'w_RS_S_x [rad s^-1]'", "'nan' is not finite"}},
      {"NaN accel z", next + ",0,0,0,0,0,NaN\n", true, {":2002: field 'a_RS_S_z [m s^-2]'"}},
      {"text", next + ",0,0,x1,0,0,9.81\n", true, {":2002: field 'w_RS_S_z [rad s^-1]'", "'x1'"}},
      {"empty field",
       next + ",0,0,0,,0,9.81\n",
       true,
       {":2002: field 'a_RS_S_x [m s^-2]'", "empty"}},
      {"absurd",
       next + ",0,0,0,1e308,0,9.81\n",
       true,
       {":2002: field 'a_RS_S_x [m s^-2]'", "outside"}},
      {"repeated stamp",
       "1403715283257142976,0,0,0,0,0,9.81\n",
       true,
       {":2002: field 'timestamp [ns]'", "duplicate timestamp"}},
      {"earlier stamp",
       "1403715273262142976,0,0,0,0,0,9.81\n",
       true,
       {":2002: field 'timestamp [ns]'", "earlier than the previous row's"}},
      {"negative stamp",
       "-5,0,0,0,0,0,9.81\n",
       true,
       {":2002: field 'timestamp [ns]'", "negative"}},
      {"short row",
       next + ",0,0\n",
       true,
       {":2002: field 'w_RS_S_z [rad s^-1]'", "7 fields, found 3"}},
      {"long row", next + ",0,0,0,0,0,9.81,1\n", true, {":2002: field 'column 8'", "7 (timestamp"}},
      {"accelerometer first",
       "#timestamp [ns],a_x,a_y,a_z,w_x,w_y,w_z\n1000,0,0,9.81,0,0,0\n",
       false,
       {":1: field 'a_x'", "must be the gyroscope"}},
  };
}

TEST(StreamingImuCsv, BadInputNamesTheFileLineAndField) {
  const std::string dir = testing::MakeTempDir();
  const std::string good = ImuCsvText(ImuStream(2000, 41));
  for (const BadCsv& c : BadCsvCases()) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/imu.csv";
    testing::WriteFileBytes(path, (c.after_rows ? good : "") + c.text);
    size_t visited = 0;
    try {
      ForEachImuCsvSample(path, [&](const ImuSample&) { ++visited; });
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + c.expected.front(), 0), 0u) << e.what();
      for (const std::string& expected : c.expected)
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
            << "expected '" << expected << "' in: " << e.what();
      // The same error from the vector form.
      try {
        ReadImuCsv(path);
        ADD_FAILURE() << "ReadImuCsv accepted";
      } catch (const InputError& again) {
        EXPECT_STREQ(again.what(), e.what());
      }
    }
    EXPECT_EQ(visited, c.after_rows ? 2000u : 0u);
  }
}

// `mavloc imu-noise FILE --out DIR` in a scratch folder: exit 2, one line, nothing at DIR.
void ExpectCliRefuses(const std::string& dir, const std::string& args,
                      const std::vector<std::string>& expected) {
  SCOPED_TRACE("mavloc " + args);
  fs::remove_all(dir + "/out");
  const testing::CliRun run = testing::RunCliIn(dir, args + " --out out");
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  for (const std::string& e : expected)
    EXPECT_NE(run.err.find(e), std::string::npos) << "expected '" << e << "' in: " << run.err;
  EXPECT_FALSE(fs::exists(dir + "/out")) << "an output folder was left behind";
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos)
        << entry.path() << " left behind";
}

TEST(StreamingImuNoiseCli, BadInputExitsTwoWithOneLineAndWritesNothing) {
  const std::string dir = testing::MakeTempDir();
  const std::string good = ImuCsvText(ImuStream(2000, 51));
  for (const BadCsv& c : BadCsvCases()) {
    testing::WriteFileBytes(dir + "/imu.csv", (c.after_rows ? good : "") + c.text);
    std::vector<std::string> expected = c.expected;
    expected.front() = "imu.csv" + expected.front();
    ExpectCliRefuses(dir, "imu-noise imu.csv", expected);
  }
  // Streams the sampling check refuses, with the reason and the file.
  const std::vector<ImuSample> stream = ImuStream(4000, 52);
  testing::WriteFileBytes(dir + "/imu.csv", ImuCsvText({stream.begin(), stream.begin() + 999}));
  ExpectCliRefuses(dir, "imu-noise imu.csv", {"imu.csv: 999 samples", "at least 1000"});
  std::vector<ImuSample> gappy = stream;
  for (size_t i = 2000; i < gappy.size(); ++i) gappy[i].t_ns += kNsPerSecond;
  testing::WriteFileBytes(dir + "/imu.csv", ImuCsvText(gappy));
  ExpectCliRefuses(dir, "imu-noise imu.csv", {"imu.csv: the stream has 1 gap", "--from/--to"});
  // A window without samples, a file without IMU samples, a missing file, a bad --max-tau.
  testing::WriteFileBytes(dir + "/imu.csv", ImuCsvText(stream));
  ExpectCliRefuses(
      dir, "imu-noise imu.csv --from 100",
      {"imu.csv: field '--from/--to'", "no sample between 100 s and inf s", "19.995 s long"});
  ExpectCliRefuses(dir, "imu-noise imu.csv --max-tau 0.001",
                   {"imu.csv: field '--max-tau'", "0 cluster size(s)"});
  ExpectCliRefuses(dir, "imu-noise imu.csv --max-tau -1", {"--max-tau -1", "> 0"});
  ExpectCliRefuses(dir, "imu-noise imu.csv --max-tau nan", {"--max-tau", "nan"});
  ExpectCliRefuses(dir, "imu-noise missing.csv", {"missing.csv", "does not exist"});
  fs::create_directories(dir + "/dataset/mav0");
  ExpectCliRefuses(dir, "imu-noise dataset", {"dataset", "without mav0/imu0/data.csv"});
}

TEST(StreamingImuNoiseCli, MaxTauIsHonouredAndTheNumbersAreTheBatchOnes) {
  // 400 s at 200 Hz with --max-tau 20: allan_deviation.csv ends at tau <= 20 s, with the numbers
  // of the batch form on the samples read back.
  const std::string dir = testing::MakeTempDir();
  const std::vector<ImuSample> stream = ImuStream(80000, 61);
  testing::WriteFileBytes(dir + "/imu.csv", ImuCsvText(stream));
  const testing::CliRun run = testing::RunCliIn(dir, "imu-noise imu.csv --out out --max-tau 20");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::ifstream csv(dir + "/out/allan_deviation.csv");
  std::string line, last;
  std::getline(csv, line);
  size_t rows = 0;
  while (std::getline(csv, line)) {
    last = line;
    ++rows;
  }
  ASSERT_GT(rows, 30u);
  const double last_tau = std::stod(last.substr(0, last.find(',')));
  EXPECT_LE(last_tau, 20.0);
  EXPECT_GT(last_tau, 15.0);
  AllanOptions options;
  options.max_tau_s = 20.0;
  const std::vector<ImuSample> read = ReadImuCsv(dir + "/imu.csv");
  std::vector<double> series(read.size());
  for (size_t i = 0; i < read.size(); ++i) series[i] = read[i].accel_m_s2.z();
  const AllanCurve batch = OverlappingAllanDeviation(series, 0.005, options);
  ASSERT_EQ(batch.points.size(), rows);
  // accel_z_adev is column 2 + 5 * 3 (0-based 17), printed with 7 significant digits.
  std::vector<std::string> fields;
  for (size_t begin = 0;;) {
    const size_t comma = last.find(',', begin);
    fields.push_back(last.substr(begin, comma - begin));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  ASSERT_EQ(fields.size(), 20u);
  EXPECT_EQ(fields[17], fmt::format("{:.6e}", batch.points.back().adev));
}

}  // namespace
}  // namespace mavloc
