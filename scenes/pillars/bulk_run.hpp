// bulk_run.hpp — an MDPD fluid at rest in a fully periodic box (the `pillars` driver's --mode bulk):
// the equilibrium observables that a run of LAMMPS' pair_style mdpd/rhosum + mdpd with fix mvv/dpd
// also gives (docs/mdpd.md, scripts/compare_lammps_mdpd), per sample:
//   ⟨ρ̄⟩       the mean many-body density (1/N) Σ_i ρ̄_i (LAMMPS: compute reduce ave of atom rho);
//   k_BT       Σ m v²/(D(N − 1)) (LAMMPS' compute temp: no centre-of-mass subtraction, dof D(N − 1));
//   P          (Σ m v² + W_C + W_D)/(D V), W_C and W_D the conservative and dissipative virials
//              (kernels/mdpd/conservative_virial.hpp; W_D with the half-step velocities the force
//              saw, v − ½dt f/m, as LAMMPS' press, whose random-force part has zero mean);
// and g(r) over all samples (host, all pairs under the minimum image, normalized as LAMMPS' compute
// rdf: shells of the bin's volume, density (N − 1)/V).
// Velocities are the full-step ones, densities and virial those of the step's force evaluation.
#pragma once

#include "kernels/mdpd/conservative_virial.hpp"
#include "scenes/pillars/pillar_runs.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

namespace mesoflow::pillars {

struct BulkSamples {
  std::vector<double> step, mean_density, temperature, pressure, pressure_virial, pressure_dissipative;
  std::vector<double> rdf_r, rdf;  // bin centres and g(r)
};

template <int D>
class BulkRun {
 public:
  using System = mdpd::MdpdSystem<D, double, Kokkos::DefaultExecutionSpace>;

  // The fluid of `par` at --density in a box of edges --box (x, and y in 3D) and --lz (last axis),
  // started at rest; g(r) in bins of rdf_bin up to rdf_max (at most half the shortest edge).
  BulkRun(const PillarRunParameters& par, double rdf_max, double rdf_bin)
      : mp_(pillar_fluid(par, D)),
        geometry_(periodic_run_geometry<D>(par, 2.4)),
        sys_(mp_, periodic_box<D>(geometry_), std::uint64_t(par.seed), periodic_run_options(par)) {
    fill_fluid(sys_, geometry_, par.density, std::uint64_t(par.seed));
    sys_.begin();
    const double shortest = D == 3 ? std::min({geometry_.Lx, geometry_.Ly, geometry_.Lz})
                                   : std::min(geometry_.Lx, geometry_.Ly);
    if (!(rdf_bin > 0)) throw std::invalid_argument("--rdf-bin must be > 0");
    rdf_max_ = std::min(rdf_max, 0.5 * shortest);
    rdf_bin_ = rdf_bin;
    rdf_bins_ = std::max(1, int(rdf_max_ / rdf_bin_));
  }

