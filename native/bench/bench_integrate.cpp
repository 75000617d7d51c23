// The Poisson integrator against Frankot-Chellappa (the time to beat: at most 3 times it) and against
// the sparse direct solvers of well-kept libraries on the same system: Eigen's SimplicialLDLT (what
// the Poisson integrator used before) and, where CMake found it, CHOLMOD's supernodal Cholesky
// (SuiteSparse; BLAS as Debian installs it). Full frames and a disk with holes and islands, at 512,
// 1024 and 2048 pixels square; gradients of a bumpy surface plus noise, so that they are not
// integrable.
//
// Run: ./build/native/shadecut_bench --benchmark_filter=Integrate --benchmark_repetitions=3
//        --benchmark_report_aggregates_only=true
#include <shadecut/integrate/integrate.hpp>
#include <shadecut/support/mask_components.hpp>

#include <Eigen/SparseCholesky>
#include <benchmark/benchmark.h>
#ifdef SHADECUT_BENCH_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

namespace {

using namespace shadecut;

struct Problem {
  NormalMap normals;
  Mask mask;
};

const Problem& problem(int size, bool full_frame) {
  static std::map<std::pair<int, bool>, Problem> cache;
  auto found = cache.find({size, full_frame});
  if (found != cache.end()) return found->second;
  Problem made{NormalMap(size, size), Mask::Constant(size, size, true)};
  std::mt19937 rng(size);
  std::normal_distribution<double> noise(0.0, 0.1);
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      const double x = double(c) / size, y = double(r) / size;
      const double p = std::sin(12 * x) * std::cos(7 * y) + noise(rng), q = std::cos(9 * x + 3 * y) + noise(rng);
      made.normals.xyz.row(Eigen::Index(r) * size + c) = Eigen::Vector3d(-p, -q, 1.0).normalized().cast<float>().transpose();
      if (full_frame) continue;
      const bool disk = std::hypot(x - 0.5, y - 0.5) < 0.45;
      const bool hole = std::hypot(x - 0.35, y - 0.4) < 0.08 || std::hypot(x - 0.65, y - 0.6) < 0.05;
      const bool island = std::hypot(x - 0.35, y - 0.4) < 0.03;
      made.mask(r, c) = (disk && !hole) || island;
    }
  }
  return cache.emplace(std::make_pair(size, full_frame), std::move(made)).first->second;
}

void BM_Integrate(benchmark::State& state, Integrator integrator, bool full_frame) {
  const Problem& input = problem(int(state.range(0)), full_frame);
  for (auto _ : state) benchmark::DoNotOptimize(integrate_normals(input.normals, input.mask, integrator).data());
}

// The same normal equations as the Poisson integrator (one pixel of each part pinned), solved by a
// sparse direct factorisation.
template <class Solver>
void BM_IntegrateDirect(benchmark::State& state, bool full_frame) {
  const Problem& input = problem(int(state.range(0)), full_frame);
  const int rows = input.normals.rows, cols = input.normals.cols;
  for (auto _ : state) {
    const MaskComponents parts = mask_components(input.mask);
    std::vector<int> unknown(std::size_t(rows) * cols, -1);
    std::vector<bool> pinned(std::size_t(parts.count), false);
    int count = 0;
    for (int i = 0; i < rows * cols; ++i) {
      const int part = parts.labels.data()[i];
      if (part < 0) continue;
      if (pinned[std::size_t(part)]) unknown[std::size_t(i)] = count++;
      pinned[std::size_t(part)] = true;
    }
    auto slope = [&](int i, int axis) { return -double(input.normals.xyz(i, axis)) / double(input.normals.xyz(i, 2)); };
    std::vector<Eigen::Triplet<double>> lower;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(count);
    auto edge = [&](int a, int b, double rise) {
      const int ua = unknown[std::size_t(a)], ub = unknown[std::size_t(b)];
      if (ua >= 0) lower.emplace_back(ua, ua, 1.0), rhs[ua] -= rise;
      if (ub >= 0) lower.emplace_back(ub, ub, 1.0), rhs[ub] += rise;
      if (ua >= 0 && ub >= 0) lower.emplace_back(std::max(ua, ub), std::min(ua, ub), -1.0);
    };
    for (int i = 0; i < rows * cols; ++i) {
      if (!input.mask.data()[i]) continue;
      if (i % cols + 1 < cols && input.mask.data()[i + 1]) edge(i, i + 1, 0.5 * (slope(i, 0) + slope(i + 1, 0)));
      if (i + cols < rows * cols && input.mask.data()[i + cols]) edge(i, i + cols, -0.5 * (slope(i, 1) + slope(i + cols, 1)));
    }
    Eigen::SparseMatrix<double> laplacian(count, count);
    laplacian.setFromTriplets(lower.begin(), lower.end());
    Solver solver(laplacian);
    const Eigen::VectorXd depth = solver.solve(rhs);
    benchmark::DoNotOptimize(depth.data());
  }
}

void register_integrate_benchmarks() {
  for (const bool full_frame : {true, false}) {
    const std::string mask = full_frame ? "/full_frame" : "/holes_and_islands";
    auto sizes = [](benchmark::internal::Benchmark* bench, std::initializer_list<int> sizes) {
      for (int size : sizes) bench->Arg(size);
      bench->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);
    };
    sizes(benchmark::RegisterBenchmark(("BM_Integrate/poisson" + mask).c_str(), BM_Integrate, Integrator::Poisson, full_frame),
          {512, 1024, 2048});
    sizes(benchmark::RegisterBenchmark(("BM_Integrate/frankot_chellappa" + mask).c_str(), BM_Integrate,
                                       Integrator::FrankotChellappa, full_frame),
          {512, 1024, 2048});
    using Ldlt = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>;
    sizes(benchmark::RegisterBenchmark(("BM_Integrate/eigen_simplicial_ldlt" + mask).c_str(), BM_IntegrateDirect<Ldlt>,
                                       full_frame),
          {512, 1024});
#ifdef SHADECUT_BENCH_CHOLMOD
    using Supernodal = Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>;
    sizes(benchmark::RegisterBenchmark(("BM_Integrate/cholmod_supernodal" + mask).c_str(),
                                       BM_IntegrateDirect<Supernodal>, full_frame),
          {512, 1024, 2048});
#endif
  }
}

const bool registered = (register_integrate_benchmarks(), true);

}  // namespace
