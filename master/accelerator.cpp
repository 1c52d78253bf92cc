#include "accelerator.hpp"

#include <stdexcept>

namespace railcosim {

std::string to_string(AcceleratorKind k) {
  switch (k) {
    case AcceleratorKind::kConstant:
      return "constant";
    case AcceleratorKind::kAitken:
      return "aitken";
    case AcceleratorKind::kIqnIls:
      return "iqn-ils";
  }
  return "?";
}

AcceleratorKind parse_accelerator(const std::string& s, const std::string& what) {
  for (AcceleratorKind k :
       {AcceleratorKind::kConstant, AcceleratorKind::kAitken, AcceleratorKind::kIqnIls})
    if (to_string(k) == s) return k;
  std::string msg = what;
  msg += ": unknown accelerator '";
  msg += s;
  msg += "' (constant, aitken or iqn-ils)";
  throw std::invalid_argument(msg);
}

void Accelerator::set_weights(const std::vector<double>&) {}

namespace {

using Eigen::VectorXd;

// Common part: the per-entry weights of the current window.
class Weighted : public Accelerator {
 public:
  explicit Weighted(std::vector<int> blocks) : blocks_(std::move(blocks)) {
    int n = 0;
    for (int b : blocks_) n += b;
    weight_ = VectorXd::Ones(n);
  }
  void set_weights(const std::vector<double>& scale) override {
    if (scale.size() != blocks_.size())
      throw std::logic_error("accelerator: one weight per block expected");
    Eigen::Index at = 0;
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
      weight_.segment(at, blocks_[b]).setConstant(scale[b]);
      at += blocks_[b];
    }
  }
  void start_window() override {}

 protected:
  VectorXd weighted(const VectorXd& v) const { return weight_.cwiseProduct(v); }
  std::vector<int> blocks_;
  VectorXd weight_;
};

class Constant final : public Weighted {
 public:
  Constant(double omega, std::vector<int> blocks) : Weighted(std::move(blocks)), omega_(omega) {}
  VectorXd next(const VectorXd& x, const VectorXd& gx) override { return x + omega_ * (gx - x); }

 private:
  double omega_;
};

// Aitken's dynamic relaxation; the factor restarts from its initial value in
// every window.
class Aitken final : public Weighted {
 public:
  Aitken(double omega0, std::vector<int> blocks) : Weighted(std::move(blocks)), omega0_(omega0) {}
  void start_window() override { first_ = true; }
  VectorXd next(const VectorXd& x, const VectorXd& gx) override {
    const VectorXd r = gx - x;
    if (first_) {
      omega_ = omega0_;
      first_ = false;
    } else {
      const VectorXd dr = weighted(r - prev_r_);
      const double den = dr.squaredNorm();
      if (den > 0) omega_ = -omega_ * weighted(prev_r_).dot(dr) / den;
    }
    prev_r_ = r;
    return x + omega_ * (gx - x);
  }

 private:
  double omega0_, omega_ = 0;
  bool first_ = true;
  VectorXd prev_r_;
};

// Interface quasi-Newton with an approximation of the inverse Jacobian from
// least squares (IQN-ILS, Degroote et al. 2009): the columns are the changes
// of the residual r = G(x) - x (V) and of G(x) (W) between iterations, of
// this window and of up to `windows_reused` past ones, newest first.
class IqnIls final : public Weighted {
 public:
  IqnIls(const AcceleratorOptions& o, std::vector<int> blocks)
      : Weighted(std::move(blocks)), o_(o) {}

  void start_window() override {
    have_prev_ = false;
    current_.clear();
  }

  VectorXd next(const VectorXd& x, const VectorXd& gx) override {
    const VectorXd r = gx - x;
    if (have_prev_) current_.push_front({r - prev_r_, gx - prev_g_});
    prev_r_ = r;
    prev_g_ = gx;
    have_prev_ = true;

    // The columns, newest first, kept by the QR filter.
    std::vector<const Column*> cols;
    for (const Column& c : current_) cols.push_back(&c);
    for (const auto& w : past_)
      for (const Column& c : w) cols.push_back(&c);
    // Modified Gram–Schmidt over the weighted columns, newest first: V = Q R
    // for the kept ones; a column mostly in the span of newer ones is dropped.
    std::vector<VectorXd> q;
    std::vector<std::vector<double>> rcols;  // the columns of R
    std::vector<const Column*> kept;
    for (const Column* c : cols) {
      if (static_cast<int>(kept.size()) >= o_.max_columns) break;
      VectorXd p = weighted(c->dr);
      const double norm = p.norm();
      if (!(norm > 0)) continue;
      std::vector<double> rc;
      for (const VectorXd& b : q) {
        rc.push_back(b.dot(p));
        p -= rc.back() * b;
      }
      const double rest = p.norm();
      if (rest < o_.filter_limit * norm) continue;
      rc.push_back(rest);
      q.push_back(p / rest);
      rcols.push_back(std::move(rc));
      kept.push_back(c);
    }
    if (kept.empty()) return x + o_.relaxation * r;

    // alpha minimises ||V alpha + r||: R alpha = -Q^T r, by back substitution.
    const std::size_t k = kept.size();
    const VectorXd rw = weighted(r);
    std::vector<double> alpha(k);
    for (std::size_t i = 0; i < k; ++i) alpha[i] = -q[i].dot(rw);
    for (std::size_t i = k; i-- > 0;) {
      for (std::size_t j = i + 1; j < k; ++j) alpha[i] -= rcols[j][i] * alpha[j];
      alpha[i] /= rcols[i][i];
    }
    VectorXd next = gx;
    for (std::size_t i = 0; i < k; ++i) next += alpha[i] * kept[i]->dg;
    return next;
  }

  void end_window() override {
    if (!current_.empty()) past_.push_front(std::move(current_));
    current_.clear();
    while (static_cast<int>(past_.size()) > o_.windows_reused) past_.pop_back();
  }

 private:
  struct Column {
    VectorXd dr, dg;
  };
  AcceleratorOptions o_;
  bool have_prev_ = false;
  VectorXd prev_r_, prev_g_;
  std::deque<Column> current_;
  std::deque<std::deque<Column>> past_;
};

}  // namespace

std::unique_ptr<Accelerator> make_accelerator(const AcceleratorOptions& o,
                                              std::vector<int> blocks) {
  if (!(o.relaxation > 0 && o.relaxation <= 1))
    throw std::invalid_argument("the relaxation factor must be in (0, 1]");
  switch (o.kind) {
    case AcceleratorKind::kConstant:
      return std::make_unique<Constant>(o.relaxation, std::move(blocks));
    case AcceleratorKind::kAitken:
      return std::make_unique<Aitken>(o.relaxation, std::move(blocks));
    case AcceleratorKind::kIqnIls:
      return std::make_unique<IqnIls>(o, std::move(blocks));
  }
  throw std::logic_error("make_accelerator: unknown kind");
}

}  // namespace railcosim
