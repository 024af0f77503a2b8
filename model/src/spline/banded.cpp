#include "leafdig/model/spline/banded.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace leafdig::model {

BandedMatrix::BandedMatrix(int n, int kl, int ku)
    : n_(n), kl_(kl), ku_(ku), width_(2 * kl + ku + 1), data_(static_cast<std::size_t>(n * (2 * kl + ku + 1)), 0.0) {}

void BandedMatrix::set(int i, int j, double value) {
  if (i < 0 || j < 0 || i >= n_ || j >= n_ || j < i - kl_ || j > i + ku_) {
    throw std::out_of_range("banded matrix: entry outside the band");
  }
  at(i, j) = value;
}

double BandedMatrix::get(int i, int j) const {
  if (i < 0 || j < 0 || i >= n_ || j >= n_ || !inWindow(i, j)) return 0.0;
  return data_[static_cast<std::size_t>(i * width_ + (j - first(i)))];
}

Eigen::MatrixXd BandedMatrix::solve(Eigen::MatrixXd rhs) && {
  const int upper = kl_ + ku_;  // upper bandwidth after pivoting
  for (int k = 0; k < n_; ++k) {
    const int last = std::min(n_ - 1, k + kl_);
    int pivot = k;
    for (int r = k + 1; r <= last; ++r) {
      if (std::abs(get(r, k)) > std::abs(get(pivot, k))) pivot = r;
    }
    if (get(pivot, k) == 0.0) throw std::runtime_error("banded solve: singular matrix");
    if (pivot != k) {
      const int hi = std::min(n_ - 1, k + upper);
      for (int j = k; j <= hi; ++j) {
        const double a = get(k, j);
        const double b = get(pivot, j);
        at(k, j) = b;
        at(pivot, j) = a;
      }
      rhs.row(k).swap(rhs.row(pivot));
    }
    const double diag = at(k, k);
    const int hi = std::min(n_ - 1, k + upper);
    for (int r = k + 1; r <= last; ++r) {
      const double factor = get(r, k) / diag;
      if (factor == 0.0) continue;
      at(r, k) = 0.0;
      for (int j = k + 1; j <= hi; ++j) at(r, j) -= factor * get(k, j);
      rhs.row(r) -= factor * rhs.row(k);
    }
  }
  for (int k = n_ - 1; k >= 0; --k) {
    const int hi = std::min(n_ - 1, k + upper);
    for (int j = k + 1; j <= hi; ++j) rhs.row(k) -= get(k, j) * rhs.row(j);
    rhs.row(k) /= get(k, k);
  }
  return rhs;
}

}  // namespace leafdig::model
