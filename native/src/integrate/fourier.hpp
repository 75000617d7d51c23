// The discrete Fourier and cosine transforms of an image-sized field, shared by the Fourier-domain
// integrator (integrate.cpp), the Poisson solve of a whole rectangle (grid_poisson.cpp) and the relief
// light estimator (estimate_relief_light.cpp).
#pragma once

#include <complex>
#include <vector>

namespace shadecut::detail {

/// Angular frequency of DFT bin k of n, in radians per pixel. The Nyquist bin of an even n gets 0: it
/// is its own mirror, so any other value would make a real field's spectrum non-Hermitian.
double angular_frequency(int k, int n);

enum class FourierDirection { Forward, Inverse };

/// The 2-D discrete Fourier transform of a rows x cols row-major field, in place: rows, then columns,
/// by Eigen's FFT (kissfft, header-only, any length), in parallel over lines. The inverse is scaled
/// by 1 / (rows cols).
void fourier_2d(std::vector<std::complex<double>>& field, int rows, int cols, FourierDirection direction);

/// The 2-D discrete cosine transform of a rows x cols row-major real field, in place, along rows then
/// columns. Forward is the DCT-II, X[k] = sum_n x[n] cos(pi k (n + 1/2) / N) along each line, whose
/// basis vectors are the eigenvectors of a path's graph Laplacian (Neumann boundary); Inverse undoes
/// it exactly (the DCT-III scaled by 2 / N, the k = 0 term by 1 / N). Each line costs one complex FFT
/// of its own length (Makhoul 1980), two lines sharing it.
void cosine_2d(std::vector<double>& field, int rows, int cols, FourierDirection direction);

}  // namespace shadecut::detail
