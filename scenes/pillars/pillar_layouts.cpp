#include "scenes/pillars/pillar_layouts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <stdexcept>
#include <string>

namespace mesoflow::pillars {

namespace {

constexpr double pi = 3.14159265358979323846;

std::string str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

// Minimum-image component: exact for a rectangular box.
double min_image(double dx, double length) { return dx - length * std::round(dx / length); }

double wrap(double x, double length) {
  double w = x - length * std::floor(x / length);
  return w >= length ? 0.0 : w;  // x slightly below 0 can round up to exactly `length`
}

// Uniform in [0, 1) from 53 random bits: the same sequence with every standard library.
double uniform01(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }

}  // namespace

double PillarLayout::porosity() const {
  return 1.0 - double(centres.size()) * pi * diameter * diameter / (4.0 * length_x * length_y);
}

double PillarLayout::min_gap() const {
  if (centres.empty()) return std::numeric_limits<double>::infinity();
  double min_d2 = std::min(length_x, length_y);  // a pillar and its own nearest image
  min_d2 *= min_d2;
  for (std::size_t i = 0; i < centres.size(); ++i)
    for (std::size_t j = i + 1; j < centres.size(); ++j) {
      const double dx = min_image(centres[i][0] - centres[j][0], length_x);
      const double dy = min_image(centres[i][1] - centres[j][1], length_y);
      min_d2 = std::min(min_d2, dx * dx + dy * dy);
    }
  return std::sqrt(min_d2) - diameter;
}

Lattice parse_lattice(const std::string& name) {
  if (name == "square") return Lattice::square;
  if (name == "rotated-square") return Lattice::rotated_square;
  if (name == "hexagonal") return Lattice::hexagonal;
  throw std::invalid_argument("parse_lattice: unknown lattice '" + name +
                              "'; allowed: square, rotated-square, hexagonal");
}

std::string lattice_name(Lattice lattice) {
  switch (lattice) {
    case Lattice::square: return "square";
    case Lattice::rotated_square: return "rotated-square";
    case Lattice::hexagonal: return "hexagonal";
  }
  return "?";
}

double max_packing_fraction(Lattice lattice) {
  return lattice == Lattice::hexagonal ? pi / (2.0 * std::sqrt(3.0)) : pi / 4.0;
}

PillarLayout regular_lattice(Lattice lattice, double porosity, double diameter, int cells_x, int cells_y) {
  const double eps_min = 1.0 - max_packing_fraction(lattice);
  if (!(porosity > eps_min && porosity < 1.0))
    throw std::invalid_argument("regular_lattice: porosity must be in (" + str(eps_min) + ", 1) for the " +
                                lattice_name(lattice) + " lattice (pillars touch at the lower end), got " +
                                str(porosity));
  if (!(diameter > 0) || !std::isfinite(diameter))
    throw std::invalid_argument("regular_lattice: diameter must be finite and > 0, got " + str(diameter));
  if (cells_x < 1 || cells_y < 1)
    throw std::invalid_argument("regular_lattice: cells_x and cells_y must be >= 1, got " +
                                std::to_string(cells_x) + " and " + std::to_string(cells_y));
  const double phi = 1.0 - porosity;
  double cell_x = 0, cell_y = 0;
  std::vector<std::array<double, 2>> basis;  // pillar positions in units of the cell
  switch (lattice) {
    case Lattice::square:
      cell_x = cell_y = diameter * std::sqrt(pi / (4.0 * phi));
      basis = {{0.5, 0.5}};
      break;
    case Lattice::rotated_square:
      cell_x = cell_y = diameter * std::sqrt(pi / (4.0 * phi)) * std::sqrt(2.0);
      basis = {{0.25, 0.25}, {0.75, 0.75}};
      break;
    case Lattice::hexagonal:
      cell_x = diameter * std::sqrt(pi / (2.0 * std::sqrt(3.0) * phi));
      cell_y = std::sqrt(3.0) * cell_x;
      basis = {{0.25, 0.25}, {0.75, 0.75}};
      break;
  }
  PillarLayout layout;
  layout.length_x = cells_x * cell_x;
  layout.length_y = cells_y * cell_y;
  layout.diameter = diameter;
  for (int j = 0; j < cells_y; ++j)
    for (int i = 0; i < cells_x; ++i)
      for (const auto& b : basis) layout.centres.push_back({(i + b[0]) * cell_x, (j + b[1]) * cell_y});
  return layout;
}

PillarLayout irregular_array(int pillars, double porosity, double diameter, double aspect,
                             double exclusion_factor, long long mc_sweeps, std::uint64_t seed,
                             MonteCarloStats* stats) {
  const std::string f = "irregular_array: ";
  if (pillars < 1) throw std::invalid_argument(f + "pillars must be >= 1, got " + std::to_string(pillars));
  if (!(porosity > 0 && porosity < 1))
    throw std::invalid_argument(f + "porosity must be in (0, 1), got " + str(porosity));
  if (!(diameter > 0) || !std::isfinite(diameter))
    throw std::invalid_argument(f + "diameter must be finite and > 0, got " + str(diameter));
  if (!(aspect > 0) || !std::isfinite(aspect))
    throw std::invalid_argument(f + "aspect (Ly/Lx) must be finite and > 0, got " + str(aspect));
  if (!(exclusion_factor >= 1) || !std::isfinite(exclusion_factor))
    throw std::invalid_argument(f + "exclusion_factor must be finite and >= 1, got " + str(exclusion_factor));
  if (mc_sweeps < 0) throw std::invalid_argument(f + "mc_sweeps must be >= 0, got " + std::to_string(mc_sweeps));

  const int n = pillars;
  const double area = n * pi * diameter * diameter / (4.0 * (1.0 - porosity));
  PillarLayout layout;
  layout.length_x = std::sqrt(area / aspect);
  layout.length_y = aspect * layout.length_x;
  layout.diameter = diameter;
  const double Lx = layout.length_x, Ly = layout.length_y;
  const double d_star = exclusion_factor * diameter, d_star2 = d_star * d_star;

  // Near-square starting lattice nx × ny >= n with the widest spacing.
  int nx = 1, ny = n;
  double spacing = 0;
  for (int kx = 1; kx <= n; ++kx) {
    const int ky = (n + kx - 1) / kx;
    const double s = std::min(Lx / kx, Ly / ky);
    if (s > spacing) spacing = s, nx = kx, ny = ky;
  }
  if (!(spacing > d_star * (1 + 1e-12)))
    throw std::invalid_argument(
        f + "the " + std::to_string(n) + " exclusion discs of diameter exclusion_factor*d = " + str(d_star) +
        " cover " + str((1 - porosity) * exclusion_factor * exclusion_factor) +
        " of the box ((1 - porosity)*exclusion_factor^2); the square-lattice start needs a spacing > d*, "
        "i.e. this fraction below pi/4 = 0.785 (less when " + std::to_string(n) +
        " sites do not fill a lattice evenly at aspect " + str(aspect) +
        "): raise the porosity or lower the exclusion_factor");

  std::mt19937_64 rng(seed);
  std::vector<int> sites(std::size_t(nx) * ny);
  for (std::size_t s = 0; s < sites.size(); ++s) sites[s] = int(s);
  for (std::size_t s = sites.size() - 1; s > 0; --s) std::swap(sites[s], sites[rng() % (s + 1)]);
  auto& pos = layout.centres;
  pos.resize(n);
  for (int i = 0; i < n; ++i)
    pos[i] = {(sites[i] % nx + 0.5) * Lx / nx, (sites[i] / nx + 0.5) * Ly / ny};

  // Cell list with cells at least d* wide; a 3 × 3 neighbourhood then holds every possible
  // overlap. Below 3 cells in a direction the neighbourhood would repeat cells: check all pairs.
  const int ncx = int(Lx / d_star), ncy = int(Ly / d_star);
  const bool use_cells = ncx >= 3 && ncy >= 3;
  std::vector<std::vector<int>> members(use_cells ? std::size_t(ncx) * ncy : 0);
  std::vector<int> cell_of(n, 0);
  auto cell_index = [&](double x, double y) {
    const int cx = std::min(int(x / Lx * ncx), ncx - 1), cy = std::min(int(y / Ly * ncy), ncy - 1);
    return cy * ncx + cx;
  };
  if (use_cells)
    for (int i = 0; i < n; ++i) members[cell_of[i] = cell_index(pos[i][0], pos[i][1])].push_back(i);

  auto overlaps = [&](int i, double x, double y) {
    auto hit = [&](int j) {
      if (j == i) return false;
      const double dx = min_image(x - pos[j][0], Lx), dy = min_image(y - pos[j][1], Ly);
      return dx * dx + dy * dy < d_star2;
    };
    if (!use_cells) {
      for (int j = 0; j < n; ++j)
        if (hit(j)) return true;
      return false;
    }
    const int c = cell_index(x, y), cx = c % ncx, cy = c / ncx;
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox)
        for (int j : members[((cy + oy + ncy) % ncy) * ncx + (cx + ox + ncx) % ncx])
          if (hit(j)) return true;
    return false;
  };

