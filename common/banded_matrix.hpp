// Symmetric banded matrices and their Cholesky factorisation.
//
// The track's mass, damping and stiffness matrices couple each degree of
// freedom only with a few neighbours (half-bandwidth 4 for the rail with
// sleepers interleaved), so every product and solve costs O(n * kd) and a
// factorisation O(n * kd^2) instead of the O(n^3) of a dense matrix.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace railcosim {

using Vector = Eigen::VectorXd;

// A symmetric n x n matrix stored by its lower band: entry (i, j) with
// 0 <= i - j <= kd lives at band_(i - j, j).
class SymmetricBandMatrix {
 public:
  SymmetricBandMatrix() = default;
  SymmetricBandMatrix(int n, int half_bandwidth);

  int size() const { return n_; }
  int half_bandwidth() const { return kd_; }

  // Adds v to A(i, j) and, by symmetry, to A(j, i). |i - j| must be <= kd.
  void add(int i, int j, double v);
  double operator()(int i, int j) const;

  // y = A x.
  void multiply(const Vector& x, Vector& y) const;
  // y += s * A x.
  void multiply_add(double s, const Vector& x, Vector& y) const;
  // y += a * A x + b * B z in one pass (A and B share n and kd).
  static void multiply_add2(double a, const SymmetricBandMatrix& A, const Vector& x, double b,
                            const SymmetricBandMatrix& B, const Vector& z, Vector& y);

  // Returns a*this + b*B + c*C (all three share n and kd).
  static SymmetricBandMatrix combine(double a, const SymmetricBandMatrix& A, double b,
                                     const SymmetricBandMatrix& B, double c,
                                     const SymmetricBandMatrix& C);

  Eigen::MatrixXd to_dense() const;

 private:
  friend class BandCholesky;
  int n_ = 0;
  int kd_ = 0;
  // Column j of the lower band, A(j..j+kd, j), at band_[j * (kd + 1) + d].
  std::vector<double> band_;
  // Row i of the whole band, A(i, i-kd..i+kd), at rows_[i * (2 kd + 1)]:
  // made on first use by the products, dropped by add().
  mutable std::vector<double> rows_;
  const std::vector<double>& full_rows() const;
  // The nonzeros of each full row, in the order of the row (a mass or
  // damping matrix leaves most of its band empty): row i's are
  // entries_[starts_[i] .. starts_[i + 1]). Made on first use, dropped by add().
  struct Entry {
    int col;
    double value;
  };
  mutable std::vector<Entry> entries_;
  mutable std::vector<int> starts_;
  void make_entries() const;
  double& at(int d, int j) { return band_[static_cast<std::size_t>(j) * (kd_ + 1) + d]; }
  double at(int d, int j) const { return band_[static_cast<std::size_t>(j) * (kd_ + 1) + d]; }
};

// A = L L^T for a symmetric positive definite band matrix; L keeps the band.
class BandCholesky {
 public:
  BandCholesky() = default;
  // Throws std::runtime_error if A is not positive definite.
  explicit BandCholesky(const SymmetricBandMatrix& A);

  bool empty() const { return n_ == 0; }
  // Solves A x = b in place.
  void solve_in_place(Vector& b) const;

 private:
  int n_ = 0;
  int kd_ = 0;
  // The solves read L by rows going forward and by columns going backward,
  // so both layouts are kept, each contiguous: row i holds L(i, i-kd..i-1)
  // (zeros before row kd), column j holds L(j+1..j+kd, j).
  std::vector<double> rows_, cols_, inv_diag_;
};

}  // namespace railcosim
