#include "banded_matrix.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

namespace railcosim {

SymmetricBandMatrix::SymmetricBandMatrix(int n, int half_bandwidth)
    : n_(n), kd_(half_bandwidth), band_(static_cast<std::size_t>(n) * (half_bandwidth + 1), 0.0) {
  assert(n >= 0 && half_bandwidth >= 0);
}

void SymmetricBandMatrix::add(int i, int j, double v) {
  if (i < j) std::swap(i, j);
  assert(i - j <= kd_ && i < n_ && j >= 0);
  at(i - j, j) += v;
  rows_.clear();
  entries_.clear();
  starts_.clear();
}

void SymmetricBandMatrix::make_entries() const {
  if (!starts_.empty() || n_ == 0) return;
  const std::vector<double>& rows = full_rows();
  const std::size_t w = 2 * static_cast<std::size_t>(kd_) + 1;
  starts_.reserve(static_cast<std::size_t>(n_) + 1);
  for (int i = 0; i < n_; ++i) {
    starts_.push_back(static_cast<int>(entries_.size()));
    for (int d = -kd_; d <= kd_; ++d) {
      const double v = rows[i * w + static_cast<std::size_t>(d + kd_)];
      if (v != 0.0) entries_.push_back({i + d, v});
    }
  }
  starts_.push_back(static_cast<int>(entries_.size()));
}

const std::vector<double>& SymmetricBandMatrix::full_rows() const {
  if (rows_.empty() && n_ > 0) {
    const std::size_t w = 2 * static_cast<std::size_t>(kd_) + 1;
    rows_.assign(w * n_, 0.0);
    for (int i = 0; i < n_; ++i)
      for (int d = -kd_; d <= kd_; ++d)
        if (i + d >= 0 && i + d < n_) rows_[i * w + (d + kd_)] = (*this)(i, i + d);
  }
  return rows_;
}

double SymmetricBandMatrix::operator()(int i, int j) const {
  if (i < j) std::swap(i, j);
  if (i - j > kd_) return 0.0;
  return at(i - j, j);
}

void SymmetricBandMatrix::multiply(const Vector& x, Vector& y) const {
  y.setZero(n_);
  multiply_add(1.0, x, y);
}

namespace {

// y_i += s * (sum over the band of A(i, j) x_j), row by row: every y_i is
// written once, so no store waits for the load of a neighbour. KD > 0 fixes
// the bandwidth at compile time (the loops unroll); KD = 0 reads it from kd.
// y_i += sum_t s_t (A_t x_t)_i, row by row over the full rows of the band
// (2 kd + 1 contiguous values each), so every y_i is written once and each
// row is a short dot product the compiler vectorises. KD > 0 fixes the
// bandwidth at compile time; KD = 0 reads it from kd_runtime.
template <int KD, int TERMS>
void band_multiply_add(int n, int kd_runtime, const double* const* rows, const double* s,
                       const double* const* xs, double* y) {
  const int kd = KD > 0 ? KD : kd_runtime;
  const std::size_t w = 2 * static_cast<std::size_t>(kd) + 1;
  auto edge_row = [&](int i) {
    double total = 0.0;
    for (int t = 0; t < TERMS; ++t) {
      const double* row = rows[t] + i * w;
      double acc = 0.0;
      for (int d = -kd; d <= kd; ++d)
        if (i + d >= 0 && i + d < n) acc += row[d + kd] * xs[t][i + d];
      total += s[t] * acc;
    }
    y[i] += total;
  };
  const int lo = std::min(kd, n), hi = std::max(lo, n - kd);
  for (int i = 0; i < lo; ++i) edge_row(i);
  for (int i = lo; i < hi; ++i) {
    double total = 0.0;
    for (int t = 0; t < TERMS; ++t) {
      const double* row = rows[t] + i * w;
      const double* x = xs[t] + (i - kd);
      double acc = 0.0;
      for (int d = 0; d < 2 * kd + 1; ++d) acc += row[d] * x[d];
      total += s[t] * acc;
    }
    y[i] += total;
  }
  for (int i = hi; i < n; ++i) edge_row(i);
}

template <int TERMS>
void dispatch_multiply_add(int n, int kd, const double* const* rows, const double* s,
                           const double* const* xs, double* y) {
  switch (kd) {
    case 1:
      band_multiply_add<1, TERMS>(n, kd, rows, s, xs, y);
      break;
    case 2:
      band_multiply_add<2, TERMS>(n, kd, rows, s, xs, y);
      break;
    case 3:
      band_multiply_add<3, TERMS>(n, kd, rows, s, xs, y);
      break;
    case 4:
      band_multiply_add<4, TERMS>(n, kd, rows, s, xs, y);
      break;
    default:
      band_multiply_add<0, TERMS>(n, kd, rows, s, xs, y);
      break;
  }
}

}  // namespace

void SymmetricBandMatrix::multiply_add(double s, const Vector& x, Vector& y) const {
  assert(x.size() == n_ && y.size() == n_);
  const double* rows[1] = {full_rows().data()};
  const double* xs[1] = {x.data()};
  dispatch_multiply_add<1>(n_, kd_, rows, &s, xs, y.data());
}

void SymmetricBandMatrix::multiply_add2(double a, const SymmetricBandMatrix& A, const Vector& x,
                                        double b, const SymmetricBandMatrix& B, const Vector& z,
                                        Vector& y) {
  assert(A.n_ == B.n_ && A.kd_ == B.kd_ && x.size() == A.n_ && z.size() == A.n_ &&
         y.size() == A.n_);
  // Row by row over the nonzeros only, each row's terms in the band's order:
  // the sums are those of the full band product less its exact zeros.
  A.make_entries();
  B.make_entries();
  const Entry* ea = A.entries_.data();
  const Entry* eb = B.entries_.data();
  const int* sa = A.starts_.data();
  const int* sb = B.starts_.data();
  const double* xd = x.data();
  const double* zd = z.data();
  double* yd = y.data();
  for (int i = 0; i < A.n_; ++i) {
    double acc_a = 0.0, acc_b = 0.0;
    for (int k = sa[i]; k < sa[i + 1]; ++k) acc_a += ea[k].value * xd[ea[k].col];
    for (int k = sb[i]; k < sb[i + 1]; ++k) acc_b += eb[k].value * zd[eb[k].col];
    yd[i] += a * acc_a + b * acc_b;
  }
}

SymmetricBandMatrix SymmetricBandMatrix::combine(double a, const SymmetricBandMatrix& A, double b,
                                                 const SymmetricBandMatrix& B, double c,
                                                 const SymmetricBandMatrix& C) {
  assert(A.n_ == B.n_ && B.n_ == C.n_ && A.kd_ == B.kd_ && B.kd_ == C.kd_);
  SymmetricBandMatrix out(A.n_, A.kd_);
  for (std::size_t k = 0; k < out.band_.size(); ++k)
    out.band_[k] = a * A.band_[k] + b * B.band_[k] + c * C.band_[k];
  return out;
}

Eigen::MatrixXd SymmetricBandMatrix::to_dense() const {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n_, n_);
  for (int j = 0; j < n_; ++j)
    for (int d = 0; d <= kd_ && j + d < n_; ++d) {
      D(j + d, j) = at(d, j);
      D(j, j + d) = at(d, j);
    }
  return D;
}

