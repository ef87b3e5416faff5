// Discrete Fourier transforms: Cooley-Tukey radix-2, and Bluestein (1970) for other lengths.
#include "meso/relief/fourier.h"

#include <cmath>
#include <numbers>

namespace meso {
namespace {

// In-place radix-2 FFT (a.size() a power of two); `sign` -1 forward, +1 inverse (no 1/n).
void fft(std::vector<Complex>& a, int sign) {
  const size_t n = a.size();
  for (size_t i = 1, j = 0; i < n; ++i) {
    size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  for (size_t len = 2; len <= n; len <<= 1) {
    const double angle = sign * 2.0 * std::numbers::pi / static_cast<double>(len);
    for (size_t k = 0; k < len / 2; ++k) {
      const Complex w = std::polar(1.0, angle * static_cast<double>(k));
      for (size_t i = 0; i < n; i += len) {
        const Complex u = a[i + k], v = a[i + k + len / 2] * w;
        a[i + k] = u + v;
        a[i + k + len / 2] = u - v;
      }
    }
  }
}

bool isPowerOfTwo(size_t n) { return n > 0 && (n & (n - 1)) == 0; }

}  // namespace

Dft::Dft(size_t n) : n_(n), m_(n) {
  if (isPowerOfTwo(n) || n == 0) return;
  m_ = 1;
  while (m_ < 2 * n - 1) m_ <<= 1;
  // jk = (j^2 + k^2 - (k - j)^2) / 2 turns the DFT into a convolution with the chirp
  // w_t = exp(-i pi t^2 / n); t^2 is reduced mod 2n so that the angle stays accurate.
  chirp_.resize(n);
  for (size_t t = 0; t < n; ++t)
    chirp_[t] = std::polar(
        1.0, -std::numbers::pi * static_cast<double>((t * t) % (2 * n)) / static_cast<double>(n));
  kernel_.assign(m_, Complex(0.0));
  for (size_t t = 0; t < n; ++t) kernel_[t] = kernel_[(m_ - t) % m_] = std::conj(chirp_[t]);
  fft(kernel_, -1);
}

void Dft::forward(std::vector<Complex>& data) const {
  if (m_ == n_) return fft(data, -1);
  data.resize(m_, Complex(0.0));
  for (size_t t = 0; t < n_; ++t) data[t] *= chirp_[t];
  for (size_t t = n_; t < m_; ++t) data[t] = 0.0;
  fft(data, -1);
  for (size_t k = 0; k < m_; ++k) data[k] *= kernel_[k];
  fft(data, +1);
  data.resize(n_);
  for (size_t k = 0; k < n_; ++k) data[k] *= chirp_[k] / static_cast<double>(m_);
}

void Dft::inverse(std::vector<Complex>& data) const {
  for (Complex& c : data) c = std::conj(c);
  forward(data);
  for (Complex& c : data) c = std::conj(c) / static_cast<double>(n_);
}

void dft2d(std::vector<Complex>& data, size_t width, size_t height, bool inverse) {
  const Dft rows(width), columns(height);
  std::vector<Complex> line;
  for (size_t y = 0; y < height; ++y) {
    line.assign(data.begin() + y * width, data.begin() + (y + 1) * width);
    inverse ? rows.inverse(line) : rows.forward(line);
    std::copy(line.begin(), line.end(), data.begin() + y * width);
  }
  for (size_t x = 0; x < width; ++x) {
    line.resize(height);
    for (size_t y = 0; y < height; ++y) line[y] = data[y * width + x];
    inverse ? columns.inverse(line) : columns.forward(line);
    for (size_t y = 0; y < height; ++y) data[y * width + x] = line[y];
  }
}

}  // namespace meso
