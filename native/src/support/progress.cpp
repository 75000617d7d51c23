#include <shadecut/support/progress.hpp>

#include <shadecut/support/errors.hpp>

namespace shadecut {

void Progress::report(double within, const std::string& stage) const {
  if (callback_ && !callback_(begin_ + (end_ - begin_) * within, stage)) throw Cancelled();
}

}  // namespace shadecut
