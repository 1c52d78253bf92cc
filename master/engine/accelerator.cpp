#include "engine/accelerator.hpp"

#include <stdexcept>

namespace railcosim::engine {

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
  std::unique_ptr<Accelerator> clone() const override { return std::make_unique<Constant>(*this); }
  Constant(const AcceleratorOptions& o, std::vector<int> blocks)
      : Weighted(std::move(blocks)), omega_(o.relaxation) {}
  VectorXd next(const VectorXd& x, const VectorXd& gx) override { return x + omega_ * (gx - x); }

 private:
  double omega_;
};

// Aitken's dynamic relaxation; the factor restarts from its initial value in
// every window.
class Aitken final : public Weighted {
 public:
  std::unique_ptr<Accelerator> clone() const override { return std::make_unique<Aitken>(*this); }
  Aitken(const AcceleratorOptions& o, std::vector<int> blocks)
      : Weighted(std::move(blocks)), omega0_(o.relaxation) {}
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
  std::unique_ptr<Accelerator> clone() const override { return std::make_unique<IqnIls>(*this); }
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

template <class A>
std::unique_ptr<Accelerator> make(const AcceleratorOptions& o, std::vector<int> blocks) {
  return std::make_unique<A>(o, std::move(blocks));
}

struct Registered {
  std::string_view name;
  std::unique_ptr<Accelerator> (*make)(const AcceleratorOptions&, std::vector<int>);
};

// Every accelerator the product knows, by name (`--accelerator`, study
// plans, summary.json): a new one is its class, built from the options and
// the blocks, and one line here.
constexpr Registered kAccelerators[] = {
    {AcceleratorKind::kConstant.name(), make<Constant>},
    {AcceleratorKind::kAitken.name(), make<Aitken>},
    {AcceleratorKind::kIqnIls.name(), make<IqnIls>},
};

}  // namespace

// Makes kinds from the table's names (AcceleratorKind's constructor is private).
class AcceleratorRegistry {
 public:
  static AcceleratorKind kind(std::string_view name) { return AcceleratorKind(name); }
};

std::string to_string(AcceleratorKind k) {
  return std::string(k.name());
}

std::vector<std::string> accelerator_names() {
  std::vector<std::string> names;
  for (const Registered& r : kAccelerators) names.emplace_back(r.name);
  return names;
}

AcceleratorKind parse_accelerator(const std::string& s, const std::string& what) {
  for (const Registered& r : kAccelerators)
    if (r.name == s) return AcceleratorRegistry::kind(r.name);
  std::string msg = what + ": unknown accelerator '" + s + "' (";
  for (const Registered& r : kAccelerators) {
    if (&r != &kAccelerators[0])
      msg += &r == &kAccelerators[std::size(kAccelerators) - 1] ? " or " : ", ";
    msg += r.name;
  }
  throw std::invalid_argument(msg + ")");
}

std::unique_ptr<Accelerator> make_accelerator(const AcceleratorOptions& o,
                                              std::vector<int> blocks) {
  if (!(o.relaxation > 0 && o.relaxation <= 1))
    throw std::invalid_argument("the relaxation factor must be in (0, 1]");
  for (const Registered& r : kAccelerators)
    if (r.name == o.kind.name()) return r.make(o, std::move(blocks));
  throw std::logic_error("make_accelerator: no accelerator '" + to_string(o.kind) + "'");
}

}  // namespace railcosim::engine
