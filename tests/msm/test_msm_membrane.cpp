// MSM membrane (kernels/msm): the bond force of eq. (7) is minus the gradient of its energy (across
// periodic boundaries too), obeys Newton's third law to round-off and is bitwise the same on Serial
// and OpenMP; the CSR rows list every bond at both ends; the capsule membrane has the paper's
// 5124 particles and 25 602 bonds (§3) on two icospheres of the right radii and topology; and the
// in-plane elasticity of the two-layer network, measured on a flat periodic patch, is compared with
// the paper's E = 5 k_b/(√3 δ_ave), ν = 1/4 (§4).
#include "finite_difference.hpp"
#include "kernels/common/fire.hpp"
#include "kernels/msm/capsule_mesh.hpp"
#include "kernels/msm/harmonic_bonds.hpp"
#include "scenes/capsule/membrane_elasticity.hpp"
#include "test_types.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <utility>
#include <vector>

namespace mesoflow {
namespace {

using msm::BondKind;
using msm::DiagonalBonds;
using msm::HarmonicBonds;
using msm::MembraneMesh;

// The mesh's particles, each displaced from its rest position by a uniform random amount in
// [−amplitude, amplitude] per component, so every bond is stretched or compressed.
template <class Real, class Exec>
Particles<3, Real, Exec> displaced_particles(const MembraneMesh& mesh, double amplitude, unsigned seed) {
  Particles<3, Real, Exec> p(std::size_t(mesh.num_particles()), "msm_test");
  auto x = Kokkos::create_mirror_view(p.x);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (int i = 0; i < mesh.num_particles(); ++i)
    for (int d = 0; d < 3; ++d) x(i, d) = Real(mesh.position[std::size_t(i)][std::size_t(d)] + u(gen));
  Kokkos::deep_copy(p.x, x);
  return p;
}

// Periodic in x and y with the mesh's period where it has one, open otherwise.
template <class Real>
Box<3, Real> mesh_box(const MembraneMesh& mesh, double strain_x = 0, double strain_y = 0) {
  if (!(mesh.period[0] > 0)) return Box<3, Real>::cube(Real(1), false);
  const Real lo[3] = {0, 0, -10};
  const Real length[3] = {Real(mesh.period[0] * (1 + strain_x)), Real(mesh.period[1] * (1 + strain_y)), 20};
  const bool periodic[3] = {true, true, false};
  return Box<3, Real>(lo, length, periodic);
}

msm::CapsuleMembraneParameters capsule(int level, DiagonalBonds diagonals = DiagonalBonds::one_per_quad) {
  msm::CapsuleMembraneParameters par;
  par.radius = 0.5;      // d = 1
  par.thickness = 0.04;  // about δ_ave at level 4
  par.level = level;
  par.bonds.k_b = 10;
  par.bonds.diagonals = diagonals;
  return par;
}

msm::FlatMembraneParameters patch(DiagonalBonds diagonals, double thickness = 1.0) {
  msm::FlatMembraneParameters par;
  par.nx = 6;
  par.ny = 6;
  par.spacing = 1;
  par.thickness = thickness;
  par.bonds.k_b = 1;
  par.bonds.diagonals = diagonals;
  return par;
}

// ---------------------------------------------------------------------------------------------
// Eq. (7)

// Two particles 0.5 apart through the periodic boundary of a box of 4, r0 = 0.3, k = 2:
// F_0 = k (r − r0) r̂ = 0.4 towards particle 1 (−x through the boundary), F_1 = −F_0,
// U = ½ k (r − r0)² = 0.04.
TEST(MsmHarmonicBonds, TwoParticlesAcrossThePeriodicBoundary) {
  using Exec = Kokkos::DefaultExecutionSpace;
  Particles<3, double, Exec> p(2);
  auto x = Kokkos::create_mirror_view(p.x);
  x(0, 0) = 0.2;
  x(1, 0) = 3.7;
  for (int i = 0; i < 2; ++i) x(i, 1) = x(i, 2) = 1.0;
  Kokkos::deep_copy(p.x, x);
  const HarmonicBonds<3, double, Exec> bonds(msm::make_harmonic_bond_list<double, Exec>({{0, 1}}, {2.0}, {0.3}));
  const auto box = Box<3, double>::cube(4.0, true);
  p.zero_forces();
  bonds.accumulate(p, box);
  const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
  EXPECT_NEAR(f(0, 0), -0.4, 1e-14);
  EXPECT_NEAR(f(1, 0), 0.4, 1e-14);
  for (int i = 0; i < 2; ++i)
    for (int d = 1; d < 3; ++d) EXPECT_EQ(f(i, d), 0.0);
  EXPECT_NEAR(bonds.energy(p, box), 0.04, 1e-15);
}

// −∂U/∂x_i by central differences against F_i, on a capsule (level 2, open box) and on a flat
// periodic patch (bonds through the boundary), both diagonal variants, particles displaced by up
// to 10% of a bond.
TEST(MsmHarmonicBonds, ForceIsMinusTheGradientOfTheEnergy) {
  using Exec = Kokkos::DefaultExecutionSpace;
  for (auto diagonals : {DiagonalBonds::one_per_quad, DiagonalBonds::both_per_quad}) {
    const MembraneMesh meshes[2] = {msm::capsule_membrane(capsule(2, diagonals)), msm::flat_membrane(patch(diagonals))};
    for (const auto& mesh : meshes) {
      const double delta = mesh.mean_in_layer_bond_length();
      auto p = displaced_particles<double, Exec>(mesh, 0.1 * delta, 17);
      const auto box = mesh_box<double>(mesh);
      const HarmonicBonds<3, double, Exec> bonds(msm::upload_bonds<double, Exec>(mesh));
      auto energy = [&] {
        p.zero_forces();
        bonds.accumulate(p, box);
        return bonds.energy(p, box);
      };
      const auto c = testing::check_gradient(p, energy, 1e-6 * delta);
      std::printf("[ msm ] finite-difference check, %s, %s diagonal(s) per quad: max |F_fd − F|/max|F| = %.2e\n",
                  mesh.period[0] > 0 ? "flat periodic patch" : "capsule level 2",
                  diagonals == DiagonalBonds::one_per_quad ? "one" : "both", c.max_error);
      EXPECT_GT(c.max_force, 0.01 * mesh.k[0] * delta);
      EXPECT_LT(c.max_error, 1e-6);
    }
  }
}

template <class T>
class MsmBondTest : public ::testing::Test {};
TYPED_TEST_SUITE(MsmBondTest, testing::BackendsAndPrecisions);

// Σ_i F_i = 0 relative to Σ|F|: 64 ε (each bond's two ends are evaluated from opposite
// separations, so the pair forces cancel to the rounding of the row sums).
TYPED_TEST(MsmBondTest, NewtonsThirdLawToRoundOff) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
  const auto mesh = msm::capsule_membrane(capsule(3));
  auto p = displaced_particles<Real, Exec>(mesh, 0.005, 5);
  const HarmonicBonds<3, Real, Exec> bonds(msm::upload_bonds<Real, Exec>(mesh));
  p.zero_forces();
  bonds.accumulate(p, mesh_box<Real>(mesh));
  const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.f);
  double sum[3] = {0, 0, 0}, magnitude = 0;
  for (int i = 0; i < mesh.num_particles(); ++i)
    for (int d = 0; d < 3; ++d) {
      sum[d] += double(f(i, d));
      magnitude += std::abs(double(f(i, d)));
    }
  EXPECT_GT(magnitude, 1.0);
  for (int d = 0; d < 3; ++d) EXPECT_LT(std::abs(sum[d]), 64 * testing::eps<Real>() * magnitude) << d;
}

