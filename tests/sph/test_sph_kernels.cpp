// SPH kernels (kernels/sph): the smoothing kernels integrate to one in 2D and 3D and their
// derivatives match finite differences of W; the Tait equation of state of eq. (6) and the choice
// of c0; the time-step limits; the fused pair loop against an O(N²) evaluation of eqs. (4) and (5)
// (the paper's walls and Morris walls, 2D and 3D); momentum conservation of the pair forces; and on a
// lattice the continuity eq. (4) gives dρ/dt = −ρ∇·u (its sign) and the viscous term of eq. (5)
// gives ν∇²u.
#include "scenes/capsule/sph_system.hpp"
#include "test_types.hpp"

#include <array>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace mesoflow {
namespace {

using namespace sph;

constexpr double pi = 3.14159265358979323846;

// ∫ W dV by the midpoint rule on a Cartesian grid of cell a over the cube [−support, support]^D.
template <int D, class Kernel>
double cartesian_integral(const Kernel& k, int cells_per_support) {
  const double s = double(k.support), a = s / cells_per_support;
  const int m = 2 * cells_per_support;
  double sum = 0;
  if constexpr (D == 2) {
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        const double x = -s + (i + 0.5) * a, y = -s + (j + 0.5) * a;
        sum += k.value(std::sqrt(x * x + y * y));
      }
    return sum * a * a;
  } else {
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j)
        for (int l = 0; l < m; ++l) {
          const double x = -s + (i + 0.5) * a, y = -s + (j + 0.5) * a, z = -s + (l + 0.5) * a;
          sum += k.value(std::sqrt(x * x + y * y + z * z));
        }
    return sum * a * a * a;
  }
}

// ∫ W dV as a radial integral, composite Simpson.
template <int D, class Kernel>
double radial_integral(const Kernel& k, int intervals) {
  const double s = double(k.support), a = s / intervals;
  double sum = 0;
  for (int i = 0; i <= intervals; ++i) {
    const double r = i * a;
    const double shell = D == 2 ? 2 * pi * r : 4 * pi * r * r;
    const double w = i == 0 || i == intervals ? 1 : (i % 2 ? 4 : 2);
    sum += w * shell * k.value(r);
  }
  return sum * a / 3;
}

template <int D, class Kernel>
void expect_normalised(double h) {
  const Kernel k(h);
  const double radial = radial_integral<D>(k, 2000);
  const double cartesian = cartesian_integral<D>(k, D == 2 ? 400 : 80);
  std::cout << "[ measured ] " << Kernel::name << " " << D << "D, h = " << h << ": |∫W dV − 1| radial "
            << std::abs(radial - 1) << ", cartesian " << std::abs(cartesian - 1) << "\n";
  EXPECT_NEAR(radial, 1.0, 1e-4) << Kernel::name << " " << D << "D";
  EXPECT_NEAR(cartesian, 1.0, 1e-4) << Kernel::name << " " << D << "D";
}

TEST(SphSmoothingKernels, IntegrateToOneIn2DAnd3D) {
  for (double h : {0.7, 2.5}) {
    expect_normalised<2, LucyKernel<2, double>>(h);
    expect_normalised<3, LucyKernel<3, double>>(h);
    expect_normalised<2, CubicSplineKernel<2, double>>(h);
    expect_normalised<3, CubicSplineKernel<3, double>>(h);
    expect_normalised<2, WendlandC2Kernel<2, double>>(h);
    expect_normalised<3, WendlandC2Kernel<3, double>>(h);
  }
}

