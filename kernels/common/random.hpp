// random.hpp — counter-based random numbers for kernels: Philox4x32-10 keyed on (seed, step, ids).
//
// Every random number in a time step is a pure function of (seed, step, stream tag, ids, draw
// index), so results do not depend on the thread count, the execution order or the backend, and a
// pair's noise is symmetric by construction (HOOMD-blue's RandomGenerator convention). The
// Kokkos::Random_XorShift64_Pool helper at the end is for initial conditions only.
#pragma once

#include "kernel_launch.hpp"
#include "kokkos_compat.hpp"

#include <Kokkos_Random.hpp>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <type_traits>

namespace mesoflow {

struct PhiloxCounter {
  std::uint32_t v[4];
};

struct PhiloxKey {
  std::uint32_t v[2];
};

// Philox4x32-10: Salmon, Moraes, Dror & Shaw, "Parallel random numbers: as easy as 1, 2, 3",
// SC'11 (2011), doi:10.1145/2063384.2063405. Bit-identical to Random123's philox4x32_R(10, ...).
KOKKOS_INLINE_FUNCTION PhiloxCounter philox4x32_10(PhiloxCounter ctr, PhiloxKey key) {
  constexpr std::uint32_t multiplier0 = 0xD2511F53u;
  constexpr std::uint32_t multiplier1 = 0xCD9E8D57u;
  constexpr std::uint32_t weyl0 = 0x9E3779B9u;
  constexpr std::uint32_t weyl1 = 0xBB67AE85u;
  for (int round = 0; round < 10; ++round) {
    if (round > 0) {
      key.v[0] += weyl0;
      key.v[1] += weyl1;
    }
    const std::uint64_t product0 = static_cast<std::uint64_t>(multiplier0) * ctr.v[0];
    const std::uint64_t product1 = static_cast<std::uint64_t>(multiplier1) * ctr.v[2];
    const PhiloxCounter next = {{static_cast<std::uint32_t>(product1 >> 32) ^ ctr.v[1] ^ key.v[0],
                                 static_cast<std::uint32_t>(product1),
                                 static_cast<std::uint32_t>(product0 >> 32) ^ ctr.v[3] ^ key.v[1],
                                 static_cast<std::uint32_t>(product0)}};
    ctr = next;
  }
  return ctr;
}

// Stream tags: which kind of object a stream belongs to. They are folded into the counter, so the
// pair (i, j), the cell i and the particle i never share numbers. Tags are 8 bits; values from
// `user` on are free for other purposes (one per kernel that needs its own noise).
namespace stream_tag {
constexpr std::uint32_t pair = 1;
constexpr std::uint32_t cell = 2;
constexpr std::uint32_t particle = 3;
constexpr std::uint32_t initial_condition = 4;
constexpr std::uint32_t user = 16;
}  // namespace stream_tag

// Floating-point numbers from random bits. Only the top p bits of `bits` are used, p = 24 for
// float and 53 for double, so every result is exact (no rounding towards an end point).

// (0, 1]: (k + 1) 2^-p for the top-bits integer k (Random123's u01 convention). Never 0, so
// log() of it is finite.
template <class Real>
KOKKOS_INLINE_FUNCTION Real uniform_from_bits(std::uint64_t bits) {
  static_assert(std::is_same<Real, float>::value || std::is_same<Real, double>::value,
                "uniform_from_bits: float or double");
  if constexpr (std::is_same<Real, float>::value) {
    return static_cast<float>((bits >> 40) + 1) * 0x1p-24f;
  } else {
    return static_cast<double>((bits >> 11) + 1) * 0x1p-53;
  }
}

// (-1, 1): (2k + 1 - 2^p) 2^-p. Open at both ends and symmetric: flipping every bit negates the
// result, so the distribution has mean exactly 0.
template <class Real>
KOKKOS_INLINE_FUNCTION Real symmetric_from_bits(std::uint64_t bits) {
  static_assert(std::is_same<Real, float>::value || std::is_same<Real, double>::value,
                "symmetric_from_bits: float or double");
  if constexpr (std::is_same<Real, float>::value) {
    const std::int32_t odd =
        2 * static_cast<std::int32_t>(bits >> 40) + 1 - (std::int32_t(1) << 24);
    return static_cast<float>(odd) * 0x1p-24f;
  } else {
    const std::int64_t odd =
        2 * static_cast<std::int64_t>(bits >> 11) + 1 - (std::int64_t(1) << 53);
    return static_cast<double>(odd) * 0x1p-53;
  }
}

// A short random sequence identified by (seed, step, tag, a, b). Packing (documented because
// results of published runs depend on it):
//   key     = (seed bits 0-31, seed bits 32-63)
//   counter = (a, b, step bits 0-31, step bits 32-39 << 24 | tag << 16 | block)
// `block` counts the Philox calls of this stream; each yields four 32-bit words, used in order.
// Limits: ids a, b < 2^32; step is taken modulo 2^40; tag < 256; at most 2^16 blocks (2^18 words)
// per stream. The object is cheap to construct: make one per (pair, cell, particle) in the kernel
// and let it go out of scope; never share one across threads.
class RandomStream {
 public:
  KOKKOS_INLINE_FUNCTION RandomStream(std::uint64_t seed, std::uint64_t step, std::uint32_t tag,
                                      std::uint32_t a, std::uint32_t b = 0)
      : key_{{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}},
        counter_{
            {a, b, static_cast<std::uint32_t>(step),
             ((static_cast<std::uint32_t>(step >> 32) & 0xFFu) << 24) | ((tag & 0xFFu) << 16)}} {}

