// capsule_mesh.cpp — host-side construction of the two-layer membrane (capsule_mesh.hpp, paper §3).
#include "capsule_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

namespace mesoflow::msm {

namespace {

using Point = std::array<double, 3>;

Point normalized(const Point& p) {
  const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  return {p[0] / r, p[1] / r, p[2] / r};
}

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

LayerTriangulation icosphere(int level) {
  require(level >= 0 && level <= 9, "icosphere: level must be in [0, 9], got " + std::to_string(level));
  const double t = (1 + std::sqrt(5.0)) / 2;
  LayerTriangulation s;
  s.vertex = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
              {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& v : s.vertex) v = normalized(v);
  s.triangle = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      const Point& pa = s.vertex[std::size_t(a)];
      const Point& pb = s.vertex[std::size_t(b)];
      s.vertex.push_back(normalized({pa[0] + pb[0], pa[1] + pb[1], pa[2] + pb[2]}));
      const int m = int(s.vertex.size()) - 1;
      midpoint.emplace(key, m);
      return m;
    };
    std::vector<std::array<int, 3>> finer;
    finer.reserve(4 * s.triangle.size());
    for (const auto& f : s.triangle) {
      const int ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    s.triangle = std::move(finer);
  }
  for (const auto& f : s.triangle)
    for (int e = 0; e < 3; ++e) {
      const int a = f[std::size_t(e)], b = f[std::size_t((e + 1) % 3)];
      s.edge.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(s.edge.begin(), s.edge.end());
  s.edge.erase(std::unique(s.edge.begin(), s.edge.end()), s.edge.end());
  return s;
}

void MembraneBondParameters::validate() const {
  require(std::isfinite(k_b) && k_b > 0, "membrane: k_b must be > 0, got " + std::to_string(k_b));
  require(std::isfinite(diagonal_factor) && diagonal_factor >= 0,
          "membrane: diagonal_factor must be >= 0, got " + std::to_string(diagonal_factor));
}

double MembraneMesh::mean_in_layer_bond_length() const {
  double sum = 0;
  long long n = 0;
  for (std::size_t b = 0; b < bond.size(); ++b)
    if (kind[b] == BondKind::in_layer) {
      sum += r0[b];
      ++n;
    }
  return n > 0 ? sum / double(n) : 0.0;
}

MembraneMesh two_layer_membrane(const LayerTriangulation& outer, const std::vector<std::array<double, 3>>& inner,
                                const MembraneBondParameters& bonds, const std::array<double, 3>& period) {
  bonds.validate();
  const int n = int(outer.vertex.size());
  require(inner.size() == outer.vertex.size(), "membrane: " + std::to_string(outer.vertex.size()) +
                                                   " outer but " + std::to_string(inner.size()) + " inner vertices");
  MembraneMesh m;
  m.vertices_per_layer = n;
  m.period = period;
  m.triangle = outer.triangle;
  m.position = outer.vertex;
  m.position.insert(m.position.end(), inner.begin(), inner.end());

  auto add = [&](int a, int b, double k, BondKind kind) {
    const auto& pa = m.position[std::size_t(a)];
    const auto& pb = m.position[std::size_t(b)];
    double r2 = 0;
    for (std::size_t d = 0; d < 3; ++d) {
      double dx = pb[d] - pa[d];
      if (period[d] > 0) dx -= period[d] * std::round(dx / period[d]);
      r2 += dx * dx;
    }
    m.bond.push_back({a, b});
    m.k.push_back(k);
    m.r0.push_back(std::sqrt(r2));
    m.kind.push_back(kind);
  };
  const std::size_t num_diagonals = (bonds.diagonals == DiagonalBonds::both_per_quad ? 2 : 1) * outer.edge.size();
  const std::size_t total = 2 * outer.edge.size() + std::size_t(n) + num_diagonals;
  m.bond.reserve(total);
  m.k.reserve(total);
  m.r0.reserve(total);
  m.kind.reserve(total);
  const double k_b = bonds.k_b, k_d = bonds.diagonal_factor * bonds.k_b;
  for (int layer = 0; layer < 2; ++layer)
    for (const auto& e : outer.edge) add(layer * n + e[0], layer * n + e[1], k_b, BondKind::in_layer);
  for (int v = 0; v < n; ++v) add(v, n + v, k_b, BondKind::partner);
  for (const auto& e : outer.edge) {
    add(e[0], n + e[1], k_d, BondKind::diagonal);
    if (bonds.diagonals == DiagonalBonds::both_per_quad) add(e[1], n + e[0], k_d, BondKind::diagonal);
  }
  for (std::size_t b = 0; b < m.r0.size(); ++b)
    require(m.r0[b] > 0, "membrane: bond " + std::to_string(b) + " joins two coincident particles");
  return m;
}

void CapsuleMembraneParameters::validate() const {
  require(std::isfinite(radius) && radius > 0, "capsule membrane: radius must be > 0, got " + std::to_string(radius));
  require(std::isfinite(thickness) && thickness > 0 && thickness < radius,
          "capsule membrane: thickness h_t must be in (0, radius = " + std::to_string(radius) + "), got " +
              std::to_string(thickness));
  for (double c : centre) require(std::isfinite(c), "capsule membrane: centre must be finite");
  bonds.validate();
}

MembraneMesh capsule_membrane(const CapsuleMembraneParameters& par) {
  par.validate();
  LayerTriangulation sphere = icosphere(par.level);
  std::vector<Point> inner(sphere.vertex.size());
  const double r_in = par.radius - par.thickness;
  for (std::size_t v = 0; v < sphere.vertex.size(); ++v) {
    const Point u = sphere.vertex[v];
    for (std::size_t d = 0; d < 3; ++d) {
      sphere.vertex[v][d] = par.centre[d] + par.radius * u[d];
      inner[v][d] = par.centre[d] + r_in * u[d];
    }
  }
  return two_layer_membrane(sphere, inner, par.bonds);
}

void FlatMembraneParameters::validate() const {
  require(nx >= 3, "flat membrane: nx must be >= 3, got " + std::to_string(nx));
  require(ny >= 4 && ny % 2 == 0, "flat membrane: ny must be even and >= 4, got " + std::to_string(ny));
  require(std::isfinite(spacing) && spacing > 0, "flat membrane: spacing must be > 0, got " + std::to_string(spacing));
  require(std::isfinite(thickness) && thickness > 0,
          "flat membrane: thickness must be > 0, got " + std::to_string(thickness));
  require(std::isfinite(z0), "flat membrane: z0 must be finite");
  bonds.validate();
}

MembraneMesh flat_membrane(const FlatMembraneParameters& par) {
  par.validate();
  const int nx = par.nx, ny = par.ny;
  const double dx = par.spacing, dy = 0.5 * std::sqrt(3.0) * par.spacing;
  auto site = [&](int i, int j) { return ((i % nx + nx) % nx) + nx * ((j % ny + ny) % ny); };
  LayerTriangulation top;
  std::vector<Point> bottom;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5 * (j % 2)) * dx, y = j * dy;
      top.vertex.push_back({x, y, par.z0 + par.thickness});
      bottom.push_back({x, y, par.z0});
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      // The sites up-left and up-right of (i, j): rows alternate their half-spacing shift.
      const int s = site(i, j), east = site(i + 1, j);
      const int up_left = site(j % 2 ? i : i - 1, j + 1), up_right = site(j % 2 ? i + 1 : i, j + 1);
      top.edge.push_back({s, east});      // lattice vector at 0°
      top.edge.push_back({s, up_right});  // 60°
      top.edge.push_back({s, up_left});   // 120°
      top.triangle.push_back({s, east, up_right});
      top.triangle.push_back({s, up_right, up_left});
    }
  return two_layer_membrane(top, bottom, par.bonds, {nx * dx, ny * dy, 0.0});
}

}  // namespace mesoflow::msm
