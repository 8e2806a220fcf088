// Hopper walls (kernels/common/geometry.hpp: hopper_walls_2d/3d, the revolved wedge) and the
// soft-particle wall repulsion of eq. 3 (kernels/sp/wall_repulsion.hpp): the walls are where the
// hopper paper puts them (side walls W apart, an orifice of width w at height 0, the exit walls at
// θ_w); the 3D base is the 2D profile revolved (rotating a point about the axis keeps its distance);
// the repulsion is minus the gradient of its energy near walls, corners and the orifice rim in 2D and
// 3D, sums the walls a particle overlaps, and depends on the particle's own diameter.
#include "kernels/common/geometry.hpp"
#include "kernels/sp/wall_repulsion.hpp"
#include "finite_difference.hpp"
#include "test_types.hpp"

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace mesoflow {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using V2 = Vec<2, double>;
using V3 = Vec<3, double>;

double nearest_distance2(const std::vector<Shape<2, double>>& walls, const V2& x) {
  return nearest_surface(walls.data(), int(walls.size()), x).distance;
}
double nearest_distance3(const std::vector<Shape<3, double>>& walls, const V3& x) {
  return nearest_surface(walls.data(), int(walls.size()), x).distance;
}

TEST(HopperWalls, FlatBottomed2DHopperHasItsWallsAndOrifice) {
  const auto walls = hopper_walls_2d<double>(30.0, 4.0, 90.0);
  EXPECT_NEAR(nearest_distance2(walls, V2{{0.0, 10.0}}), std::sqrt(104.0), 1e-12);  // above the orifice: its rims
  EXPECT_NEAR(nearest_distance2(walls, V2{{8.0, 10.0}}), 7.0, 1e-12);              // the side wall x = 15
  EXPECT_NEAR(nearest_distance2(walls, V2{{12.0, 10.0}}), 3.0, 1e-12);   // 3 from the side wall x = 15
  EXPECT_NEAR(nearest_distance2(walls, V2{{8.0, 0.5}}), 0.5, 1e-12);     // above the exit wall
  EXPECT_NEAR(nearest_distance2(walls, V2{{0.0, 0.0}}), 2.0, 1e-12);     // orifice centre: the rims
  EXPECT_GT(nearest_distance2(walls, V2{{0.0, -1.0}}), 1.0);  // falling freely below the orifice
  EXPECT_LT(nearest_distance2(walls, V2{{8.0, -0.5}}), 0.0);  // inside the exit wall
  EXPECT_THROW(hopper_walls_2d<double>(30.0, 40.0, 90.0), std::invalid_argument);
  EXPECT_THROW(hopper_walls_2d<double>(30.0, 4.0, 0.0), std::invalid_argument);
  EXPECT_THROW(hopper_walls_2d<double>(30.0, 4.0, 120.0), std::invalid_argument);
}

TEST(HopperWalls, SlantedExitWallsMeetTheSideWallsAtThetaW) {
  const double theta = 60.0, t = theta * M_PI / 180;
  const auto walls = hopper_walls_2d<double>(30.0, 4.0, theta);
  // A point above the right exit wall, along its normal: the wall through (2, 0) along (sin θ, cos θ).
  const V2 on_wall{{2.0 + 5 * std::sin(t), 5 * std::cos(t)}};
  const V2 normal{{-std::cos(t), std::sin(t)}};
  EXPECT_NEAR(nearest_distance2(walls, on_wall + 0.7 * normal), 0.7, 1e-12);
}

TEST(HopperWalls, CylindricalHopperBaseIsTheRevolvedProfile) {
  const auto walls3 = hopper_walls_3d<double>(20.0, 4.0, 90.0);
  EXPECT_NEAR(nearest_distance3(walls3, V3{{0.0, 0.0, 6.0}}), std::sqrt(40.0), 1e-12);  // axis: the rim
  EXPECT_NEAR(nearest_distance3(walls3, V3{{0.0, 8.5, 5.0}}), 1.5, 1e-12);   // near the cylinder
  EXPECT_NEAR(nearest_distance3(walls3, V3{{5.0, 0.0, 0.4}}), 0.4, 1e-12);   // above the base
  EXPECT_NEAR(nearest_distance3(walls3, V3{{0.0, 0.0, 0.0}}), 2.0, 1e-12);   // orifice centre: the rim
  // Any meridian gives the 2D profile's distance: rotate points about the axis.
  const auto walls2 = hopper_walls_2d<double>(20.0, 4.0, 90.0);
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-9.5, 9.5), z(-3.0, 6.0), phi(0, 2 * M_PI);
  for (int k = 0; k < 200; ++k) {
    const double x = u(gen), y = z(gen), a = phi(gen);
    const V3 p{{std::abs(x) * std::cos(a), std::abs(x) * std::sin(a), y}};
    EXPECT_NEAR(nearest_distance3(walls3, p), nearest_distance2(walls2, V2{{std::abs(x), y}}), 1e-12)
        << "rho " << std::abs(x) << " z " << y;
  }
  const auto crossing_the_axis = [] {
    return Shape<3, double>::revolved_wedge(V3{{0, 0, 0}}, V3{{0, 0, 1}}, V2{{1, 0}}, V2{{-1, 0}}, V2{{0, -1}});
  };
  EXPECT_THROW(crossing_the_axis(), std::invalid_argument);
}