// Each row sums its own particle's bonds in a fixed order: the forces on this backend are those of
// Serial (one thread) bit for bit, on OpenMP whatever its thread count, and within the FMA-contraction
// bound on a device; accumulate() adds to what is in f. A flat periodic patch (one diagonal per quad) and a level-3 capsule (both diagonals).
TYPED_TEST(MsmBondTest, ForcesAreBitwiseIdenticalOnHostBackendsAndThreadCounts) {
  using Exec = typename TypeParam::exec;
  using Real = typename TypeParam::real;
#ifdef KOKKOS_ENABLE_SERIAL
  using Reference = Kokkos::Serial;
#else
  using Reference = Kokkos::DefaultHostExecutionSpace;
#endif
  const MembraneMesh meshes[2] = {msm::flat_membrane(patch(DiagonalBonds::one_per_quad)),
                                  msm::capsule_membrane(capsule(3, DiagonalBonds::both_per_quad))};
  for (const auto& mesh : meshes) {
    const double amplitude = 0.1 * mesh.mean_in_layer_bond_length();
    auto a = displaced_particles<Real, Exec>(mesh, amplitude, 9);
    auto b = displaced_particles<Real, Reference>(mesh, amplitude, 9);
    const HarmonicBonds<3, Real, Exec> bonds_a(msm::upload_bonds<Real, Exec>(mesh));
    const HarmonicBonds<3, Real, Reference> bonds_b(msm::upload_bonds<Real, Reference>(mesh));
    Kokkos::deep_copy(a.f, Real(0.25));
    b.zero_forces();
    bonds_a.accumulate(a, mesh_box<Real>(mesh));
    bonds_b.accumulate(b, mesh_box<Real>(mesh));
    const auto fa = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.f);
    const auto fb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.f);
    // On a device, FMA contraction (testing::agrees_with_host): at most 12 bonds per particle of
    // about 20 operations each, at the scale of K_i r (K_i ≤ 11 k_b, k_b ≤ 10, r ≤ twice the mean
    // bond length): r − r_0 cancels, so the rounding of r is what counts.
    const int operations = 12 * 20 + 1;
    const double scale = 11 * 10 * 2 * mesh.mean_in_layer_bond_length() + 0.25;
    int nonzero = 0;
    for (int i = 0; i < mesh.num_particles(); ++i)
      for (int d = 0; d < 3; ++d) {
        nonzero += fb(i, d) != Real(0);
        ASSERT_TRUE((testing::agrees_with_host<Exec, Real>(fa(i, d), Real(0.25) + fb(i, d), operations, scale)))
            << i << " " << d << ", " << Exec::name() << " with " << concurrency<Exec>() << " threads";
      }
    EXPECT_GT(nonzero, 2 * mesh.num_particles());
  }
  std::printf("[ msm ] bond forces equal (bitwise on host backends): %s, %d thread(s), vs %s, 1 thread\n", Exec::name(),
              concurrency<Exec>(), Reference::name());
}

