// The C library symbols _core asks for are pinned to old versions, so that one zip loads on every
// glibc from 2.35 on (docs/portable_addon.md), whatever glibc it was built with.
//
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

#if defined(__x86_64__)
// Built with glibc 2.38 or newer (Debian 13 and later, for Blender's Python 3.13 and 3.14), the
// headers turn strtoll and strtoul into their C23 forms, __isoc23_strtoll and __isoc23_strtoul
// (GLIBC_2.38; they differ only in reading "0b" with base 0 or 2, which ShadeCut never asks), and
// fmod binds to fmod@GLIBC_2.38 (the same function, another version). Hidden definitions here take
// this module's calls to the forms every glibc has. This file is compiled with -fno-builtin-fmod,
// so that its fmod is a hidden definition and not GCC's built-in.
extern "C" {
long long shadecut_strtoll_before_c23(const char*, char**, int) __asm__("strtoll");
unsigned long shadecut_strtoul_before_c23(const char*, char**, int) __asm__("strtoul");
double shadecut_fmod_2_2_5(double, double);
__asm__(".symver shadecut_fmod_2_2_5, fmod@GLIBC_2.2.5");

__attribute__((visibility("hidden"))) long long __isoc23_strtoll(const char* text, char** end, int base) {
  return shadecut_strtoll_before_c23(text, end, base);
}

__attribute__((visibility("hidden"))) unsigned long __isoc23_strtoul(const char* text, char** end, int base) {
  return shadecut_strtoul_before_c23(text, end, base);
}

__attribute__((visibility("hidden"))) double fmod(double x, double y) { return shadecut_fmod_2_2_5(x, y); }
}
#endif
