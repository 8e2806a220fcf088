// restart.hpp — what a restarted run must share with the run it continues: the scene signature
// kept in the checkpoint, and the check that refuses a checkpoint written by another scene.
#pragma once

#include "drivers/common/cli.hpp"
#include "io/checkpoint.hpp"

#include <set>
#include <stdexcept>
#include <string>

namespace mesoflow::driver {

// The resolved parameters of `app` (key=value, space-separated) but those in `may_change` (the run
// length, the checkpoint interval, the threads, the output options): the scene a restart continues.
inline std::string scene_signature(const cli::DriverApp& app, const std::set<std::string>& may_change) {
  std::string s;
  for (const auto& [key, value] : app.resolved_parameters())
    if (may_change.count(key) == 0) s += key + "=" + value + " ";
  return s;
}

// --restart without a checkpoint at `path`: std::invalid_argument naming it.
inline void require_checkpoint(const std::string& path) {
  if (!io::checkpoint_exists(path)) throw std::invalid_argument("--restart: no checkpoint " + path + " to resume from");
}

// Refuses (std::invalid_argument) the checkpoint `ck` at `path` when its "scene" string is not
// `signature`; `may_change` names the options that may differ ("--steps and --threads").
inline void check_restart_scene(const io::CheckpointReader& ck, const std::string& path, const std::string& signature,
                                const std::string& may_change) {
  const std::string stored = ck.get_string("scene");
  if (stored != signature)
    throw std::invalid_argument("--restart: " + path + " was written by another scene (" + stored + "); only " +
                                may_change + " may change");
}

}  // namespace mesoflow::driver
