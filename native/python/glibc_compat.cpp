// libstdc++.a's random.o, which the static C++ runtime brings in along with its exception classes,
// calls arc4random, new in glibc 2.36; nothing in ShadeCut uses std::random_device. This definition,
// from getrandom (glibc 2.25), lets _core load on glibc 2.35 (Ubuntu 22.04), the version of its other
// newest symbols (_dl_find_object, hypot). Hidden, so only this module's copy of random.o sees it.
#include <sys/random.h>

#include <cerrno>
#include <cstdint>
#include <exception>

extern "C" __attribute__((visibility("hidden"))) std::uint32_t arc4random(void) {
  std::uint32_t value = 0;
  for (;;) {
    const ssize_t got = getrandom(&value, sizeof value, 0);
    if (got == ssize_t(sizeof value)) return value;
    if (got < 0 && errno != EINTR) std::terminate();
  }
}