// dW/dr against the central difference of W, (1/r) dW/dr against dW/dr / r, zero at and beyond
// the support, and the float evaluators against the double ones.
template <class Kernel, class KernelF>
void expect_consistent_derivatives(double h) {
  const Kernel k(h);
  const KernelF kf{float(h)};
  const double s = double(k.support), step = 1e-5 * h;
  double max_dw = 0;
  for (int i = 1; i < 400; ++i) max_dw = std::max(max_dw, std::abs(k.derivative(s * i / 400)));
  double fd_error = 0, over_r_error = 0, float_error = 0;
  for (int i = 1; i < 400; ++i) {
    const double r = s * (i - 0.37) / 400;  // avoids the spline's joint at r = h exactly
    const double fd = (k.value(r + step) - k.value(r - step)) / (2 * step);
    fd_error = std::max(fd_error, std::abs(fd - k.derivative(r)) / max_dw);
    over_r_error = std::max(over_r_error, std::abs(k.derivative_over_r(r) * r - k.derivative(r)) / max_dw);
    float_error = std::max(float_error, std::abs(double(kf.derivative(float(r))) - k.derivative(r)) / max_dw);
    float_error = std::max(float_error, std::abs(double(kf.value(float(r))) - k.value(r)) / k.value(0));
  }
  std::cout << "[ measured ] " << Kernel::name << ": max |dW/dr − finite difference| / max |dW/dr| = " << fd_error
            << "\n";
  EXPECT_LT(fd_error, 1e-8) << Kernel::name;
  EXPECT_LT(over_r_error, 1e-14) << Kernel::name;
  EXPECT_LT(float_error, 1e-6) << Kernel::name;
  EXPECT_TRUE(std::isfinite(k.derivative_over_r(0.0)));
  EXPECT_LT(k.derivative_over_r(0.0), 0.0);
  EXPECT_NEAR(k.derivative_over_r(1e-9 * h), k.derivative_over_r(0.0), 1e-6 * std::abs(k.derivative_over_r(0.0)));
  EXPECT_EQ(k.value(s), 0.0);
  EXPECT_EQ(k.derivative(s), 0.0);
  EXPECT_EQ(k.derivative_over_r(s), 0.0);
  EXPECT_EQ(k.value(1.5 * s), 0.0);
  EXPECT_NEAR(k.value(s * (1 - 1e-4)), 0.0, 1e-9 * k.value(0));  // continuous at the support
}

TEST(SphSmoothingKernels, DerivativesMatchFiniteDifferencesOfW) {
  for (double h : {0.5, 3.0}) {
    expect_consistent_derivatives<LucyKernel<3, double>, LucyKernel<3, float>>(h);
    expect_consistent_derivatives<LucyKernel<2, double>, LucyKernel<2, float>>(h);
    expect_consistent_derivatives<CubicSplineKernel<3, double>, CubicSplineKernel<3, float>>(h);
    expect_consistent_derivatives<CubicSplineKernel<2, double>, CubicSplineKernel<2, float>>(h);
    expect_consistent_derivatives<WendlandC2Kernel<3, double>, WendlandC2Kernel<3, float>>(h);
    expect_consistent_derivatives<WendlandC2Kernel<2, double>, WendlandC2Kernel<2, float>>(h);
  }
}

// Lucy's support is h (the paper's and LAMMPS' convention), W(0) = 105/(16π h³) in 3D, 5/(π h²) in
// 2D; the splines' support is 2h.
TEST(SphSmoothingKernels, SupportRadiiAndLucyConstants) {
  using Lucy3 = LucyKernel<3, double>;
  using Lucy2 = LucyKernel<2, double>;
  using Cubic3 = CubicSplineKernel<3, double>;
  using Cubic2 = CubicSplineKernel<2, double>;
  using Wendland3 = WendlandC2Kernel<3, double>;
  using Wendland2 = WendlandC2Kernel<2, double>;
  const double h = 1.3;
  EXPECT_EQ(Lucy3(h).support, h);
  EXPECT_EQ(Cubic3(h).support, 2 * h);
  EXPECT_EQ(Wendland2(h).support, 2 * h);
  EXPECT_NEAR(Lucy3(h).value(0), 105 / (16 * pi * h * h * h), 1e-14);
  EXPECT_NEAR(Lucy2(h).value(0), 5 / (pi * h * h), 1e-14);
  EXPECT_NEAR(Cubic3(h).value(0), 1 / (pi * h * h * h), 1e-14);
  EXPECT_NEAR(Wendland3(h).value(0), 21 / (16 * pi * h * h * h), 1e-14);
  EXPECT_THROW(Lucy3(0.0), std::invalid_argument);
  EXPECT_THROW(Cubic2(-1.0), std::invalid_argument);
  EXPECT_THROW(Wendland3(std::nan("")), std::invalid_argument);
}

