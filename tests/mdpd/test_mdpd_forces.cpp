// MDPD pair forces (kernels/mdpd): the conservative force of eq. (9a) is minus the gradient of its
// potential (normalized density weight), the density weights integrate to one, Newton's third law
// holds to round-off with every term on (random and dissipative forces, WCA cores), half and full
// neighbor lists give the same forces, the random force is pairwise symmetric and reproducible, a
// zero coefficient removes its term, and the Lucy density matches LAMMPS' mdpd/rhosum formula: no
// self term unless asked for (issue 28, item 6); densities and the conservative virial of a random
// configuration against a brute-force sum over all pairs.
#include "finite_difference.hpp"
#include "kernels/mdpd/conservative_virial.hpp"
#include "scenes/pillars/mdpd_system.hpp"
#include "test_types.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace mesoflow {
namespace {

using mdpd::MdpdParameters;
using mdpd::MdpdSystem;

template <int D, class Real, class Exec>
MdpdSystem<D, Real, Exec> random_system(const MdpdParameters& par, double L, int n, unsigned seed,
                                        NeighborListKind kind, double k_S = 12.5) {
  mdpd::MdpdOptions opt;
  opt.list_kind = kind;
  opt.sort_every = 0;  // keep particle order: the tests index particles
  opt.k_S = k_S;
  MdpdSystem<D, Real, Exec> sys(par, Box<D, Real>::cube(Real(L), true), 99, opt);
  sys.allocate(n);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(0.0, L), g(-1.0, 1.0);
  auto x = Kokkos::create_mirror_view(sys.particles.x);
  auto v = Kokkos::create_mirror_view(sys.particles.v);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < D; ++d) {
      x(i, d) = Real(u(gen));
      v(i, d) = Real(g(gen));
    }
  Kokkos::deep_copy(sys.particles.x, x);
  Kokkos::deep_copy(sys.particles.v, v);
  return sys;
}

// U = Σ_{i<j} ½ A r_A w_A² + Σ_i ψ(ρ̄_i) on the host, all pairs (minimum image).
template <int D, class View>
double conservative_energy(const View& x, const MdpdParameters& par, double L) {
  const auto pot = mdpd::ConservativePotential::make<D>(par);
  const mdpd::DensityWeight<D, double> w(mdpd::DensityKernel::normalized, par.r_B);
  const int n = int(x.extent(0));
  std::vector<double> rho(n, 0.0);
  double u = 0;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      double r2 = 0;
      for (int d = 0; d < D; ++d) {
        double dx = double(x(i, d)) - double(x(j, d));
        dx -= L * std::round(dx / L);
        r2 += dx * dx;
      }
      const double r = std::sqrt(r2);
      u += pot.pair(r);
      if (r < par.r_B) {
        rho[i] += w(r);
        rho[j] += w(r);
      }
    }
  for (int i = 0; i < n; ++i) u += pot.many_body(rho[i]);
  return u;
}

template <int D>
void check_conservative_gradient(NeighborListKind kind) {
  using Exec = Kokkos::DefaultExecutionSpace;
  MdpdParameters par;
  par.R = 0;  // conservative forces only
  if (D == 2) par.B = 30;
  const double L = 3.0;
  const int n = D == 2 ? 54 : 162;  // ρ = 6
  auto sys = random_system<D, double, Exec>(par, L, n, 5, kind);
  auto energy = [&] {
    sys.begin();
    const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sys.particles.x);
    return conservative_energy<D>(x, par, L);
  };
  const auto c = testing::check_gradient(sys.particles, energy, 1e-6);
  EXPECT_GT(c.max_force, 1.0);
  EXPECT_LT(c.max_error, 1e-6) << "max |F_fd - F| / max |F|, " << D << "D";
}

TEST(MdpdConservativeForce, IsMinusTheGradientOfItsPotential3D) {
  check_conservative_gradient<3>(NeighborListKind::half);
  check_conservative_gradient<3>(NeighborListKind::full);
}
TEST(MdpdConservativeForce, IsMinusTheGradientOfItsPotential2D) {
  check_conservative_gradient<2>(NeighborListKind::half);
  check_conservative_gradient<2>(NeighborListKind::full);
}

