// obstacle_sweep.hpp — the records and statistics of an obstacle-array sweep (capillary-droplets
// §4.2–4.3, Appendices C–E), host-only (no Kokkos): the finished replicas of the `obstacles`
// driver, their checkpoint (fields declared once, replica_fields()), the statistics of a sweep point
// (clogging_statistics.hpp) and the results file. The replicas themselves run in
// scenes/droplets/obstacles_ensemble.hpp.
//
// Units: lengths in σ (the undeformed droplet diameter), times in t0 = √(σ/g).
#pragma once

#include "analysis/droplets/clogging_statistics.hpp"
#include "io/checkpoint.hpp"
#include "io/h5md_writer.hpp"
#include "io/hdf5_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace mesoflow::droplets {

// One (strength, w_ob) point of the sweep; strength is Γ (DP) or E_w (SP).
struct SweepPoint {
  double strength, gap;
};

// A finished replica, as checkpointed and written (trivially copyable: ranks send it as bytes).
struct FinishedReplica {
  int point, replica;
  std::uint64_t seed;
  bool clogged;
  double distance, time, final_x, final_y, steady_speed;  // ReplicaRecord's (clog_detection.hpp)
  int early;  // the early clog test's classification (early_decision in clog_detection.hpp)
  double early_distance, early_time, early_rate, early_crossing;
};

// The checkpointed fields of a finished replica, declared once: writing and reading both walk this
// list. visit.template field<S>(name, members...) stores the members, converted to S, as the
// columns of the checkpoint entry `name` (one row per replica).
template <class Replica, class Visit>
void replica_fields(Replica& r, Visit&& visit) {
  visit.template field<int>("point", r.point);
  visit.template field<int>("replica", r.replica);
  visit.template field<int>("clogged", r.clogged);
  visit.template field<std::int64_t>("seed", r.seed);
  visit.template field<double>("record", r.distance, r.time, r.final_x, r.final_y, r.steady_speed);
  visit.template field<int>("early", r.early);
  visit.template field<double>("early_record", r.early_distance, r.early_time, r.early_rate, r.early_crossing);
}

namespace sweep_detail {

// Collects the columns of every replica, then puts them (replica_fields' order).
struct ColumnWriter {
  std::vector<std::string> order;
  std::map<std::string, std::size_t> width;
  std::map<std::string, std::vector<int>> ints;
  std::map<std::string, std::vector<std::int64_t>> int64s;
  std::map<std::string, std::vector<double>> reals;

  template <class S>
  std::vector<S>& column(const std::string& name) {
    if constexpr (std::is_same_v<S, int>) return ints[name];
    else if constexpr (std::is_same_v<S, std::int64_t>) return int64s[name];
    else return reals[name];
  }
  template <class S, class... M>
  void field(const std::string& name, const M&... members) {
    if (width.emplace(name, sizeof...(M)).second) order.push_back(name);
    auto& c = column<S>(name);
    (c.push_back(static_cast<S>(members)), ...);
  }
  void put(io::CheckpointWriter& w, std::size_t rows) {
    for (const std::string& name : order) {
      const std::vector<std::size_t> shape =
          width[name] == 1 ? std::vector<std::size_t>{rows} : std::vector<std::size_t>{rows, width[name]};
      if (ints.count(name)) w.put(name, ints[name].data(), shape);
      else if (int64s.count(name)) w.put(name, int64s[name].data(), shape);
      else w.put(name, reals[name].data(), shape);
    }
  }
};

// Reads each column once and hands replica k its row.
struct ColumnReader {
  explicit ColumnReader(const io::CheckpointReader& reader) : r(reader) {}
  const io::CheckpointReader& r;
  std::size_t row = 0;
  std::map<std::string, std::vector<int>> ints;
  std::map<std::string, std::vector<std::int64_t>> int64s;
  std::map<std::string, std::vector<double>> reals;