// Eq. (6) with γ = 7: p = c0²ρ0/7 [(ρ/ρ0)^7 − 1].
TEST(SphTaitEquationOfState, ValuesOfEquation6) {
  const double rho0 = 1000, c0 = 1.5;
  const TaitEquationOfState<double> eos(rho0, c0);
  EXPECT_EQ(eos.gamma, 7);
  EXPECT_EQ(eos.pressure(rho0), 0.0);
  for (double s : {0.97, 0.999, 1.0001, 1.01, 1.05}) {
    const double expected = c0 * c0 * rho0 / 7 * (std::pow(s, 7) - 1);
    EXPECT_NEAR(eos.pressure(s * rho0), expected, 1e-12 * std::abs(expected)) << s;
    const TaitEquationOfState<float> eos_f(rho0, c0);
    const float rho_f = float(s * rho0);  // the float pressure of the float density
    const double expected_f = c0 * c0 * rho0 / 7 * (std::pow(double(rho_f) / rho0, 7) - 1);
    EXPECT_NEAR(double(eos_f.pressure(rho_f)), expected_f, 2e-6 * std::abs(expected_f)) << s;
  }
  EXPECT_NEAR(eos.pressure(1.01 * rho0), 23.1864, 1e-4);  // 2.25·1000/7·(1.01⁷ − 1)
  EXPECT_LT(eos.pressure(0.99 * rho0), 0.0);
  EXPECT_NEAR(eos.sound_speed(rho0), c0, 1e-15);
  EXPECT_NEAR(eos.sound_speed(1.1 * rho0), c0 * std::pow(1.1, 3), 1e-12);
  // dp/dρ = c² (central difference).
  const double r = 1.02 * rho0, d = 1e-4;
  EXPECT_NEAR((eos.pressure(r + d) - eos.pressure(r - d)) / (2 * d), std::pow(eos.sound_speed(r), 2), 1e-7);
  const TaitEquationOfState<double> linear(rho0, c0, 1);
  EXPECT_NEAR(linear.pressure(1.02 * rho0), c0 * c0 * 0.02 * rho0, 1e-12);
  EXPECT_THROW(TaitEquationOfState<double>(0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(TaitEquationOfState<double>(1.0, -1.0), std::invalid_argument);
  EXPECT_THROW(TaitEquationOfState<double>(1.0, 1.0, 0), std::invalid_argument);
}

// c0 = 10 U_max: a 1% density change already makes a pressure ≥ ρ0 U_max², twice the stagnation
// pressure ½ρ0U² that a flow at U_max can build, so the density varies by less than 1%.
TEST(SphTaitEquationOfState, SpeedOfSoundKeepsDensityVariationsBelowOnePercent) {
  const double u_max = 0.3, rho0 = 1000;
  const double c0 = speed_of_sound_for_velocity(u_max);
  EXPECT_DOUBLE_EQ(c0, 3.0);
  const TaitEquationOfState<double> eos(rho0, c0);
  EXPECT_GT(eos.pressure(1.01 * rho0), rho0 * u_max * u_max);
  EXPECT_LT(-eos.pressure(0.99 * rho0), 1.0 * rho0 * u_max * u_max);  // rarefaction: 0.93 ρ0U²
  EXPECT_GT(-eos.pressure(0.99 * rho0), 0.5 * rho0 * u_max * u_max);
  EXPECT_THROW(speed_of_sound_for_velocity(u_max, 5), std::invalid_argument);
  EXPECT_THROW(speed_of_sound_for_velocity(0.0), std::invalid_argument);
  // Morris et al.: c0² = max(U², νU/L, F L)/δ.
  EXPECT_NEAR(morris_speed_of_sound(1.0, 0.0, 1.0, 0.0), 10.0, 1e-12);
  EXPECT_NEAR(morris_speed_of_sound(0.1, 1.0, 10.0, 0.008), std::sqrt(0.08 / 0.01), 1e-12);
  EXPECT_NEAR(morris_speed_of_sound(0.01, 1.0, 1.0, 0.0), 1.0, 1e-12);
  EXPECT_THROW(morris_speed_of_sound(0.0, 0.0, 1.0, 0.0), std::invalid_argument);
}

TEST(SphTimeStep, LimitsAndTheBindingOne) {
  const auto l = sph_time_step_limits(0.5, 2.0, 10.0, 4.0);
  EXPECT_DOUBLE_EQ(l.viscous, 0.125 * 0.25 / 2.0);
  EXPECT_DOUBLE_EQ(l.acoustic, 0.25 * 0.5 / 10.0);
  EXPECT_DOUBLE_EQ(l.force, 0.25 * std::sqrt(0.5 / 4.0));
  EXPECT_DOUBLE_EQ(l.dt(), l.acoustic);
  EXPECT_STREQ(l.binding(), "acoustic");
  EXPECT_STREQ(sph_time_step_limits(0.5, 20.0, 10.0, 4.0).binding(), "viscous");
  EXPECT_STREQ(sph_time_step_limits(0.5, 0.0, 1.0, 400.0).binding(), "force");
  EXPECT_TRUE(std::isinf(sph_time_step_limits(0.5, 0.0, 1.0, 0.0).viscous));
  SphTimeStepCoefficients paper;
  paper.viscous = 0.5;  // the paper's ζ = 0.125 on h_Lucy = 2 × our h
  EXPECT_DOUBLE_EQ(sph_time_step_limits(0.5, 2.0, 10.0, 4.0, paper).viscous, 0.125 * 1.0 / 2.0);
  EXPECT_DOUBLE_EQ(time_step_length(LucyKernel<3, double>(3.0)), 1.5);
  EXPECT_DOUBLE_EQ(time_step_length(CubicSplineKernel<3, double>(1.5)), 1.5);
  EXPECT_THROW(sph_time_step_limits(0.0, 1.0, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(sph_time_step_limits(1.0, 1.0, 0.0, 1.0), std::invalid_argument);
}

// ---- The pair loop ----------------------------------------------------------------------------------

template <class View>
auto host_copy(const View& v) {
  auto h = Kokkos::create_mirror(Kokkos::HostSpace(), v);
  Kokkos::deep_copy(h, v);
  return h;
}

// A random cloud in a periodic cube of side L at about `per_volume` particles per unit volume,
// Lucy kernel of support h; random masses, densities (±3%), viscosities and velocities; every
// `wall_every`-th particle a wall at rest with a random unit normal and depth (0: no walls).
template <int D, class Real, class Exec>
SphSystem<D, Real, Exec> random_cloud(double L, int n, double h, unsigned seed, int wall_every,
                                      WallVelocity walls = WallVelocity::prescribed,
                                      NeighborListKind list = NeighborListKind::full) {
  SphOptions opt;
  opt.list_kind = list;
  opt.sort_every = 0;  // keep particle order: the tests index particles
  opt.wall_velocity = walls;
  SphSystem<D, Real, Exec> sys(LucyKernel<D, Real>(Real(h)), TaitEquationOfState<Real>(1.0, 5.0),
                               Box<D, Real>::cube(Real(L), true), Real(1e-3), opt);
  sys.allocate(n);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto x = Kokkos::create_mirror_view(sys.particles.x);
  auto v = Kokkos::create_mirror_view(sys.particles.v);
  auto m = Kokkos::create_mirror_view(sys.particles.mass);
  auto type = Kokkos::create_mirror_view(sys.particles.type);
  auto rho = Kokkos::create_mirror_view(sys.rho);
  auto mu = Kokkos::create_mirror_view(sys.mu);
  for (int i = 0; i < n; ++i) {
    const bool wall = wall_every > 0 && i % wall_every == 0;
    type(i) = wall ? particle_type::wall : particle_type::fluid;
    for (int d = 0; d < D; ++d) {
      x(i, d) = Real(L * u(gen));
      v(i, d) = wall ? Real(0) : Real(2 * u(gen) - 1);
    }
    m(i) = Real(0.8 + 0.4 * u(gen));
    rho(i) = Real(0.97 + 0.06 * u(gen));
    mu(i) = Real(0.5 + u(gen));
  }
  Kokkos::deep_copy(sys.particles.x, x);
  Kokkos::deep_copy(sys.particles.v, v);
  Kokkos::deep_copy(sys.particles.mass, m);
  Kokkos::deep_copy(sys.particles.type, type);
  Kokkos::deep_copy(sys.rho, rho);
  Kokkos::deep_copy(sys.mu, mu);
  if (walls == WallVelocity::morris) {
    auto geo = Kokkos::create_mirror_view(sys.wall_geometry);
    for (int i = 0; i < n; ++i) {
      double norm = 0, g[D];
      for (int d = 0; d < D; ++d) {
        g[d] = 2 * u(gen) - 1;
        norm += g[d] * g[d];
      }
      for (int d = 0; d < D; ++d) geo(i, d) = Real(g[d] / std::sqrt(norm));
      geo(i, D) = Real(0.5 * h * u(gen));
    }
    Kokkos::deep_copy(sys.wall_geometry, geo);
  }
  return sys;
}

// Eqs. (4) and (5) for every particle over all pairs (minimum image), in double on the host.
template <int D, class Sys>
void brute_force(const Sys& sys, const BodyForce<D, double>& body, double beta_max, std::vector<double>& f,
                 std::vector<double>& drho) {
  const auto x = host_copy(sys.particles.x);
  const auto v = host_copy(sys.particles.v);
  const auto m = host_copy(sys.particles.mass);
  const auto type = host_copy(sys.particles.type);
  const auto rho = host_copy(sys.rho);
  const auto mu = host_copy(sys.mu);
  const int n = int(x.extent(0));
  const double L = double(sys.box().length[0]);
  const LucyKernel<D, double> k(double(sys.kernel().h));
  const TaitEquationOfState<double> eos(double(sys.equation_of_state().rho0), double(sys.equation_of_state().c0));
  const bool morris = sys.wall_geometry.extent(0) > 0;
  auto geo = Kokkos::create_mirror(Kokkos::HostSpace(), sys.wall_geometry);
  if (morris) Kokkos::deep_copy(geo, sys.wall_geometry);
  f.assign(std::size_t(n) * D, 0.0);
  drho.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    const double pi_ = eos.pressure(double(rho(i)));
    for (int j = 0; j < n; ++j) {
      if (j == i) continue;
      double dr[D], r2 = 0;
      for (int d = 0; d < D; ++d) {
        dr[d] = double(x(i, d)) - double(x(j, d));
        dr[d] -= L * std::round(dr[d] / L);
        r2 += dr[d] * dr[d];
      }
      const double r = std::sqrt(r2);
      if (r >= double(k.support)) continue;
      const double grad = k.derivative(r) / r;  // ∇_i W_ij = grad · dr
      const double pj = eos.pressure(double(rho(j)));
      double uij[D], u_dot_r = 0;
      for (int d = 0; d < D; ++d) {
        uij[d] = double(v(i, d)) - double(v(j, d));
        u_dot_r += uij[d] * dr[d];
      }
      drho[i] += double(m(j)) * u_dot_r * grad;
      double beta = 1;
      if (morris && (type(i) == particle_type::wall) != (type(j) == particle_type::wall)) {
        const int w = type(i) == particle_type::wall ? i : j;
        double offset = 0;
        for (int d = 0; d < D; ++d) offset += (w == i ? -dr[d] : dr[d]) * double(geo(w, d));
        const double d_fluid = offset - double(geo(w, D));
        beta = d_fluid > 0 ? std::min(beta_max, 1 + double(geo(w, D)) / d_fluid) : beta_max;
      }
      const double mm = double(m(i)) * double(m(j));
      const double p_term = mm * (pi_ / (double(rho(i)) * double(rho(i))) + pj / (double(rho(j)) * double(rho(j))));
      const double v_term = mm * (double(mu(i)) + double(mu(j))) / (double(rho(i)) * double(rho(j)));
      for (int d = 0; d < D; ++d) f[std::size_t(i) * D + d] += -p_term * grad * dr[d] + v_term * grad * beta * uij[d];
    }
    if (type(i) == particle_type::fluid)
      for (int d = 0; d < D; ++d) f[std::size_t(i) * D + d] += double(m(i)) * body.g[d];
  }
}

template <class T>
class SphPairTest : public ::testing::Test {};
TYPED_TEST_SUITE(SphPairTest, testing::BackendsAndPrecisions);

template <int D, class Real, class Exec>
void expect_matches_brute_force(WallVelocity walls, NeighborListKind list) {
  const double L = D == 3 ? 6.0 : 9.0, h = 1.6;
  const int n = D == 3 ? 700 : 300;
  auto sys = random_cloud<D, Real, Exec>(L, n, h, 11, 4, walls, list);
  BodyForce<D, Real> body;
  BodyForce<D, double> body_d;
  for (int d = 0; d < D; ++d) {
    body.g[d] = Real(0.1 * (d + 1));
    body_d.g[d] = double(body.g[d]);
  }
  sys.set_body_force(body);
  sys.begin();
  std::vector<double> f_ref, drho_ref;
  brute_force<D>(sys, body_d, SphOptions().beta_max, f_ref, drho_ref);
  const auto f = host_copy(sys.particles.f);
  const auto drho = host_copy(sys.drho);
  double f_scale = 0, rate_scale = 0, f_err = 0, rate_err = 0;
  for (int i = 0; i < n; ++i) {
    rate_scale = std::max(rate_scale, std::abs(drho_ref[i]));
    rate_err = std::max(rate_err, std::abs(double(drho(i)) - drho_ref[i]));
    for (int d = 0; d < D; ++d) {
      f_scale = std::max(f_scale, std::abs(f_ref[std::size_t(i) * D + d]));
      f_err = std::max(f_err, std::abs(double(f(i, d)) - f_ref[std::size_t(i) * D + d]));
    }
  }
  const double tol = 200 * testing::eps<Real>();
  EXPECT_GT(f_scale, 1.0);
  EXPECT_GT(rate_scale, 1.0);
  const char* kind = list == NeighborListKind::half ? "half" : "full";
  EXPECT_LT(f_err / f_scale, tol) << D << "D, " << kind << " list";
  EXPECT_LT(rate_err / rate_scale, tol) << D << "D, " << kind << " list";
}

// The fused loop over a full or a half list gives eqs. (4)–(5) plus the body force, as an
// all-pairs sum does: walls at rest, the paper's walls and Morris walls, 3D and 2D.
TYPED_TEST(SphPairTest, MatchesAllPairsEvaluationOfEquations4And5) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  for (auto list : {NeighborListKind::full, NeighborListKind::half}) {
    expect_matches_brute_force<3, Real, Exec>(WallVelocity::prescribed, list);
    expect_matches_brute_force<3, Real, Exec>(WallVelocity::morris, list);
    expect_matches_brute_force<2, Real, Exec>(WallVelocity::prescribed, list);
    expect_matches_brute_force<2, Real, Exec>(WallVelocity::morris, list);
  }
}

// Σ_i f_i = 0 for a random cloud without walls and body force (random masses, densities,
// viscosities, velocities), relative to Σ|f|; and with Morris walls, whose wall particles take
// the reaction.
TYPED_TEST(SphPairTest, PairForcesConserveMomentum) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  for (auto list : {NeighborListKind::full, NeighborListKind::half}) {
    for (auto walls : {WallVelocity::prescribed, WallVelocity::morris}) {
      const int n = 1000;
      auto sys = random_cloud<3, Real, Exec>(7.0, n, 1.6, 5, walls == WallVelocity::morris ? 3 : 0, walls, list);
      sys.begin();
      const auto f = host_copy(sys.particles.f);
      double sum[3] = {0, 0, 0}, magnitude = 0;
      for (int i = 0; i < n; ++i)
        for (int d = 0; d < 3; ++d) {
          sum[d] += double(f(i, d));
          magnitude += std::abs(double(f(i, d)));
        }
      double worst = 0;
      for (int d = 0; d < 3; ++d) worst = std::max(worst, std::abs(sum[d]) / magnitude);
      std::cout << "[ measured ] |Σ f| / Σ|f| = " << worst << (walls == WallVelocity::morris ? " (Morris walls)" : "")
                << " (" << (sizeof(Real) == 4 ? "float" : "double") << ")\n";
      EXPECT_GT(magnitude, 1.0);
      EXPECT_LT(worst, 16 * testing::eps<Real>());
    }
  }
}

// A simple cubic lattice of spacing 1, 13³ particles, open boundaries; the centre particle sees a
// full Lucy support of 3 spacings. Velocity u(x) given per particle, ρ = ρ0 = m = 1, μ.
template <class Velocity>
SphSystem<3, double, Kokkos::DefaultHostExecutionSpace> lattice(double mu, Velocity&& velocity, int& centre) {
  using Exec = Kokkos::DefaultHostExecutionSpace;
  const int m = 13;
  const double lo[3] = {-7, -7, -7}, len[3] = {14, 14, 14};
  const bool periodic[3] = {false, false, false};
  SphOptions opt;
  opt.sort_every = 0;
  SphSystem<3, double, Exec> sys(LucyKernel<3, double>(3.0), TaitEquationOfState<double>(1.0, 10.0),
                                 Box<3, double>(lo, len, periodic), 1e-3, opt);
  sys.allocate(m * m * m);
  auto x = Kokkos::create_mirror_view(sys.particles.x);
  auto v = Kokkos::create_mirror_view(sys.particles.v);
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b)
      for (int c = 0; c < m; ++c) {
        const int i = (a * m + b) * m + c;
        const double p[3] = {a - 6.0, b - 6.0, c - 6.0};
        for (int d = 0; d < 3; ++d) x(i, d) = p[d];
        const auto u = velocity(p);
        for (int d = 0; d < 3; ++d) v(i, d) = u[d];
      }
  centre = (6 * m + 6) * m + 6;
  Kokkos::deep_copy(sys.particles.x, x);
  Kokkos::deep_copy(sys.particles.v, v);
  Kokkos::deep_copy(sys.mu, mu);
  sys.begin();
  return sys;
}

