// obstacles — single droplets falling through random obstacle arrays (capillary-droplets §4.2–4.3,
// Appendices C–E), DP or SP model: ensembles of replicas, each in its own Poisson-disk array, give
// the clogging probability P(r) (Kaplan–Meier), the clogging decay length λ of eq. 16 (maximum
// likelihood with right-censored replicas, likelihood-ratio interval) and, for replicas that flow
// to the end, the steady-state speed ⟨v_g⟩/v_t (App. D). One command sweeps Γ (DP) or E_w (SP)
// and w_ob.
//
// Units (capillary-droplets §2.2, scenes/droplets/droplet_scene.hpp): length σ (undeformed droplet
// diameter), acceleration g, areal mass density ρ; time t0 = √(σ/g). M = π/4; b∞ = M/V_t (eq. 15);
// Γ, K_a, K_l, E_w are the dimensionless coefficients of eqs. 1–3 and 8.
//
// Defaults: the paper's clogging scene (σ_ob = 0.3σ, w_ob = 0.2σ, Γ = 1.09, App. C; b0 = 0 as in
// §4.3/App. E), threshold E_k/E_t = 10⁻¹⁷. The paper uses L = 500σ, T = 2·10⁵ t0 and N_s = 50; the
// defaults here (L = 40σ, T = 200 t0, N_s = 16, N_v = 64) run in minutes on two cores. L = 40σ is
// beyond λ ≈ 24σ of App. C, so a replica rarely revisits its own obstacles before it clogs; with
// v ≤ v_t = 0.08 a droplet travels at most 16σ in 200 t0, so many replicas at the paper's point are
// right-censored, which the estimator of λ accounts for (raise --time-limit to narrow the interval).
// K_l/Γ defaults to 0.1, not the paper's 10⁻³: a held droplet's vertices slide along its interface
// at the rate π² k_l/b∞ (docs/droplets.md, deviation 4), so at 10⁻³ E_k reaches the clog threshold
// only after ~10⁴ t0 at Γ ≈ 1 and every replica would end right-censored within T.
//
// Output (<out> = --output without its extension): <out>.h5 (H5MD-style: /h5md, /parameters as
// attributes, /results/replicas, /results/points, /results/survival), <out>.csv (one row per sweep
// point), <out>.json (run summary), <out>.ckpt.h5 (finished replicas, replaced atomically as they
// finish; --restart resumes a killed sweep from it without recomputing them).
//
// Under mpirun/srun (docs/scale-out.md) the sweep's work items, (point, replica) pairs in
// point-major order less those already finished, are dealt round robin to the ranks
// (drivers/common/ensemble_mpi.hpp); each rank runs its share in batches as above and records what
// it finishes in its own <out>.rank<r>.ckpt.h5 (replaced atomically). Rank 0 gathers the records,
// writes the files above and merges the rank checkpoints into <out>.ckpt.h5, then removes them.
// --restart reads <out>.ckpt.h5 and every <out>.rank<r>.ckpt.h5, whatever the number of ranks now.
// A replica's record depends only on its seed, so the results do not depend on the number of ranks.
#include "drivers/common/cli.hpp"
#include "drivers/common/ensemble_mpi.hpp"
#include "drivers/common/output_paths.hpp"
#include "drivers/common/progress.hpp"
#include "analysis/droplets/clogging_statistics.hpp"
#include "scenes/droplets/obstacles_ensemble.hpp"
#include "io/checkpoint.hpp"
#include "io/h5md_writer.hpp"
#include "io/hdf5_util.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

