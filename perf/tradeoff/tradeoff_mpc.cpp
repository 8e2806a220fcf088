// tradeoff_mpc.cpp — speed–accuracy trade-off of the 2D MPC-AT+a solvent (issue 8): cost per unit
// physical time against the error of its shear viscosity, over particles per cell n and the MPC time
// step h, in float and double.
//
// Observable: η from periodic Poiseuille flow (split_body_force.hpp) in a fully periodic box
// L_x × L_y = 10a × 20a (no walls, so no slip enters), fitted from the profile's curvature
// (periodic_poiseuille.hpp, bins within 2a of the force reversals left out). Reference: eq. (B.3) of
// the paper, the analytic AT+a viscosity for the same n and h (η depends on n and h, so settings are
// compared through η/η_B3); the finest setting in double gives the converged ratio r_ref = η/η_B3
// and each row also carries its deviation from r_ref.
//
// Each run: solvent uniform, Maxwell–Boltzmann velocities plus the expected profile (with η_B3),
// g chosen so that u_max = 0.5 a/τ with η_B3, a warm-up of 3 relaxation times (L/2)²/(π²ν) of the
// slowest mode (≥ 5τ), then `--sample-time` τ sampled every 0.1τ in 10 blocks. Cost: wall and
// process-CPU seconds of the whole run (warm-up, sorting every 25 steps and sampling included) per τ.
// Units: a = m = k_BT = 1, τ = a√(m/k_BT).
#include "drivers/common/cli.hpp"
#include "kernels/common/kokkos_compat.hpp"
#include "kernels/common/random.hpp"
#include "kernels/common/reductions.hpp"
#include "kernels/mpc/collision_grid.hpp"
#include "kernels/mpc/maxwell_boltzmann.hpp"
#include "kernels/mpc/mpc_collision.hpp"
#include "kernels/mpc/split_body_force.hpp"
#include "perf/tradeoff/cost_clock.hpp"
#include "perf/tradeoff/periodic_poiseuille.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace mesoflow {
namespace {

constexpr double kLx = 10, kLy = 20, kUmax = 0.5, kExclude = 2.0;
constexpr int kBins = 20, kBlocks = 10, kSortInterval = 25;

// Eq. (B.3) with m = a = k_BT = 1 in d = 2.
double viscosity_b3(double n, double h) {
  const int d = 2;
  return n * h * (n / (n - (d + 2) / 4.0) - 0.5) + (n - 7.0 / 5.0) / (24 * h);
}

struct Settings {
  double sample_time = 600;
  long long seed = 2024;
};

struct Row {
  std::string precision;
  int n = 0;
  double h = 0;
  long long particles = 0, steps = 0;
  double warmup_time = 0, sample_time = 0, g = 0, eta_b3 = 0, eta = 0, eta_stderr = 0;
  double wall_per_tau = 0, cpu_per_tau = 0;
  double err_b3() const { return eta / eta_b3 - 1; }
};

template <class Real>
Row run_case(int n, double h, const Settings& s) {
  using Exec = Kokkos::DefaultExecutionSpace;
  using view = Kokkos::View<Real* [2], Kokkos::LayoutLeft, Exec>;
  const double eta_b3 = viscosity_b3(n, h);
  const double rho = n;  // m = 1
  // u_max = ρ g (L_y/2)² / (8η) at the centre of each half.
  const double g = kUmax * 8 * eta_b3 / (rho * 0.25 * kLy * kLy);
  const double relax = 0.25 * kLy * kLy / (M_PI * M_PI * eta_b3 / rho);
  const long long warmup = std::llround(std::max(5.0, 3 * relax) / h);
  const long long every = std::max(1LL, std::llround(0.1 / h));
  const long long samples = std::max<long long>(kBlocks, std::llround(s.sample_time / h) / every);
  const long long steps = warmup + samples * every;

  const auto grid = mpc::make_collision_grid<2, Real>(Real(1), Kokkos::Array<Real, 2>{0, 0},
                                                      Kokkos::Array<Real, 2>{Real(kLx), Real(kLy)},
                                                      Kokkos::Array<int, 2>{1, 1});
  const int N = int(std::lround(n * kLx * kLy));
  view x("mesoflow::tradeoff::mpc::x", N), v("mesoflow::tradeoff::mpc::v", N);
  const Real lo[2] = {0, 0}, hi[2] = {Real(kLx), Real(kLy)};
  fill_uniform_counter(x, lo, hi, std::uint64_t(s.seed), 0);
  mpc::fill_maxwell_boltzmann<2, Real, Exec>(v, Real(1), Real(1), std::uint64_t(s.seed), 1);
  {
    // Start from the expected profile (set-up, before the time loop).
    auto xh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), x);
    auto vh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
    const double a = rho * g / (2 * eta_b3), half = 0.5 * kLy;
    for (int i = 0; i < N; ++i) {
      const double y = double(xh(i, 1));
      const double yp = y < half ? y : y - half;
      vh(i, 0) += Real((y < half ? 1.0 : -1.0) * a * yp * (half - yp));
    }
    Kokkos::deep_copy(v, vh);
  }
  mpc::CollisionParameters<Real> cp;
  cp.rule = mpc::CollisionRule::at_plus_a;
  cp.seed = std::uint64_t(s.seed);
  mpc::MpcCollision<2, Real, Exec> collision(grid, cp, std::size_t(N));
  const Kokkos::Array<Real, 2> no_g{0, 0};
  constexpr int NB = kBins;
  tradeoff::BlockedProfile profile(kBins, kBlocks, samples);

  Kokkos::fence();
  const tradeoff::CostClock clock;
  long long sample = 0;
  for (long long step = 0; step < steps; ++step) {
    mpc::kick_split_body_force(x, v, Real(g), Real(h), collision.grid(), 1);
    collision.stream_and_collide(x, v, Real(h), no_g, std::uint64_t(step));
    if ((step + 1) % kSortInterval == 0) collision.sort_by_cell(x, v);
    if (step >= warmup && (step - warmup + 1) % every == 0) {
      const double bw = kLy / kBins;
      const auto sums = parallel_sum<2 * NB, Exec>(
          "mesoflow::tradeoff::mpc::profile", N, KOKKOS_LAMBDA(int i, double(&acc)[2 * NB]) {
            int b = int(double(x(i, 1)) / bw);
            b = b < 0 ? 0 : (b >= NB ? NB - 1 : b);
            acc[b] += 1.0;
            acc[NB + b] += double(v(i, 0));
          });
      profile.add(sample++, sums, NB);
    }
  }
  Kokkos::fence();
  const tradeoff::Cost cost = clock.elapsed();
  const auto fit = profile.fit(kLy, kExclude);

  Row r;
  r.precision = sizeof(Real) == 4 ? "float" : "double";
  r.n = n;
  r.h = h;
  r.particles = N;
  r.steps = steps;
  r.warmup_time = double(warmup) * h;
  r.sample_time = double(samples * every) * h;
  r.g = g;
  r.eta_b3 = eta_b3;
  r.eta = rho * g / (2 * fit.curvature);
  r.eta_stderr = r.eta * fit.curvature_stderr / fit.curvature;
  r.wall_per_tau = cost.wall / (double(steps) * h);
  r.cpu_per_tau = cost.cpu / (double(steps) * h);
  return r;
}