  template <class S>
  const std::vector<S>& column(const std::string& name) {
    auto& cache = [&]() -> std::map<std::string, std::vector<S>>& {
      if constexpr (std::is_same_v<S, int>) return ints;
      else if constexpr (std::is_same_v<S, std::int64_t>) return int64s;
      else return reals;
    }();
    auto it = cache.find(name);
    if (it == cache.end()) {
      it = cache.emplace(name, std::vector<S>()).first;
      r.get(name, it->second);
    }
    return it->second;
  }
  template <class S, class... M>
  void field(const std::string& name, M&... members) {
    const std::vector<S>& c = column<S>(name);
    std::size_t j = row * sizeof...(M);
    ((members = static_cast<M>(c.at(j++))), ...);
  }
};

}  // namespace sweep_detail

// Writes the finished replicas `done` and the run's parameter fingerprint to the checkpoint `path`
// (atomically, io/checkpoint.hpp).
inline void write_replica_checkpoint(const std::string& path, const std::string& parameters,
                                     const std::vector<FinishedReplica>& done) {
  io::CheckpointWriter w(path);
  w.put_string("parameters", parameters);
  w.put_scalar("finished", std::int64_t(done.size()));
  if (!done.empty()) {
    sweep_detail::ColumnWriter columns;
    for (const FinishedReplica& f : done) replica_fields(f, columns);
    columns.put(w, done.size());
  }
  w.commit();
}

// The finished replicas of the checkpoint `path`; throws std::invalid_argument (naming --restart)
// when there is none or it was written with other parameters.
inline std::vector<FinishedReplica> read_replica_checkpoint(const std::string& path, const std::string& parameters) {
  if (!io::checkpoint_exists(path)) throw std::invalid_argument("--restart: no checkpoint " + path + " to resume from");
  const io::CheckpointReader r(path);
  if (r.get_string("parameters") != parameters)
    throw std::invalid_argument("--restart: " + path +
                                " was written with other parameters; resume with the same ones (or drop --restart)");
  std::vector<FinishedReplica> done(std::size_t(r.get_scalar_int64("finished")));
  sweep_detail::ColumnReader columns(r);
  for (columns.row = 0; columns.row < done.size(); ++columns.row) replica_fields(done[columns.row], columns);
  return done;
}

// The partial checkpoint of MPI rank `rank`: <out>.rank<r>.ckpt.h5 beside <out>.ckpt.h5.
inline std::string rank_checkpoint(const std::string& checkpoint, int rank) {
  const std::string suffix = ".ckpt.h5";
  return checkpoint.substr(0, checkpoint.size() - suffix.size()) + ".rank" + std::to_string(rank) + suffix;
}