// The CSR rows: one per bonded particle, in ascending order, offset by first_particle; each bond
// listed at both of its ends with the other end as partner, in increasing bond order.
TEST(MsmHarmonicBondList, RowsListEveryBondAtBothEnds) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const auto mesh = msm::flat_membrane(patch(DiagonalBonds::one_per_quad));
  const int first = 5;
  const auto list = msm::upload_bonds<double, Exec>(mesh, first);
  ASSERT_EQ(list.num_bonds(), mesh.num_bonds());
  ASSERT_EQ(list.num_rows(), mesh.num_particles());
  EXPECT_EQ(list.max_particle, first + mesh.num_particles() - 1);
  const auto rows = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), list.row_particle);
  const auto offset = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), list.offset);
  const auto bond = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), list.incident_bond);
  const auto partner = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), list.incident_partner);
  std::vector<int> seen(std::size_t(mesh.num_bonds()), 0);
  for (int r = 0; r < list.num_rows(); ++r) {
    EXPECT_EQ(rows(r), first + r);
    // One-per-quad diagonals on the flat lattice: 6 in-layer + 1 partner + 3 diagonals each.
    EXPECT_EQ(offset(r + 1) - offset(r), 10) << r;
    for (int e = offset(r); e < offset(r + 1); ++e) {
      const auto& ends = mesh.bond[std::size_t(bond(e))];
      const int i = rows(r) - first, j = partner(e) - first;
      EXPECT_TRUE((ends[0] == i && ends[1] == j) || (ends[0] == j && ends[1] == i)) << r << " " << e;
      if (e > offset(r)) {
        EXPECT_LT(bond(e - 1), bond(e));
      }
      ++seen[std::size_t(bond(e))];
    }
  }
  for (int s : seen) EXPECT_EQ(s, 2);

  using List = msm::HarmonicBondList<double, Exec>;
  EXPECT_THROW((List(msm::make_harmonic_bond_list<double, Exec>({{1, 1}}, {1.0}, {1.0}))), std::invalid_argument);
  EXPECT_THROW((List(msm::make_harmonic_bond_list<double, Exec>({{0, 1}}, {-1.0}, {1.0}))), std::invalid_argument);
  EXPECT_THROW((List(msm::make_harmonic_bond_list<double, Exec>({{0, 1}}, {1.0}, {1.0, 2.0}))), std::invalid_argument);
  const HarmonicBonds<3, double, Exec> bonds(list);
  Particles<3, double, Exec> too_few(std::size_t(mesh.num_particles()));
  EXPECT_THROW(bonds.accumulate(too_few, mesh_box<double>(mesh)), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// The membrane mesh (§3, Fig. 1b)

// Level ℓ: V = 10·4^ℓ + 2, E = 30·4^ℓ, F = 20·4^ℓ, V − E + F = 2; 12 vertices of valence 5, the
// rest 6; vertices on the unit sphere; triangles counter-clockwise seen from outside; each edge in
// two triangles.
TEST(MsmIcosphere, CountsEulerCharacteristicValenceAndOrientation) {
  for (int level = 0; level <= 4; ++level) {
    const auto s = msm::icosphere(level);
    const int p = 1 << (2 * level);
    const int V = int(s.vertex.size()), E = int(s.edge.size()), F = int(s.triangle.size());
    EXPECT_EQ(V, 10 * p + 2);
    EXPECT_EQ(E, 30 * p);
    EXPECT_EQ(F, 20 * p);
    EXPECT_EQ(V - E + F, 2);
    std::vector<int> valence(std::size_t(V), 0);
    for (const auto& e : s.edge) {
      EXPECT_LT(e[0], e[1]);
      ++valence[std::size_t(e[0])];
      ++valence[std::size_t(e[1])];
    }
    EXPECT_EQ(std::count(valence.begin(), valence.end(), 5), 12) << level;
    EXPECT_EQ(std::count(valence.begin(), valence.end(), 6), V - 12) << level;
    for (const auto& v : s.vertex) EXPECT_NEAR(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), 1.0, 1e-14);
    std::map<std::pair<int, int>, int> in_triangles;
    for (const auto& t : s.triangle) {
      const auto &a = s.vertex[std::size_t(t[0])], &b = s.vertex[std::size_t(t[1])], &c = s.vertex[std::size_t(t[2])];
      const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
      EXPECT_GT(n[0] * (a[0] + b[0] + c[0]) + n[1] * (a[1] + b[1] + c[1]) + n[2] * (a[2] + b[2] + c[2]), 0.0);
      for (int k = 0; k < 3; ++k) {
        const int i = t[std::size_t(k)], j = t[std::size_t((k + 1) % 3)];
        ++in_triangles[{std::min(i, j), std::max(i, j)}];
      }
    }
    EXPECT_EQ(int(in_triangles.size()), E);
    for (const auto& [edge, count] : in_triangles) EXPECT_EQ(count, 2);
  }
}