// ∫ w_ρ dV = 1 for the normalized weight (2D and 3D); the Lucy weight too. The self term is off
// unless asked for (LAMMPS' pair_mdpd_rhosum.cpp starts every ρ_i from zero); on, it is w(0):
// 105/(16π h³) (3D Lucy), 5/(π h²) (2D Lucy), the prefactor of the normalized weight.
TEST(MdpdDensityWeight, IntegratesToOne) {
  const double h = 0.75, pi = 3.14159265358979323846;
  for (auto kernel : {mdpd::DensityKernel::normalized, mdpd::DensityKernel::lucy}) {
    const mdpd::DensityWeight<3, double> w3(kernel, h);
    const mdpd::DensityWeight<2, double> w2(kernel, h);
    double i3 = 0, i2 = 0;
    const int m = 200000;
    for (int k = 0; k < m; ++k) {
      const double r = (k + 0.5) * h / m;
      i3 += 4 * pi * r * r * w3(r) * h / m;
      i2 += 2 * pi * r * w2(r) * h / m;
    }
    EXPECT_NEAR(i3, 1.0, 1e-9);
    EXPECT_NEAR(i2, 1.0, 1e-9);
  }
  using Weight3 = mdpd::DensityWeight<3, double>;
  using Weight2 = mdpd::DensityWeight<2, double>;
  const auto on = mdpd::DensitySelfTerm::on;
  EXPECT_EQ(Weight3(mdpd::DensityKernel::lucy, h).self, 0.0);
  EXPECT_EQ(Weight2(mdpd::DensityKernel::lucy, h).self, 0.0);
  EXPECT_EQ(Weight3(mdpd::DensityKernel::normalized, h).self, 0.0);
  EXPECT_EQ(Weight2(mdpd::DensityKernel::normalized, h).self, 0.0);
  EXPECT_NEAR(Weight3(mdpd::DensityKernel::lucy, h, on).self, 105 / (16 * pi * h * h * h), 1e-12);
  EXPECT_NEAR(Weight2(mdpd::DensityKernel::lucy, h, on).self, 5 / (pi * h * h), 1e-12);
  EXPECT_NEAR(Weight3(mdpd::DensityKernel::normalized, h, on).self, 15 / (2 * pi * h * h * h), 1e-12);
  EXPECT_NEAR(Weight2(mdpd::DensityKernel::normalized, h, on).self, 6 / (pi * h * h), 1e-12);
  EXPECT_EQ(MdpdParameters{}.density_self_term, mdpd::DensitySelfTerm::off);
}

template <class T>
class MdpdPairTest : public ::testing::Test {};
TYPED_TEST_SUITE(MdpdPairTest, testing::BackendsAndPrecisions);

// Σ_i F_i = 0 with conservative, dissipative, random and WCA core forces on (tethers off: they are
// external), relative to Σ|F|: 64 ε.
TYPED_TEST(MdpdPairTest, NewtonsThirdLawToRoundOff) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  for (auto kind : {NeighborListKind::half, NeighborListKind::full}) {
    MdpdParameters par;
    auto sys = random_system<3, Real, Exec>(par, 4.0, 384, 7, kind, 0.0);
    auto type = Kokkos::create_mirror_view(sys.particles.type);
    for (int i = 0; i < 384; ++i) type(i) = i % 5 == 0 ? mdpd::particle_type::solid_core : (i % 5 == 1 ? 1 : 0);
    Kokkos::deep_copy(sys.particles.type, type);
    sys.begin();
    ASSERT_TRUE(sys.has_core());
    const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sys.particles.f);
    double sum[3] = {0, 0, 0}, magnitude = 0;
    for (int i = 0; i < 384; ++i)
      for (int d = 0; d < 3; ++d) {
        sum[d] += double(f(i, d));
        magnitude += std::abs(double(f(i, d)));
      }
    for (int d = 0; d < 3; ++d) EXPECT_LT(std::abs(sum[d]), 64 * testing::eps<Real>() * magnitude) << d;
  }
}