  // `equilibrate` steps, then `steps` with a sample every `sample_every` (g(r) every rdf_every-th
  // sample; 0: none); progress(done) after every step.
  BulkSamples run(long long equilibrate, long long steps, long long sample_every, long long rdf_every,
                  long long check_every, const std::function<void(long long)>& progress) {
    watchdog::NanWatchdog watch(watched(sys_), check_every);
    for (long long s = 0; s < equilibrate; ++s) {
      sys_.step();
      watch.after_step();
      progress(s + 1);
    }
    BulkSamples out;
    std::vector<double> hist(std::size_t(rdf_bins_), 0.0);
    long long rdf_samples = 0, samples = 0;
    const int n = int(sys_.particles.size());
    const double volume = this->volume();
    for (long long s = 0; s < steps; ++s) {
      sys_.step();
      watch.after_step();
      if ((s + 1) % sample_every == 0) {
        watch.check();  // no sample from a non-finite state
        const auto v = sys_.particles.v;
        const auto m = sys_.particles.mass;
        const auto rho = sys_.rho;
        const auto sums = parallel_sum<2, Kokkos::DefaultExecutionSpace>(
            "mesoflow::pillars::bulk_sums", n, KOKKOS_LAMBDA(int i, double(&acc)[2]) {
              double v2 = 0;
              for (int d = 0; d < D; ++d) v2 += double(v(i, d)) * double(v(i, d));
              acc[0] += double(m(i)) * v2;
              acc[1] += double(rho(i));
            });
        const double w = mdpd::conservative_virial(mp_, sys_.particles.x, sys_.rho, sys_.neighbor_list(), sys_.box());
        half_step_velocities();
        const double wd = mdpd::dissipative_virial(mp_, sys_.particles.x, v_half_, sys_.neighbor_list(), sys_.box());
        out.step.push_back(double(sys_.current_step()));
        out.mean_density.push_back(sums[1] / n);
        out.temperature.push_back(sums[0] / (double(D) * (n - 1)));
        out.pressure.push_back((sums[0] + w + wd) / (double(D) * volume));
        out.pressure_virial.push_back(w / (double(D) * volume));
        out.pressure_dissipative.push_back(wd / (double(D) * volume));
        if (rdf_every > 0 && samples % rdf_every == 0) {
          add_pair_histogram(hist);
          ++rdf_samples;
        }
        ++samples;
      }
      progress(equilibrate + s + 1);
    }
    constexpr double pi = 3.14159265358979323846;
    const double pair_density = double(n) * double(n - 1) / volume;  // N (N − 1)/V, as LAMMPS' rdf
    for (int b = 0; b < rdf_bins_; ++b) {
      const double lo = b * rdf_bin_, hi = (b + 1) * rdf_bin_;
      const double shell = D == 3 ? 4.0 / 3.0 * pi * (hi * hi * hi - lo * lo * lo) : pi * (hi * hi - lo * lo);
      out.rdf_r.push_back((b + 0.5) * rdf_bin_);
      out.rdf.push_back(rdf_samples > 0 ? 2.0 * hist[std::size_t(b)] / (rdf_samples * pair_density * shell) : 0.0);
    }
    return out;
  }

  const System& system() const { return sys_; }
  const mdpd::MdpdParameters& fluid() const { return mp_; }
  double volume() const {
    return D == 3 ? geometry_.Lx * geometry_.Ly * geometry_.Lz : geometry_.Lx * geometry_.Ly;
  }
  double number_density() const { return double(sys_.particles.size()) / volume(); }
  double rdf_max() const { return rdf_max_; }

  // v_half_ ← v − ½dt f/m: the velocities the last force evaluation's dissipative force saw
  // (mdpd_system.hpp: λ = ½). Public only because nvcc rejects a KOKKOS_LAMBDA in a private member.
  void half_step_velocities() {
    const int n = int(sys_.particles.size());
    if (int(v_half_.extent(0)) != n) v_half_ = typename System::vector_view("mesoflow::pillars::v_half", n);
    const auto v = sys_.particles.v, f = sys_.particles.f, vh = v_half_;
    const auto m = sys_.particles.mass;
    const double half_dt = 0.5 * mp_.dt;
    mesoflow::launch::parallel_for(
        "mesoflow::pillars::half_step_velocities", Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, n),
        KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < D; ++d) vh(i, d) = v(i, d) - half_dt * f(i, d) / m(i);
        });
  }

 private:
  // Counts every pair (i < j) at minimum-image distance < rdf_max_ into hist (host, O(N²)).
  void add_pair_histogram(std::vector<double>& hist) {
    if (x_host_.extent(0) != sys_.particles.x.extent(0)) x_host_ = Kokkos::create_mirror_view(sys_.particles.x);
    Kokkos::deep_copy(x_host_, sys_.particles.x);  // no copy on host backends (the mirror is the view)
    const auto x = x_host_;
    const int n = int(x.extent(0));
    const double L[3] = {geometry_.Lx, geometry_.Ly, geometry_.Lz};
    const double max2 = rdf_max_ * rdf_max_;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        double r2 = 0;
        for (int d = 0; d < D; ++d) {
          double dx = double(x(i, d)) - double(x(j, d));
          dx -= L[d] * std::nearbyint(dx / L[d]);
          r2 += dx * dx;
        }
        if (r2 >= max2) continue;
        const int b = int(std::sqrt(r2) / rdf_bin_);
        if (b < rdf_bins_) hist[std::size_t(b)] += 1.0;
      }
  }

  mdpd::MdpdParameters mp_;
  SceneGeometry geometry_;
  System sys_;
  typename System::vector_view v_half_;
  typename System::vector_view::HostMirror x_host_;  // positions for g(r), allocated once
  double rdf_max_ = 0, rdf_bin_ = 0.02;
  int rdf_bins_ = 1;
};

}  // namespace mesoflow::pillars
