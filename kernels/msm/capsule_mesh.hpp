// capsule_mesh.hpp — the capsule membrane of paper §3 (Fig. 1b) as a mass-spring network (§2.3,
// eq. 7): two concentric triangulated spheres a distance h_t apart, particles on the vertices;
// host-side setup (capsule_mesh.cpp), with helpers that upload it into the Views of
// harmonic_bonds.hpp and of Particles.
//
// Each sphere is an icosphere: an icosahedron whose triangles are split into four, level times,
// every new vertex projected onto the sphere; level ℓ has V = 10·4^ℓ + 2 vertices, E = 30·4^ℓ
// edges and F = 20·4^ℓ triangles (V − E + F = 2), 12 vertices of valence 5 and the rest of 6. The
// outer sphere has the capsule's radius a (the paper's r = d/2: the paper does not say which of the
// two spheres is the capsule surface; we take the outer one, which the outer fluid sees and whose
// extent the deformation index D_∞ measures), the inner one a − h_t; vertex v of the inner sphere
// sits radially below vertex v of the outer one (its "adjacent particle"). Particles 0 .. V − 1
// are the outer layer, V .. 2V − 1 the inner one.
//
// Bonds, as §3 states them, rest lengths = the initial distances:
//   in-layer   every edge of both spheres,                            k_b
//   partner    v (outer) — v (inner),                                 k_b
//   diagonal   a particle — a neighbour of its partner on the other sphere,   2/3 k_b
// How many diagonals: the paper's capsule has 5124 particles = 2V at ℓ = 4 (V = 2562, E = 7680)
// and 25 602 bonds. In-layer and partner bonds make 2E + V = 17 922; the remaining 7680 = E, i.e.
// ONE diagonal per in-layer edge — per quadrilateral side face (u, v, v', u') of the prism layer
// between the spheres, which thus splits into tetrahedra (the shell's bonds are the edges of a
// tetrahedral mesh, 3E + V). Bonding every particle to every neighbour of its partner would put
// both diagonals in each quad: 2E = 15 360 diagonals, 33 282 bonds, not the paper's count (the
// only other split into 3E + V — in-layer bonds on one sphere only, both diagonals — contradicts
// "connected to their neighboring particles on the same sphere"). DiagonalBonds::one_per_quad is
// the paper's count; both_per_quad is the crossed variant. Only the crossed network has the
// in-plane elasticity §4 quotes, E = 5 k_b/(√3 δ_ave) and ν = 1/4 (exactly, at h_t = δ_ave, E being
// the stretching modulus over h_t); the paper's count gives ν = 1/3 and, at h_t = δ_ave, 0.84 of
// that E (tests/msm/test_msm_membrane.cpp derives and measures both).
// Which diagonal of a quad: the triangulation's edges are oriented, edge (u → v) giving the bond
// u (outer) — v (inner). The icosphere orients each edge from its lower to its higher vertex index,
// i.e. the diagonal through the quad's lowest-numbered vertex, the standard consistent rule for
// splitting prisms into tetrahedra (Dompierre, Labbé, Vallet & Camarero, 8th International Meshing
// Roundtable, 1999); the flat lattice orients its edges along the lattice vectors at 0°, 60° and
// 120°, the same diagonal in every quad of a direction.
//
// δ_ave ("the average length of bonds on the membrane", §4) is taken as the mean rest length of the
// in-layer bonds of both spheres: the lattice spacing of the triangulated network, which is what
// E = 5 k_b/(√3 δ_ave) is written in (a mean over all bonds would mix in h_t and the √(δ² + h_t²)
// diagonals).
//
// The flat patch (flat_membrane): the same two-layer construction on a periodic triangular lattice
// in the xy plane, outer layer at z0 + h_t above the inner one at z0: for measuring the in-plane
// elastic constants of the network.
#pragma once

