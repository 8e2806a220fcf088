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
// §4.3/App. E), threshold E_k/E_t = 10⁻¹⁷, obstacle area fraction φ = 0.0248 (the paper does not
// state it; calibrated once to λ = 24σ on this scene, docs/droplets.md). The paper uses L = 500σ, T = 2·10⁵ t0 and N_s = 50; the
// defaults here (L = 40σ, T = 200 t0, N_s = 16, N_v = 64) run in minutes on two cores. With
// v ≤ v_t = 0.08 a droplet travels at most 16σ in 200 t0 < L, so no replica comes back through the
// periodic image of its own path (which inflates λ: the driver warns when v_t T > L); many replicas
// at the paper's point are right-censored, which the estimator of λ accounts for (raise
// --time-limit, and --box-length with it, to narrow the interval).
// K_l/Γ defaults to 0.1, not the paper's 10⁻³: a held droplet's vertices slide along its interface
// at the rate π² k_l/b∞ (docs/droplets.md, deviation 4), so at 10⁻³ E_k reaches the clog threshold
// only after ~10⁴ t0 at Γ ≈ 1 and every replica would end right-censored within T.
// --shape-dt TARGET (DP) lets each droplet halve its own time step while the area mode of its
// current shape has ω Δt > TARGET (down to Δt0/4096) and double it back below TARGET/2, where a
// fixed step would stop the run (scenes/droplets/droplet_scene.hpp, adapt_time_steps); each
// replica's clock follows its own steps.
// --obstacle-contacts edges (DP) makes the obstacles repel whole edges, not only vertices
// (kernels/dp/edge_obstacle_repulsion.hpp): below K_l·N_v ≈ 1.2 an obstacle otherwise passes
// between two vertices and through a floppy droplet (docs/droplets.md, finding 7).
//
// Output (<out> = --output without its extension): <out>.h5 (H5MD-style: /h5md, /parameters as
// attributes, /results/replicas, /results/points, /results/survival), <out>.csv (one row per sweep
// point), <out>.replicas.csv (one row per replica: both classifications of --clog-test both),
// <out>.json (run summary), <out>.ckpt.h5 (finished replicas, replaced atomically as they
// finish; --restart resumes a killed sweep from it without recomputing them).
//
// Scheduling (DP): --schedule sweep (the default) runs every (point, replica) of the sweep in one
// batch of --batch slots, each droplet with its point's Γ, K_l and time step, a finished replica's
// slot refilled with the next and the batch compacted once the queue is empty
// (scenes/droplets/obstacles_ensemble.hpp, run_sweep_batched); --schedule points runs one batch of a
// point after another, each ending with its slowest replica. A replica's record does not depend on
// the schedule when the sweep has one w_ob (with several, the obstacle grid of the smallest serves
// all and the records move in their last bits). SP sweeps run point by point.
//
// Under mpirun/srun (docs/scale-out.md) the sweep's work items, (point, replica) pairs in
// point-major order less those already finished, are dealt round robin to the ranks
// (drivers/common/ensemble_mpi.hpp); each rank runs its share as above and records what
// it finishes in its own <out>.rank<r>.ckpt.h5 (replaced atomically). Rank 0 gathers the records,
// writes the files above and merges the rank checkpoints into <out>.ckpt.h5, then removes them.
// --restart reads <out>.ckpt.h5 and every <out>.rank<r>.ckpt.h5, whatever the number of ranks now.
// A replica's record depends only on its seed, so the results do not depend on the number of ranks.
#include "drivers/common/cli.hpp"
#include "drivers/common/ensemble_mpi.hpp"
#include "drivers/common/json_summary.hpp"
#include "drivers/common/output_paths.hpp"
#include "drivers/common/progress.hpp"
#include "analysis/droplets/obstacle_sweep.hpp"
#include "scenes/droplets/obstacles_ensemble.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <optional>

namespace mesoflow::droplets {
namespace {

struct Parameters {
  std::string model = "dp";
  std::string line_tension = "1.09";   // Γ list (DP)
  std::string sp_wall_energy = "10";   // E_w list (SP)
  std::string obstacle_contacts = "vertices";  // DP: what the obstacles repel
  std::string gap = "0.2";             // w_ob list
  std::string clog_test = "full";      // full, early or both (scenes/droplets/clog_detection.hpp)
  std::string schedule = "sweep";      // DP: sweep (one batch for every point, refilled) or points
  int replicas = 16;
  double confidence = 0.95;
  ObstacleSweep sweep;                 // the scene of every point but (strength, w_ob)
  long long seed = 1;
  int threads = 0;
  bool restart = false;
};

std::string fingerprint(const cli::DriverApp& app) {
  std::string out;
  for (const auto& [key, value] : app.resolved_parameters())
    if (key != "restart" && key != "threads") out += key + "=" + value + "\n";
  return out;
}

void run(const Parameters& par, const cli::DriverApp& app, const std::vector<SweepPoint>& points,
         const ensemble::Ranks& ranks) {
  const bool sp = par.sweep.soft_particles;
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
    write_replica_checkpoint(out.checkpoint, parameters, done);
    for (const std::string& f : partials) std::remove(f.c_str());
  }
  ranks.barrier();

