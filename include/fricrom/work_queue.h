// Independent units of work (parameter values of a sweep, frequencies of a bound curve, α samples)
// run on several threads with dynamic load balancing: units differ in cost (FE points near a
// resonance take 10x the others), so each worker takes the next pending unit when it is free.
#pragma once

#include <functional>
#include <vector>

namespace fricrom {

// The cores this process may run on (its CPU affinity mask; the machine's count if unknown).
int UsableCores();

// Worker threads for `requested` (0 = UsableCores()), at most `units`, at least 1.
int WorkerThreads(int requested, int units);

// Runs unit(i) for every i in `pending` (in that order of hand-out) on WorkerThreads(threads, n)
// threads. finished(i) is called after unit(i) returned, one call at a time (under a lock), in
// completion order: the place to make a result durable. If a unit or finished() throws, no new
// unit is handed out and the first exception is rethrown once the running units have ended.
// unit() must not share mutable state between indices; with one thread everything runs on the
// calling thread.
void RunWorkUnits(const std::vector<int>& pending, int threads,
                  const std::function<void(int)>& unit, const std::function<void(int)>& finished);

}  // namespace fricrom