#include "kernels/common/particles.hpp"
#include "harmonic_bonds.hpp"

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesoflow::msm {

enum class BondKind : int { in_layer = 0, partner = 1, diagonal = 2 };

// Diagonal bonds per quadrilateral between the layers: one (the paper's 25 602-bond count) or both.
enum class DiagonalBonds { one_per_quad, both_per_quad };

// One triangulated layer: vertices, triangles counter-clockwise seen from outside (from +z for the
// flat lattice), and each edge once, oriented (u → v) for the diagonal rule.
struct LayerTriangulation {
  std::vector<std::array<double, 3>> vertex;
  std::vector<std::array<int, 3>> triangle;
  std::vector<std::array<int, 2>> edge;
};

// The level-ℓ icosphere on the unit sphere (edges oriented from lower to higher index).
LayerTriangulation icosphere(int level);

struct MembraneBondParameters {
  double k_b = 1;                           // eq. (7): in-layer and partner bonds
  double diagonal_factor = 2.0 / 3.0;       // diagonal bonds: diagonal_factor · k_b (§3: 2/3)
  DiagonalBonds diagonals = DiagonalBonds::one_per_quad;
  void validate() const;
};

// Particles (outer layer 0 .. V − 1, inner layer V .. 2V − 1, partner of v is v + V) and bonds.
struct MembraneMesh {
  int vertices_per_layer = 0;
  std::vector<std::array<double, 3>> position;
  std::vector<std::array<int, 3>> triangle;  // of the outer layer; the inner layer's are + V
  std::vector<std::array<int, 2>> bond;
  std::vector<double> k, r0;
  std::vector<BondKind> kind;
  std::array<double, 3> period{};  // periodic box lengths the rest lengths were measured in; 0: open

  int num_particles() const { return int(position.size()); }
  int num_bonds() const { return int(bond.size()); }
  // δ_ave: the mean rest length of the in-layer bonds of both layers.
  double mean_in_layer_bond_length() const;
};

// Two layers over one triangulation: `outer` gives the outer vertices, `inner` the inner ones (same
// numbering); bonds as described above, rest lengths the distances (minimum image along the axes
// where period > 0).
MembraneMesh two_layer_membrane(const LayerTriangulation& outer, const std::vector<std::array<double, 3>>& inner,
                                const MembraneBondParameters& bonds, const std::array<double, 3>& period = {});

struct CapsuleMembraneParameters {
  std::array<double, 3> centre{};
  double radius = 0.5;    // a: outer sphere (capsule radius r = d/2)
  double thickness = 0;   // h_t: the inner sphere has radius a − h_t; required, in (0, a)
  int level = 4;          // icosphere subdivisions: the paper's 5124 particles are level 4
  MembraneBondParameters bonds;
  void validate() const;
};

MembraneMesh capsule_membrane(const CapsuleMembraneParameters& par);

struct FlatMembraneParameters {
  int nx = 6, ny = 6;     // lattice sites along x and rows along y (ny even: periodic rows)
  double spacing = 1;     // δ: in-layer bond length
  double thickness = 1;   // h_t: layer separation along z
  double z0 = 0;          // inner layer height
  MembraneBondParameters bonds;
  void validate() const;
};

// Periodic in x and y with period (nx δ, ny √3/2 δ, 0); site (i, j) of row j at
// ((i + (j mod 2)/2) δ, j √3/2 δ), index i + nx j.
MembraneMesh flat_membrane(const FlatMembraneParameters& par);

// The mesh's bonds as a HarmonicBondList on ExecSpace, its particles starting at first_particle.
template <class Real, class ExecSpace>
HarmonicBondList<Real, ExecSpace> upload_bonds(const MembraneMesh& mesh, int first_particle = 0) {
  return make_harmonic_bond_list<Real, ExecSpace>(mesh.bond, mesh.k, mesh.r0, first_particle);
}

// p.x rows first_particle .. first_particle + 2V − 1 ← the mesh's positions (setup: a host copy).
template <int D, class Real, class ExecSpace>
void upload_positions(const MembraneMesh& mesh, const Particles<D, Real, ExecSpace>& p, int first_particle = 0) {
  static_assert(D == 3, "the membrane mesh is three-dimensional");
  if (first_particle < 0 || std::size_t(first_particle + mesh.num_particles()) > p.size())
    throw std::invalid_argument("upload_positions: " + std::to_string(mesh.num_particles()) +
                                " membrane particles from " + std::to_string(first_particle) + " do not fit into " +
                                std::to_string(p.size()) + " particles");
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
  for (int i = 0; i < mesh.num_particles(); ++i)
    for (int d = 0; d < 3; ++d) x(first_particle + i, d) = Real(mesh.position[std::size_t(i)][std::size_t(d)]);
  Kokkos::deep_copy(p.x, x);
}

}  // namespace mesoflow::msm