  double step = std::max(0.5 * (spacing - d_star), 1e-3 * diameter);
  const double log_min = std::log(1e-9 * diameter), log_max = std::log(0.5 * std::min(Lx, Ly));
  double log_step = std::log(step), log_step_sum = 0;
  long long averaged = 0;
  const long long adapt_sweeps = mc_sweeps / 5;
  long long attempted = 0, accepted = 0;
  for (long long sweep = 0; sweep < mc_sweeps; ++sweep) {
    long long sweep_accepted = 0;
    for (int move = 0; move < n; ++move) {
      const int i = int(rng() % std::uint64_t(n));
      const double x = wrap(pos[i][0] + step * (2 * uniform01(rng) - 1), Lx);
      const double y = wrap(pos[i][1] + step * (2 * uniform01(rng) - 1), Ly);
      if (overlaps(i, x, y)) continue;
      pos[i] = {x, y};
      ++sweep_accepted;
      if (use_cells) {
        const int c = cell_index(x, y);
        if (c != cell_of[i]) {
          auto& old = members[cell_of[i]];
          *std::find(old.begin(), old.end(), i) = old.back();
          old.pop_back();
          members[cell_of[i] = c].push_back(i);
        }
      }
    }
    if (sweep < adapt_sweeps) {
      // Robbins–Monro on ln δ with a decaying gain; the frozen step is the average of ln δ over the
      // second half of the adaptation, which damps the noise of sweeps of only a few dozen moves.
      const double acceptance = double(sweep_accepted) / n;
      log_step = std::clamp(log_step + 2.0 / std::sqrt(1.0 + sweep) * (acceptance - 0.4), log_min, log_max);
      if (2 * sweep >= adapt_sweeps) log_step_sum += log_step, ++averaged;
      step = sweep + 1 < adapt_sweeps ? std::exp(log_step) : std::exp(log_step_sum / averaged);
    } else {
      attempted += n;
      accepted += sweep_accepted;
    }
  }
  if (stats) {
    stats->acceptance_ratio = attempted > 0 ? double(accepted) / attempted : std::numeric_limits<double>::quiet_NaN();
    stats->step_size = step;
    stats->attempted_moves = mc_sweeps * n;
  }
  return layout;
}

