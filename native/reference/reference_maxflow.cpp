#include "reference_maxflow.hpp"

#include "support/enum_names.hpp"
#include "graphcut/maxflow_impl.hpp"

#include <shadecut/support/errors.hpp>

#include <string>
#include <vector>

namespace shadecut {

namespace maxflow_internal {
std::unique_ptr<MaxFlowSolver> make_opencv_solver();
std::unique_ptr<MaxFlowSolver> make_boost_solver();
}  // namespace maxflow_internal

namespace {

const std::vector<std::string>& maxflow_kind_names() {
  static const std::vector<std::string> names{"grid", "opencv", "boost"};
  return names;
}

}  // namespace

MaxFlowKind parse_maxflow_kind(const std::string& name) {
  return parse_enum<MaxFlowKind>(maxflow_kind_names(), name, "max-flow solver");
}

std::string to_string(MaxFlowKind kind) { return maxflow_kind_names().at(std::size_t(kind)); }

std::unique_ptr<MaxFlowSolver> make_maxflow_solver(MaxFlowKind kind) {
  switch (kind) {
    case MaxFlowKind::Grid: return make_maxflow_solver();
    case MaxFlowKind::OpenCV: return maxflow_internal::make_opencv_solver();
    case MaxFlowKind::Boost: return maxflow_internal::make_boost_solver();
  }
  throw InvalidArgument("invalid MaxFlowKind value " + std::to_string(static_cast<int>(kind)));
}

}  // namespace shadecut