namespace mesoflow::droplets {
namespace {

struct Parameters {
  std::string model = "dp";
  std::string line_tension = "1.09";   // Γ list (DP)
  std::string sp_wall_energy = "10";   // E_w list (SP)
  std::string gap = "0.2";             // w_ob list
  int replicas = 16;
  int batch = 16;
  double box_length = 40.0;
  double obstacle_diameter = 0.3;
  double obstacle_fraction = 0;  // φ; 0: maximal Poisson-disk arrays
  double time_limit = 200.0;
  double clog_threshold = 1e-17;
  double confidence = 0.95;
  int vertices = 64;
  double area_stiffness = 1e4;
  double perimeter_ratio = 0.1;  // K_l/Γ (see the file comment; the paper: 10⁻³)
  double dp_wall_energy = 0.05;
  double near_wall_drag = 0.0;
  double terminal_speed = 0.08;
  double dt = 0.0;
  bool force_dt = false;  // --force-dt
  int relax_iterations = 20000;
  long long seed = 1;
  int threads = 0;
  bool restart = false;
};

// A comma-separated list of finite reals in [lo, hi]; the error names the flag and the range.
std::vector<double> parse_list(const std::string& flag, const std::string& text, double lo, double hi) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  const std::string range = "comma-separated reals in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    double v = 0;
    const auto [end, error] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (item.empty() || error != std::errc() || end != item.data() + item.size() || !std::isfinite(v) || v < lo ||
        v > hi)
      throw std::invalid_argument(flag + ": value '" + item + "' in '" + text + "' is not allowed; expected " + range);
    values.push_back(v);
  }
  if (values.empty()) throw std::invalid_argument(flag + ": empty list; expected " + range);
  return values;
}

// One (strength, w_ob) point of the sweep; strength is Γ (DP) or E_w (SP).
struct SweepPoint {
  double strength, gap;
};

// A finished replica, as checkpointed and written.
struct FinishedReplica {
  int point, replica;
  std::uint64_t seed;
  ReplicaRecord record;
};

std::string fingerprint(const cli::DriverApp& app) {
  std::string out;
  for (const auto& [key, value] : app.resolved_parameters())
    if (key != "restart" && key != "threads") out += key + "=" + value + "\n";
  return out;
}

void write_checkpoint(const std::string& path, const std::string& parameters, const std::vector<FinishedReplica>& done) {
  const std::size_t n = done.size();
  std::vector<int> point(n), replica(n), clogged(n);
  std::vector<std::int64_t> seed(n);
  std::vector<double> values(n * 5);
  for (std::size_t k = 0; k < n; ++k) {
    point[k] = done[k].point;
    replica[k] = done[k].replica;
    clogged[k] = done[k].record.clogged ? 1 : 0;
    seed[k] = std::int64_t(done[k].seed);
    const ReplicaRecord& r = done[k].record;
    const double row[5] = {r.distance, r.time, r.final_x, r.final_y, r.steady_speed};
    std::copy(row, row + 5, values.begin() + std::ptrdiff_t(5 * k));
  }
  io::CheckpointWriter w(path);
  w.put_string("parameters", parameters);
  w.put_scalar("finished", std::int64_t(n));
  if (n > 0) {
    w.put("point", point.data(), {n});
    w.put("replica", replica.data(), {n});
    w.put("clogged", clogged.data(), {n});
    w.put("seed", seed.data(), {n});
    w.put("record", values.data(), {n, 5});
  }
  w.commit();
}

std::vector<FinishedReplica> read_checkpoint(const std::string& path, const std::string& parameters) {
  if (!io::checkpoint_exists(path))
    throw std::invalid_argument("--restart: no checkpoint " + path + " to resume from");
  const io::CheckpointReader r(path);
  if (r.get_string("parameters") != parameters)
    throw std::invalid_argument("--restart: " + path +
                                " was written with other parameters; resume with the same ones (or drop --restart)");
  std::vector<FinishedReplica> done(std::size_t(r.get_scalar_int64("finished")));
  if (done.empty()) return done;
  std::vector<int> point, replica, clogged;
  std::vector<std::int64_t> seed;
  std::vector<double> values;
  r.get("point", point);
  r.get("replica", replica);
  r.get("clogged", clogged);
  r.get("seed", seed);
  r.get("record", values);
  for (std::size_t k = 0; k < done.size(); ++k) {
    done[k].point = point[k];
    done[k].replica = replica[k];
    done[k].seed = std::uint64_t(seed[k]);
    ReplicaRecord& rec = done[k].record;
    rec.clogged = clogged[k] != 0;
    rec.distance = values[5 * k];
    rec.time = values[5 * k + 1];
    rec.final_x = values[5 * k + 2];
    rec.final_y = values[5 * k + 3];
    rec.steady_speed = values[5 * k + 4];
  }
  return done;
}