void write_csv(const PillarLayout& layout, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("write_csv: cannot open '" + path + "' for writing");
  char buf[128];
  auto line = [&](const char* key, double v) {
    std::snprintf(buf, sizeof buf, "# %s = %.17g\n", key, v);
    out << buf;
  };
  line("Lx", layout.length_x);
  line("Ly", layout.length_y);
  line("d", layout.diameter);
  line("porosity", layout.porosity());
  out << "x,y\n";
  for (const auto& c : layout.centres) {
    std::snprintf(buf, sizeof buf, "%.17g,%.17g\n", c[0], c[1]);
    out << buf;
  }
  if (!out) throw std::runtime_error("write_csv: error while writing '" + path + "'");
}

PillarLayout read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("read_csv: cannot open '" + path + "'");
  auto trim = [](const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r"), e = s.find_last_not_of(" \t\r");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
  };
  auto number = [](const std::string& s, double& v) {
    if (s.empty()) return false;
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size() && std::isfinite(v);
  };
  std::map<std::string, double> header;
  PillarLayout layout;
  std::string raw;
  int line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    const std::string where = "read_csv: " + path + ":" + std::to_string(line_no) + ": ";
    const std::string s = trim(raw);
    if (s.empty() || s == "x,y") continue;
    if (s[0] == '#') {
      const auto eq = s.find('=');
      if (eq == std::string::npos) continue;  // a plain comment
      const std::string key = trim(s.substr(1, eq - 1)), value = trim(s.substr(eq + 1));
      if (key != "Lx" && key != "Ly" && key != "d" && key != "porosity") continue;
      double v;
      if (!number(value, v)) throw std::invalid_argument(where + "'" + key + "' is not a number: '" + value + "'");
      header[key] = v;
      continue;
    }
    const auto comma = s.find(',');
    double x = 0, y = 0;
    if (comma == std::string::npos || !number(trim(s.substr(0, comma)), x) || !number(trim(s.substr(comma + 1)), y))
      throw std::invalid_argument(where + "expected 'x,y' with two numbers, got '" + s + "'");
    layout.centres.push_back({x, y});
  }
  const std::string f = "read_csv: " + path + ": ";
  for (const char* key : {"Lx", "Ly"})
    if (!header.count(key) || !(header[key] > 0))
      throw std::invalid_argument(f + "needs a header line '# " + key + " = <value > 0>'");
  if (layout.centres.empty()) throw std::invalid_argument(f + "no pillar centres");
  layout.length_x = header["Lx"];
  layout.length_y = header["Ly"];
  for (auto& c : layout.centres) c = {wrap(c[0], layout.length_x), wrap(c[1], layout.length_y)};
  const bool has_d = header.count("d") != 0, has_eps = header.count("porosity") != 0;
  if (has_eps && !(header["porosity"] > 0 && header["porosity"] < 1))
    throw std::invalid_argument(f + "porosity must be in (0, 1), got " + str(header["porosity"]));
  if (has_d) {
    if (!(header["d"] > 0)) throw std::invalid_argument(f + "d must be > 0, got " + str(header["d"]));
    layout.diameter = header["d"];
    if (has_eps && std::abs(layout.porosity() - header["porosity"]) > 1e-9)
      throw std::invalid_argument(f + "'# porosity = " + str(header["porosity"]) + "' disagrees with the " +
                               str(layout.porosity()) + " given by Lx, Ly, d and the " +
                               std::to_string(layout.centres.size()) + " centres");
  } else if (has_eps) {
    layout.diameter = std::sqrt(4.0 * (1.0 - header["porosity"]) * layout.length_x * layout.length_y /
                                (double(layout.centres.size()) * pi));
  } else {
    throw std::invalid_argument(f + "needs '# d = <diameter>' or '# porosity = <porosity>'");
  }
  return layout;
}

}  // namespace mesoflow::pillars