BandCholesky::BandCholesky(const SymmetricBandMatrix& A) : n_(A.n_), kd_(A.kd_) {
  // Column-oriented band Cholesky on a copy of the band: for each column j,
  // subtract the contributions of the previous kd columns, then scale.
  SymmetricBandMatrix L = A;
  for (int j = 0; j < n_; ++j) {
    const int k0 = std::max(0, j - kd_);
    for (int k = k0; k < j; ++k) {
      const double ljk = L.at(j - k, k);
      const int imax = std::min(n_ - 1, k + kd_);
      for (int i = j; i <= imax; ++i) L.at(i - j, j) -= L.at(i - k, k) * ljk;
    }
    const double pivot = L.at(0, j);
    if (!(pivot > 0.0) || !std::isfinite(pivot))
      throw std::runtime_error("matrix is not positive definite (pivot " + std::to_string(pivot) +
                               " at row " + std::to_string(j) + ")");
    const double d = std::sqrt(pivot);
    L.at(0, j) = d;
    const int imax = std::min(n_ - 1, j + kd_);
    for (int i = j + 1; i <= imax; ++i) L.at(i - j, j) /= d;
  }
  const auto kd = static_cast<std::size_t>(kd_);
  rows_.assign(static_cast<std::size_t>(n_) * kd, 0.0);
  cols_.assign(static_cast<std::size_t>(n_) * kd, 0.0);
  inv_diag_.resize(n_);
  for (int j = 0; j < n_; ++j) {
    inv_diag_[j] = 1.0 / L.at(0, j);
    for (int d = 1; d <= kd_ && j + d < n_; ++d) {
      const double lij = L.at(d, j);  // L(j + d, j)
      cols_[j * kd + (d - 1)] = lij;
      rows_[(j + d) * kd + (kd - d)] = lij;
    }
  }
}