// The partial checkpoint of MPI rank `rank`: <out>.rank<r>.ckpt.h5 beside <out>.ckpt.h5.
std::string rank_checkpoint(const std::string& checkpoint, int rank) {
  const std::string suffix = ".ckpt.h5";
  return checkpoint.substr(0, checkpoint.size() - suffix.size()) + ".rank" + std::to_string(rank) + suffix;
}

// The partial checkpoints <out>.rank<r>.ckpt.h5 that exist now, of any number of ranks.
std::vector<std::string> rank_checkpoints(const std::string& checkpoint) {
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
std::vector<FinishedReplica> read_finished(const std::string& checkpoint, const std::vector<std::string>& partials,
                                           const std::string& parameters) {
  std::vector<FinishedReplica> done = read_checkpoint(checkpoint, parameters);
  for (const std::string& partial : partials)
    for (const FinishedReplica& f : read_checkpoint(partial, parameters))
      if (std::none_of(done.begin(), done.end(),
                       [&](const FinishedReplica& d) { return d.point == f.point && d.replica == f.replica; }))
        done.push_back(f);
  return done;
}

// The records a rank sends to rank 0, as bytes.
std::vector<char> to_bytes(const std::vector<FinishedReplica>& records) {
  static_assert(std::is_trivially_copyable_v<FinishedReplica>);
  std::vector<char> bytes;
  for (const FinishedReplica& f : records) ensemble::append_bytes(bytes, f);
  return bytes;
}

void append_from_bytes(const std::vector<char>& bytes, std::vector<FinishedReplica>& records) {
  for (std::size_t offset = 0; offset < bytes.size();) records.push_back(ensemble::read_bytes<FinishedReplica>(bytes, offset));
}

// Statistics of one sweep point.
struct PointSummary {
  int replicas = 0, clogged = 0, flowing = 0;
  DecayLengthEstimate lambda{};
  std::vector<SurvivalPoint> survival;
  double mean_speed_ratio = 0, speed_ratio_error = 0;  // ⟨v_g⟩/v_t over flowing replicas, its standard error
};

PointSummary summarize(const std::vector<FinishedReplica>& replicas, double terminal_speed, double level) {
  PointSummary s;
  std::vector<ReplicaOutcome> outcomes;
  std::vector<double> ratios;
  for (const FinishedReplica& f : replicas) {
    outcomes.push_back({std::max(0.0, f.record.distance), f.record.clogged});
    if (!f.record.clogged) ratios.push_back(f.record.steady_speed / terminal_speed);
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

std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream out;
  out << std::setprecision(10) << v;
  return out.str();
}

template <class T>
void write_vector(hid_t loc, const std::string& path, const std::vector<T>& v, const std::string& unit = "") {
  // The shape spelled out: nvcc's front end loses the braces of `{v.size()}` in this template.
  const std::vector<hsize_t> shape{hsize_t(v.size())};
  const io::Dataset d = io::write_dataset(loc, path, io::native_type<T>(), io::native_type<T>(), shape, v.data());
  if (!unit.empty()) io::write_attribute(d.get(), "unit", unit);
}

void write_results(const std::string& path, const cli::DriverApp& app, bool sp, const std::vector<SweepPoint>& points,
                   const std::vector<FinishedReplica>& done, const std::vector<PointSummary>& summaries) {
  const std::string tmp = path + ".tmp";
  {
    io::H5mdWriter h5(tmp, "mesoflow", MESOFLOW_VERSION, "mesoflow obstacles");
    for (const auto& [key, value] : app.resolved_parameters())
      if (key != "restart" && key != "threads") h5.set_parameter(key, value);
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
    for (std::size_t k = 0; k < n; ++k) {
      point[k] = done[k].point;
      replica[k] = done[k].replica;
      seed[k] = static_cast<long long>(done[k].seed);
      clogged[k] = done[k].record.clogged ? 1 : 0;
      distance[k] = done[k].record.distance;
      time[k] = done[k].record.time;
      final_position[2 * k] = done[k].record.final_x;
      final_position[2 * k + 1] = done[k].record.final_y;
      speed[k] = done[k].record.steady_speed;
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

// The scene of one sweep point.
ObstacleEnsembleParameters ensemble_parameters(const Parameters& par, const SweepPoint& point) {
  const bool sp = par.model == "sp";
  ObstacleEnsembleParameters ens;
  ens.model = sp ? DropletModel::soft_particle : DropletModel::deformable_polygon;
  ens.droplet.vertices = par.vertices;
  ens.droplet.line_tension = sp ? ens.droplet.line_tension : point.strength;
  ens.droplet.area_stiffness = par.area_stiffness;
  ens.droplet.perimeter_stiffness = par.perimeter_ratio * ens.droplet.line_tension;
  ens.droplet.wall_energy = par.dp_wall_energy;
  ens.droplet.near_wall_drag = par.near_wall_drag;
  ens.droplet.terminal_speed = par.terminal_speed;
  ens.droplet.dt = par.dt;
  ens.droplet.force_dt = par.force_dt;
  ens.soft.wall_energy = sp ? point.strength : ens.soft.wall_energy;
  ens.soft.terminal_speed = par.terminal_speed;
  ens.soft.dt = par.dt;
  ens.soft.force_dt = par.force_dt;
  ens.box_length = par.box_length;
  ens.obstacle_diameter = par.obstacle_diameter;
  ens.obstacle_fraction = par.obstacle_fraction;
  ens.gap = point.gap;
  ens.time_limit = par.time_limit;
  ens.clog_threshold = par.clog_threshold;
  ens.relax_iterations = par.relax_iterations;
  return ens;
}

// The time step of a sweep point; throws std::invalid_argument (naming dt) above the stability limit.
double point_time_step(const ObstacleEnsembleParameters& ens) {
  return ens.model == DropletModel::soft_particle ? resolve_time_step(ens.soft) : resolve_time_step(ens.droplet, true);
}

void run(const Parameters& par, const cli::DriverApp& app, const std::vector<SweepPoint>& points,
         const ensemble::Ranks& ranks) {
  const bool sp = par.model == "sp";
  const bool talk = !app.quiet() && ranks.root();
  const driver::OutputPaths out(app.output());
  const std::string parameters = fingerprint(app);
  // Every rank reads the same checkpoints before rank 0 merges them into <out>.ckpt.h5 (or, without
  // --restart, starts it afresh) and removes the rank checkpoints.
  const std::vector<std::string> partials = rank_checkpoints(out.checkpoint);
  std::vector<FinishedReplica> done;
  if (par.restart) done = read_finished(out.checkpoint, partials, parameters);
  const std::size_t resumed = done.size();
  if (par.restart && talk)
    std::cerr << "obstacles: resumed " << resumed << " finished replicas from " << out.checkpoint
              << (partials.empty() ? "" : " and " + std::to_string(partials.size()) + " rank checkpoints") << "\n";
  ranks.barrier();
  if (ranks.root()) {
    write_checkpoint(out.checkpoint, parameters, done);
    for (const std::string& f : partials) std::remove(f.c_str());
  }
  ranks.barrier();

  // This rank's share of the unfinished (point, replica) items, by point.
  std::vector<std::vector<int>> todo(points.size());
  {
    std::vector<std::pair<int, int>> pending;
    for (std::size_t p = 0; p < points.size(); ++p)
      for (int j = 0; j < par.replicas; ++j)
        if (std::none_of(done.begin(), done.end(),
                         [&](const FinishedReplica& f) { return f.point == int(p) && f.replica == j; }))
          pending.emplace_back(int(p), j);
    for (const std::size_t i : ensemble::shard(pending.size(), ranks.rank(), ranks.size()))
      todo[std::size_t(pending[i].first)].push_back(pending[i].second);
  }
  // One rank keeps everything in <out>.ckpt.h5, as without MPI; a rank of several keeps what it
  // finishes in its own file.
  std::vector<FinishedReplica> fresh;
  const auto record_finished = [&](const FinishedReplica& f) {
    fresh.push_back(f);
    if (ranks.size() == 1) {
      done.push_back(f);
      write_checkpoint(out.checkpoint, parameters, done);
    } else {
      write_checkpoint(rank_checkpoint(out.checkpoint, ranks.rank()), parameters, fresh);
    }
  };

  const auto t_start = std::chrono::steady_clock::now();
  long long steps_run = 0, vertex_steps = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    const ObstacleEnsembleParameters ens = ensemble_parameters(par, points[p]);
    const std::vector<int>& pending = todo[p];
    for (std::size_t first = 0; first < pending.size(); first += std::size_t(par.batch)) {
      const std::vector<int> batch(pending.begin() + std::ptrdiff_t(first),
                                   pending.begin() + std::ptrdiff_t(std::min(pending.size(), first + std::size_t(par.batch))));
      std::vector<std::uint64_t> seeds;
      for (const int j : batch) seeds.push_back(replica_seed(std::uint64_t(par.seed), j));
      const long long batch_steps = static_cast<long long>(std::ceil(par.time_limit / point_time_step(ens)));
      cli::ProgressLine progress(batch_steps, (long long)(batch.size()) * (sp ? 1 : par.vertices), talk);
      if (talk)
        std::cerr << "obstacles: point " << p + 1 << "/" << points.size() << " (" << (sp ? "E_w = " : "Gamma = ")
                  << points[p].strength << ", w_ob = " << points[p].gap << "), replicas " << batch.front() << ".."
                  << batch.back() << "\n";
      long long last_steps = 0;
      run_obstacle_batch<double>(
          ens, seeds,
          [&](int k, const ReplicaRecord& record) {
            record_finished({int(p), batch[std::size_t(k)], seeds[std::size_t(k)], record});
          },
          [&](long long steps) {
            last_steps = steps;
            progress.update(std::min(steps, batch_steps));
          });
      progress.finish();
      steps_run += last_steps;
      vertex_steps += last_steps * (long long)(batch.size()) * (sp ? 1 : par.vertices);
    }
  }
  // Rank 0 gathers every rank's records and writes the outputs; the other ranks are done.
  const std::size_t computed = std::size_t(ranks.sum((long long)(fresh.size())));
  steps_run = ranks.sum(steps_run);
  vertex_steps = ranks.sum(vertex_steps);
  const std::vector<std::vector<char>> gathered = ranks.gather(to_bytes(fresh));
  if (!ranks.root()) return;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (ranks.size() > 1) {
    for (std::size_t r = 0; r < gathered.size(); ++r) append_from_bytes(gathered[r], done);
    write_checkpoint(out.checkpoint, parameters, done);
    for (int r = 0; r < ranks.size(); ++r) std::remove(rank_checkpoint(out.checkpoint, r).c_str());
  }

  std::sort(done.begin(), done.end(), [](const FinishedReplica& a, const FinishedReplica& b) {
    return a.point != b.point ? a.point < b.point : a.replica < b.replica;
  });
  std::vector<PointSummary> summaries;
  for (std::size_t p = 0; p < points.size(); ++p) {
    std::vector<FinishedReplica> here;
    for (const FinishedReplica& f : done)
      if (f.point == int(p)) here.push_back(f);
    summaries.push_back(summarize(here, par.terminal_speed, par.confidence));
  }
  write_results(out.trajectory, app, sp, points, done, summaries);

  std::ofstream csv(out.csv);
  csv << (sp ? "wall_energy" : "line_tension")
      << ",gap,replicas,clogged,decay_length,decay_length_lower,decay_length_upper,flowing,mean_speed_ratio,"
         "mean_speed_ratio_error\n";
  for (std::size_t p = 0; p < points.size(); ++p) {
    const PointSummary& s = summaries[p];
    csv << number(points[p].strength) << "," << number(points[p].gap) << "," << s.replicas << "," << s.clogged << ","
        << number(s.lambda.lambda) << "," << number(s.lambda.lower) << "," << number(s.lambda.upper) << ","
        << s.flowing << "," << (s.flowing > 0 ? number(s.mean_speed_ratio) : "") << ","
        << (s.flowing > 1 ? number(s.speed_ratio_error) : "") << "\n";
  }
  const auto json_number = [](double v) { return std::isfinite(v) ? number(v) : std::string("null"); };
  std::ofstream json(out.summary);
  json << "{\n  \"driver\": \"obstacles\",\n  \"model\": \"" << par.model << "\",\n  \"points\": " << points.size()
       << ",\n  \"replicas_per_point\": " << par.replicas << ",\n  \"ranks\": " << ranks.size()
       << ",\n  \"replicas_resumed\": " << resumed
       << ",\n  \"replicas_computed\": " << computed << ",\n  \"steps_run\": " << steps_run
       << ",\n  \"wall_seconds\": " << json_number(wall) << ",\n  \"vertex_steps_per_second\": "
       << json_number(wall > 0 ? double(vertex_steps) / wall : 0.0) << ",\n  \"decay_length\": ["
       << [&] {
            std::string s;
            for (std::size_t p = 0; p < points.size(); ++p)
              s += (p ? ", " : "") + json_number(summaries[p].lambda.lambda);
            return s;
          }()
       << "],\n  \"kokkos\": \"" << kokkos_configuration() << "\"\n}\n";
  if (!app.quiet())
    for (std::size_t p = 0; p < points.size(); ++p)
      std::cout << (sp ? "E_w = " : "Gamma = ") << points[p].strength << ", w_ob = " << points[p].gap
                << ": N_s = " << summaries[p].replicas << ", N_clog = " << summaries[p].clogged
                << ", lambda = " << number(summaries[p].lambda.lambda) << " [" << number(summaries[p].lambda.lower)
                << ", " << number(summaries[p].lambda.upper) << "] sigma"
                << (summaries[p].flowing > 0 ? ", <v_g>/v_t = " + number(summaries[p].mean_speed_ratio) : "") << "\n";
}

}  // namespace
}  // namespace mesoflow::droplets

int main(int argc, char** argv) {
  using mesoflow::cli::Bounds;
  mesoflow::droplets::Parameters par;
  mesoflow::ensemble::Ranks ranks;  // MPI, when launched by mpirun/srun: before Kokkos, ended after it
  mesoflow::cli::DriverApp app(
      "Single droplets through random obstacle arrays (capillary-droplets §4.2-4.3): clogging decay length and "
      "steady speed over ensembles of obstacle arrays, DP or SP model",
      "obstacles.h5");
  app.add_choice("--model", par.model, "droplet model: dp (deformable polygon) or sp (soft particle)", {"dp", "sp"});
  app.add_string("--line-tension", par.line_tension, "DP sweep: line tensions Γ, comma-separated, each in [0.001, 100]");
  app.add_string("--sp-wall-energy", par.sp_wall_energy,
                 "SP sweep: stiffnesses E_w of eq. 8, comma-separated, each in [0.001, 10000]");
  app.add_string("--gap", par.gap, "sweep: minimum obstacle gaps w_ob/σ, comma-separated, each in [0.01, 10]");
  app.add_int("--replicas", par.replicas, "replicas N_s per sweep point (each its own obstacle array)", 1, 100000);
  app.add_int("--batch", par.batch, "replicas advanced together in one set of kernel launches", 1, 100000);
  app.add_real("--box-length", par.box_length, "side L/σ of the periodic box", 10.0, 2000.0);
  app.add_real("--obstacle-diameter", par.obstacle_diameter, "obstacle diameter σ_ob/σ", 0.01, 10.0);
  app.add_real("--obstacle-fraction", par.obstacle_fraction,
               "obstacle area fraction φ (0: maximal Poisson-disk arrays, the densest the gap allows)", 0.0, 0.5);
  app.add_positive("--time-limit", par.time_limit, "run time T/t0 of a replica that does not clog");
  app.add_real("--clog-threshold", par.clog_threshold, "clog when E_k/E_t falls below this (App. C)", 0.0, 1.0,
               Bounds::open);
  app.add_real("--confidence", par.confidence, "confidence level of the interval on λ", 0.0, 1.0, Bounds::open);
  app.add_int("--vertices", par.vertices, "DP: vertices N_v per droplet", 8, 4096);
  app.add_real("--area-stiffness", par.area_stiffness, "DP: area stiffness K_a", 0.0, 1e8);
  app.add_real("--perimeter-ratio", par.perimeter_ratio, "DP: perimeter elasticity over line tension K_l/Γ", 0.0, 10.0);
  app.add_real("--dp-wall-energy", par.dp_wall_energy, "DP: vertex-obstacle energy E_w of eq. 3", 0.0, 1e4,
               Bounds::left_open);
  app.add_real("--near-wall-drag", par.near_wall_drag, "DP: near-wall drag b0/b∞ of eq. 6", 0.0, 100.0);
  app.add_real("--terminal-speed", par.terminal_speed, "terminal speed V_t (eq. 15)", 0.0, 10.0, Bounds::left_open);
  app.add_real("--dt", par.dt, "time step Δt/t0 (0: 10⁻³ or the stability limit if smaller)", 0.0, 0.01);
  app.add_flag(mesoflow::cli::force_dt_flag, par.force_dt, mesoflow::cli::force_dt_help);
  app.add_int("--relax-iterations", par.relax_iterations, "FIRE iterations of the initial relaxation", 0, 10000000);
  app.add_int("--seed", par.seed, "base seed of the replicas' obstacle arrays", 0, 4294967295LL);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--restart", par.restart, "resume a killed sweep from <output>.ckpt.h5 (the same parameters)");
  return ranks.finish(app.run(argc, argv, [&] {
    const bool sp = par.model == "sp";
    const auto strengths = sp ? mesoflow::droplets::parse_list("--sp-wall-energy", par.sp_wall_energy, 0.001, 1e4)
                              : mesoflow::droplets::parse_list("--line-tension", par.line_tension, 0.001, 100.0);
    const auto gaps = mesoflow::droplets::parse_list("--gap", par.gap, 0.01, 10.0);
    for (const double w : gaps)
      if (par.box_length < 4 * (par.obstacle_diameter + w) || par.box_length < 10)
        throw std::invalid_argument("--box-length: must be >= 4 (sigma_ob + w_ob) = " +
                                    std::to_string(4 * (par.obstacle_diameter + w)) + " for --gap " + std::to_string(w));
    std::vector<mesoflow::droplets::SweepPoint> points;
    for (const double s : strengths)
      for (const double w : gaps) {
        points.push_back({s, w});
        const auto ens = mesoflow::droplets::ensemble_parameters(par, points.back());
        ens.droplet.validate();
        ens.soft.validate();
        mesoflow::droplets::point_time_step(ens);
      }
    ranks.start();
    mesoflow::KokkosScope kokkos(par.threads);
    mesoflow::droplets::run(par, app, points, ranks);
  }));
}