// The partial checkpoints <out>.rank<r>.ckpt.h5 that exist now, of any number of ranks.
inline std::vector<std::string> rank_checkpoints(const std::string& checkpoint) {
  namespace fs = std::filesystem;
  const fs::path path(checkpoint);
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const std::string name = path.filename().string(), suffix = ".ckpt.h5";
  const std::string prefix = name.substr(0, name.size() - suffix.size()) + ".rank";
  std::vector<std::string> found;
  std::error_code error;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, error)) {
    const std::string f = e.path().filename().string();
    if (f.size() <= prefix.size() + suffix.size() || f.compare(0, prefix.size(), prefix) != 0 ||
        f.compare(f.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string digits = f.substr(prefix.size(), f.size() - prefix.size() - suffix.size());
    if (digits.find_first_not_of("0123456789") == std::string::npos) found.push_back((dir / f).string());
  }
  std::sort(found.begin(), found.end());
  return found;
}

// --restart: the finished replicas of <out>.ckpt.h5 and of the rank checkpoints `partials`, each once.
inline std::vector<FinishedReplica> read_finished(const std::string& checkpoint, const std::vector<std::string>& partials,
                                                  const std::string& parameters) {
  std::vector<FinishedReplica> done = read_replica_checkpoint(checkpoint, parameters);
  for (const std::string& partial : partials)
    for (const FinishedReplica& f : read_replica_checkpoint(partial, parameters))
      if (std::none_of(done.begin(), done.end(),
                       [&](const FinishedReplica& d) { return d.point == f.point && d.replica == f.replica; }))
        done.push_back(f);
  return done;
}

// Statistics of one sweep point.
struct PointSummary {
  int replicas = 0, clogged = 0, flowing = 0;
  DecayLengthEstimate lambda{};
  std::vector<SurvivalPoint> survival;
  double mean_speed_ratio = 0, speed_ratio_error = 0;  // ⟨v_g⟩/v_t over flowing replicas, its standard error
};

// λ (eq. 16, clogging_statistics.hpp) at confidence `level`, the survival curve and ⟨v_g⟩/v_t of
// the replicas of one point.
inline PointSummary summarize(const std::vector<FinishedReplica>& replicas, double terminal_speed, double level) {
  PointSummary s;
  std::vector<ReplicaOutcome> outcomes;
  std::vector<double> ratios;
  for (const FinishedReplica& f : replicas) {
    outcomes.push_back({std::max(0.0, f.distance), f.clogged});
    if (!f.clogged) ratios.push_back(f.steady_speed / terminal_speed);
  }
  s.replicas = int(replicas.size());
  s.lambda = decay_length(outcomes, level);
  s.clogged = s.lambda.clogged;
  s.survival = survival_curve(outcomes);
  s.flowing = int(ratios.size());
  if (!ratios.empty()) {
    double sum = 0;
    for (const double r : ratios) sum += r;
    s.mean_speed_ratio = sum / double(ratios.size());
    if (ratios.size() > 1) {
      double var = 0;
      for (const double r : ratios) var += (r - s.mean_speed_ratio) * (r - s.mean_speed_ratio);
      s.speed_ratio_error = std::sqrt(var / double(ratios.size() - 1) / double(ratios.size()));
    }
  }
  return s;
}

// The summaries of every point, from the finished replicas sorted by point.
inline std::vector<PointSummary> summarize_points(const std::vector<FinishedReplica>& done, std::size_t points,
                                                  double terminal_speed, double level) {
  std::vector<PointSummary> summaries;
  for (std::size_t p = 0; p < points; ++p) {
    std::vector<FinishedReplica> here;
    for (const FinishedReplica& f : done)
      if (f.point == int(p)) here.push_back(f);
    summaries.push_back(summarize(here, terminal_speed, level));
  }
  return summaries;
}

// A number with 10 significant digits (inf as "inf"), as the CSV and console print them.
inline std::string sweep_number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream out;
  out << std::setprecision(10) << v;
  return out.str();
}

namespace sweep_detail {
template <class T>
void write_vector(hid_t loc, const std::string& path, const std::vector<T>& v, const std::string& unit = "") {
  // The shape spelled out: nvcc's front end loses the braces of `{v.size()}` in this template.
  const std::vector<hsize_t> shape{hsize_t(v.size())};
  const io::Dataset d = io::write_dataset(loc, path, io::native_type<T>(), io::native_type<T>(), shape, v.data());
  if (!unit.empty()) io::write_attribute(d.get(), "unit", unit);
}
}  // namespace sweep_detail