  // This rank's share of the unfinished (point, replica) items, by point.
  const auto todo = ensemble::pending_shard(points.size(), par.replicas, ranks, [&](std::size_t p, int j) {
    return std::any_of(done.begin(), done.end(), [&](const FinishedReplica& f) { return f.point == int(p) && f.replica == j; });
  });
  std::vector<std::pair<double, double>> at;
  for (const SweepPoint& point : points) at.emplace_back(point.strength, point.gap);
  // One rank keeps everything in <out>.ckpt.h5, as without MPI; a rank of several keeps what it
  // finishes in its own file.
  std::vector<FinishedReplica> fresh;
  const auto t_start = std::chrono::steady_clock::now();
  std::optional<cli::ProgressLine> progress;
  const auto record = [&](std::size_t p, int replica, std::uint64_t seed, const ReplicaRecord& r) {
    fresh.push_back({int(p), replica, seed, r.clogged, r.distance, r.time, r.final_x, r.final_y, r.steady_speed,
                     r.early, r.early_distance, r.early_time, r.early_rate, r.early_crossing});
    if (ranks.size() == 1) {
      done.push_back(fresh.back());
      write_replica_checkpoint(out.checkpoint, parameters, done);
    } else {
      write_replica_checkpoint(rank_checkpoint(out.checkpoint, ranks.rank()), parameters, fresh);
    }
  };
  SweepSteps steps;
  int deepest_dt_level = 0;
  if (!sp && par.schedule == "sweep") {
    // Every (point, replica) of this rank's share in one refilled batch (run_sweep_batched).
    std::vector<ObstacleEnsembleParameters> scenes;
    long long total = 0, items = 0;
    for (std::size_t p = 0; p < points.size(); ++p) {
      scenes.push_back(par.sweep.at(points[p].strength, points[p].gap));
      total += (long long)(todo[p].size()) * (long long)std::ceil(par.sweep.time_limit / ObstacleSweep::time_step(scenes.back()));
      items += (long long)(todo[p].size());
    }
    if (items > 0) {
      progress.emplace(total, par.sweep.bodies(), talk);
      if (talk)
        std::cerr << "obstacles: " << items << " replicas of " << points.size() << " points in one batch of "
                  << std::min<long long>(items, par.sweep.batch) << " slots\n";
      const BatchedSweepStats stats = run_sweep_batched<double>(scenes, todo, std::uint64_t(par.seed), par.sweep.batch,
                                                                record, [&](long long s) { progress->update(s); });
      steps.steps = stats.steps;
      steps.replica_steps = stats.replica_steps;
      deepest_dt_level = stats.deepest_dt_level;
    }
  } else {
  steps = run_sweep_points(
      par.sweep, at, todo, std::uint64_t(par.seed),
      [&](std::size_t p, const std::vector<int>& batch, long long batch_steps) {
        if (progress) progress->finish();
        progress.emplace(batch_steps, (long long)(batch.size()) * par.sweep.bodies(), talk);
        if (talk)
          std::cerr << "obstacles: point " << p + 1 << "/" << points.size() << " (" << (sp ? "E_w = " : "Gamma = ")
                    << points[p].strength << ", w_ob = " << points[p].gap << "), replicas " << batch.front() << ".."
                    << batch.back() << "\n";
      },
      record, [&](long long s) { progress->update(s); });
  }
  if (progress) progress->finish();
  // Rank 0 gathers every rank's records and writes the outputs; the other ranks are done.
  const std::size_t computed = std::size_t(ranks.sum((long long)(fresh.size())));
  const long long steps_run = ranks.sum(steps.steps);
  const long long vertex_steps = ranks.sum(steps.replica_steps * par.sweep.bodies());
  std::vector<char> bytes;
  for (const FinishedReplica& f : fresh) ensemble::append_bytes(bytes, f);
  const std::vector<std::vector<char>> gathered = ranks.gather(bytes);
  if (!ranks.root()) return;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (ranks.size() > 1) {
    for (const std::vector<char>& b : gathered)
      for (std::size_t offset = 0; offset < b.size();) done.push_back(ensemble::read_bytes<FinishedReplica>(b, offset));
    write_replica_checkpoint(out.checkpoint, parameters, done);
    for (int r = 0; r < ranks.size(); ++r) std::remove(rank_checkpoint(out.checkpoint, r).c_str());
  }

