#include "analysis/crystal/phonon_spectra.hpp"

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include "io/hdf5_util.hpp"

namespace mesoflow::crystal {

namespace {

using cplx = std::complex<double>;
constexpr double pi = 3.14159265358979323846;

// A mode whose mean power is at most this fraction of its field's largest is round-off only.
constexpr double empty_mode = 1e-20;

std::string str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

void check_positive(const char* fn, const char* name, double v) {
  if (!std::isfinite(v) || !(v > 0))
    throw std::invalid_argument(std::string(fn) + ": " + name + " must be finite and > 0, got " + str(v));
}

void check_shape(const char* fn, std::size_t droplets, std::size_t frames) {
  if (droplets < 2)
    throw std::invalid_argument(std::string(fn) + ": needs N >= 2 droplets, got " + std::to_string(droplets));
  if (frames < 2) throw std::invalid_argument(std::string(fn) + ": needs T >= 2 frames, got " + std::to_string(frames));
}

void check_field(const char* fn, const char* name, const std::vector<double>& f, std::size_t droplets,
                 std::size_t frames) {
  check_shape(fn, droplets, frames);
  if (f.size() != droplets * frames)
    throw std::invalid_argument(std::string(fn) + ": " + name + " must hold N T = " +
                                std::to_string(droplets * frames) + " values, got " + std::to_string(f.size()));
  for (std::size_t i = 0; i < f.size(); ++i)
    if (!std::isfinite(f[i]))
      throw std::invalid_argument(std::string(fn) + ": " + name + "[" + std::to_string(i) +
                                  "] (t = " + std::to_string(i / droplets) + ", j = " + std::to_string(i % droplets) +
                                  ") is not finite");
}

// Shifted index p = 0..n−1 → mode number m = p − ⌊n/2⌋.
long shifted_mode(std::size_t p, std::size_t n) { return long(p) - long(n / 2); }

// m mod n in 0..n−1.
std::size_t wrap(long m, std::size_t n) {
  const long r = m % long(n);
  return std::size_t(r < 0 ? r + long(n) : r);
}

// f_j(t) minus its time mean per j when asked (field at [t N + j]).
std::vector<double> without_mean(const std::vector<double>& f, std::size_t N, std::size_t T, bool subtract) {
  std::vector<double> g = f;
  if (!subtract) return g;
  for (std::size_t j = 0; j < N; ++j) {
    double mean = 0;
    for (std::size_t t = 0; t < T; ++t) mean += f[t * N + j];
    mean /= double(T);
    for (std::size_t t = 0; t < T; ++t) g[t * N + j] -= mean;
  }
  return g;
}

// G[t N + m] = Σ_j g_j(t) e^{−2πi jm/N}, m = 0..N−1: the modes along the train, frame by frame.
std::vector<cplx> train_modes(const std::vector<double>& g, std::size_t N, std::size_t T) {
  Eigen::FFT<double> fft;
  std::vector<cplx> in(N), out(N), G(N * T);
  for (std::size_t t = 0; t < T; ++t) {
    for (std::size_t j = 0; j < N; ++j) in[j] = g[t * N + j];
    fft.fwd(out, in);
    std::copy(out.begin(), out.end(), G.begin() + long(t * N));
  }
  return G;
}

}  // namespace

Elongations elongations(const std::vector<double>& x, const std::vector<double>& y, std::size_t droplets,
                        std::size_t frames, double a, double y_center) {
  check_field("elongations", "x", x, droplets, frames);
  check_field("elongations", "y", y, droplets, frames);
  check_positive("elongations", "a", a);
  if (!std::isfinite(y_center))
    throw std::invalid_argument("elongations: y_center must be finite, got " + str(y_center));
  const std::size_t N = droplets;
  Elongations e{N, frames, std::vector<double>(N * frames), std::vector<double>(N * frames)};
  for (std::size_t t = 0; t < frames; ++t) {
    const double* xt = &x[t * N];
    const double* yt = &y[t * N];
    for (std::size_t j = 0; j < N; ++j) {
      // §4: x_N = x_0 + N a (the periodic image of droplet 0), y_N = y_0.
      const double x_next = j + 1 < N ? xt[j + 1] : xt[0] + double(N) * a;
      const double y_next = j + 1 < N ? yt[j + 1] : yt[0];
      e.dx[t * N + j] = x_next - xt[j];
      e.dy[t * N + j] = y_next - y_center;
    }
  }
  return e;
}

std::vector<double> window_weights(TimeWindow window, std::size_t frames) {
  std::vector<double> w(frames, 1.0);
  if (window == TimeWindow::hann)
    for (std::size_t t = 0; t < frames; ++t) {
      const double s = std::sin(pi * double(t) / double(frames));
      w[t] = s * s;
    }
  return w;
}

std::vector<double> wavenumbers(std::size_t droplets, double a) {
  check_positive("wavenumbers", "a", a);
  std::vector<double> k(droplets);
  for (std::size_t p = 0; p < droplets; ++p) k[p] = 2 * pi * double(shifted_mode(p, droplets)) / (double(droplets) * a);
  return k;
}

std::vector<double> frequencies(std::size_t frames, double dt) {
  check_positive("frequencies", "dt", dt);
  std::vector<double> omega(frames);
  for (std::size_t q = 0; q < frames; ++q) omega[q] = 2 * pi * double(shifted_mode(q, frames)) / (double(frames) * dt);
  return omega;
}

std::vector<double> power_spectrum(const std::vector<double>& field, std::size_t droplets, std::size_t frames,
                                   const SpectrumOptions& options) {
  check_field("power_spectrum", "field", field, droplets, frames);
  const std::size_t N = droplets, T = frames;
  std::vector<double> g = without_mean(field, N, T, options.subtract_mean);
  const std::vector<double> w = window_weights(options.window, T);
  for (std::size_t t = 0; t < T; ++t)
    for (std::size_t j = 0; j < N; ++j) g[t * N + j] *= w[t];
  const std::vector<cplx> G = train_modes(g, N, T);

  // F(m, n) = Σ_t G_t(m) e^{−2πi tn/T}; the convention's e^{+itω_lΔt} = e^{−2πi t(−l)/T}, so
  // x̃(k_m, ω_l) = F(m, −l mod T).
  Eigen::FFT<double> fft;
  std::vector<cplx> in(T), out(T);
  std::vector<double> P(N * T);
  for (std::size_t p = 0; p < N; ++p) {
    const std::size_t m = wrap(shifted_mode(p, N), N);
    for (std::size_t t = 0; t < T; ++t) in[t] = G[t * N + m];
    fft.fwd(out, in);
    for (std::size_t q = 0; q < T; ++q) P[p * T + q] = std::norm(out[wrap(-shifted_mode(q, T), T)]);
  }
  return P;
}

PowerSpectra power_spectra(const Elongations& e, double a, double dt, const SpectrumOptions& options) {
  check_positive("power_spectra", "a", a);
  check_positive("power_spectra", "dt", dt);
  PowerSpectra s;
  s.droplets = e.droplets;
  s.frames = e.frames;
  s.a = a;
  s.dt = dt;
  s.options = options;
  s.k = wavenumbers(e.droplets, a);
  s.omega = frequencies(e.frames, dt);
  s.transverse = power_spectrum(e.dy, e.droplets, e.frames, options);
  s.longitudinal = power_spectrum(e.dx, e.droplets, e.frames, options);
  return s;
}

ModeCorrelation mode_correlation(const Elongations& e, double a) {
  check_field("mode_correlation", "dx", e.dx, e.droplets, e.frames);
  check_field("mode_correlation", "dy", e.dy, e.droplets, e.frames);
  check_positive("mode_correlation", "a", a);
  const std::size_t N = e.droplets, T = e.frames;
  const std::vector<cplx> X = train_modes(without_mean(e.dx, N, T, true), N, T);
  const std::vector<cplx> Y = train_modes(without_mean(e.dy, N, T, true), N, T);

  // Per shifted mode p: the series over t, its mean power, mean amplitude and amplitude variance.
  struct Mode {
    std::vector<cplx> z;
    std::vector<double> amp;
    double power = 0, mean_amp = 0, var_amp = 0;
  };
  const auto modes = [&](const std::vector<cplx>& Z) {
    std::vector<Mode> out(N);
    for (std::size_t p = 0; p < N; ++p) {
      Mode& md = out[p];
      const std::size_t m = wrap(shifted_mode(p, N), N);
      md.z.resize(T);
      md.amp.resize(T);
      for (std::size_t t = 0; t < T; ++t) {
        md.z[t] = Z[t * N + m];
        md.amp[t] = std::abs(md.z[t]);
        md.power += std::norm(md.z[t]);
        md.mean_amp += md.amp[t];
      }
      md.power /= double(T);
      md.mean_amp /= double(T);
      for (std::size_t t = 0; t < T; ++t) md.var_amp += (md.amp[t] - md.mean_amp) * (md.amp[t] - md.mean_amp);
      md.var_amp /= double(T);
    }
    return out;
  };
  const std::vector<Mode> mx = modes(X), my = modes(Y);
  double max_x = 0, max_y = 0;
  for (std::size_t p = 0; p < N; ++p) {
    max_x = std::max(max_x, mx[p].power);
    max_y = std::max(max_y, my[p].power);
  }

  ModeCorrelation c;
  c.droplets = N;
  c.frames = T;
  c.a = a;
  c.k = wavenumbers(N, a);
  for (std::size_t p = 0; p < N; ++p) c.mode.push_back(int(shifted_mode(p, N)));
  c.complex_literal.assign(N * N, 0.0);
  c.amplitude.assign(N * N, 0.0);
  c.amplitude_fluctuation.assign(N * N, 0.0);
  for (std::size_t px = 0; px < N; ++px) {
    const Mode& u = mx[px];
    if (!(u.power > empty_mode * max_x)) continue;
    for (std::size_t py = 0; py < N; ++py) {
      const Mode& v = my[py];
      if (!(v.power > empty_mode * max_y)) continue;
      cplx product = 0;
      double amp_product = 0, fluct_product = 0;
      for (std::size_t t = 0; t < T; ++t) {
        product += u.z[t] * v.z[t];
        amp_product += u.amp[t] * v.amp[t];
        fluct_product += (u.amp[t] - u.mean_amp) * (v.amp[t] - v.mean_amp);
      }
      const double norm = std::sqrt(u.power * v.power);
      c.complex_literal[px * N + py] = std::abs(product) / double(T) / norm;
      c.amplitude[px * N + py] = amp_product / double(T) / norm;
      if (u.var_amp > empty_mode * max_x && v.var_amp > empty_mode * max_y)
        c.amplitude_fluctuation[px * N + py] = fluct_product / double(T) / std::sqrt(u.var_amp * v.var_amp);
    }
  }
  return c;
}

namespace {

template <class T>
void write_array(hid_t loc, const std::string& path, const std::vector<T>& v, const std::vector<hsize_t>& shape,
                 const std::string& equation = "") {
  const io::Dataset d = io::write_dataset(loc, path, io::native_type<T>(), io::native_type<T>(), shape, v.data());
  if (!equation.empty()) io::write_attribute(d.get(), "equation", equation);
}

std::vector<double> theory_grid(const DispersionTheory& theory, std::size_t points) {
  std::vector<double> k(points);
  for (std::size_t i = 0; i < points; ++i) k[i] = (-1 + 2 * double(i) / double(points - 1)) * pi / theory.a();
  return k;
}

template <class F>
std::vector<double> evaluate(const std::vector<double>& k, F f) {
  std::vector<double> out(k.size());
  for (std::size_t i = 0; i < k.size(); ++i) out[i] = f(k[i]);
  return out;
}

}  // namespace

void write_phonon_analysis(const std::string& h5_path, const CrystalParameters& p, const PowerSpectra& spectra,
                           const ModeCorrelation& correlation, std::size_t theory_points) {
  const char* fn = "write_phonon_analysis";
  check_parameters(p);
  const std::size_t N = spectra.droplets, T = spectra.frames;
  if (spectra.a != p.a || correlation.a != p.a)
    throw std::invalid_argument(std::string(fn) + ": spectra and correlation must use a = " + str(p.a) + ", got " +
                                str(spectra.a) + " and " + str(correlation.a));
  if (correlation.droplets != N || correlation.frames != T)
    throw std::invalid_argument(std::string(fn) + ": spectra (N = " + std::to_string(N) + ", T = " + std::to_string(T) +
                                ") and correlation (N = " + std::to_string(correlation.droplets) +
                                ", T = " + std::to_string(correlation.frames) + ") come from different elongations");
  if (spectra.k.size() != N || spectra.omega.size() != T || spectra.transverse.size() != N * T ||
      spectra.longitudinal.size() != N * T || correlation.mode.size() != N || correlation.k.size() != N ||
      correlation.complex_literal.size() != N * N || correlation.amplitude.size() != N * N ||
      correlation.amplitude_fluctuation.size() != N * N)
    throw std::invalid_argument(std::string(fn) + ": spectra or correlation arrays do not match N = " +
                                std::to_string(N) + ", T = " + std::to_string(T));
  if (theory_points < 2)
    throw std::invalid_argument(std::string(fn) + ": theory_points must be >= 2, got " + std::to_string(theory_points));
  const DispersionTheory theory(p);

  io::File file = io::create_file(h5_path);
  const hid_t root = file.get();
  io::write_attribute(root, "a", p.a);
  io::write_attribute(root, "W", p.W);
  io::write_attribute(root, "R", p.R);
  io::write_attribute(root, "u_d", p.u_d);
  io::write_attribute(root, "u_oil", p.u_oil);
  io::write_attribute(root, "K", velocity_ratio(p));
  io::write_attribute(root, "B", theory.B());
  io::write_attribute(root, "beta", theory.beta());
  io::write_attribute(root, "y_center", 0.5 * p.W);
  io::write_attribute(root, "N", static_cast<long long>(N));
  io::write_attribute(root, "T", static_cast<long long>(T));
  io::write_attribute(root, "dt", spectra.dt);
  io::write_attribute(
      root, "convention",
      std::string("x(k, omega) = sum_t sum_j dx_j(t) exp[-i(j k a - t omega dt)]: a wave exp[i(k0 j a - omega0 t)] "
                  "peaks at (k0, omega0); omega > 0 for k > 0 travels forward (+x) as in eqs. (3), (4), (8)"));

  {
    const io::Group g = io::require_group(root, "spectra");
    write_array(g.get(), "k", spectra.k, {N});
    write_array(g.get(), "omega", spectra.omega, {T});
    write_array(g.get(), "transverse", spectra.transverse, {N, T}, "2");
    write_array(g.get(), "longitudinal", spectra.longitudinal, {N, T}, "1");
    io::write_attribute(g.get(), "window",
                        std::string(spectra.options.window == TimeWindow::hann ? "hann" : "rectangular"));
    io::write_attribute(g.get(), "subtract_mean", spectra.options.subtract_mean);
  }
  {
    const io::Group g = io::require_group(root, "theory");
    const std::vector<double> k = theory_grid(theory, theory_points);
    write_array(g.get(), "k", k, {k.size()});
    const std::vector<hsize_t> shape{k.size()};
    write_array(g.get(), "omega_transverse", evaluate(k, [&](double x) { return theory.transverse(x); }), shape, "3");
    write_array(g.get(), "omega_longitudinal", evaluate(k, [&](double x) { return theory.longitudinal(x); }), shape,
                "4");
    write_array(g.get(), "omega_coupled", evaluate(k, [&](double x) { return theory.longitudinal_coupled(x); }), shape,
                "8");
    write_array(g.get(), "omega_longitudinal_continuum",
                evaluate(k, [&](double x) { return theory.longitudinal_continuum(x); }), shape, "11");
    write_array(g.get(), "omega_transverse_continuum",
                evaluate(k, [&](double x) { return theory.transverse_continuum(x); }), shape, "12");
    write_array(g.get(), "omega_longitudinal_nn",
                evaluate(k, [&](double x) { return theory.longitudinal_nearest_neighbour(x); }), shape, "13");
    write_array(g.get(), "omega_transverse_nn",
                evaluate(k, [&](double x) { return theory.transverse_nearest_neighbour(x); }), shape, "14");
    io::write_attribute(g.get(), "phase_velocity", theory.phase_velocity());
  }
  {
    const io::Group g = io::require_group(root, "correlation");
    write_array(g.get(), "mode", correlation.mode, {N});
    write_array(g.get(), "k", correlation.k, {N});
    write_array(g.get(), "complex_literal", correlation.complex_literal, {N, N}, "5");
    write_array(g.get(), "amplitude", correlation.amplitude, {N, N});
    write_array(g.get(), "amplitude_fluctuation", correlation.amplitude_fluctuation, {N, N});
    io::write_attribute(g.get(), "ridge", std::string("amplitude_fluctuation"));
  }
  if (file.close() < 0) throw std::runtime_error(std::string(fn) + ": cannot close " + h5_path);
}

void write_theory_csv(const std::string& csv_path, const DispersionTheory& theory, std::size_t points) {
  if (points < 2) throw std::invalid_argument("write_theory_csv: points must be >= 2, got " + std::to_string(points));
  std::ofstream out(csv_path);
  if (!out) throw std::runtime_error("write_theory_csv: cannot write " + csv_path);
  out << "k,omega_eq3,omega_eq4,omega_eq8,omega_eq11,omega_eq12,omega_eq13,omega_eq14\n";
  out.precision(17);  // round-trips every double
  for (double k : theory_grid(theory, points))
    out << k << ',' << theory.transverse(k) << ',' << theory.longitudinal(k) << ',' << theory.longitudinal_coupled(k)
        << ',' << theory.longitudinal_continuum(k) << ',' << theory.transverse_continuum(k) << ','
        << theory.longitudinal_nearest_neighbour(k) << ',' << theory.transverse_nearest_neighbour(k) << '\n';
  out.close();
  if (!out) throw std::runtime_error("write_theory_csv: cannot write " + csv_path);
}

}  // namespace mesoflow::crystal
