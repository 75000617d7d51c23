// Exceptions thrown by ShadeCut. The Python bindings map them to ValueError, shadecut.Cancelled and
// OSError respectively, so every layer reports the same message.
#pragma once

#include <stdexcept>
#include <string>

namespace shadecut {

/// Bad input: wrong shapes, non-finite pixels, a light below the horizon, ... The message says what.
class InvalidArgument : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The caller's progress callback asked to stop. Nothing partial is returned.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("shadecut: cancelled by the progress callback") {}
};

/// A file could not be read or written.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace shadecut