// The paper's capsule: 5124 particles and 25 602 bonds = 2·7680 in-layer + 2562 partner + 7680
// diagonal (one per quad); with both diagonals per quad it would be 33 282. Outer sphere at radius
// a, inner at a − h_t; partner bonds of length h_t; every rest length positive; every quad between
// the layers (in-layer edge) holds exactly one diagonal, of stiffness 2/3 k_b.
TEST(MsmCapsuleMembrane, HasThePapersParticleAndBondCounts) {
  const auto par = capsule(4);
  const auto mesh = msm::capsule_membrane(par);
  const int V = 2562;
  EXPECT_EQ(mesh.vertices_per_layer, V);
  EXPECT_EQ(mesh.num_particles(), 5124);
  EXPECT_EQ(mesh.num_bonds(), 25602);
  EXPECT_EQ(std::count(mesh.kind.begin(), mesh.kind.end(), BondKind::in_layer), 2 * 7680);
  EXPECT_EQ(std::count(mesh.kind.begin(), mesh.kind.end(), BondKind::partner), V);
  EXPECT_EQ(std::count(mesh.kind.begin(), mesh.kind.end(), BondKind::diagonal), 7680);
  EXPECT_EQ(msm::capsule_membrane(capsule(4, DiagonalBonds::both_per_quad)).num_bonds(), 33282);
  EXPECT_EQ(int(mesh.triangle.size()), 5120);

  const double a = par.radius, h = par.thickness;
  for (int i = 0; i < mesh.num_particles(); ++i) {
    const auto& x = mesh.position[std::size_t(i)];
    EXPECT_NEAR(std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), i < V ? a : a - h, 1e-14) << i;
  }
  std::map<std::pair<int, int>, int> diagonals_per_quad;
  std::vector<int> valence(std::size_t(V), 0);
  double sum_all = 0, lo = 1e300, hi = 0;
  for (int b = 0; b < mesh.num_bonds(); ++b) {
    const auto& e = mesh.bond[std::size_t(b)];
    const double r0 = mesh.r0[std::size_t(b)], k = mesh.k[std::size_t(b)];
    const auto& xa = mesh.position[std::size_t(e[0])];
    const auto& xb = mesh.position[std::size_t(e[1])];
    EXPECT_GT(r0, 0.0);
    EXPECT_NEAR(r0, std::hypot(xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2]), 1e-15);
    sum_all += r0;
    switch (mesh.kind[std::size_t(b)]) {
      case BondKind::in_layer:
        EXPECT_EQ(k, par.bonds.k_b);
        EXPECT_EQ(e[0] < V, e[1] < V);
        if (e[0] < V) {
          diagonals_per_quad[{e[0], e[1]}] += 0;
          ++valence[std::size_t(e[0])];
          ++valence[std::size_t(e[1])];
        }
        lo = std::min(lo, r0);
        hi = std::max(hi, r0);
        break;
      case BondKind::partner:
        EXPECT_EQ(k, par.bonds.k_b);
        EXPECT_EQ(e[1], e[0] + V);
        EXPECT_NEAR(r0, h, 1e-14);
        break;
      case BondKind::diagonal: {
        EXPECT_EQ(k, 2.0 / 3.0 * par.bonds.k_b);
        ASSERT_LT(e[0], V);
        ASSERT_GE(e[1], V);
        const int u = e[0], v = e[1] - V;
        ++diagonals_per_quad[{std::min(u, v), std::max(u, v)}];
        break;
      }
    }
  }
  EXPECT_EQ(int(diagonals_per_quad.size()), 7680);  // no diagonal outside an in-layer edge's quad
  for (const auto& [edge, count] : diagonals_per_quad) EXPECT_EQ(count, 1) << edge.first << " " << edge.second;
  EXPECT_EQ(std::count(valence.begin(), valence.end(), 5), 12);
  EXPECT_EQ(std::count(valence.begin(), valence.end(), 6), V - 12);

  // δ_ave: in-layer lengths scale with the radius, so it is the unit icosphere's mean edge times the
  // mean of the two radii, a − h_t/2.
  const auto unit = msm::icosphere(4);
  double unit_edge = 0;
  for (const auto& e : unit.edge) {
    const auto &p = unit.vertex[std::size_t(e[0])], &q = unit.vertex[std::size_t(e[1])];
    unit_edge += std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]) / double(unit.edge.size());
  }
  const double delta = mesh.mean_in_layer_bond_length();
  std::printf("[ msm ] capsule a = %.3g, h_t = %.3g, level 4: δ_ave = %.5f (in-layer bonds %.5f .. %.5f), "
              "mean over all bonds %.5f; unit-sphere mean edge %.5f\n",
              a, h, delta, lo, hi, sum_all / mesh.num_bonds(), unit_edge);
  EXPECT_NEAR(delta, unit_edge * (a - h / 2), 1e-12);
  EXPECT_GT(delta, lo);
  EXPECT_LT(delta, hi);
}