  // The next 32 random bits.
  KOKKOS_INLINE_FUNCTION std::uint32_t next_u32() {
    if (used_ == 4) {
      PhiloxCounter ctr = counter_;
      ctr.v[3] |= block_ & 0xFFFFu;
      words_ = philox4x32_10(ctr, key_);
      ++block_;
      used_ = 0;
    }
    return words_.v[used_++];
  }

  // The next 64 random bits: two consecutive words, the first in the high half.
  KOKKOS_INLINE_FUNCTION std::uint64_t next_u64() {
    const std::uint64_t high = next_u32();
    return (high << 32) | next_u32();
  }

  // Uniform in (0, 1]; uses one word for float, two for double.
  template <class Real>
  KOKKOS_INLINE_FUNCTION Real uniform() {
    return uniform_from_bits<Real>(next_bits<Real>());
  }

  // Uniform in (-1, 1), symmetric about 0 (the DPD random-force weight); the same words as
  // uniform().
  template <class Real>
  KOKKOS_INLINE_FUNCTION Real uniform_symmetric() {
    return symmetric_from_bits<Real>(next_bits<Real>());
  }

  // Uniform in [lo, hi) for lo < hi, as for a coordinate in a periodic box. lo + (hi - lo) u can
  // round up to hi; that case returns lo, its periodic image.
  template <class Real>
  KOKKOS_INLINE_FUNCTION Real uniform_in(Real lo, Real hi) {
    const Real x = lo + (hi - lo) * (Real(1) - uniform<Real>());
    return x < hi ? x : lo;
  }

  // Standard normal deviate by the Box–Muller transform. Each transform gives two deviates; the
  // second is kept and returned by the next call (in whichever precision that call asks for).
  // Tails are cut at sqrt(-2 ln 2^-p): |z| <= 5.77 for float, 8.57 for double.
  template <class Real>
  KOKKOS_INLINE_FUNCTION Real normal() {
    if (has_spare_normal_) {
      has_spare_normal_ = false;
      return static_cast<Real>(spare_normal_);
    }
    const Real radius = kmath::sqrt(Real(-2) * kmath::log(uniform<Real>()));
    const Real angle = Real(6.283185307179586476925) * uniform<Real>();
    spare_normal_ = radius * kmath::sin(angle);
    has_spare_normal_ = true;
    return radius * kmath::cos(angle);
  }

 private:
  template <class Real>
  KOKKOS_INLINE_FUNCTION std::uint64_t next_bits() {
    if constexpr (std::is_same<Real, float>::value) {
      return static_cast<std::uint64_t>(next_u32()) << 32;
    } else {
      return next_u64();
    }
  }

