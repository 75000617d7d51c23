#include <shadecut/support/memory.hpp>

#if defined(__unix__) || defined(__APPLE__)
#include <sys/resource.h>
#endif

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace shadecut {

namespace {

constexpr std::uint64_t kUnknown = std::numeric_limits<std::uint64_t>::max();

// The value of `key` (in kB) in a /proc file of "Key:   value kB" lines, in bytes; kUnknown if absent.
std::uint64_t proc_kilobytes(const char* path, const std::string& key) {
  std::ifstream file(path);
  std::string line;
  while (std::getline(file, line)) {
    if (line.compare(0, key.size(), key) != 0 || line.size() <= key.size() || line[key.size()] != ':') continue;
    std::istringstream value(line.substr(key.size() + 1));
    std::uint64_t kilobytes = 0;
    if (value >> kilobytes) return kilobytes * 1024;
  }
  return kUnknown;
}

// The first number in a file ("max" or unreadable: kUnknown).
std::uint64_t file_number(const std::string& path) {
  std::ifstream file(path);
  std::uint64_t value = 0;
  return file >> value ? value : kUnknown;
}

// The cgroup v2 folder of this process ("0::/path" in /proc/self/cgroup), or "" when there is none.
std::string cgroup_folder() {
  std::ifstream file("/proc/self/cgroup");
  std::string line;
  while (std::getline(file, line))
    if (line.rfind("0::", 0) == 0) return "/sys/fs/cgroup" + line.substr(3);
  return "";
}

std::uint64_t less(std::uint64_t limit, std::uint64_t used) {
  if (limit == kUnknown) return kUnknown;
  return used == kUnknown ? limit : (limit > used ? limit - used : 0);
}

}  // namespace

std::uint64_t available_memory() {
  std::uint64_t available = proc_kilobytes("/proc/meminfo", "MemAvailable");
  const std::string group = cgroup_folder();
  if (!group.empty())
    available = std::min(available, less(file_number(group + "/memory.max"), file_number(group + "/memory.current")));
#if defined(__unix__) || defined(__APPLE__)
  rlimit address_space{};
  if (getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY)
    available = std::min(available, less(std::uint64_t(address_space.rlim_cur), proc_kilobytes("/proc/self/status", "VmSize")));
#endif
  return available;
}

std::string memory_text(std::uint64_t bytes) {
  char text[32];
  if (bytes >= (std::uint64_t(1) << 30)) std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / double(1 << 30));
  else std::snprintf(text, sizeof text, "%.0f MB", double(bytes) / double(1 << 20));
  return text;
}

}  // namespace shadecut
