// How core's searches and sweeps are handed threads without having any: a runner the caller
// provides (calibration/parallel_for.hpp's pool), or none for a serial run.
#pragma once

#include <functional>

namespace tofcomp::core {

// Runs task(i) for every i in [0, count), in any order and possibly at once (the caller's
// threads: core has none); each task writes only its own results.
using ParallelFor = std::function<void(int count, const std::function<void(int)>& task)>;

}  // namespace tofcomp::core
