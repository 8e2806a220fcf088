// pillar_layouts.hpp — 2D pillar (disc) configurations for the pillar-array permeability paper
// (Hulikal Chakrapani et al., Soft Matter 2023): the regular lattices of Fig. 1 (square, square
// rotated by 45°, hexagonal with rows along the flow) and the irregular arrays of section 2.3
// (hard-disk Monte Carlo of discs of diameter d* = 1.2 d started on a square lattice), in a
// periodic rectangle [0, Lx) × [0, Ly) with the flow along +x. Host-side, no Kokkos.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace mesoflow::pillars {

struct PillarLayout {
  double length_x = 0, length_y = 0;  // periodic box Lx × Ly
  double diameter = 0;                // pillar diameter d
  std::vector<std::array<double, 2>> centres;

  // ε = 1 − N π d² / (4 Lx Ly): the fluid area fraction (2D porosity).
  double porosity() const;
  // Smallest surface-to-surface distance between two pillars, periodic images (a pillar's own
  // images included) counted; negative if pillars overlap. Minimum image is exact in a rectangle.
  double min_gap() const;
};

// Fig. 1: Sqr, Rot Sqr, Hex.
enum class Lattice { square, rotated_square, hexagonal };

// "square", "rotated-square", "hexagonal"; anything else throws std::invalid_argument naming them.
Lattice parse_lattice(const std::string& name);
std::string lattice_name(Lattice lattice);

// The highest solid fraction of a lattice (touching pillars): π/4 for both square lattices,
// π/(2√3) for the hexagonal one. A porosity must exceed 1 minus this.
double max_packing_fraction(Lattice lattice);

// cells_x × cells_y conventional cells of the lattice at porosity ε (exact) and diameter d, solid
// fraction φ = 1 − ε:
//   square:         spacing s = d √(π/(4φ)), lattice vectors along x and y, cell s × s, 1 pillar;
//   rotated_square: the same lattice turned by 45°, cell s√2 × s√2 with 2 pillars, nearest
//                   neighbours at ±45° to the flow;
//   hexagonal:      nearest-neighbour distance a = d √(π/(2√3 φ)), rows along x, cell a × √3 a
//                   with 2 pillars.
// Pillars sit at cell centres (square) or at 1/4 and 3/4 of the cell diagonal, so none straddles
// the periodic boundary.
// Throws std::invalid_argument (naming the parameter and the allowed range) for ε outside
// (1 − max_packing_fraction, 1), d ≤ 0 or cells < 1.
PillarLayout regular_lattice(Lattice lattice, double porosity, double diameter, int cells_x, int cells_y);

// What the Monte Carlo of irregular_array did.
struct MonteCarloStats {
  double acceptance_ratio = 0;    // accepted / attempted moves after the step size was frozen
  double step_size = 0;           // the frozen maximum displacement per Cartesian component
  long long attempted_moves = 0;  // all sweeps, adaptation included
};

// Section 2.3: `pillars` discs in a periodic rectangle with Ly/Lx = aspect whose area gives the
// porosity ε exactly for diameter d. Hard discs of diameter d* = exclusion_factor · d (1.2 in the
// paper, leaving gaps ≥ 0.2 d between pillars) start on the near-square lattice nx × ny ≥ pillars
// with the widest spacing (vacant sites chosen at random); a Monte Carlo move displaces a random
// disc by a uniform step in [−δ, δ]² and is rejected on any overlap (minimum image, cell list).
// One sweep = `pillars` attempted moves. During the first fifth of the sweeps ln δ follows a
// Robbins–Monro iteration towards 40 % acceptance after every sweep; δ is then frozen at the mean of
// ln δ over the second half of that phase. Deterministic for a given seed. The paper's
// "10⁷ MC steps" for 800 discs are 12 500 sweeps.
// The start needs a lattice spacing > d*, which requires the d* discs to cover less than π/4 ≈ 0.785
// of the box (φ · exclusion_factor² < π/4; somewhat less when the lattice is not filled evenly);
// impossible inputs throw std::invalid_argument saying so. Also throws for pillars < 1, ε outside
// (0, 1), d ≤ 0, aspect ≤ 0, exclusion_factor < 1, mc_sweeps < 0.
PillarLayout irregular_array(int pillars, double porosity, double diameter, double aspect,
                             double exclusion_factor, long long mc_sweeps, std::uint64_t seed,
                             MonteCarloStats* stats = nullptr);

// CSV with a comment header, so that users can supply their own layouts (e.g. the paper's etched
// 800-pillar cells):
//   # Lx = 123.4
//   # Ly = 61.7
//   # d = 5
//   # porosity = 0.55          (written for information)
//   x,y
//   1.25,3.5
// read_csv needs Lx and Ly; d may be left out if porosity is given (d is then chosen to give that
// porosity, e.g. to rescale an etched layout to the measured porosity); if both are given they
// must agree to 1e-9. Centres are wrapped into the box. Errors name the file and the line.
void write_csv(const PillarLayout& layout, const std::string& path);
PillarLayout read_csv(const std::string& path);

}  // namespace mesoflow::pillars