// Particles of two sizes scattered near the walls, corners and the orifice rim.
template <int D>
struct WallScene {
  Particles<D, double, Exec> p;
  Geometry<D, double, Exec> walls;
  sp::SoftSphereRepulsion<double> sizes{1.0, {1.0, 1.4}};

  WallScene(const std::vector<Shape<D, double>>& shapes, const std::vector<Vec<D, double>>& x)
      : p(int(x.size()), "walls"), walls(shapes) {
    auto h = Kokkos::create_mirror_view(p.x);
    auto t = Kokkos::create_mirror_view(p.type);
    for (std::size_t i = 0; i < x.size(); ++i) {
      for (int d = 0; d < D; ++d) h(i, d) = x[i][d];
      t(i) = int(i % 2);
    }
    Kokkos::deep_copy(p.x, h);
    Kokkos::deep_copy(p.type, t);
  }
  double energy() {
    p.zero_forces();
    return sp::accumulate_wall_repulsion(50.0, sizes, walls, p);
  }
};

template <int D>
void expect_wall_force_is_minus_gradient(WallScene<D>& s) {
  // The force is continuous at contact but its derivative jumps (stiffness ε_w(2/σ)² = 200 here):
  // a particle within h of d = σ/2 sees an O(h·stiffness) central-difference error (5.8·10⁻⁶ of
  // max |F| at h = 10⁻⁶, 5.8·10⁻⁷ at 10⁻⁷), hence h = 10⁻⁸, where round-off is still ~10⁻⁸.
  const auto c = testing::check_gradient(s.p, [&] { return s.energy(); }, 1e-8);
  std::cout << "[ fd ] wall repulsion " << D << "D: " << s.p.size() << " particles, max error / max |F| = "
            << c.max_error << "\n";
  EXPECT_GT(c.max_force, 1.0);
  EXPECT_LE(c.max_error, 1e-6);
}

TEST(WallRepulsion, ForceIsMinusTheEnergyGradient2D) {
  std::vector<V2> x;
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> jitter(-0.35, 0.35);
  const V2 spots[] = {{{14.7, 5.0}}, {{-14.6, 3.0}}, {{14.6, 0.3}}, {{2.1, 0.3}}, {{-2.2, 0.35}}, {{6.0, 0.25}},
                      {{0.0, 0.3}},  {{1.9, -0.1}}};  // walls, corners, the rims
  for (const V2& c : spots)
    for (int k = 0; k < 3; ++k) x.push_back(V2{{c[0] + jitter(gen), c[1] + jitter(gen)}});
  WallScene<2> s(hopper_walls_2d<double>(30.0, 4.0, 90.0), x);
  expect_wall_force_is_minus_gradient(s);
  WallScene<2> slanted(hopper_walls_2d<double>(30.0, 4.0, 60.0), x);
  expect_wall_force_is_minus_gradient(slanted);
}

TEST(WallRepulsion, ForceIsMinusTheEnergyGradient3D) {
  std::vector<V3> x;
  std::mt19937 gen(6);
  std::uniform_real_distribution<double> jitter(-0.35, 0.35);
  const V3 spots[] = {{{9.6, 0.0, 4.0}}, {{0.0, -9.7, 0.3}}, {{2.1, 0.2, 0.3}}, {{-1.5, 1.4, 0.3}},
                      {{5.0, 5.0, 0.25}}, {{1.95, 0.0, -0.1}}};
  for (const V3& c : spots)
    for (int k = 0; k < 3; ++k) x.push_back(V3{{c[0] + jitter(gen), c[1] + jitter(gen), c[2] + jitter(gen)}});
  WallScene<3> s(hopper_walls_3d<double>(20.0, 4.0, 90.0), x);
  expect_wall_force_is_minus_gradient(s);
}