// Half and full lists: same densities and forces (the noise is keyed on the pair, not the list).
TYPED_TEST(MdpdPairTest, HalfAndFullListsAgree) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  MdpdParameters par;
  auto half = random_system<2, Real, Exec>(par, 5.0, 150, 3, NeighborListKind::half);
  auto full = random_system<2, Real, Exec>(par, 5.0, 150, 3, NeighborListKind::full);
  half.begin();
  full.begin();
  const auto fh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), half.particles.f);
  const auto ff = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), full.particles.f);
  const auto rh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), half.rho);
  const auto rf = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), full.rho);
  double scale = 0;
  for (int i = 0; i < 150; ++i)
    for (int d = 0; d < 2; ++d) scale = std::max(scale, std::abs(double(ff(i, d))));
  for (int i = 0; i < 150; ++i) {
    EXPECT_NEAR(double(rh(i)), double(rf(i)), 64 * testing::eps<Real>() * 10) << i;
    for (int d = 0; d < 2; ++d) EXPECT_NEAR(double(fh(i, d)), double(ff(i, d)), 256 * testing::eps<Real>() * scale) << i;
  }
}

// Two particles: the random force is equal and opposite, changes from step to step, and the same
// seed and step reproduce it; its variance matches R² w_R²/dt · (one uniform variable of variance 1).
TEST(MdpdRandomForce, PairwiseSymmetricAndUnitVariance) {
  MdpdParameters par;
  const mdpd::DissipativeRandomForce<double> thermo(par, 11);
  const double r = 0.4, w = 1 - r;
  double sum = 0, sum2 = 0;
  const int m = 200000;
  for (int s = 0; s < m; ++s) {
    const double a = thermo.magnitude(r, 0.0, std::uint64_t(s), 3, 8);
    EXPECT_EQ(a, thermo.magnitude(r, 0.0, std::uint64_t(s), 8, 3));
    sum += a;
    sum2 += a * a;
  }
  const double mean = sum / m, var = sum2 / m - mean * mean;
  const double expected = par.R * par.R * w * w / par.dt;
  EXPECT_NEAR(mean, 0.0, 5 * std::sqrt(expected / m));
  EXPECT_NEAR(var / expected, 1.0, 0.01);  // standard error of the variance of a uniform: 0.0017
  // The dissipative part: −D w² (v·r̂) with D = R²/(2kT) = 72.
  EXPECT_NEAR(thermo.magnitude(r, 1.0, 0, 3, 8) - thermo.magnitude(r, 0.0, 0, 3, 8), -72 * w * w, 1e-12);
}

// The single-draw pair noise is the first number of the general pair stream.
TEST(MdpdRandomForce, SingleDrawMatchesPairStream) {
  for (std::uint32_t i = 0; i < 50; ++i) {
    auto s = pair_stream(77, 1234567890123ull, i, 1000 - i);
    EXPECT_EQ(pair_uniform_symmetric<double>(77, 1234567890123ull, i, 1000 - i), s.uniform_symmetric<double>());
    auto t = pair_stream(77, 5, 1000 - i, i);
    EXPECT_EQ(pair_uniform_symmetric<float>(77, 5, i, 1000 - i), t.uniform_symmetric<float>());
  }
}

// R = 0 compiles the thermostat out: forces do not depend on velocities. The two evaluations are
// compared bit for bit, so on a device backend the forces are summed in the deterministic-sum mode
// (full lists, testing::reproducible_by_default): a half list's atomic scatter differed in the last
// bits between the two evaluations on the H200 (2026-11-28).
TEST(MdpdPairForce, ZeroThermostatCoefficientsRemoveTheTerm) {
  using Exec = Kokkos::DefaultExecutionSpace;
  MdpdParameters par;
  par.R = 0;
  const auto kind = testing::reproducible_by_default<Exec>() ? NeighborListKind::half : NeighborListKind::full;
  auto a = random_system<3, double, Exec>(par, 3.0, 162, 2, kind);
  a.begin();
  const auto f0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.particles.f);
  Kokkos::deep_copy(a.particles.v, 5.0);
  a.begin();
  const auto f1 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.particles.f);
  for (int i = 0; i < 162; ++i)
    for (int d = 0; d < 3; ++d) EXPECT_EQ(f0(i, d), f1(i, d));
}