// The results file (H5MD-style: /h5md, /parameters as attributes, /results/replicas, /results/points,
// /results/survival), written to <path>.tmp and renamed. `parameters`: name → value attributes.
inline void write_sweep_results(const std::string& path, const std::vector<std::pair<std::string, std::string>>& parameters,
                                bool sp, const std::vector<SweepPoint>& points, const std::vector<FinishedReplica>& done,
                                const std::vector<PointSummary>& summaries, const std::string& version) {
  using sweep_detail::write_vector;
  const std::string tmp = path + ".tmp";
  {
    io::H5mdWriter h5(tmp, "mesoflow", version, "mesoflow obstacles");
    for (const auto& [key, value] : parameters) h5.set_parameter(key, value);
  }
  {
    io::File file = io::open_file(tmp, H5F_ACC_RDWR);
    const io::Group results = io::require_group(file.get(), "results");
    io::write_attribute(results.get(), "model", std::string(sp ? "sp" : "dp"));
    io::write_attribute(results.get(), "units", std::string("length sigma, time t0 = sqrt(sigma/g)"));
    const std::size_t n = done.size();
    std::vector<int> point(n), replica(n), clogged(n);
    std::vector<long long> seed(n);
    std::vector<double> distance(n), time(n), final_position(2 * n), speed(n);
    std::vector<int> early(n);
    std::vector<double> early_distance(n), early_time(n), early_rate(n), early_crossing(n);
    for (std::size_t k = 0; k < n; ++k) {
      point[k] = done[k].point;
      replica[k] = done[k].replica;
      seed[k] = static_cast<long long>(done[k].seed);
      clogged[k] = done[k].clogged ? 1 : 0;
      distance[k] = done[k].distance;
      time[k] = done[k].time;
      final_position[2 * k] = done[k].final_x;
      final_position[2 * k + 1] = done[k].final_y;
      speed[k] = done[k].steady_speed;
      early[k] = done[k].early;
      early_distance[k] = done[k].early_distance;
      early_time[k] = done[k].early_time;
      early_rate[k] = done[k].early_rate;
      early_crossing[k] = done[k].early_crossing;
    }
    write_vector(results.get(), "replicas/point", point);
    write_vector(results.get(), "replicas/replica", replica);
    write_vector(results.get(), "replicas/obstacle_seed", seed);
    write_vector(results.get(), "replicas/clogged", clogged);
    write_vector(results.get(), "replicas/distance", distance, "sigma");
    write_vector(results.get(), "replicas/time", time, "t0");
    io::write_dataset(results.get(), "replicas/final_position", io::native_type<double>(), io::native_type<double>(),
                      {n, 2}, final_position.data());
    write_vector(results.get(), "replicas/steady_speed", speed, "sigma/t0");
    write_vector(results.get(), "replicas/early_decision", early);
    write_vector(results.get(), "replicas/early_distance", early_distance, "sigma");
    write_vector(results.get(), "replicas/early_time", early_time, "t0");
    write_vector(results.get(), "replicas/early_rate", early_rate, "1/t0");
    write_vector(results.get(), "replicas/early_crossing", early_crossing, "t0");
    std::vector<double> strength, gap, lambda, lower, upper, total, mean_speed, speed_error;
    std::vector<int> replicas, n_clog, flowing;
    for (std::size_t p = 0; p < points.size(); ++p) {
      const PointSummary& s = summaries[p];
      strength.push_back(points[p].strength);
      gap.push_back(points[p].gap);
      replicas.push_back(s.replicas);
      n_clog.push_back(s.clogged);
      flowing.push_back(s.flowing);
      lambda.push_back(s.lambda.lambda);
      lower.push_back(s.lambda.lower);
      upper.push_back(s.lambda.upper);
      total.push_back(s.lambda.total_distance);
      mean_speed.push_back(s.mean_speed_ratio);
      speed_error.push_back(s.speed_ratio_error);
      std::vector<double> r, prob;
      for (const SurvivalPoint& q : s.survival) {
        r.push_back(q.distance);
        prob.push_back(q.probability);
      }
      write_vector(results.get(), "survival/point_" + std::to_string(p) + "/distance", r, "sigma");
      write_vector(results.get(), "survival/point_" + std::to_string(p) + "/probability", prob);
    }
    write_vector(results.get(), sp ? "points/wall_energy" : "points/line_tension", strength);
    write_vector(results.get(), "points/gap", gap, "sigma");
    write_vector(results.get(), "points/replicas", replicas);
    write_vector(results.get(), "points/clogged", n_clog);
    write_vector(results.get(), "points/flowing", flowing);
    write_vector(results.get(), "points/decay_length", lambda, "sigma");
    write_vector(results.get(), "points/decay_length_lower", lower, "sigma");
    write_vector(results.get(), "points/decay_length_upper", upper, "sigma");
    write_vector(results.get(), "points/total_distance", total, "sigma");
    write_vector(results.get(), "points/mean_speed_ratio", mean_speed);
    write_vector(results.get(), "points/mean_speed_ratio_error", speed_error);
    if (file.close() < 0) throw std::runtime_error("obstacles: cannot close " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("obstacles: cannot rename " + tmp + " to " + path);
}

// The sweep's CSV: one row per point.
inline void write_sweep_csv(const std::string& path, bool sp, const std::vector<SweepPoint>& points,
                            const std::vector<PointSummary>& summaries) {
  std::ofstream csv(path);
  csv << (sp ? "wall_energy" : "line_tension")
      << ",gap,replicas,clogged,decay_length,decay_length_lower,decay_length_upper,flowing,mean_speed_ratio,"
         "mean_speed_ratio_error\n";
  for (std::size_t p = 0; p < points.size(); ++p) {
    const PointSummary& s = summaries[p];
    csv << sweep_number(points[p].strength) << "," << sweep_number(points[p].gap) << "," << s.replicas << ","
        << s.clogged << "," << sweep_number(s.lambda.lambda) << "," << sweep_number(s.lambda.lower) << ","
        << sweep_number(s.lambda.upper) << "," << s.flowing << ","
        << (s.flowing > 0 ? sweep_number(s.mean_speed_ratio) : "") << ","
        << (s.flowing > 1 ? sweep_number(s.speed_ratio_error) : "") << "\n";
  }
}

// One row per finished replica (sorted by point, then replica): both classifications and their
// (r, t) when the early clog test ran (--clog-test early or both; clog_detection.hpp).
inline void write_replicas_csv(const std::string& path, bool sp, const std::vector<SweepPoint>& points,
                               const std::vector<FinishedReplica>& done) {
  std::ofstream csv(path);
  csv << (sp ? "wall_energy" : "line_tension")
      << ",gap,replica,seed,clogged,distance,time,steady_speed,early_decision,early_clogged,early_distance,early_time,"
         "early_rate,early_crossing\n";
  for (const FinishedReplica& f : done)
    csv << sweep_number(points[std::size_t(f.point)].strength) << "," << sweep_number(points[std::size_t(f.point)].gap)
        << "," << f.replica << "," << f.seed << "," << (f.clogged ? 1 : 0) << "," << sweep_number(f.distance) << ","
        << sweep_number(f.time) << "," << sweep_number(f.steady_speed) << "," << f.early << ","
        << (f.early != 0 ? 1 : 0) << "," << sweep_number(f.early_distance) << "," << sweep_number(f.early_time) << ","
        << sweep_number(f.early_rate) << "," << sweep_number(f.early_crossing) << "\n";
}

// Simulated time of the finished replicas up to their records (the test that ended them) and up
// to the early decision (--clog-test early/both), and the replicas the two tests classify
// differently.
struct ClogTestTotals {
  double recorded = 0, early = 0;
  int disagreements = 0;
};
inline ClogTestTotals clog_test_totals(const std::vector<FinishedReplica>& done) {
  ClogTestTotals t;
  for (const FinishedReplica& f : done) {
    t.recorded += f.time;
    t.early += f.early_time;
    t.disagreements += (f.early != 0) != f.clogged ? 1 : 0;
  }
  return t;
}

// One line of the driver's report for a sweep point: N_s, N_clog, λ with its interval, ⟨v_g⟩/v_t.
inline std::string point_line(bool sp, const SweepPoint& point, const PointSummary& s) {
  std::ostringstream out;
  out << (sp ? "E_w = " : "Gamma = ") << point.strength << ", w_ob = " << point.gap << ": N_s = " << s.replicas
      << ", N_clog = " << s.clogged << ", lambda = " << sweep_number(s.lambda.lambda) << " ["
      << sweep_number(s.lambda.lower) << ", " << sweep_number(s.lambda.upper) << "] sigma"
      << (s.flowing > 0 ? ", <v_g>/v_t = " + sweep_number(s.mean_speed_ratio) : "");
  return out.str();
}

}  // namespace mesoflow::droplets