// Eq. (4) with the plus sign: for u = A x, dρ/dt = −ρ0 tr A (eq. 1, compression raises density);
// the paper's printed minus sign would give +ρ0 tr A.
TEST(SphContinuityDensity, RateIsMinusRhoTimesDivergence) {
  const double A[3][3] = {{0.3, 0.1, -0.2}, {0.05, -0.7, 0.4}, {0.2, 0.3, -0.1}};  // tr A = −0.5
  int centre = 0;
  auto sys = lattice(0.0, [&](const double (&p)[3]) {
    std::array<double, 3> u{};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) u[r] += A[r][c] * p[c];
    return u;
  }, centre);
  const auto drho = host_copy(sys.drho);
  std::cout << "[ measured ] lattice dρ/dt = " << drho(centre) << " against −ρ0 ∇·u = 0.5\n";
  EXPECT_NEAR(drho(centre), 0.5, 0.01 * 0.5);
}

// The viscous term of eq. (5) for u = (γ z², 0, 0): f_x/m = ν ∇²u_x = 2νγ, no other component.
TEST(SphPressureViscousForce, ViscousTermIsNuLaplacianOnALattice) {
  const double mu = 0.7, gamma = 0.2;
  int centre = 0;
  auto sys = lattice(mu, [&](const double (&p)[3]) { return std::array<double, 3>{gamma * p[2] * p[2], 0, 0}; },
                     centre);
  const auto f = host_copy(sys.particles.f);
  std::cout << "[ measured ] lattice viscous acceleration = " << f(centre, 0) << " against ν∇²u = " << 2 * mu * gamma
            << "\n";
  EXPECT_NEAR(f(centre, 0), 2 * mu * gamma, 0.01 * 2 * mu * gamma);
  EXPECT_NEAR(f(centre, 1), 0.0, 1e-12);
  EXPECT_NEAR(f(centre, 2), 0.0, 1e-12);
}

}  // namespace
}  // namespace mesoflow