void run(bool quick, const Settings& s, const std::string& json_path, bool quiet) {
  const std::vector<int> ns = quick ? std::vector<int>{3, 10, 40} : std::vector<int>{3, 5, 10, 20, 40, 80};
  const std::vector<double> hs = quick ? std::vector<double>{0.1} : std::vector<double>{0.02, 0.05, 0.1, 0.2};
  std::vector<Row> rows;
  for (const char* precision : {"double", "float"}) {
    for (double h : hs) {
      for (int n : ns) {
        rows.push_back(std::string(precision) == "double" ? run_case<double>(n, h, s) : run_case<float>(n, h, s));
        const Row& r = rows.back();
        if (!quiet)
          std::cerr << std::setprecision(4) << "tradeoff_mpc: " << r.precision << " n = " << n << " h = " << h
                    << ": eta " << r.eta << " ± " << r.eta_stderr << " (B.3 " << r.eta_b3 << ", " << 100 * r.err_b3()
                    << "%), " << r.cpu_per_tau << " cpu s/tau, " << r.wall_per_tau << " wall s/tau\n";
      }
    }
  }
  // Reference: the finest setting (largest n, smallest h) in double.
  const int n_ref = ns.back();
  const double h_ref = hs.front();
  const Row* ref = nullptr;
  for (const Row& r : rows)
    if (r.precision == "double" && r.n == n_ref && r.h == h_ref) ref = &r;
  const double r_ref = ref->eta / ref->eta_b3;
  const Row* next = nullptr;  // the second-finest n at the same h: the reference's own convergence
  for (const Row& r : rows)
    if (r.precision == "double" && r.n == ns[ns.size() - 2] && r.h == h_ref) next = &r;

  const std::string stem = json_path.size() > 5 && json_path.substr(json_path.size() - 5) == ".json"
                               ? json_path.substr(0, json_path.size() - 5)
                               : json_path;
  std::ofstream csv(stem + ".csv");
  csv << "precision,n,h,particles,steps,warmup_tau,sample_tau,g,eta_b3,eta,eta_stderr,rel_err_b3,rel_err_b3_stderr,"
         "rel_err_ref,wall_s_per_tau,cpu_s_per_tau\n"
      << std::setprecision(9);
  for (const Row& r : rows)
    csv << r.precision << "," << r.n << "," << r.h << "," << r.particles << "," << r.steps << "," << r.warmup_time << ","
        << r.sample_time << "," << r.g << "," << r.eta_b3 << "," << r.eta << "," << r.eta_stderr << "," << r.err_b3()
        << "," << r.eta_stderr / r.eta_b3 << "," << (r.eta / r.eta_b3) / r_ref - 1 << "," << r.wall_per_tau << ","
        << r.cpu_per_tau << "\n";
  std::ofstream json(json_path);
  json << std::setprecision(9) << "{\n  \"program\": \"tradeoff_mpc\",\n  \"observable\": \"shear viscosity (periodic "
       << "Poiseuille, AT+a, 2D)\",\n  \"box\": [" << kLx << ", " << kLy << "],\n  \"u_max\": " << kUmax
       << ",\n  \"quick\": " << (quick ? "true" : "false") << ",\n  \"threads\": " << concurrency<Kokkos::DefaultExecutionSpace>()
       << ",\n  \"reference\": {\"n\": " << n_ref << ", \"h\": " << h_ref << ", \"eta_over_b3\": " << r_ref
       << ", \"stderr\": " << ref->eta_stderr / ref->eta_b3 << ", \"next_n\": " << next->n
       << ", \"next_eta_over_b3\": " << next->eta / next->eta_b3 << ", \"next_stderr\": " << next->eta_stderr / next->eta_b3
       << "},\n  \"float_vs_double\": [";
  bool first = true;
  for (const Row& f : rows) {
    if (f.precision != "float") continue;
    for (const Row& d : rows) {
      if (d.precision != "double" || d.n != f.n || d.h != f.h) continue;
      json << (first ? "\n" : ",\n") << "    {\"n\": " << f.n << ", \"h\": " << f.h
           << ", \"cpu_speedup\": " << d.cpu_per_tau / f.cpu_per_tau << ", \"wall_speedup\": " << d.wall_per_tau / f.wall_per_tau
           << ", \"eta_float_over_double_minus_1\": " << f.eta / d.eta - 1 << ", \"combined_stderr\": "
           << std::hypot(f.eta_stderr / d.eta, d.eta_stderr / d.eta) << "}";
      first = false;
    }
  }
  json << "\n  ]\n}\n";
  if (!quiet) std::cerr << "tradeoff_mpc: wrote " << stem << ".csv and " << json_path << "\n";
}

}  // namespace
}  // namespace mesoflow

int main(int argc, char** argv) {
  mesoflow::Settings s;
  bool quick = false;
  int threads = 1;
  mesoflow::cli::DriverApp app("MPC speed–accuracy trade-off: cost per τ against the error of the viscosity",
                               "tradeoff_mpc.json");
  app.add_flag("--quick", quick, "small grid (n = 3, 10, 40 at h = 0.1) for the ctest");
  app.add_real("--sample-time", s.sample_time, "sampled physical time per setting (τ)", 1.0, 1e6);
  app.add_int("--seed", s.seed, "random seed", 0, 4294967295LL);
  app.add_int("--threads", threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  return app.run(argc, argv, [&] {
    mesoflow::KokkosScope kokkos(threads);
    mesoflow::run(quick, s, app.output(), app.quiet());
  });
}