// Lucy density of LAMMPS' mdpd/rhosum: a pair at r = h/2 in 3D gives ρ = w(h/2) by default, as
// LAMMPS (rho[i] = 0, then Σ_{j≠i} w), w(r) = 105/(16π h³)(1 + 3r/h)(1 − r/h)³; with the self
// term on, ρ = w(0) + w(h/2).
TEST(MdpdDensityWeight, LucyPairDensityMatchesLammpsFormula) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const double pi = 3.14159265358979323846, h = 0.75, c = 105 / (16 * pi * h * h * h);
  const double pair = c * (1 + 1.5) * 0.125;
  for (const bool self : {false, true}) {
    MdpdParameters par;
    par.density_kernel = mdpd::DensityKernel::lucy;
    if (self) par.density_self_term = mdpd::DensitySelfTerm::on;
    par.R = 0;
    mdpd::MdpdOptions opt;
    opt.sort_every = 0;
    MdpdSystem<3, double, Exec> sys(par, Box<3, double>::cube(4.0, true), 1, opt);
    sys.allocate(2);
    auto x = Kokkos::create_mirror_view(sys.particles.x);
    x(0, 0) = 1.0;
    x(1, 0) = 1.0 + 0.375;
    Kokkos::deep_copy(sys.particles.x, x);
    sys.begin();
    const auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sys.rho);
    const double expected = (self ? c : 0.0) + pair;
    EXPECT_NEAR(rho(0), expected, 1e-12) << "self term " << (self ? "on" : "off");
    EXPECT_NEAR(rho(1), expected, 1e-12) << "self term " << (self ? "on" : "off");
  }
}

// ρ̄_i of a random configuration (ρ = 6, periodic) against a brute-force host sum over all pairs
// under the minimum image with the weights written out (not DensityWeight): both kernels, both
// lists, 3D and 2D, with and without the self term; the default parameters give no self term. The
// conservative virial Σ_{i<j} r f^C(r) against the same brute-force pairs.
template <int D>
void check_density_brute_force(mdpd::DensityKernel kernel, mdpd::DensitySelfTerm self, bool use_defaults,
                               NeighborListKind kind) {
  using Exec = Kokkos::DefaultExecutionSpace;
  MdpdParameters par;
  par.R = 0;
  par.density_kernel = kernel;
  if (!use_defaults) par.density_self_term = self;
  if (D == 2) par.B = 30;
  const double L = 3.0, pi = 3.14159265358979323846, h = par.r_B;
  const int n = D == 2 ? 54 : 162;
  auto sys = random_system<D, double, Exec>(par, L, n, 11, kind);
  sys.begin();
  const bool lucy = kernel == mdpd::DensityKernel::lucy;
  const double hd = D == 2 ? h * h : h * h * h;
  const double c = (lucy ? (D == 2 ? 5 / pi : 105 / (16 * pi)) : (D == 2 ? 6 / pi : 15 / (2 * pi))) / hd;
  const auto w = [&](double r) {
    const double s = 1 - r / h;
    return lucy ? c * (1 + 3 * r / h) * s * s * s : c * s * s;
  };
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sys.particles.x);
  const double self_weight = self == mdpd::DensitySelfTerm::on ? c : 0.0;
  std::vector<double> rho(n, self_weight), dist;
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      double r2 = 0;
      for (int d = 0; d < D; ++d) {
        double dx = x(i, d) - x(j, d);
        dx -= L * std::round(dx / L);
        r2 += dx * dx;
      }
      const double r = std::sqrt(r2);
      if (r < h) {
        rho[i] += w(r);
        rho[j] += w(r);
      }
      if (r < par.r_A) {
        pairs.push_back({i, j});
        dist.push_back(r);
      }
    }
  const auto got = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sys.rho);
  double max_err = 0;
  for (int i = 0; i < n; ++i) max_err = std::max(max_err, std::abs(got(i) - rho[i]));
  EXPECT_LT(max_err, 1e-10) << D << "D, kernel " << (lucy ? "lucy" : "normalized") << ", self term "
                            << mdpd::to_string(self) << (use_defaults ? " (default)" : "");
  double virial = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const double r = dist[k];
    double f = par.A * (1 - r / par.r_A);
    if (r < par.r_B) f += par.B * (rho[pairs[k].first] + rho[pairs[k].second]) * (1 - r / par.r_B);
    virial += r * f;
  }
  const double got_virial = mdpd::conservative_virial(par, sys.particles.x, sys.rho, sys.neighbor_list(), sys.box());
  EXPECT_NEAR(got_virial, virial, 1e-9 * std::abs(virial)) << D << "D virial";
}

