// A task over indices run on a few threads, for the searches' independent fits (the structure
// search's folds, the model search's candidates) and the EM sweeps' stripes. Each task writes
// only its own slot of the results, so a run on any number of threads gives the serial run's
// results bit for bit. The threads are a pool kept for the process's life; calls may nest (a
// task may call parallel_for) and run at once from several threads.
#pragma once

#include <functional>

#include "core/parallel_for.hpp"

namespace tofcomp::calibration {

// Threads to run: `requested`, or one per core when it is 0.
int thread_count(int requested);

// Runs task(i) for i in [0, n) on up to `threads` threads (the caller's among them, the others
// the pool's when idle), each index once; the first exception a task throws is rethrown once
// all have ended.
void parallel_for(int n, int threads, const std::function<void(int)>& task);

// core::ParallelFor on `threads` threads (0: one per core).
core::ParallelFor parallel_runner(int threads);

}  // namespace tofcomp::calibration
