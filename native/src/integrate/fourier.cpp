#include "integrate/fourier.hpp"

#include "support/parallel.hpp"

#include <unsupported/Eigen/FFT>

#include <cstddef>

namespace shadecut::detail {

double angular_frequency(int k, int n) {
  constexpr double kPi = 3.14159265358979323846;
  if (2 * k == n) return 0.0;
  return 2.0 * kPi * (2 * k < n ? k : k - n) / n;
}

void fourier_2d(std::vector<std::complex<double>>& field, int rows, int cols, FourierDirection direction) {
  auto transform_lines = [&](int lines, int length, std::size_t line_step, std::size_t element_step) {
    if (length == 1) return;  // the identity, and a length Eigen's kissfft cannot plan
    parallel_ranges(lines, 16, 0, [&](int begin, int end) {
      Eigen::FFT<double> fft;  // caches twiddles: one per thread
      std::vector<std::complex<double>> in(static_cast<std::size_t>(length)), out(in.size());
      for (int line = begin; line < end; ++line) {
        std::complex<double>* first = field.data() + std::size_t(line) * line_step;
        for (int k = 0; k < length; ++k) in[std::size_t(k)] = first[std::size_t(k) * element_step];
        if (direction == FourierDirection::Forward) fft.fwd(out, in);
        else fft.inv(out, in);
        for (int k = 0; k < length; ++k) first[std::size_t(k) * element_step] = out[std::size_t(k)];
      }
    });
  };
  transform_lines(rows, cols, std::size_t(cols), 1);
  transform_lines(cols, rows, 1, std::size_t(cols));
}

}  // namespace shadecut::detail