// The flat patch is a torus (V − E + F = 0) of valence 6; bonds of lengths δ, h_t and √(δ² + h_t²).
TEST(MsmFlatMembrane, IsAPeriodicTwoLayerTriangularLattice) {
  const auto par = patch(DiagonalBonds::both_per_quad, 0.8);
  const auto mesh = msm::flat_membrane(par);
  const int V = par.nx * par.ny;
  ASSERT_EQ(mesh.vertices_per_layer, V);
  const auto in_layer = std::count(mesh.kind.begin(), mesh.kind.end(), BondKind::in_layer);
  EXPECT_EQ(V - in_layer / 2 + int(mesh.triangle.size()), 0);
  EXPECT_EQ(mesh.num_bonds(), 3 * V * 2 + V + 2 * 3 * V);
  EXPECT_NEAR(mesh.period[0], 6.0, 1e-15);
  EXPECT_NEAR(mesh.period[1], 6 * std::sqrt(0.75), 1e-15);
  std::vector<int> valence(std::size_t(2 * V), 0);
  for (int b = 0; b < mesh.num_bonds(); ++b) {
    const auto kind = mesh.kind[std::size_t(b)];
    const double expected = kind == BondKind::in_layer ? 1.0 : (kind == BondKind::partner ? 0.8 : std::hypot(1.0, 0.8));
    EXPECT_NEAR(mesh.r0[std::size_t(b)], expected, 1e-14) << b;
    if (kind == BondKind::in_layer) {
      ++valence[std::size_t(mesh.bond[std::size_t(b)][0])];
      ++valence[std::size_t(mesh.bond[std::size_t(b)][1])];
    }
  }
  for (int v : valence) EXPECT_EQ(v, 6);
  EXPECT_NEAR(mesh.mean_in_layer_bond_length(), 1.0, 1e-14);
  msm::FlatMembraneParameters odd = par;
  odd.ny = 5;
  EXPECT_THROW(msm::flat_membrane(odd), std::invalid_argument);
  auto thick = capsule(2);
  thick.thickness = thick.radius;
  EXPECT_THROW(msm::capsule_membrane(thick), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// In-plane elasticity of the two-layer network (§4: "E = 5 k_b/(√3 δ_ave) and ν = 1/4")
//
// What is tested. The paper's surface shear modulus G_s = ½ E/(1 + ν) · h_t makes E a
// three-dimensional Young's modulus of a shell of thickness h_t, i.e. the membrane's 2D
// (stretching) modulus is E_2D = E h_t. We measure, on a flat periodic patch stretched along x by
// ε_xx = ±1% with the y box length relaxed (σ_yy = 0, energy minimised over ε_yy), the free
// particles relaxed by FIRE at each box shape:
//   E_2D = (1/A) ∂²U/∂ε_xx²,   ν = −dε_yy/dε_xx,   E = E_2D / h_t,
// and compare E with 5 k_b/(√3 δ) (δ = δ_ave: all in-layer bonds of the patch have length δ).
//
// Linear elasticity of the network (Cauchy–Born, with the relative displacement of the two layers
// relaxed): a bond along n of stiffness k and in-plane length δ_p adds k δ_p² n n n n to the
// stiffness per cell. In-layer bonds: two triangular lattices of spacing δ. Each diagonal (length
// L = √(δ² + h_t²)) adds, through its in-plane projection, a spring k_d δ²/L² along its direction;
// at h_t = δ that is (2/3 k_b)/2 = k_b/3. An in-plane dilation tr ε also stretches the diagonals'
// in-plane parts, which pull the layers together against the partner bonds and so lowers λ.
//  * both diagonals per quad (33 282 bonds on the capsule): per cell and lattice direction two
//    in-layer bonds k_b and two diagonals k_b/3, i.e. K = 8k_b/3 → μ = (√3/4) K = 2k_b/√3; the
//    layer gap relaxes by −δ tr ε/3, which lowers λ by 2k_b/(3√3) → λ = 4k_b/(3√3).
//    E_2D = 4μ(λ+μ)/(λ+2μ) = 5k_b/√3 and ν = λ/(λ+2μ) = 1/4 exactly: the paper's
//    E = 5k_b/(√3 δ_ave) and ν = 1/4 at h_t = δ_ave.
//  * one diagonal per quad (the paper's 25 602 bonds): 3 diagonals per cell, polar (0°, 60°,
//    120°), so the layers also slide in-plane relative to each other under strain; the relaxed
//    constants (the same calculation, done numerically) are E_2D = (21/5) k_b/√3 along x (and
//    189/47 k_b/√3 along y: this network is anisotropic) and ν = 1/3. At h_t = δ that is
//    E = 0.84 of the paper's formula and ν = 4/3 of 1/4, and no thickness mends both: ν = 1/3 at
//    every h_t (E_2D/h_t equals 5k_b/(√3 δ) only at h_t ≈ 0.85 δ).
// So the paper's bond count and its elastic constants describe different networks. We build the
// count (one_per_quad) by default, keep the crossed variant (both_per_quad) that has the paper's
// constants, and test each against its own linear elasticity: the crossed one against the paper's
// formula within 5%, the paper's count against (21/5) k_b/√3 and 1/3 within 1%.
// E_2D does not scale with h_t, so E = E_2D/h_t = 5k_b/(√3 δ) holds at one thickness only (crossed:
// E_2D = 5.78, 5.25, 5.00, 4.81, 4.60 k_b/√3 at h_t/δ = 0.5, 0.8, 1, 1.2, 1.5).

// The measurement itself is capsule::measure_membrane_moduli (scenes/capsule/membrane_elasticity.hpp):
// the same 6 × 6 patch (δ = 1, k_b = 1) strained by ±1% and relaxed by FIRE, which the capsule driver
// uses for its Ca.

TEST(MsmMembraneElasticity, CrossedDiagonalsGiveThePapersYoungsModulusAndPoissonRatio) {
  const auto par = patch(DiagonalBonds::both_per_quad, 1.0);
  const auto mesh = msm::flat_membrane(par);
  const double delta = mesh.mean_in_layer_bond_length(), k_b = par.bonds.k_b, h_t = par.thickness;
  const auto moduli = capsule::measure_membrane_moduli(h_t / delta, par.bonds.diagonals);
  const double E2D = moduli.young * k_b, nu = moduli.poisson;
  const double E = E2D / h_t, E_paper = 5 * k_b / (std::sqrt(3.0) * delta);
  std::printf("[ msm ] both diagonals, h_t = δ: E = E_2D/h_t = %.5f k_b/δ, paper 5/√3 = %.5f (ratio %.5f); "
              "ν = %.5f, paper 1/4 (ratio %.5f)\n",
              E * delta / k_b, E_paper * delta / k_b, E / E_paper, nu, nu / 0.25);
  EXPECT_NEAR(E / E_paper, 1.0, 0.05);
  EXPECT_NEAR(nu / 0.25, 1.0, 0.05);
}

TEST(MsmMembraneElasticity, PaperBondCountGivesItsOwnLinearElasticityNotThePapersFormula) {
  const auto par = patch(DiagonalBonds::one_per_quad, 1.0);
  const auto mesh = msm::flat_membrane(par);
  const double delta = mesh.mean_in_layer_bond_length(), k_b = par.bonds.k_b, h_t = par.thickness;
  const auto moduli = capsule::measure_membrane_moduli(h_t / delta, par.bonds.diagonals);
  const double E2D = moduli.young * k_b, nu = moduli.poisson;
  const double E = E2D / h_t, E_paper = 5 * k_b / (std::sqrt(3.0) * delta);
  const double E_network = 4.2 * k_b / (std::sqrt(3.0) * delta);  // (21/5) k_b/(√3 δ) at h_t = δ
  std::printf("[ msm ] one diagonal per quad (paper's count), h_t = δ: E = %.5f k_b/δ, network theory %.5f, "
              "paper %.5f (ratio to paper %.4f); ν = %.5f, network theory 1/3, paper 1/4 (ratio %.4f)\n",
              E * delta / k_b, E_network * delta / k_b, E_paper * delta / k_b, E / E_paper, nu, nu / 0.25);
  EXPECT_NEAR(E / E_network, 1.0, 0.01);
  EXPECT_NEAR(nu * 3, 1.0, 0.01);
}


// The moduli the capsule driver uses for Ca (scenes/capsule/membrane_elasticity.hpp, issue 29 item 1):
// area and shear moduli from equibiaxial and pure-shear strains of the patch. The crossed network at
// h_t = δ has, from the Cauchy–Born calculation above, μ = 2k_b/√3 and λ = 4k_b/(3√3): G_s = μ and
// K_A = λ + μ = 10k_b/(3√3), and these with E_2D and ν measured by the uniaxial test obey the
// isotropic relations E_2D = 4K_A G_s/(K_A + G_s), ν = (K_A − G_s)/(K_A + G_s).
TEST(MsmMembraneElasticity, MeasuredShearAndAreaModuliOfTheCrossedNetwork) {
  const auto m = capsule::measure_membrane_moduli(1.0, DiagonalBonds::both_per_quad);
  const double s3 = std::sqrt(3.0);
  std::printf("[ msm ] both diagonals, h_t = δ: G_s = %.5f k_b (theory 2/√3 = %.5f), K_A = %.5f k_b (theory "
              "10/(3√3) = %.5f), E_2D = %.5f, ν = %.5f\n",
              m.shear, 2 / s3, m.area, 10 / (3 * s3), m.young, m.poisson);
  EXPECT_NEAR(m.shear / (2 / s3), 1.0, 0.01);
  EXPECT_NEAR(m.area / (10 / (3 * s3)), 1.0, 0.01);
  EXPECT_NEAR(m.young / (4 * m.area * m.shear / (m.area + m.shear)), 1.0, 0.01);
  EXPECT_NEAR(m.poisson, (m.area - m.shear) / (m.area + m.shear), 0.01);
}

// The paper's count (one diagonal per quad) at the capsule runs' h_t/δ: its G_s is not §4's
// E h_t/(2(1 + ν)) — the network's moduli do not grow with h_t as that formula does — and the ratio
// is what converts the capillary numbers of runs made with the formula (docs/sph-capsules.md).
TEST(MsmMembraneElasticity, PaperCountShearModulusAgainstTheFormulaAcrossThickness) {
  const double s3 = std::sqrt(3.0);
  double previous_ratio = 0;
  for (double h : {0.5, 1.0, 2.0}) {
    const auto m = capsule::measure_membrane_moduli(h, DiagonalBonds::one_per_quad);
    const double formula = 5.0 / s3 * h / (2 * 1.25);  // G_s/k_b of §4 at δ = 1
    const double ratio = m.shear / formula;
    std::printf("[ msm ] one diagonal per quad, h_t/δ = %.1f: G_s = %.5f k_b, K_A = %.5f k_b, E_2D = %.5f k_b, "
                "ν = %.4f; §4's formula G_s = %.5f k_b (network/formula %.4f)\n",
                h, m.shear, m.area, m.young, m.poisson, formula, ratio);
    EXPECT_GT(m.shear, 0);
    EXPECT_GT(m.area, m.shear);  // ν > 0
    if (h == 1.0) {
      // E_2D and ν of the uniaxial test above: (21/5)/√3 and 1/3.
      EXPECT_NEAR(m.young / (4.2 / s3), 1.0, 0.01);
      EXPECT_NEAR(m.poisson * 3, 1.0, 0.01);
    }
    if (previous_ratio > 0) {
      EXPECT_LT(ratio, previous_ratio);  // the formula grows ∝ h_t, the network does not
    }
    previous_ratio = ratio;
  }
}

}  // namespace
}  // namespace mesoflow
