// test_random.cpp — Philox4x32-10 known answers, reproducibility and symmetry of the counter-based
// streams, and the statistics of their uniform and normal deviates (kernels/common/random.hpp).
//
// Statistical bounds are 5 standard deviations of the estimator at the sample size used (2^20
// draws), so a correct generator fails a check with probability below 1e-6 and, the seeds being
// fixed, the tests are deterministic.
#include <gtest/gtest.h>

#include "kernels/common/random.hpp"
#include "test_types.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <vector>

namespace {

using mesoflow::PhiloxCounter;
using mesoflow::PhiloxKey;
using mesoflow::RandomStream;
namespace stream_tag = mesoflow::stream_tag;

#if defined(KOKKOS_ENABLE_OPENMP) && defined(KOKKOS_ENABLE_SERIAL)
using Backends = ::testing::Types<Kokkos::Serial, Kokkos::OpenMP>;
#else
using Backends = ::testing::Types<Kokkos::DefaultExecutionSpace>;
#endif
using Precisions = ::testing::Types<float, double>;

constexpr double kSigmas = 5;
constexpr int kStreams = 1 << 17;
constexpr int kPerStream = 8;  // kStreams * kPerStream = 2^20 draws per sample
constexpr std::uint64_t kSeed = 0x5eed0f5eed5eedull;
constexpr std::uint64_t kStep = 1234567;

// ---------------------------------------------------------------------------------------------
// Known answers: the "philox4x32 10" lines of Random123's tests/kat_vectors.

struct KnownAnswer {
  PhiloxCounter ctr;
  PhiloxKey key;
  PhiloxCounter expected;
};

constexpr KnownAnswer kKnownAnswers[3] = {
    {{{0x00000000u, 0x00000000u, 0x00000000u, 0x00000000u}},
     {{0x00000000u, 0x00000000u}},
     {{0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u}}},
    {{{0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu}},
     {{0xffffffffu, 0xffffffffu}},
     {{0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu}}},
    {{{0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u}},
     {{0xa4093822u, 0x299f31d0u}},
     {{0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}}},
};

void expect_words_eq(const PhiloxCounter& expected, const PhiloxCounter& actual, int vector) {
  for (int w = 0; w < 4; ++w)
    EXPECT_EQ(expected.v[w], actual.v[w]) << "known-answer vector " << vector << ", word " << w;
}

template <class Exec>
std::vector<PhiloxCounter> philox_in_kernel() {
  Kokkos::Array<KnownAnswer, 3> inputs;
  for (int n = 0; n < 3; ++n) inputs[n] = kKnownAnswers[n];
  Kokkos::View<PhiloxCounter*, Exec> out("mesoflow::test_random::philox_out", 3);
  Kokkos::parallel_for(
      "mesoflow::test_random::philox", Kokkos::RangePolicy<Exec>(0, 3), KOKKOS_LAMBDA(const int n) {
        out(n) = mesoflow::philox4x32_10(inputs[n].ctr, inputs[n].key);
      });
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  return std::vector<PhiloxCounter>(host.data(), host.data() + 3);
}

// ---------------------------------------------------------------------------------------------
// Drawing samples inside kernels: stream s (one per kernel index, in a scrambled order on request)
// writes its first `per_stream` values to row s.

enum class Draw { bits, uniform, symmetric, normal };

struct ParticleStreams {
  std::uint64_t seed, step;
  KOKKOS_INLINE_FUNCTION RandomStream operator()(std::uint32_t s) const {
    return mesoflow::particle_stream(seed, step, s);
  }
};

struct CellStreams {
  std::uint64_t seed, step;
  KOKKOS_INLINE_FUNCTION RandomStream operator()(std::uint32_t s) const {
    return mesoflow::cell_stream(seed, step, s);
  }
};

// Pair (s, s + offset), listed as (s + offset, s) when `reversed`.
struct PairStreams {
  std::uint64_t seed, step;
  std::uint32_t offset;
  bool reversed;
  KOKKOS_INLINE_FUNCTION RandomStream operator()(std::uint32_t s) const {
    return reversed ? mesoflow::pair_stream(seed, step, s + offset, s)
                    : mesoflow::pair_stream(seed, step, s, s + offset);
  }
};

template <class Real>
KOKKOS_INLINE_FUNCTION double draw_one(RandomStream& rs, Draw kind) {
  switch (kind) {
    case Draw::bits:
      return rs.next_u32();
    case Draw::uniform:
      return rs.uniform<Real>();
    case Draw::symmetric:
      return rs.uniform_symmetric<Real>();
    case Draw::normal:
      return rs.normal<Real>();
  }
  return 0;
}

// Row-major (n_streams × per_stream) values, as doubles (exact for every Real and for bits).
template <class Exec, class Real, class MakeStream>
std::vector<double> draw(const MakeStream& make, int n_streams, int per_stream, Draw kind,
                         bool scrambled = false) {
  Kokkos::View<double**, Kokkos::LayoutRight, Exec> out("mesoflow::test_random::draws", n_streams,
                                                        per_stream);
  Kokkos::parallel_for(
      "mesoflow::test_random::draw", Kokkos::RangePolicy<Exec>(0, n_streams),
      KOKKOS_LAMBDA(const int t) {
        const std::uint32_t s = scrambled
                                    ? static_cast<std::uint32_t>(static_cast<std::uint64_t>(t) *
                                                                 2654435761u % n_streams)
                                    : static_cast<std::uint32_t>(t);
        RandomStream rs = make(s);
        for (int k = 0; k < per_stream; ++k) out(s, k) = draw_one<Real>(rs, kind);
      });
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  return std::vector<double>(host.data(), host.data() + host.size());
}

// The same values from a plain host loop.
template <class Real, class MakeStream>
std::vector<double> draw_on_host(const MakeStream& make, int n_streams, int per_stream, Draw kind) {
  std::vector<double> values;
  values.reserve(static_cast<std::size_t>(n_streams) * per_stream);
  for (int s = 0; s < n_streams; ++s) {
    RandomStream rs = make(static_cast<std::uint32_t>(s));
    for (int k = 0; k < per_stream; ++k) values.push_back(draw_one<Real>(rs, kind));
  }
  return values;
}

template <class Exec, class Real>
Kokkos::View<Real* [3], Kokkos::LayoutLeft, Exec> counter_filled(int n, std::uint64_t seed,
                                                                 std::uint32_t field) {
  Kokkos::View<Real* [3], Kokkos::LayoutLeft, Exec> x("mesoflow::test_random::x", n);
  const Real lo[3] = {Real(-1), Real(0), Real(10)};
  const Real hi[3] = {Real(1), Real(0.5), Real(110)};
  mesoflow::fill_uniform_counter(x, lo, hi, seed, field);
  return x;
}

// ---------------------------------------------------------------------------------------------
// Statistics, accumulated in double on the host.

struct Moments {
  double mean = 0, variance = 0, fourth_central = 0, min = 0, max = 0;
};

Moments moments(const std::vector<double>& x) {
  Moments m;
  double sum = 0;
  for (double v : x) sum += v;
  m.mean = sum / x.size();
  double s2 = 0, s4 = 0;
  for (double v : x) {
    const double d2 = (v - m.mean) * (v - m.mean);
    s2 += d2;
    s4 += d2 * d2;
  }
  m.variance = s2 / (x.size() - 1);
  m.fourth_central = s4 / x.size();
  m.min = *std::min_element(x.begin(), x.end());
  m.max = *std::max_element(x.begin(), x.end());
  return m;
}

// Pearson's chi-square of x against the uniform distribution on [lo, hi] in `bins` equal bins.
double chi_square_uniform(const std::vector<double>& x, int bins, double lo, double hi) {
  std::vector<double> counts(bins, 0.0);
  for (double v : x) {
    const int b = static_cast<int>((v - lo) / (hi - lo) * bins);
    counts[std::clamp(b, 0, bins - 1)] += 1;
  }
  const double expected = static_cast<double>(x.size()) / bins;
  double chi2 = 0;
  for (double c : counts) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

// Quantile of the chi-square distribution with `dof` degrees of freedom at standard-normal score
// z, by the Wilson–Hilferty transformation (relative error < 1e-3 at dof = 63).
double chi_square_quantile(int dof, double z) {
  const double a = 2.0 / (9.0 * dof);
  return dof * std::pow(1 - a + z * std::sqrt(a), 3);
}

// Kolmogorov–Smirnov statistic of x against the standard normal CDF.
double kolmogorov_smirnov_normal(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  double d = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double cdf = 0.5 * std::erfc(-x[k] / std::sqrt(2.0));
    d = std::max({d, cdf - k / n, (k + 1) / n - cdf});
  }
  return d;
}

// Asymptotic Kolmogorov distribution: P(sqrt(n) D > t) = p at t = sqrt(-ln(p / 2) / 2).
double kolmogorov_smirnov_bound(std::size_t n, double p) {
  return std::sqrt(-std::log(p / 2) / 2) / std::sqrt(static_cast<double>(n));
}

double correlation(const std::vector<double>& x, const std::vector<double>& y) {
  const Moments mx = moments(x), my = moments(y);
  double sxy = 0;
  for (std::size_t k = 0; k < x.size(); ++k) sxy += (x[k] - mx.mean) * (y[k] - my.mean);
  return sxy / (x.size() - 1) / std::sqrt(mx.variance * my.variance);
}

// Two-sided tail probability of a 5-sigma normal deviate.
constexpr double kFiveSigmaTail = 5.733e-7;

// ---------------------------------------------------------------------------------------------
// Philox and the stream layout (host).

TEST(RandomPhilox, KnownAnswersOnHost) {
  for (int n = 0; n < 3; ++n)
    expect_words_eq(kKnownAnswers[n].expected,
                    mesoflow::philox4x32_10(kKnownAnswers[n].ctr, kKnownAnswers[n].key), n);
}

TEST(RandomStream, FollowsDocumentedPacking) {
  const std::uint64_t seed = 0x0123456789abcdefull;
  const std::uint64_t step = 0x12'3456'789aull;  // 37 bits
  const std::uint32_t tag = stream_tag::user + 5, a = 0xdeadbeefu, b = 77;
  RandomStream rs(seed, step, tag, a, b);
  const PhiloxKey key = {{0x89abcdefu, 0x01234567u}};
  for (std::uint32_t block = 0; block < 3; ++block) {
    const PhiloxCounter ctr = {{a, b, 0x3456789au, (0x12u << 24) | (tag << 16) | block}};
    const PhiloxCounter words = mesoflow::philox4x32_10(ctr, key);
    for (int w = 0; w < 4; ++w)
      EXPECT_EQ(words.v[w], rs.next_u32()) << "block " << block << ", word " << w;
  }
  // The step is used modulo 2^40.
  RandomStream wrapped(seed, step + (std::uint64_t(1) << 40), tag, a, b),
      same(seed, step, tag, a, b);
  EXPECT_EQ(same.next_u64(), wrapped.next_u64());
  // A 64-bit draw is two words, high first; float draws one word, double two.
  RandomStream words(seed, step, tag, a, b), wide(seed, step, tag, a, b);
  const std::uint64_t high = words.next_u32();
  EXPECT_EQ((high << 32) | words.next_u32(), wide.next_u64());
  RandomStream f(seed, step, tag, a, b), d(seed, step, tag, a, b), ref(seed, step, tag, a, b);
  f.uniform<float>();
  d.uniform<double>();
  ref.next_u32();
  EXPECT_EQ(ref.next_u32(), f.next_u32());
  EXPECT_EQ(ref.next_u32(), d.next_u32());
}

TEST(RandomStream, DifferentKeysGiveDifferentValues) {
  const std::uint64_t seed = 42, step = 1000;
  const std::uint32_t a = 7, b = 9;
  auto first_words = [](RandomStream rs) {
    std::vector<std::uint32_t> w(8);
    for (auto& x : w) x = rs.next_u32();
    return w;
  };
  const auto base = first_words(RandomStream(seed, step, stream_tag::user, a, b));
  EXPECT_EQ(base, first_words(RandomStream(seed, step, stream_tag::user, a, b)));
  const std::vector<RandomStream> changed = {
      RandomStream(seed + 1, step, stream_tag::user, a, b),
      RandomStream(seed + (std::uint64_t(1) << 32), step, stream_tag::user, a, b),
      RandomStream(seed, step + 1, stream_tag::user, a, b),
      RandomStream(seed, step + (std::uint64_t(1) << 32), stream_tag::user, a, b),
      RandomStream(seed, step, stream_tag::user + 1, a, b),
      RandomStream(seed, step, stream_tag::user, a + 1, b),
      RandomStream(seed, step, stream_tag::user, a, b + 1),
      RandomStream(seed, step, stream_tag::user, b, a),
  };
  for (std::size_t c = 0; c < changed.size(); ++c)
    EXPECT_NE(base, first_words(changed[c])) << "changed key/counter field " << c;

  // Pair, cell and particle streams of equal indices are distinct.
  const auto pair = first_words(mesoflow::pair_stream(seed, step, 0, a));
  const auto cell = first_words(mesoflow::cell_stream(seed, step, a));
  const auto particle = first_words(mesoflow::particle_stream(seed, step, a));
  EXPECT_NE(pair, cell);
  EXPECT_NE(pair, particle);
  EXPECT_NE(cell, particle);
  EXPECT_NE(pair, first_words(RandomStream(seed, step, stream_tag::user, 0, a)));
}

TEST(RandomStream, DistinctIdsNeverShareTheirFirstDraw) {
  const int n = 1 << 16;
  std::set<std::uint64_t> firsts;
  for (std::uint32_t i = 0; i < n; ++i) {
    firsts.insert(mesoflow::particle_stream(kSeed, kStep, i).next_u64());
    firsts.insert(mesoflow::cell_stream(kSeed, kStep, i).next_u64());
    firsts.insert(mesoflow::pair_stream(kSeed, kStep, i, i + 1).next_u64());
    firsts.insert(mesoflow::particle_stream(kSeed, kStep + 1, i).next_u64());
  }
  EXPECT_EQ(firsts.size(), std::size_t(4) * n);
}

TEST(RandomStream, LongStreamsDoNotRepeat) {
  RandomStream rs(kSeed, kStep, stream_tag::user, 3, 4);
  std::vector<std::uint32_t> words(1 << 14);
  for (auto& w : words) w = rs.next_u32();
  std::sort(words.begin(), words.end());
  // 2^14 words: a repeated 32-bit value is expected with probability ~3%; none for this seed.
  EXPECT_EQ(std::adjacent_find(words.begin(), words.end()), words.end());
}

TEST(RandomStream, NormalCachesTheSecondBoxMullerDeviate) {
  RandomStream normals(kSeed, kStep, stream_tag::user, 1),
      uniforms(kSeed, kStep, stream_tag::user, 1);
  for (int pair = 0; pair < 4; ++pair) {
    const double z0 = normals.normal<double>(), z1 = normals.normal<double>();
    const double u1 = uniforms.uniform<double>(), u2 = uniforms.uniform<double>();
    const double radius = std::sqrt(-2 * std::log(u1)), angle = 6.283185307179586 * u2;
    EXPECT_NEAR(radius * std::cos(angle), z0, 1e-14);
    EXPECT_NEAR(radius * std::sin(angle), z1, 1e-14);
  }
  EXPECT_EQ(uniforms.next_u32(), normals.next_u32());
}

// ---------------------------------------------------------------------------------------------
// Conversions at the ends of the bit range (host, per precision).

template <class Real>
class RandomConversion : public ::testing::Test {};
TYPED_TEST_SUITE(RandomConversion, Precisions);

TYPED_TEST(RandomConversion, EndPointsStayInsideDocumentedIntervals) {
  using Real = TypeParam;
  const Real ulp = std::is_same<Real, float>::value ? Real(0x1p-24) : Real(0x1p-53);
  const std::uint64_t zero = 0, ones = ~std::uint64_t(0);

  EXPECT_EQ(ulp, mesoflow::uniform_from_bits<Real>(zero));
  EXPECT_EQ(Real(1), mesoflow::uniform_from_bits<Real>(ones));
  EXPECT_EQ(Real(0.5), mesoflow::uniform_from_bits<Real>(ones >> 1));
  EXPECT_EQ(Real(-1) + ulp, mesoflow::symmetric_from_bits<Real>(zero));
  EXPECT_EQ(Real(1) - ulp, mesoflow::symmetric_from_bits<Real>(ones));
  for (std::uint64_t bits : {zero, ones, std::uint64_t(0x0123456789abcdefull), ones >> 1})
    EXPECT_EQ(-mesoflow::symmetric_from_bits<Real>(bits),
              mesoflow::symmetric_from_bits<Real>(~bits));

  // Box–Muller's radius stays finite at the smallest uniform and is zero at the largest.
  const Real smallest = mesoflow::uniform_from_bits<Real>(zero);
  const Real r_max = mesoflow::kmath::sqrt(Real(-2) * mesoflow::kmath::log(smallest));
  EXPECT_TRUE(std::isfinite(r_max));
  EXPECT_NEAR(std::sqrt(-2 * std::log(static_cast<double>(ulp))), r_max, 1e-5);
  EXPECT_EQ(Real(0), mesoflow::kmath::log(mesoflow::uniform_from_bits<Real>(ones)));

  // uniform_in maps onto [lo, hi): both ends of the bit range for a range where rounding matters.
  const Real lo = Real(0), hi = Real(100);
  for (int k = 0; k < 1000; ++k) {
    RandomStream rs(kSeed, kStep, stream_tag::user, k);
    const Real x = rs.uniform_in<Real>(lo, hi);
    EXPECT_TRUE(x >= lo && x < hi) << x;
  }
}

// ---------------------------------------------------------------------------------------------
// Kernels on each backend: known answers, reproducibility, symmetry.

template <class Exec>
class RandomKernel : public ::testing::Test {};
TYPED_TEST_SUITE(RandomKernel, Backends);

TYPED_TEST(RandomKernel, PhiloxKnownAnswersInKernel) {
  const auto out = philox_in_kernel<TypeParam>();
  for (int n = 0; n < 3; ++n) expect_words_eq(kKnownAnswers[n].expected, out[n], n);
}

TYPED_TEST(RandomKernel, StreamsMatchHostInAnyOrder) {
  using Exec = TypeParam;
  const int n = 4099;  // not a power of two: the scrambled order is a true permutation of [0, n)
  const ParticleStreams particles{kSeed, kStep};
  const CellStreams cells{kSeed, kStep};
  const PairStreams pairs{kSeed, kStep, 17, false};
  // Bits and uniforms are integer arithmetic and exact scalings: equal on every backend. Normals go
  // through log, sqrt and cos/sin (device math within 2 ulp of the host's) and products a device
  // compiler may contract: equal on host backends, within testing::agrees_with_host's bound of 30
  // operations at the deviate's own scale (plus 1) on a device.
  for (Draw kind : {Draw::bits, Draw::uniform, Draw::normal}) {
    const auto ref_particles = draw_on_host<double>(particles, n, 9, kind);
    const auto ref_cells = draw_on_host<float>(cells, n, 9, kind);
    const auto ref_pairs = draw_on_host<float>(pairs, n, 9, kind);
    const std::vector<double> got[4] = {draw<Exec, double>(particles, n, 9, kind),
                                        draw<Exec, double>(particles, n, 9, kind, true),
                                        draw<Exec, float>(cells, n, 9, kind, true),
                                        draw<Exec, float>(pairs, n, 9, kind, true)};
    const std::vector<double>* ref[4] = {&ref_particles, &ref_particles, &ref_cells, &ref_pairs};
    for (int c = 0; c < 4; ++c) {
      if (kind != Draw::normal || mesoflow::testing::has_host_arithmetic<Exec>()) {
        EXPECT_EQ(*ref[c], got[c]) << "case " << c;
        continue;
      }
      ASSERT_EQ(ref[c]->size(), got[c].size());
      for (std::size_t k = 0; k < got[c].size(); ++k) {
        const double r = (*ref[c])[k];
        const auto ok = c < 2 ? mesoflow::testing::agrees_with_host<Exec, double>(got[c][k], r, 30, std::abs(r) + 1)
                              : mesoflow::testing::agrees_with_host<Exec, float>(got[c][k], r, 30, std::abs(r) + 1);
        ASSERT_TRUE(ok) << "case " << c << " value " << k;
      }
    }
  }
}

TYPED_TEST(RandomKernel, PairStreamsAreSymmetric) {
  using Exec = TypeParam;
  const int n = 10000;
  for (Draw kind : {Draw::bits, Draw::normal}) {
    const auto ij = draw<Exec, double>(PairStreams{kSeed, kStep, 5, false}, n, 8, kind);
    const auto ji = draw<Exec, double>(PairStreams{kSeed, kStep, 5, true}, n, 8, kind, true);
    const auto ik = draw<Exec, double>(PairStreams{kSeed, kStep, 6, false}, n, 8, kind);
    EXPECT_EQ(ij, ji);
    std::size_t equal = 0;
    for (std::size_t k = 0; k < ij.size(); ++k) equal += ij[k] == ik[k];
    EXPECT_EQ(equal, 0u) << "pair (i, i+5) and (i, i+6) share values";
  }
}

TYPED_TEST(RandomKernel, PoolFillStaysInRange) {
  using Exec = TypeParam;
  Kokkos::View<double* [2], Kokkos::LayoutLeft, Exec> x("mesoflow::test_random::pool_x", 5000);
  Kokkos::View<float*, Exec> y("mesoflow::test_random::pool_y", 5000);
  mesoflow::fill_uniform(x, -2.0, 3.0, 99);
  mesoflow::fill_uniform(y, 0.0f, 1.0f, 99);
  const auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), x);
  const auto hy = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), y);
  std::set<double> distinct;
  for (std::size_t i = 0; i < hx.extent(0); ++i) {
    for (int d = 0; d < 2; ++d) {
      EXPECT_TRUE(hx(i, d) >= -2.0 && hx(i, d) <= 3.0) << hx(i, d);
      distinct.insert(hx(i, d));
    }
    EXPECT_TRUE(hy(i) >= 0.0f && hy(i) <= 1.0f) << hy(i);
  }
  EXPECT_EQ(distinct.size(), 2 * hx.extent(0));
}

