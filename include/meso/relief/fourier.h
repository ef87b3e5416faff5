// Discrete Fourier transforms of any length: radix-2 FFT, Bluestein's chirp-z otherwise.
// For the spectral tools of relief (measured highest frequency, band splitting).
#pragma once

#include <complex>
#include <cstddef>
#include <vector>

namespace meso {

using Complex = std::complex<double>;

// The DFT of one length n: X_k = sum_j x_j exp(-2 pi i j k / n). Built once per length (the
// Bluestein kernel is precomputed); the transforms themselves are const and thread-safe.
class Dft {
 public:
  explicit Dft(size_t n);
  size_t size() const { return n_; }
  // In place; `data` must hold n values (it may grow temporarily).
  void forward(std::vector<Complex>& data) const;
  // The inverse, including the 1 / n.
  void inverse(std::vector<Complex>& data) const;

 private:
  size_t n_, m_;  // m_: the FFT length (n_ for powers of two)
  std::vector<Complex> chirp_, kernel_;
};

// In-place 2D DFT of a row-major width x height array: every row, then every column.
void dft2d(std::vector<Complex>& data, size_t width, size_t height, bool inverse);

}  // namespace meso
