// checkpoint_stop.hpp — a deterministic stand-in for killing a run, for the restart tests.
//
// With MESOFLOW_STOP_AFTER_CHECKPOINT=K in the environment, a run stops as if it had been killed
// right after its K-th checkpoint: when it comes to write checkpoint K + 1 (counted in this process:
// CheckpointWriter's constructor calls before_checkpoint() before it opens any file, so every
// checkpoint of every driver counts, and no driver has to remember the call),
// before_checkpoint() ends the process at once with exit status stopped_after_checkpoint_status.
// Checkpoint K is then the one on disk and everything the run did after it (steps, frames already
// flushed to the trajectory) is work a restart must redo or drop. std::_Exit runs no destructors and
// closes no file, as SIGKILL. Unlike a kill from outside after some delay, the point of the stop is
// the same in every run, however busy the machine is (tests/drivers/restart_bit_identical.sh).
// Without the variable before_checkpoint() does nothing.
#pragma once

namespace mesoflow::io {

// The exit status of a run stopped by MESOFLOW_STOP_AFTER_CHECKPOINT (EX_TEMPFAIL of sysexits.h):
// distinct from success (0), failure (1) and usage errors (2).
inline constexpr int stopped_after_checkpoint_status = 75;

// Called by CheckpointWriter's constructor, before the checkpoint file is opened (drivers flush
// their trajectories before they checkpoint). Throws std::invalid_argument when the variable is set but is not a
// positive integer.
void before_checkpoint();

}  // namespace mesoflow::io