#if defined(KOKKOS_ENABLE_OPENMP) && defined(KOKKOS_ENABLE_SERIAL)
TEST(RandomBackends, SerialAndOpenMPGiveIdenticalValues) {
  const PairStreams pairs{kSeed, kStep, 3, false};
  const ParticleStreams particles{kSeed, kStep};
  EXPECT_EQ((draw<Kokkos::Serial, double>(pairs, 20000, 6, Draw::normal)),
            (draw<Kokkos::OpenMP, double>(pairs, 20000, 6, Draw::normal, true)));
  EXPECT_EQ((draw<Kokkos::Serial, float>(particles, 20000, 6, Draw::symmetric)),
            (draw<Kokkos::OpenMP, float>(particles, 20000, 6, Draw::symmetric, true)));
  const auto serial = counter_filled<Kokkos::Serial, double>(100003, kSeed, 0);
  const auto openmp = counter_filled<Kokkos::OpenMP, double>(100003, kSeed, 0);
  const auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), serial);
  const auto ho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), openmp);
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < hs.extent(0); ++i)
    for (int d = 0; d < 3; ++d) mismatches += hs(i, d) != ho(i, d);
  EXPECT_EQ(mismatches, 0u) << "OpenMP threads: " << mesoflow::concurrency<Kokkos::OpenMP>();
}
#endif

