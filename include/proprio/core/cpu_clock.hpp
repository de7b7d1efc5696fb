#pragma once
// The processor time of the whole process (every thread), for figures that say how much CPU a
// stage took rather than how long it waited (a shared machine's wall clock says both).

namespace proprio::core {

/// Seconds of processor time this process has used so far, every thread counted
/// (clock_gettime(CLOCK_PROCESS_CPUTIME_ID)). Differences of two calls time a stage.
double process_cpu_seconds();

}  // namespace proprio::core