TEST(MdpdDensity, MatchesBruteForceWithAndWithoutSelfTerm) {
  using mdpd::DensityKernel;
  using mdpd::DensitySelfTerm;
  for (auto kind : {NeighborListKind::half, NeighborListKind::full})
    for (auto kernel : {DensityKernel::lucy, DensityKernel::normalized}) {
      // Defaults: no self term (LAMMPS' mdpd/rhosum); this fails if a self term comes back by default.
      check_density_brute_force<3>(kernel, DensitySelfTerm::off, true, kind);
      check_density_brute_force<2>(kernel, DensitySelfTerm::off, true, kind);
      for (auto self : {DensitySelfTerm::off, DensitySelfTerm::on}) {
        check_density_brute_force<3>(kernel, self, false, kind);
        check_density_brute_force<2>(kernel, self, false, kind);
      }
    }
}

// Tethers: F = −k_S (x − s) is minus the gradient of ½ k_S |x − s|² (minimum image across the
// periodic boundary included), for solid particles only.
TEST(MdpdTetherSprings, ForceIsMinusTheGradientOfTheEnergy) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const auto box = Box<3, double>::cube(4.0, true);
  Particles<3, double, Exec> p(20);
  typename Particles<3, double, Exec>::vector_view site("site", 20);
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(0.0, 4.0), shift(-0.6, 0.6);
  auto x = Kokkos::create_mirror_view(p.x);
  auto s = Kokkos::create_mirror_view(site);
  auto type = Kokkos::create_mirror_view(p.type);
  for (int i = 0; i < 20; ++i) {
    for (int d = 0; d < 3; ++d) {
      s(i, d) = u(gen);
      x(i, d) = s(i, d) + shift(gen);  // some cross the periodic boundary
    }
    type(i) = i % 4 == 0 ? mdpd::particle_type::fluid : (i % 2 ? mdpd::particle_type::solid : mdpd::particle_type::solid_core);
  }
  Kokkos::deep_copy(p.x, x);
  Kokkos::deep_copy(site, s);
  Kokkos::deep_copy(p.type, type);
  const mdpd::TetherSprings<3, double, Exec> tether(12.5);
  auto energy = [&] {
    p.zero_forces();
    tether.accumulate(p, site, box);
    return tether.energy(p, site, box);
  };
  const auto c = testing::check_gradient(p, energy, 1e-6);
  EXPECT_GT(c.max_force, 1.0);
  EXPECT_LT(c.max_error, 1e-8);
  const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
  for (int i = 0; i < 20; i += 4)
    for (int d = 0; d < 3; ++d) EXPECT_EQ(f(i, d), 0.0) << "fluid particle " << i << " has no tether";
  using Tethers = mdpd::TetherSprings<3, double, Exec>;
  EXPECT_THROW(Tethers(-1.0), std::invalid_argument);
}

TEST(MdpdParameters, BadInputNamesTheParameter) {
  MdpdParameters par;
  par.r_B = 1.5;
  try {
    par.validate();
    FAIL() << "r_B > r_A accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("r_B must be in (0, r_A"), std::string::npos) << e.what();
  }
  par = MdpdParameters();
  par.dt = std::nan("");
  EXPECT_THROW(par.validate(), std::invalid_argument);
  EXPECT_THROW(mdpd::parse_density_kernel("gaussian"), std::invalid_argument);
  EXPECT_EQ(mdpd::parse_density_self_term("off"), mdpd::DensitySelfTerm::off);
  EXPECT_EQ(mdpd::parse_density_self_term("on"), mdpd::DensitySelfTerm::on);
  try {
    mdpd::parse_density_self_term("yes");
    FAIL() << "density self term 'yes' accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("density self term"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mesoflow
