// Phonon analysis of the microfluidic crystal (microfluidic-crystal-phonons paper, §4–5): the
// elongations with the periodic wrap, the power spectra of eqs. (1)–(2) against a direct DFT,
// Parseval, the sign convention on synthetic travelling waves, the ridge of the linear lattice
// dynamics (C.5)–(C.6) on eqs. (3)–(4), the correlation strength (5)–(7) for quadratic and linear
// coupling, and the HDF5/CSV output.
#include "scratch_dir.hpp"
#include "analysis/crystal/phonon_spectra.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/hdf5_util.hpp"

// Own namespace: this file shares a unity translation unit with others (tests/CMakeLists.txt).
namespace mesoflow::crystal::phonon_spectra_test {
namespace {

namespace fs = std::filesystem;
constexpr double pi = 3.14159265358979323846;

using ::mesoflow::testing::ScratchDir;

std::vector<double> random_field(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> g(0.3, 1.0);
  std::vector<double> f(n);
  for (double& v : f) v = g(gen);
  return f;
}

// Shifted index of mode number m on a grid of n (inverse of m = p − ⌊n/2⌋).
std::size_t index_of(long m, std::size_t n) { return std::size_t(m + long(n / 2)); }

// Positions of a crystal with given elongations: x_0(t) = drift t, x_{j+1} = x_j + δx_j (the
// elongations of each frame must sum to N a), y_j = y_center + δy_{j−1}, y_0 = y_center + δy_{N−1}.
struct Positions {
  std::vector<double> x, y;
};
Positions positions_from(const std::vector<double>& dx, const std::vector<double>& dy, std::size_t N, std::size_t T,
                         double y_center, double drift) {
  Positions p{std::vector<double>(N * T), std::vector<double>(N * T)};
  for (std::size_t t = 0; t < T; ++t) {
    p.x[t * N] = drift * double(t);
    for (std::size_t j = 0; j + 1 < N; ++j) p.x[t * N + j + 1] = p.x[t * N + j] + dx[t * N + j];
    for (std::size_t j = 0; j < N; ++j) p.y[t * N + j] = y_center + dy[t * N + (j + N - 1) % N];
  }
  return p;
}

TEST(Elongations, DefinitionsWithThePeriodicWrap) {
  // N = 4, a = 1.5, y_center = 2: δx_3 = x_0 + 4a − x_3 and δy_3 = y_0 − y_center (§4, x_N = x_0 + Na).
  const std::vector<double> x{0.1, 1.7, 3.0, 4.4,   // t = 0
                              0.6, 2.0, 3.7, 5.1};  // t = 1
  const std::vector<double> y{2.5, 1.2, 2.9, 1.0,   //
                              1.4, 2.2, 2.7, 3.3};
  const Elongations e = elongations(x, y, 4, 2, 1.5, 2.0);
  ASSERT_EQ(e.droplets, 4u);
  ASSERT_EQ(e.frames, 2u);
  const std::vector<double> dx{1.6, 1.3, 1.4, 0.1 + 6 - 4.4, 1.4, 1.7, 1.4, 0.6 + 6 - 5.1};
  const std::vector<double> dy{1.2 - 2, 2.9 - 2, 1.0 - 2, 2.5 - 2, 2.2 - 2, 2.7 - 2, 3.3 - 2, 1.4 - 2};
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_NEAR(e.dx[i], dx[i], 1e-14) << i;
    EXPECT_NEAR(e.dy[i], dy[i], 1e-14) << i;
  }
  // Σ_j δx_j(t) = N a in every frame, whatever the positions.
  const std::size_t N = 7, T = 5;
  const Elongations r = elongations(random_field(N * T, 1), random_field(N * T, 2), N, T, 0.9, 0.0);
  for (std::size_t t = 0; t < T; ++t) {
    double s = 0;
    for (std::size_t j = 0; j < N; ++j) s += r.dx[t * N + j];
    EXPECT_NEAR(s, N * 0.9, 1e-13);
  }
  EXPECT_THROW(elongations(x, y, 4, 3, 1.5, 2.0), std::invalid_argument);
  EXPECT_THROW(elongations(x, y, 4, 2, 0.0, 2.0), std::invalid_argument);
}

TEST(PowerSpectra, ShiftedGrids) {
  const auto k_even = wavenumbers(6, 2.0), k_odd = wavenumbers(5, 2.0), w = frequencies(4, 0.5);
  ASSERT_EQ(k_even.size(), 6u);
  EXPECT_DOUBLE_EQ(k_even.front(), -pi / 2.0);  // −π/a included
  EXPECT_DOUBLE_EQ(k_even[3], 0.0);
  EXPECT_DOUBLE_EQ(k_even.back(), 2 * pi * 2 / 12.0);
  EXPECT_DOUBLE_EQ(k_odd.front(), -2 * pi * 2 / 10.0);
  EXPECT_DOUBLE_EQ(k_odd.back(), 2 * pi * 2 / 10.0);
  EXPECT_DOUBLE_EQ(w.front(), -pi / 0.5);
  EXPECT_DOUBLE_EQ(w[2], 0.0);
  EXPECT_DOUBLE_EQ(w.back(), 2 * pi / 2.0);
}

TEST(PowerSpectra, MatchesTheDirectDoubleSum) {
  // P(k_p, ω_q) = |Σ_t Σ_j f_j(t) exp[−i(j k_p a − t ω_q Δt)]|² summed directly, odd and even sizes,
  // every option: 1e-12 of the largest bin.
  const double a = 1.3, dt = 0.7;
  for (auto [N, T] : {std::pair<std::size_t, std::size_t>{5, 7}, {6, 8}, {9, 4}})
    for (TimeWindow window : {TimeWindow::rectangular, TimeWindow::hann})
      for (bool subtract : {false, true}) {
        const std::vector<double> f = random_field(N * T, 10 + N);
        const SpectrumOptions opt{window, subtract};
        const std::vector<double> P = power_spectrum(f, N, T, opt);
        const auto k = wavenumbers(N, a), omega = frequencies(T, dt);
        const auto w = window_weights(window, T);
        std::vector<double> g = f;
        if (subtract)
          for (std::size_t j = 0; j < N; ++j) {
            double mean = 0;
            for (std::size_t t = 0; t < T; ++t) mean += f[t * N + j] / T;
            for (std::size_t t = 0; t < T; ++t) g[t * N + j] -= mean;
          }
        const double peak = *std::max_element(P.begin(), P.end());
        for (std::size_t p = 0; p < N; ++p)
          for (std::size_t q = 0; q < T; ++q) {
            std::complex<double> s = 0;
            for (std::size_t t = 0; t < T; ++t)
              for (std::size_t j = 0; j < N; ++j)
                s += w[t] * g[t * N + j] * std::polar(1.0, -(double(j) * k[p] * a - double(t) * omega[q] * dt));
            EXPECT_NEAR(P[p * T + q], std::norm(s), 1e-12 * peak)
                << "N " << N << " T " << T << " p " << p << " q " << q;
          }
      }
}

TEST(PowerSpectra, ParsevalToRoundOff) {
  // Σ_{k,ω} P = N T Σ_{j,t} |w_t (f_j(t) − mean_j)|² with the window and mean removal done here.
  const std::size_t N = 90, T = 101;  // the paper's 90 droplets; a prime number of frames
  const std::vector<double> f = random_field(N * T, 3);
  for (TimeWindow window : {TimeWindow::rectangular, TimeWindow::hann})
    for (bool subtract : {false, true}) {
      const std::vector<double> P = power_spectrum(f, N, T, {window, subtract});
      long double energy = 0;
      for (std::size_t j = 0; j < N; ++j) {
        long double mean = 0;
        for (std::size_t t = 0; t < T; ++t) mean += f[t * N + j];
        mean = subtract ? mean / T : 0;
        for (std::size_t t = 0; t < T; ++t) {
          const long double w = window == TimeWindow::hann ? std::pow(std::sin(pi * t / T), 2) : 1.0;
          energy += std::pow(w * (f[t * N + j] - mean), 2);
        }
      }
      long double total = 0;
      for (double v : P) total += v;
      const double rel = double(total / (N * T * energy) - 1);
      EXPECT_LT(std::abs(rel), 1e-12) << "window " << int(window) << " subtract " << subtract;
      std::cout << "[ measured ] Parseval, N 90, T 101, window " << (window == TimeWindow::hann ? "hann" : "rect")
                << ", subtract_mean " << subtract << ": relative error " << rel << "\n";
    }
}

TEST(PowerSpectra, TravellingWavesLandInTheirBinWithTheTheorysSign) {
  // δ_j(t) = A cos(k0 j a − ω0 t Δt + φ) = Re A e^{iφ} e^{i(k0 ja − ω0 tΔt)}: with the header's
  // convention the power sits at (k0, ω0) and (−k0, −ω0) only: forward waves (ω0/k0 > 0) in the
  // first and third quadrants, backward waves in the second and fourth. Rectangular window: the two
  // bins hold (N T Â/2)² each (Â the amplitude of the elongation), nothing else above round-off.
  // Hann: (N T Â/4)² and a quarter of that in each ω-neighbour.
  const std::size_t N = 12, T = 20;
  const double a = 1.5, dt = 0.3, y_center = 2.0, A = 0.4, phi = 0.7, drift = 0.21;
  const long m0 = 2;
  const double k0 = 2 * pi * m0 / (N * a);
  for (long l0 : {3L, -3L}) {
    const double w0 = 2 * pi * l0 / (T * dt);
    // Transverse: y_j − y_center = A cos(k0 (j−1) a − …), so that δy_j = y_{j+1} − y_center has the
    // phase k0 j a. Longitudinal: x_j = j a + drift t + A cos(k0 j a − …), δx_j − a of amplitude
    // 2A sin(k0 a/2).
    std::vector<double> x(N * T), y(N * T);
    for (std::size_t t = 0; t < T; ++t)
      for (std::size_t j = 0; j < N; ++j) {
        const double theta = k0 * double(j) * a - w0 * double(t) * dt + phi;
        x[t * N + j] = double(j) * a + drift * double(t) + A * std::cos(theta);
        y[t * N + j] = y_center + A * std::cos(theta - k0 * a);
      }
    const Elongations e = elongations(x, y, N, T, a, y_center);
    for (TimeWindow window : {TimeWindow::rectangular, TimeWindow::hann}) {
      const PowerSpectra s = power_spectra(e, a, dt, {window, true});
      const std::size_t p = index_of(m0, N), pm = index_of(-m0, N), q = index_of(l0, T), qm = index_of(-l0, T);
      ASSERT_NEAR(s.k[p], k0, 1e-14);
      ASSERT_NEAR(s.omega[q], w0, 1e-14);
      for (int field = 0; field < 2; ++field) {
        const std::vector<double>& P = field == 0 ? s.transverse : s.longitudinal;
        const double amplitude = field == 0 ? A : 2 * A * std::sin(0.5 * k0 * a);
        const double gain = window == TimeWindow::hann ? 0.25 : 0.5;
        const double want = std::pow(N * T * amplitude * gain, 2);
        const char* what = field == 0 ? "transverse" : "longitudinal";
        EXPECT_NEAR(P[p * T + q] / want, 1.0, 1e-12) << what << " l0 " << l0;
        EXPECT_NEAR(P[pm * T + qm] / want, 1.0, 1e-12) << what << " l0 " << l0;
        EXPECT_LT(P[p * T + qm], 1e-24 * want) << what << ": the opposite sign of omega must be empty";
        std::vector<std::size_t> filled{p * T + q, pm * T + qm};
        if (window == TimeWindow::hann) {
          for (std::size_t side : {q - 1, q + 1}) {
            EXPECT_NEAR(P[p * T + side] / want, 0.25, 1e-12) << what;
            filled.push_back(p * T + side);
          }
          for (std::size_t side : {qm - 1, qm + 1}) {
            EXPECT_NEAR(P[pm * T + side] / want, 0.25, 1e-12) << what;
            filled.push_back(pm * T + side);
          }
        }
        double rest = 0;
        for (std::size_t i = 0; i < N * T; ++i)
          if (std::find(filled.begin(), filled.end(), i) == filled.end()) rest += P[i];
        EXPECT_LT(rest, 1e-24 * want) << what << " l0 " << l0 << ": power outside the wave's bins";
      }
    }
  }
}

TEST(PowerSpectra, MeanRemovalEmptiesTheStaticBins) {
  // A static zigzag δy_j = d (−1)^j (mode m = −N/2, k = −π/a) plus a wave: left in, it fills the
  // (k = −π/a, ω = 0) bin with (N T d)²; removed, the whole ω = 0 column is empty. The lattice
  // mean δx_j = a likewise sits at (0, 0) as (N T a)².
  const std::size_t N = 10, T = 16;
  const double a = 2.0, d = 0.3, y_center = 1.0;
  std::vector<double> x(N * T), y(N * T);
  for (std::size_t t = 0; t < T; ++t)
    for (std::size_t j = 0; j < N; ++j) {
      const double wave = 0.1 * std::cos(2 * pi * (3.0 * j / N - 2.0 * t / T));
      x[t * N + j] = double(j) * a + wave;
      y[t * N + j] = y_center + d * ((j + 1) % 2 == 0 ? 1 : -1) + wave;  // δy_j = y_{j+1} − y_center
    }
  const Elongations e = elongations(x, y, N, T, a, y_center);
  const PowerSpectra kept = power_spectra(e, a, 1.0, {TimeWindow::rectangular, false});
  const PowerSpectra removed = power_spectra(e, a, 1.0, {TimeWindow::rectangular, true});
  const std::size_t q0 = index_of(0, T);
  EXPECT_NEAR(kept.transverse[index_of(-long(N / 2), N) * T + q0] / std::pow(N * T * d, 2), 1.0, 1e-12);
  EXPECT_NEAR(kept.longitudinal[index_of(0, N) * T + q0] / std::pow(N * T * a, 2), 1.0, 1e-12);
  const double peak = *std::max_element(removed.transverse.begin(), removed.transverse.end());
  for (std::size_t p = 0; p < N; ++p) {
    EXPECT_LT(removed.transverse[p * T + q0], 1e-24 * peak) << p;
    EXPECT_LT(removed.longitudinal[p * T + q0], 1e-24 * peak) << p;
  }
}

TEST(PowerSpectra, LinearLatticeDynamicsFollowEquations3And4) {
  // The linearised equations of motion (C.6) δẏ_n = −B Σ_j c⊥_j (δy_{n+j} − δy_{n−j}) and (C.5)
  // δẋ_n = 2B Σ_j c∥_j (δx_{n+j} − δx_{n−j}) on a periodic crystal of N droplets, integrated by RK4
  // from random displacements, with the paper's experimental parameters. Every mode k_m oscillates
  // at exactly ω(k_m) of eqs. (3)–(4) (plane waves e^{i(kna − ωt)}, Appendix C), so in each k column
  // of the spectra the strongest ω bin must lie within one bin width of ω⊥(k) (transverse) and
  // ω∥(k) (longitudinal), signs included. k = 0 and k = −π/a have ω = 0 (static, removed).
  const CrystalParameters par{140, 210, 64, 250, 500};
  const DispersionTheory theory(par);
  const double B = theory.B(), beta = theory.beta(), a = par.a;
  const std::size_t N = 24, T = 400, substeps = 8;
  const double dt = 0.25, h = dt / substeps;
  const int J = 40;  // c_40 ~ e^{−84}: nothing left at double precision
  std::vector<double> cp(J + 1), cl(J + 1);
  for (int j = 1; j <= J; ++j) {
    const double xj = pi * j * beta;
    cp[j] = std::pow(1 + std::cosh(xj), 2) / std::pow(std::sinh(xj), 3);
    cl[j] = std::cosh(xj) / std::pow(std::sinh(xj), 3);
  }
  const auto rhs = [&](const std::vector<double>& u, const std::vector<double>& c, double factor) {
    std::vector<double> du(N, 0.0);
    for (std::size_t n = 0; n < N; ++n) {
      double s = 0;
      for (int j = J; j >= 1; --j) s += c[j] * (u[(n + j) % N] - u[(n + N * J - j) % N]);
      du[n] = factor * s;
    }
    return du;
  };
  const auto rk4 = [&](std::vector<double>& u, const std::vector<double>& c, double factor) {
    const auto axpy = [&](const std::vector<double>& v, double s, const std::vector<double>& w) {
      std::vector<double> r(N);
      for (std::size_t n = 0; n < N; ++n) r[n] = v[n] + s * w[n];
      return r;
    };
    const auto k1 = rhs(u, c, factor), k2 = rhs(axpy(u, 0.5 * h, k1), c, factor);
    const auto k3 = rhs(axpy(u, 0.5 * h, k2), c, factor), k4 = rhs(axpy(u, h, k3), c, factor);
    for (std::size_t n = 0; n < N; ++n) u[n] += h / 6 * (k1[n] + 2 * k2[n] + 2 * k3[n] + k4[n]);
  };
  std::mt19937_64 gen(7);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> uy(N), ux(N);
  for (std::size_t n = 0; n < N; ++n) uy[n] = 5 * g(gen), ux[n] = 2 * g(gen);
  std::vector<double> x(N * T), y(N * T);
  for (std::size_t t = 0; t < T; ++t) {
    for (std::size_t n = 0; n < N; ++n) {
      x[t * N + n] = double(n) * a + par.u_d * double(t) * dt + ux[n];
      y[t * N + n] = 0.5 * par.W + uy[n];
    }
    for (std::size_t s = 0; s < substeps; ++s) {
      rk4(uy, cp, -B);
      rk4(ux, cl, 2 * B);
    }
  }
  const PowerSpectra s = power_spectra(elongations(x, y, N, T, a, 0.5 * par.W), a, dt);
  const double bin = 2 * pi / (T * dt);
  double worst_perp = 0, worst_par = 0;
  for (std::size_t p = 0; p < N; ++p) {
    const long m = long(p) - long(N / 2);
    if (m == 0 || m == -long(N / 2)) continue;
    for (int field = 0; field < 2; ++field) {
      const std::vector<double>& P = field == 0 ? s.transverse : s.longitudinal;
      const auto row = P.begin() + long(p * T);
      const double w_peak = s.omega[std::size_t(std::max_element(row, row + long(T)) - row)];
      const double w_theory = field == 0 ? theory.transverse(s.k[p]) : theory.longitudinal(s.k[p]);
      EXPECT_LE(std::abs(w_peak - w_theory), bin)
          << (field == 0 ? "transverse" : "longitudinal") << " m " << m << ": peak " << w_peak << ", eq. "
          << (field == 0 ? 3 : 4) << " " << w_theory;
      (field == 0 ? worst_perp : worst_par) =
          std::max(field == 0 ? worst_perp : worst_par, std::abs(w_peak - w_theory) / bin);
    }
  }
  std::cout << "[ measured ] lattice dynamics, N 24, T 400: largest |omega_peak - omega_theory| " << worst_perp
            << " bins (eq. 3), " << worst_par << " bins (eq. 4); bin " << bin << " rad/s\n";
}

// Correlation test signal: δy_j = A cos(k⊥ ja − ω⊥t + φ(t)) + noise, φ a random walk (phase drift),
// and δx_j = a + coupling(δy_j) + noise with the spatial mean of each frame taken out of δx − a (a
// crystal: Σ_j δx_j = N a). Built into positions and back through elongations().
template <class Coupling>
Elongations coupled_crystal(std::size_t N, std::size_t T, long m_perp, Coupling coupling, std::uint64_t seed) {
  const double a = 1.0, A = 1.0, w = 2 * pi * 0.037, y_center = 3.0;
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> dx(N * T), dy(N * T);
  double phase = 0;
  for (std::size_t t = 0; t < T; ++t) {
    phase += 0.05 * g(gen);
    double mean = 0;
    for (std::size_t j = 0; j < N; ++j) {
      dy[t * N + j] =
          A * std::cos(2 * pi * double(m_perp) * double(j) / double(N) - w * double(t) + phase) + 0.2 * g(gen);
      dx[t * N + j] = coupling(dy[t * N + j]) + 0.05 * g(gen);
      mean += dx[t * N + j] / double(N);
    }
    for (std::size_t j = 0; j < N; ++j) dx[t * N + j] += a - mean;
  }
  const Positions p = positions_from(dx, dy, N, T, y_center, 0.8);
  return elongations(p.x, p.y, N, T, a, y_center);
}

TEST(ModeCorrelation, QuadraticCouplingShowsTheRidgeInAmplitudeFluctuations) {
  // δx ∝ δy² (the figure-eight mechanism of §4): the transverse mode m⊥ = N/6 (λ = 6a, as in the
  // paper) drives the longitudinal mode 2m⊥. Which definition of C (header) puts the maximum at
  // k∥ = 2k⊥? Measured with N = 60, T = 2000 (one seed): (c) amplitude_fluctuation 0.589 there
  // against ≤ 0.094 for any other k∥ in that column; (b) amplitude 0.995 there, but 0.892 for
  // another k∥ in the column and 0.78 on average over the map (weak contrast); (a) the complex
  // literal eq. (5) 0.002 there (x̃(2m⊥) ỹ(m⊥) ∝ e^{−3iω⊥t} averages out), 0.067 at most anywhere:
  // no ridge. Bounds below: (c) > 0.4 and the rest < 0.25, (b) > 0.95, (a) < 0.1.
  const auto start = std::chrono::steady_clock::now();
  const std::size_t N = 60, T = 2000;
  const long m = 10;
  const Elongations e = coupled_crystal(
      N, T, m, [](double v) { return 0.3 * v * v; }, 11);
  const ModeCorrelation c = mode_correlation(e, 1.0);
  ASSERT_EQ(c.mode.size(), N);
  ASSERT_EQ(c.mode.front(), -30);
  const std::size_t col = index_of(m, N), up = index_of(2 * m, N), down = index_of(-2 * m, N);
  const auto at = [&](const std::vector<double>& C, std::size_t row) { return C[row * N + col]; };
  // Largest entry of column `col` away from rows `up` and `down`.
  const auto best_other = [&](const std::vector<double>& C) {
    double b = -1;
    for (std::size_t r = 0; r < N; ++r)
      if (r != up && r != down) b = std::max(b, at(C, r));
    return b;
  };
  // (c): the maximum of the column is at k∥ = ±2k⊥ (equal: |x̃| is even in k), well clear of the rest,
  // and it is the maximum of the whole map.
  const auto& F = c.amplitude_fluctuation;
  EXPECT_NEAR(at(F, up), at(F, down), 1e-12);
  EXPECT_GT(at(F, up), 0.4);
  EXPECT_LT(best_other(F), 0.25);
  const std::size_t arg = std::size_t(std::max_element(F.begin(), F.end()) - F.begin());
  EXPECT_EQ(std::abs(c.mode[arg / N]), 2 * m) << "global maximum at m_par " << c.mode[arg / N];
  EXPECT_EQ(std::abs(c.mode[arg % N]), m) << "global maximum at m_perp " << c.mode[arg % N];
  // (b): the column maximum is there too, against a high background.
  EXPECT_GT(at(c.amplitude, up), 0.95);
  EXPECT_LT(best_other(c.amplitude), at(c.amplitude, up));
  // (a): nothing at k∥ = 2k⊥ beyond the T^{−1/2} ≈ 0.022 noise level.
  EXPECT_LT(at(c.complex_literal, up), 0.1);
  EXPECT_LT(at(c.complex_literal, down), 0.1);
  // The row k∥ = 0 is empty (Σ_j δx_j = N a): C = 0 by the empty-mode rule.
  for (std::size_t r = 0; r < N; ++r) EXPECT_EQ(c.amplitude[index_of(0, N) * N + r], 0.0);
  double max_literal = 0, sum_b = 0;
  for (std::size_t i = 0; i < N * N; ++i)
    max_literal = std::max(max_literal, c.complex_literal[i]), sum_b += c.amplitude[i];
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "[ measured ] quadratic coupling, N 60, T 2000, m_perp 10: (c) " << at(F, up) << " at 2m, next "
            << best_other(F) << "; (b) " << at(c.amplitude, up) << " at 2m, next " << best_other(c.amplitude)
            << ", map mean " << sum_b / (N * N) << "; (a) " << at(c.complex_literal, up) << " at 2m, map max "
            << max_literal << "; " << seconds << " s\n";
}

TEST(ModeCorrelation, LinearCouplingPeaksAtOppositeWavevectorsInTheLiteralDefinition) {
  // δx ∝ δy: x̃(−m) ỹ(m) = c |ỹ(m)|² (real δ: x̃(−m) = x̃(m)*), so eq. (5) as printed is ≈ 1 at
  // k∥ = −k⊥ (the acoustic expectation of §4, [10]) and ≈ 0 at k∥ = +k⊥ (∝ e^{−2iω⊥t}).
  const std::size_t N = 60, T = 2000;
  const long m = 10;
  const Elongations e = coupled_crystal(
      N, T, m, [](double v) { return 0.3 * v; }, 12);
  const ModeCorrelation c = mode_correlation(e, 1.0);
  const std::size_t col = index_of(m, N);
  const double opposite = c.complex_literal[index_of(-m, N) * N + col],
               same = c.complex_literal[index_of(m, N) * N + col];
  EXPECT_GT(opposite, 0.95);
  EXPECT_LT(same, 0.1);
  std::cout << "[ measured ] linear coupling: (a) " << opposite << " at k_par = -k_perp, " << same
            << " at k_par = +k_perp\n";
}

TEST(PhononOutput, Hdf5AndCsvRoundTrip) {
  ScratchDir dir;
  const CrystalParameters par{140, 210, 64, 250, 500};
  const std::size_t N = 8, T = 16;
  const double dt = 0.5;
  std::vector<double> x(N * T), y(N * T);
  for (std::size_t t = 0; t < T; ++t)
    for (std::size_t j = 0; j < N; ++j) {
      const double theta = 2 * pi * (double(j) / N - 3.0 * double(t) / T);
      x[t * N + j] = double(j) * par.a + 2 * std::sin(2 * theta);
      y[t * N + j] = 0.5 * par.W + 30 * std::cos(theta) + 0.1 * std::sin(7.0 * t + j);
    }
  const Elongations e = elongations(x, y, N, T, par.a, 0.5 * par.W);
  const PowerSpectra s = power_spectra(e, par.a, dt);
  const ModeCorrelation c = mode_correlation(e, par.a);
  const std::string h5 = dir.file("analysis.h5"), csv = dir.file("theory.csv");
  write_phonon_analysis(h5, par, s, c, 51);
  const DispersionTheory theory(par);
  write_theory_csv(csv, theory, 11);

  const auto tr = io::read_dataset_double(h5, "/spectra/transverse");
  ASSERT_EQ(tr.shape, (std::vector<std::size_t>{N, T}));
  EXPECT_EQ(tr.values, s.transverse);
  EXPECT_EQ(io::read_dataset_double(h5, "/spectra/omega").values, s.omega);
  EXPECT_EQ(io::read_dataset_double(h5, "/correlation/amplitude_fluctuation").values, c.amplitude_fluctuation);
  const auto k = io::read_dataset_double(h5, "/theory/k").values;
  const auto w3 = io::read_dataset_double(h5, "/theory/omega_transverse").values;
  const auto w8 = io::read_dataset_double(h5, "/theory/omega_coupled").values;
  ASSERT_EQ(k.size(), 51u);
  EXPECT_DOUBLE_EQ(k.front(), -pi / par.a);
  EXPECT_DOUBLE_EQ(k.back(), pi / par.a);
  EXPECT_EQ(w3[17], theory.transverse(k[17]));
  EXPECT_EQ(w8[40], theory.longitudinal_coupled(k[40]));
  EXPECT_EQ(io::read_attribute_double(h5, "/", "B"), std::vector<double>{theory.B()});
  EXPECT_EQ(io::read_attribute_double(h5, "/", "beta"), std::vector<double>{2.0 / 3.0});
  EXPECT_EQ(io::read_attribute_double(h5, "/", "dt"), std::vector<double>{dt});
  EXPECT_EQ(io::read_attribute_int64(h5, "/", "N"), std::vector<std::int64_t>{8});
  EXPECT_EQ(io::read_attribute_int64(h5, "/", "T"), std::vector<std::int64_t>{16});
  EXPECT_EQ(io::read_attribute_string(h5, "/spectra", "window"), "hann");
  EXPECT_TRUE(io::read_attribute_bool(h5, "/spectra", "subtract_mean"));
  EXPECT_EQ(io::read_attribute_string(h5, "/theory/omega_longitudinal", "equation"), "4");
  EXPECT_EQ(io::read_attribute_double(h5, "/theory", "phase_velocity"), std::vector<double>{theory.phase_velocity()});

  std::ifstream in(csv);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "k,omega_eq3,omega_eq4,omega_eq8,omega_eq11,omega_eq12,omega_eq13,omega_eq14");
  int rows = 0;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 8u);
    EXPECT_NEAR(v[0], (-1 + 0.2 * rows) * pi / par.a, 1e-15 * pi / par.a);
    EXPECT_EQ(v[1], theory.transverse(v[0]));
    EXPECT_EQ(v[2], theory.longitudinal(v[0]));
    EXPECT_EQ(v[3], theory.longitudinal_coupled(v[0]));
    EXPECT_EQ(v[4], theory.longitudinal_continuum(v[0]));
    EXPECT_EQ(v[5], theory.transverse_continuum(v[0]));
    EXPECT_EQ(v[6], theory.longitudinal_nearest_neighbour(v[0]));
    EXPECT_EQ(v[7], theory.transverse_nearest_neighbour(v[0]));
    ++rows;
  }
  EXPECT_EQ(rows, 11);

  // Spectra and correlation from another lattice spacing are refused.
  EXPECT_THROW(write_phonon_analysis(h5, par, power_spectra(e, 2 * par.a, dt), c), std::invalid_argument);
}

}  // namespace
}  // namespace mesoflow::crystal::phonon_spectra_test
