#include "integrate/fourier.hpp"

#include "support/parallel.hpp"

#include <unsupported/Eigen/FFT>

#include <cmath>
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

namespace {

// The DCT-II of real lines a and b (N each) by one complex FFT: Makhoul's reordering (even samples
// forward, odd ones backward) turns the cosine transform into an FFT, a carried in the real part and
// b in the imaginary one, whose spectra are parted by Hermitian symmetry.
class CosineLines {
 public:
  explicit CosineLines(int length) : n_(length), packed_(std::size_t(length)), spectrum_(std::size_t(length)), turn_(std::size_t(length)) {
    constexpr double kPi = 3.14159265358979323846;
    for (int k = 0; k < n_; ++k) turn_[std::size_t(k)] = std::polar(1.0, -kPi * k / (2.0 * n_));
  }

  void forward(double* a, double* b, std::size_t step) {
    for (int m = 0; m < n_; ++m) {
      const std::size_t from = std::size_t(source(m)) * step;
      packed_[std::size_t(m)] = {a[from], b ? b[from] : 0.0};
    }
    fft_.fwd(spectrum_, packed_);
    for (int k = 0; k < n_; ++k) {
      const std::complex<double> w = spectrum_[std::size_t(k)], mirror = std::conj(spectrum_[std::size_t((n_ - k) % n_)]);
      const std::complex<double> turn = turn_[std::size_t(k)];
      a[std::size_t(k) * step] = (turn * 0.5 * (w + mirror)).real();
      if (b) b[std::size_t(k) * step] = (turn * std::complex<double>(0.0, -0.5) * (w - mirror)).real();
    }
  }

  void inverse(double* a, double* b, std::size_t step) {
    const std::complex<double> j(0.0, 1.0);
    for (int k = 0; k < n_; ++k) {
      // A line's FFT from its cosine spectrum: V[k] = e^{i pi k / 2N} (X[k] - i X[N - k]), X[N] = 0.
      auto spectrum_of = [&](const double* x) {
        const double opposite = k == 0 ? 0.0 : x[std::size_t(n_ - k) * step];
        return std::conj(turn_[std::size_t(k)]) * std::complex<double>(x[std::size_t(k) * step], -opposite);
      };
      spectrum_[std::size_t(k)] = spectrum_of(a) + (b ? j * spectrum_of(b) : 0.0);
    }
    fft_.inv(packed_, spectrum_);
    for (int m = 0; m < n_; ++m) {
      const std::size_t to = std::size_t(source(m)) * step;
      a[to] = packed_[std::size_t(m)].real();
      if (b) b[to] = packed_[std::size_t(m)].imag();
    }
  }

 private:
  // The sample at position m of the reordered line.
  int source(int m) const { return 2 * m < n_ ? 2 * m : 2 * (n_ - m) - 1; }

  int n_;
  Eigen::FFT<double> fft_;
  std::vector<std::complex<double>> packed_, spectrum_, turn_;
};

}  // namespace

void cosine_2d(std::vector<double>& field, int rows, int cols, FourierDirection direction) {
  auto transform_lines = [&](int lines, int length, std::size_t line_step, std::size_t element_step) {
    if (length == 1) return;  // the identity
    const int pairs = (lines + 1) / 2;
    parallel_ranges(pairs, 8, 0, [&](int begin, int end) {
      CosineLines transform(length);  // caches twiddles: one per thread
      for (int pair = begin; pair < end; ++pair) {
        double* a = field.data() + std::size_t(2 * pair) * line_step;
        double* b = 2 * pair + 1 < lines ? a + line_step : nullptr;
        if (direction == FourierDirection::Forward) transform.forward(a, b, element_step);
        else transform.inverse(a, b, element_step);
      }
    });
  };
  transform_lines(rows, cols, std::size_t(cols), 1);
  transform_lines(cols, rows, 1, std::size_t(cols));
}

}  // namespace shadecut::detail
