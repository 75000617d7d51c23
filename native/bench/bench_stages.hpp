// The stage counters of the benchmarks that time a whole reconstruct call.
#pragma once

#include <shadecut/pipeline/reconstruct.hpp>

#include <benchmark/benchmark.h>

#include <map>
#include <string>

namespace shadecut::bench {

/// Adds one call's seconds per stage (ReconstructStats::seconds, and its time in max-flow as
/// "maxflow") to `totals`.
inline void add_stages(const ReconstructStats& stats, std::map<std::string, double>& totals) {
  for (const auto& [stage, seconds] : stats.seconds) totals[stage] += seconds;
  totals["maxflow"] += stats.maxflow_seconds;
}

/// Reports `totals` as each stage's mean milliseconds per iteration: a counter "<stage>_ms".
inline void report_stages(benchmark::State& state, const std::map<std::string, double>& totals) {
  for (const auto& [stage, seconds] : totals)
    state.counters[stage + "_ms"] = benchmark::Counter(1e3 * seconds / double(state.iterations()));
}

}  // namespace shadecut::bench
