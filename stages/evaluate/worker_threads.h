// Spreading independent evaluations over threads (syn-evaluate --threads).
//
// Every task writes only its own result slot and each worker owns its own
// MotionEvaluator (one Simbody Workspace per thread, as Pinocchio pairs a
// shared Model with per-thread Data), so results do not depend on the number
// of threads or on which thread ran which task.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace syn {

// The default for --threads: the cores `make -jN` does not already fill. Order of precedence:
//   1. SYN_THREADS=N in the environment (N ≥ 1);
//   2. inside make with -jN (MAKEFLAGS holds "-jN"; N parallel jobs already share the cores):
//      max(1, hardware cores / N);
//   3. the hardware cores (std::thread::hardware_concurrency(), 1 when unknown).
// A bare `make -j` (no N) counts as unlimited jobs: 1 thread.
[[nodiscard]] int DefaultThreadCount();

// The same from given values (testable): `makeflags` as make exports it, `syn_threads` the variable's
// text (empty when unset), `cores` the hardware's.
[[nodiscard]] int DefaultThreadCount(const std::string& syn_threads, const std::string& makeflags, unsigned cores);

// Runs run(worker, task) for task = 0 .. tasks-1 on min(workers, tasks) threads (worker < workers), each
// thread taking the next task as it finishes one. One worker runs inline. The first exception thrown by a
// task is rethrown here once every thread has stopped.
void RunTasks(int64_t tasks, int workers, const std::function<void(int worker, int64_t task)>& run);

}  // namespace syn