  PhiloxKey key_;
  PhiloxCounter counter_;
  PhiloxCounter words_ = {{0, 0, 0, 0}};
  std::uint32_t block_ = 0;
  int used_ = 4;
  bool has_spare_normal_ = false;
  double spare_normal_ = 0;
};

// Noise shared by the pair (i, j): keyed on (min, max), so pair_stream(s, t, i, j) and
// pair_stream(s, t, j, i) give the same sequence (a full neighbor list sees both orders).
KOKKOS_INLINE_FUNCTION RandomStream pair_stream(std::uint64_t seed, std::uint64_t step,
                                                std::uint32_t i, std::uint32_t j) {
  return RandomStream(seed, step, stream_tag::pair, i < j ? i : j, i < j ? j : i);
}

// The first number of pair_stream(seed, step, i, j).uniform_symmetric<Real>(), from a single
// Philox call without the stream's bookkeeping: the DPD random force needs one number per pair.
template <class Real>
KOKKOS_INLINE_FUNCTION Real pair_uniform_symmetric(std::uint64_t seed, std::uint64_t step, std::uint32_t i,
                                                   std::uint32_t j) {
  const PhiloxKey key = {{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}};
  const PhiloxCounter ctr = {{i < j ? i : j, i < j ? j : i, static_cast<std::uint32_t>(step),
                              ((static_cast<std::uint32_t>(step >> 32) & 0xFFu) << 24) | (stream_tag::pair << 16)}};
  const PhiloxCounter w = philox4x32_10(ctr, key);
  const std::uint64_t bits = (static_cast<std::uint64_t>(w.v[0]) << 32) | w.v[1];
  return symmetric_from_bits<Real>(bits);
}

// Noise of one collision cell (MPC rotation axis and angle sign, cell thermostat), keyed on the
// global cell index so it does not depend on how cells are distributed over threads.
KOKKOS_INLINE_FUNCTION RandomStream cell_stream(std::uint64_t seed, std::uint64_t step,
                                                std::uint32_t cell_index) {
  return RandomStream(seed, step, stream_tag::cell, cell_index);
}

// Noise of one particle (Langevin and Andersen thermostats, Brownian displacements).
KOKKOS_INLINE_FUNCTION RandomStream particle_stream(std::uint64_t seed, std::uint64_t step,
                                                    std::uint32_t i) {
  return RandomStream(seed, step, stream_tag::particle, i);
}

// x(i, d) uniform in [lo[d], hi[d]) for an (n × D) View, drawn from the counter-based stream
// (seed, step 0, initial_condition, i, field): the same array at any thread count and on any
// backend. Use a different `field` for each quantity filled from one seed (positions,
// velocities, ...) so they are independent. This is what drivers use for initial conditions.
template <class View, class Real, std::size_t D>
void fill_uniform_counter(const View& x, const Real (&lo)[D], const Real (&hi)[D],
                          std::uint64_t seed, std::uint32_t field = 0) {
  static_assert(View::rank == 2, "fill_uniform_counter: an (n x D) View");
  using value_type = typename View::non_const_value_type;
  if (x.extent(1) != D) throw std::invalid_argument("fill_uniform_counter: extent(1) != D");
  Kokkos::Array<value_type, D> lower, upper;
  for (std::size_t d = 0; d < D; ++d) {
    lower[d] = static_cast<value_type>(lo[d]);
    upper[d] = static_cast<value_type>(hi[d]);
  }
  mesoflow::launch::parallel_for(
      "mesoflow::random::fill_uniform_counter",
      Kokkos::RangePolicy<typename View::execution_space>(0, x.extent(0)),
      KOKKOS_LAMBDA(const std::size_t i) {
        RandomStream rs(seed, 0, stream_tag::initial_condition, static_cast<std::uint32_t>(i),
                        field);
        for (std::size_t d = 0; d < D; ++d) x(i, d) = rs.uniform_in<value_type>(lower[d], upper[d]);
      });
}

// v uniform between lo and hi (rank 1 or 2) from a Kokkos::Random_XorShift64_Pool. Which pool state a
// row draws from depends on the thread that runs it, so the values change with the thread count
// (and backend): for throw-away setup only. Reproducible runs use fill_uniform_counter.
template <class View>
void fill_uniform(const View& v, typename View::const_value_type lo,
                  typename View::const_value_type hi, std::uint64_t seed) {
  static_assert(View::rank == 1 || View::rank == 2, "fill_uniform: a rank-1 or rank-2 View");
  using exec = typename View::execution_space;
  using value_type = typename View::non_const_value_type;
  using pool_type = Kokkos::Random_XorShift64_Pool<exec>;
  using draw_type = Kokkos::rand<typename pool_type::generator_type, value_type>;
  pool_type pool(seed);
  mesoflow::launch::parallel_for(
      "mesoflow::random::fill_uniform", Kokkos::RangePolicy<exec>(0, v.extent(0)),
      KOKKOS_LAMBDA(const std::size_t i) {
        auto generator = pool.get_state();
        // Captured here: nvcc rejects a lambda whose first use of a captured variable is inside
        // `if constexpr`.
        const View& w = v;
        const auto a = lo, b = hi;
        if constexpr (View::rank == 1) {
          w(i) = draw_type::draw(generator, a, b);
        } else {
          for (std::size_t d = 0; d < w.extent(1); ++d)
            w(i, d) = draw_type::draw(generator, a, b);
        }
        pool.free_state(generator);
      });
}

}  // namespace mesoflow