// ---------------------------------------------------------------------------------------------
// Per backend and precision: the counter-based fill and the statistics.

template <class Config>
class RandomStatistics : public ::testing::Test {};
TYPED_TEST_SUITE(RandomStatistics, mesoflow::testing::BackendsAndPrecisions);

TYPED_TEST(RandomStatistics, CounterFillIsReproducibleAndInRange) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const int n = 50000;
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(),
                                                     counter_filled<Exec, Real>(n, kSeed, 0));
  const auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(),
                                                     counter_filled<Exec, Real>(n, kSeed, 1));
  const Real lo[3] = {Real(-1), Real(0), Real(10)};
  const Real hi[3] = {Real(1), Real(0.5), Real(110)};
  std::size_t mismatches = 0, out_of_range = 0, equal_fields = 0;
  // lo + (hi − lo)·u: 2 operations a device compiler may contract (testing::agrees_with_host).
  for (int i = 0; i < n; ++i) {
    RandomStream rs(kSeed, 0, stream_tag::initial_condition, i, 0);
    for (int d = 0; d < 3; ++d) {
      mismatches += !mesoflow::testing::agrees_with_host<Exec, Real>(x(i, d), rs.uniform_in<Real>(lo[d], hi[d]), 2,
                                                                     std::abs(double(hi[d])));
      out_of_range += !(x(i, d) >= lo[d] && x(i, d) < hi[d]);
      equal_fields += x(i, d) == v(i, d);
    }
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(out_of_range, 0u);
  EXPECT_EQ(equal_fields, 0u) << "fields 0 and 1 must be independent";
  std::vector<double> column(n);
  for (int i = 0; i < n; ++i) column[i] = x(i, 2);
  const Moments m = moments(column);
  EXPECT_NEAR(60.0, m.mean, kSigmas * 100 / std::sqrt(12.0 * n));
}

