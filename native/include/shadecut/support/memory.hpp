// Memory: what a call may still allocate, so that a call too large for it is refused at once rather
// than after a long run into an allocation failure.
#pragma once

#include <cstdint>
#include <limits>
#include <string>

namespace shadecut {

/// Bytes this process may still allocate: the least of the system's available memory
/// (/proc/meminfo MemAvailable), its control group's limit less its usage (cgroup v2 memory.max and
/// memory.current) and its address-space limit (RLIMIT_AS) less its virtual size; the largest
/// uint64_t where none of them can be read (a system without /proc: no refusal).
std::uint64_t available_memory();

/// Formats a byte count for a message: "1.4 GB", "310 MB".
std::string memory_text(std::uint64_t bytes);

}  // namespace shadecut