  std::sort(done.begin(), done.end(), [](const FinishedReplica& a, const FinishedReplica& b) {
    return a.point != b.point ? a.point < b.point : a.replica < b.replica;
  });
  const auto summaries = summarize_points(done, points.size(), par.sweep.terminal_speed, par.confidence);
  std::vector<std::pair<std::string, std::string>> attributes;
  for (const auto& [key, value] : app.resolved_parameters())
    if (key != "restart" && key != "threads") attributes.emplace_back(key, value);
  write_sweep_results(out.trajectory, attributes, sp, points, done, summaries, MESOFLOW_VERSION);
  write_sweep_csv(out.csv, sp, points, summaries);
  const std::string replicas_csv = out.csv.substr(0, out.csv.size() - 4) + ".replicas.csv";
  write_replicas_csv(replicas_csv, sp, points, done);
  cli::Json json;
  json["driver"] = "obstacles";
  json["model"] = par.model;
  json["points"] = points.size();
  json["replicas_per_point"] = par.replicas;
  json["ranks"] = ranks.size();
  json["replicas_resumed"] = resumed;
  json["replicas_computed"] = computed;
  json["steps_run"] = steps_run;
  json["wall_seconds"] = cli::summary_number(wall);
  json["clog_test"] = par.clog_test;
  json["schedule"] = sp ? std::string("points") : par.schedule;
  const ClogTestTotals totals = clog_test_totals(done);  // simulated time to the record and to the early decision
  json["replica_time_recorded"] = cli::summary_number(totals.recorded);
  if (par.clog_test != "full") {
    json["replica_time_early"] = cli::summary_number(totals.early);
    json["classification_disagreements"] = totals.disagreements;
  }
  if (!sp && par.sweep.shape_dt_target > 0 && par.schedule == "sweep")
    json["deepest_shape_dt_level"] = deepest_dt_level;  // of this run's replicas: Δt0/2^level the smallest step
  json["vertex_steps_per_second"] = cli::summary_number(wall > 0 ? double(vertex_steps) / wall : 0.0);
  json["decay_length"] = cli::Json::array();
  for (const PointSummary& s : summaries) json["decay_length"].push_back(cli::summary_number(s.lambda.lambda));
  json["kokkos"] = kokkos_configuration();
  cli::write_summary(out.summary, json);
  if (!app.quiet())
    for (std::size_t p = 0; p < points.size(); ++p) std::cout << point_line(sp, points[p], summaries[p]) << "\n";
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
  app.add_int("--batch", par.sweep.batch, "replicas advanced together in one set of kernel launches", 1, 100000);
  app.add_choice("--schedule", par.schedule,
                 "DP: sweep (every point's replicas in one batch of --batch slots, refilled as replicas finish, "
                 "each at its own time step) or points (one batch after another, point by point); SP: points",
                 {"sweep", "points"});
  app.add_real("--box-length", par.sweep.box_length, "side L/σ of the periodic box", 10.0, 2000.0);
  app.add_real("--obstacle-diameter", par.sweep.obstacle_diameter, "obstacle diameter σ_ob/σ", 0.01, 10.0);
  app.add_real("--obstacle-fraction", par.sweep.obstacle_fraction,
               "obstacle area fraction φ (default: 0.0248, calibrated on Fig. 13(b); 0: maximal Poisson-disk arrays)",
               0.0, 0.5);
  app.add_positive("--time-limit", par.sweep.time_limit, "run time T/t0 of a replica that does not clog");
  app.add_real("--clog-threshold", par.sweep.clog_threshold, "clog when E_k/E_t falls below this (App. C)", 0.0, 1.0,
               Bounds::open);
  app.add_choice("--clog-test", par.clog_test,
                 "what ends a replica: full (E_k/E_t below --clog-threshold), early (that or the early clog test), "
                 "both (the threshold; the early decision recorded beside it, for validation)",
                 {"full", "early", "both"});
  app.add_real("--clog-sample-interval", par.sweep.early.sample_interval,
               "early clog test: time between samples Δt_s/t0", 1e-3, 100.0);
  app.add_real("--clog-window", par.sweep.early.window,
               "early clog test: fit window τ_w/t0 (4 to 4096 samples)", 0.0, 1e5, Bounds::left_open);
  app.add_real("--clog-tolerance", par.sweep.early.tolerance,
               "early clog test: largest displacement in the window and travel left, σ", 1e-9, 1.0);
  app.add_real("--clog-max-scatter", par.sweep.early.max_scatter,
               "early clog test: largest rms residual of the ln(E_k/E_t) fit", 0.0, 10.0, Bounds::left_open);
  app.add_real("--clog-min-rate", par.sweep.early.min_rate, "early clog test: smallest decay rate of E_k, 1/t0", 0.0,
               100.0, Bounds::left_open);
  app.add_real("--confidence", par.confidence, "confidence level of the interval on λ", 0.0, 1.0, Bounds::open);
  app.add_int("--vertices", par.sweep.vertices, "DP: vertices N_v per droplet", 8, 4096);
  app.add_real("--area-stiffness", par.sweep.area_stiffness, "DP: area stiffness K_a", 0.0, 1e8);
  app.add_real("--perimeter-ratio", par.sweep.perimeter_ratio, "DP: perimeter elasticity over line tension K_l/Γ", 0.0, 10.0);
  app.add_real("--dp-wall-energy", par.sweep.dp_wall_energy, "DP: vertex-obstacle energy E_w of eq. 3", 0.0, 1e4,
               Bounds::left_open);
  app.add_choice("--obstacle-contacts", par.obstacle_contacts,
                 "DP: what the obstacles repel: vertices (eq. 3 as printed) or edges (eq. 3's law on circulo-line "
                 "edges of width delta, so that an obstacle cannot pass between two vertices at small K_l)",
                 {"vertices", "edges"});
  app.add_real("--near-wall-drag", par.sweep.near_wall_drag, "DP: near-wall drag b0/b∞ of eq. 6", 0.0, 100.0);
  app.add_real("--terminal-speed", par.sweep.terminal_speed, "terminal speed V_t (eq. 15)", 0.0, 10.0, Bounds::left_open);
  app.add_real("--dt", par.sweep.dt, "time step Δt/t0 (0: 10⁻³ or the stability limit if smaller)", 0.0, 0.01);
  app.add_flag(mesoflow::cli::force_dt_flag, par.sweep.force_dt, mesoflow::cli::force_dt_help);
  app.add_real("--shape-dt", par.sweep.shape_dt_target,
               "DP: shape-following steps: each droplet halves its own dt while its area mode has omega dt above "
               "this target and doubles it back (up to its initial dt) below half of it (0: off, a fixed dt that "
               "stops the run when the shape outgrows it; the progress line's total assumes the initial steps)",
               0.0, 1.8);
  app.add_int("--relax-iterations", par.sweep.relax_iterations, "FIRE iterations of the initial relaxation", 0, 10000000);
  app.add_int("--seed", par.seed, "base seed of the replicas' obstacle arrays", 0, 4294967295LL);
  app.add_int("--threads", par.threads, "host threads (0: OMP_NUM_THREADS or all cores)", 0, 4096);
  app.add_flag("--restart", par.restart, "resume a killed sweep from <output>.ckpt.h5 (the same parameters)");
  return ranks.finish(app.run(argc, argv, [&] {
    par.sweep.soft_particles = par.model == "sp";
    par.sweep.edge_contacts = par.obstacle_contacts == "edges";
    if (par.sweep.soft_particles && par.sweep.edge_contacts)
      throw std::invalid_argument("--obstacle-contacts: edges needs --model dp (an SP droplet has no edges)");
    if (par.sweep.soft_particles && par.sweep.shape_dt_target > 0)
      throw std::invalid_argument("--shape-dt: needs --model dp (an SP droplet has no shape)");
    par.sweep.clog_test = mesoflow::droplets::clog_test_from_name(par.clog_test);
    const auto strengths = par.sweep.soft_particles
                               ? mesoflow::cli::parse_real_list("--sp-wall-energy", par.sp_wall_energy, 0.001, 1e4)
                               : mesoflow::cli::parse_real_list("--line-tension", par.line_tension, 0.001, 100.0);
    const auto gaps = mesoflow::cli::parse_real_list("--gap", par.gap, 0.01, 10.0);
    for (const double w : gaps) par.sweep.check_box(w);
    if (par.sweep.may_revisit_own_path())
      std::cerr << "warning: v_t T = " << par.sweep.terminal_speed * par.sweep.time_limit << " sigma exceeds --box-length "
                << par.sweep.box_length << ": a replica can come back along its own path and meet its obstacles again\n";
    std::vector<mesoflow::droplets::SweepPoint> points;
    for (const double s : strengths)
      for (const double w : gaps) {
        points.push_back({s, w});
        par.sweep.check(s, w);
      }
    ranks.start();
    mesoflow::KokkosScope kokkos(par.threads);
    mesoflow::droplets::run(par, app, points, ranks);
  }));
}
