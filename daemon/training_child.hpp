// The training child (daemon/training_process.hpp): `tofcompd --train-worker ...`, started by the
// daemon, never by hand. It limits itself first (memory, processor time, death with its parent,
// the lowest priority so that it gives way to the daemon's scans),
// reads the recording from standard input and the running calibration from fd 3, trains with a
// held-out part (calibration/held_out_training.hpp) and writes one JSON report to standard
// output: the calibration's file text, what was held out and the held-out scores. A failure is
// one line on standard error and a non-zero exit status.
#pragma once

namespace tofcomp::daemon {

// The first argument that makes tofcompd the training child.
inline constexpr const char* kTrainWorkerFlag = "--train-worker";

// The descriptor on which the daemon hands the child the running calibration (the recording is
// on standard input, the report on standard output, messages on standard error).
inline constexpr int kRunningCalibrationFd = 3;

// Exit statuses: 0 done; 1 training failed (the reason on stderr); 2 a bad command line; 3 the
// memory limit was reached.
int training_child_main(int argc, char** argv);

}  // namespace tofcomp::daemon