TYPED_TEST(RandomStatistics, UniformMomentsAndChiSquare) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const auto u =
      draw<Exec, Real>(ParticleStreams{kSeed, kStep}, kStreams, kPerStream, Draw::uniform);
  const double n = static_cast<double>(u.size());
  const Moments m = moments(u);
  const double chi2 = chi_square_uniform(u, 64, 0, 1);
  std::printf(
      "[ stats    ] uniform   n=%.0f mean=%.6f var=%.6f (1/12=%.6f) min=%.3g max=%.9g "
      "chi2(63)=%.1f\n",
      n, m.mean, m.variance, 1 / 12.0, m.min, m.max, chi2);
  EXPECT_GT(m.min, 0.0);
  EXPECT_LE(m.max, 1.0);
  EXPECT_NEAR(0.5, m.mean, kSigmas * std::sqrt(1 / 12.0 / n));
  EXPECT_NEAR(1 / 12.0, m.variance, kSigmas * std::sqrt((1 / 80.0 - 1 / 144.0) / n));
  EXPECT_GT(chi2, chi_square_quantile(63, -kSigmas));
  EXPECT_LT(chi2, chi_square_quantile(63, kSigmas));
}

TYPED_TEST(RandomStatistics, SymmetricUniformMoments) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const auto w =
      draw<Exec, Real>(PairStreams{kSeed, kStep, 1, false}, kStreams, kPerStream, Draw::symmetric);
  const double n = static_cast<double>(w.size());
  const Moments m = moments(w);
  const double chi2 = chi_square_uniform(w, 64, -1, 1);
  std::printf(
      "[ stats    ] symmetric n=%.0f mean=%.2e var=%.6f (1/3) min=%.9g max=%.9g chi2(63)=%.1f\n", n,
      m.mean, m.variance, m.min, m.max, chi2);
  EXPECT_GT(m.min, -1.0);
  EXPECT_LT(m.max, 1.0);
  EXPECT_NEAR(0.0, m.mean, kSigmas * std::sqrt(1 / 3.0 / n));
  EXPECT_NEAR(1 / 3.0, m.variance, kSigmas * std::sqrt((1 / 5.0 - 1 / 9.0) / n));
  EXPECT_GT(chi2, chi_square_quantile(63, -kSigmas));
  EXPECT_LT(chi2, chi_square_quantile(63, kSigmas));
}