// Eq. 3 for one particle above the flat base: U = (ε_w/2)(1 − 2d/σ_m)², with its own σ_m; a particle
// in the corner of side wall and base feels both walls.
TEST(WallRepulsion, UsesTheParticlesOwnDiameterAndSumsCorners) {
  WallScene<2> s(hopper_walls_2d<double>(30.0, 4.0, 90.0),
                 {V2{{8.0, 0.4}}, V2{{8.0, 0.4}}, V2{{14.65, 0.3}}});  // types 0, 1, 0
  const double e = s.energy();
  const double small = 0.5 * 50 * std::pow(1 - 2 * 0.4 / 1.0, 2), large = 0.5 * 50 * std::pow(1 - 2 * 0.4 / 1.4, 2);
  const double corner = 0.5 * 50 * (std::pow(1 - 2 * 0.35 / 1.0, 2) + std::pow(1 - 2 * 0.3 / 1.0, 2));
  EXPECT_NEAR(e, small + large + corner, 1e-12);
  auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.p.f);
  EXPECT_NEAR(f(2, 0), -50 * 2.0 * (1 - 2 * 0.35), 1e-12);  // pushed off the side wall x = 15
  EXPECT_NEAR(f(2, 1), 50 * 2.0 * (1 - 2 * 0.3), 1e-12);    // and up off the base
}

// Wall candidates marked with margin m, then every particle moved by up to m: the marked sum equals
// the full sum bitwise (forces and energy); moved further, a particle can reach an unmarked wall.
template <int D>
void expect_candidates_give_the_full_sum(const std::vector<Shape<D, double>>& shapes, double extent) {
  const int n = 4000;
  const double margin = 0.3;
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> lateral(-extent, extent), height(-1.0, 40.0), unit(-1, 1);
  std::vector<Vec<D, double>> x(n);
  for (auto& xi : x) {
    for (int d = 0; d < D - 1; ++d) xi[d] = lateral(gen);
    xi[D - 1] = height(gen);
  }
  WallScene<D> s(shapes, x);
  Kokkos::View<unsigned*, Exec> candidates("candidates", n);
  sp::find_wall_candidates(margin, s.sizes, s.walls, s.p, candidates);
  for (auto& xi : x) {
    Vec<D, double> step;
    do {
      for (int d = 0; d < D; ++d) step[d] = unit(gen);
    } while (norm2(step) > 1);
    xi += (margin * 0.999) * step;
  }
  WallScene<D> moved(shapes, x);
  const double full = moved.energy();
  auto f_full = Kokkos::create_mirror(moved.p.f);  // a copy, not an alias of the host-accessible view
  Kokkos::deep_copy(f_full, moved.p.f);
  moved.p.zero_forces();
  const double marked = sp::accumulate_wall_repulsion(50.0, moved.sizes, moved.walls, moved.p, candidates);
  const auto f_marked = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), moved.p.f);
  EXPECT_GT(full, 1.0);
  EXPECT_EQ(full, marked);
  int touching = 0;
  for (int i = 0; i < n; ++i) {
    bool any = false;
    for (int d = 0; d < D; ++d) {
      EXPECT_EQ(f_full(i, d), f_marked(i, d)) << "particle " << i;
      any = any || f_full(i, d) != 0;
    }
    touching += any;
  }
  const auto mask = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), candidates);
  int marked_particles = 0;
  for (int i = 0; i < n; ++i) marked_particles += mask(i) != 0;
  std::cout << "[ candidates ] " << D << "D: " << touching << " particles touch a wall, " << marked_particles
            << " of " << n << " marked\n";
  EXPECT_GT(touching, 50);
  EXPECT_LT(marked_particles, n / 2);  // the point: most particles skip the wall term
  // Moved 3 margins instead, some particle reaches a wall it was not marked for.
  WallScene<D> far(shapes, x);
  {
    auto h = Kokkos::create_mirror_view(far.p.x);
    Kokkos::deep_copy(h, far.p.x);
    for (int i = 0; i < n; ++i) h(i, D - 1) -= 3 * margin;
    Kokkos::deep_copy(far.p.x, h);
  }
  const double far_full = far.energy();
  far.p.zero_forces();
  EXPECT_NE(far_full, sp::accumulate_wall_repulsion(50.0, far.sizes, far.walls, far.p, candidates));
  Kokkos::View<unsigned*, Exec> wrong_size("wrong", n - 1);
  EXPECT_THROW(sp::accumulate_wall_repulsion(50.0, far.sizes, far.walls, far.p, wrong_size), std::invalid_argument);
  EXPECT_THROW(sp::find_wall_candidates(-0.1, s.sizes, s.walls, s.p, candidates), std::invalid_argument);
}

TEST(WallRepulsion, CandidateWallsGiveTheFullSumBitwise) {
  expect_candidates_give_the_full_sum<2>(hopper_walls_2d<double>(30.0, 4.0, 60.0), 15.5);
  expect_candidates_give_the_full_sum<3>(hopper_walls_3d<double>(24.0, 4.0, 90.0), 8.6);
}

}  // namespace
}  // namespace mesoflow
