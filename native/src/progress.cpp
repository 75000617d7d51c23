#include <shadecut/progress.hpp>

#include <shadecut/errors.hpp>

namespace shadecut {

void Progress::report(double within, const std::string& stage) const {
  if (callback_ && !callback_(begin_ + (end_ - begin_) * within, stage)) throw Cancelled();
}

}  // namespace shadecut
