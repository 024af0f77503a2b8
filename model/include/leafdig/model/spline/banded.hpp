#pragma once
// A small banded linear solver: Gaussian elimination with partial pivoting on a matrix with
// kl sub-diagonals and ku super-diagonals, O(n (kl+ku) kl) work instead of a dense O(n^3).
// Written here because Eigen has no banded LU and LAPACK's gbsv would add a Fortran runtime
// dependency for systems of at most a few dozen unknowns.
#include <Eigen/Core>
#include <vector>

namespace leafdig::model {

class BandedMatrix {
 public:
  BandedMatrix(int n, int kl, int ku);

  [[nodiscard]] int size() const { return n_; }
  // Entry (i, j); only |i - j| inside the band may be set. Throws std::out_of_range otherwise.
  void set(int i, int j, double value);
  [[nodiscard]] double get(int i, int j) const;

  // Solves A X = B for every column of B (n by k). The matrix is consumed (factorised in
  // place). Throws std::runtime_error when A is singular.
  [[nodiscard]] Eigen::MatrixXd solve(Eigen::MatrixXd rhs) &&;

 private:
  // Row i stores columns [i - kl, i - kl + width): room for the fill-in that row swaps
  // bring (an upper band of kl + ku after pivoting).
  [[nodiscard]] int first(int i) const { return i - kl_; }
  double& at(int i, int j) { return data_[static_cast<std::size_t>(i * width_ + (j - first(i)))]; }
  [[nodiscard]] bool inWindow(int i, int j) const { return j >= first(i) && j < first(i) + width_; }

  int n_;
  int kl_;
  int ku_;
  int width_;
  std::vector<double> data_;
};

}  // namespace leafdig::model