TYPED_TEST(RandomStatistics, NormalMomentsAndKolmogorovSmirnov) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const auto z = draw<Exec, Real>(CellStreams{kSeed, kStep}, kStreams, kPerStream, Draw::normal);
  const double n = static_cast<double>(z.size());
  std::size_t not_finite = 0;
  for (double v : z) not_finite += !std::isfinite(v);
  ASSERT_EQ(not_finite, 0u);
  const Moments m = moments(z);
  const double ks = kolmogorov_smirnov_normal(z);
  const double ks_bound = kolmogorov_smirnov_bound(z.size(), kFiveSigmaTail);
  std::printf(
      "[ stats    ] normal    n=%.0f mean=%.2e var=%.6f m4=%.4f min=%.3f max=%.3f KS D=%.2e (bound "
      "%.2e)\n",
      n, m.mean, m.variance, m.fourth_central, m.min, m.max, ks, ks_bound);
  EXPECT_NEAR(0.0, m.mean, kSigmas / std::sqrt(n));
  EXPECT_NEAR(1.0, m.variance, kSigmas * std::sqrt(2 / n));
  EXPECT_NEAR(3.0, m.fourth_central, kSigmas * std::sqrt(96 / n));
  EXPECT_LT(ks, ks_bound);
}

TYPED_TEST(RandomStatistics, NeighbouringValuesAndStreamsAreUncorrelated) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const auto draw_uniform = [](const auto& make) {
    return draw<Exec, Real>(make, kStreams, kPerStream, Draw::uniform);
  };
  const auto base = draw_uniform(PairStreams{kSeed, kStep, 1, false});  // pair (i, j = i + 1)
  const double bound = kSigmas / std::sqrt(static_cast<double>(base.size()));

  // Consecutive values within a stream (across Philox blocks too).
  std::vector<double> current, next;
  for (int s = 0; s < kStreams; ++s)
    for (int k = 0; k + 1 < kPerStream; ++k) {
      current.push_back(base[s * kPerStream + k]);
      next.push_back(base[s * kPerStream + k + 1]);
    }
  const double r_consecutive = correlation(current, next);
  EXPECT_LT(std::abs(r_consecutive), kSigmas / std::sqrt(static_cast<double>(current.size())));

  // The same draw index of neighbouring keys.
  const struct {
    const char* name;
    std::vector<double> values;
  } neighbours[] = {
      {"pair (i, j+1)", draw_uniform(PairStreams{kSeed, kStep, 2, false})},
      {"step + 1", draw_uniform(PairStreams{kSeed, kStep + 1, 1, false})},
      {"seed + 1", draw_uniform(PairStreams{kSeed + 1, kStep, 1, false})},
      {"particle i", draw_uniform(ParticleStreams{kSeed, kStep})},
      {"cell i", draw_uniform(CellStreams{kSeed, kStep})},
  };
  std::printf("[ stats    ] correlation bound %.2e; consecutive r=%+.2e", bound, r_consecutive);
  for (const auto& neighbour : neighbours) {
    const double r = correlation(base, neighbour.values);
    std::printf("; %s r=%+.2e", neighbour.name, r);
    EXPECT_LT(std::abs(r), bound) << "pair (i, i+1) against " << neighbour.name;
  }
  // Particle i against cell i: streams that differ in their tag only.
  const double r_tags = correlation(neighbours[3].values, neighbours[4].values);
  std::printf("; particle i vs cell i r=%+.2e\n", r_tags);
  EXPECT_LT(std::abs(r_tags), bound);
}

}  // namespace