namespace {

// Forward then backward substitution. The last KD unknowns found are kept in
// a small window of locals instead of being re-read from memory right after
// they were written (a store-to-load stall on every row otherwise).
template <int KD>
void band_substitute(int n, const double* rows, const double* cols, const double* inv_diag,
                     double* x) {
  double win[KD + 1] = {};  // win[KD - 1] is the newest
  for (int i = 0; i < n; ++i) {
    const double* row = rows + static_cast<std::size_t>(i) * KD;
    double s = x[i];
    for (int d = 0; d < KD; ++d) s -= row[d] * win[d];  // zeros before row KD
    s *= inv_diag[i];
    for (int d = 0; d + 1 < KD; ++d) win[d] = win[d + 1];
    if constexpr (KD > 0) win[KD - 1] = s;
    x[i] = s;
  }
  for (int d = 0; d < KD; ++d) win[d] = 0.0;
  for (int j = n - 1; j >= 0; --j) {
    const double* col = cols + static_cast<std::size_t>(j) * KD;
    double s = x[j];
    for (int d = 0; d < KD; ++d) s -= col[d] * win[d];  // win[d] = x_{j+1+d}
    s *= inv_diag[j];
    for (int d = KD - 1; d > 0; --d) win[d] = win[d - 1];
    if constexpr (KD > 0) win[0] = s;
    x[j] = s;
  }
}

void band_substitute_generic(int n, int kd, const double* rows, const double* cols,
                             const double* inv_diag, double* x) {
  for (int i = 0; i < n; ++i) {
    const double* row = rows + static_cast<std::size_t>(i) * kd;
    double s = x[i];
    for (int d = std::max(0, kd - i); d < kd; ++d) s -= row[d] * x[i - kd + d];
    x[i] = s * inv_diag[i];
  }
  for (int j = n - 1; j >= 0; --j) {
    const double* col = cols + static_cast<std::size_t>(j) * kd;
    double s = x[j];
    const int dmax = std::min(kd, n - 1 - j);
    for (int d = 0; d < dmax; ++d) s -= col[d] * x[j + 1 + d];
    x[j] = s * inv_diag[j];
  }
}

}  // namespace

void BandCholesky::solve_in_place(Vector& b) const {
  assert(b.size() == n_);
  const double *r = rows_.data(), *c = cols_.data(), *inv = inv_diag_.data();
  switch (kd_) {
    case 0:
      band_substitute<0>(n_, r, c, inv, b.data());
      break;
    case 1:
      band_substitute<1>(n_, r, c, inv, b.data());
      break;
    case 2:
      band_substitute<2>(n_, r, c, inv, b.data());
      break;
    case 3:
      band_substitute<3>(n_, r, c, inv, b.data());
      break;
    case 4:
      band_substitute<4>(n_, r, c, inv, b.data());
      break;
    default:
      band_substitute_generic(n_, kd_, r, c, inv, b.data());
      break;
  }
}

}  // namespace railcosim
