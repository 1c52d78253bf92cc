// Accelerators of an implicit coupling's fixed-point iteration x = G(x):
// given the iterate x^k and the value G(x^k) the participants returned, each
// proposes x^{k+1}. The vector is the concatenation of every accelerated
// interface quantity; `blocks` splits it into those quantities (a scale per
// block keeps metres and newtons comparable in the least-squares problems).
#pragma once

#include <Eigen/Dense>
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace railcosim::engine {

// An accelerator, by the name it is registered under: the table
// kAccelerators in accelerator.cpp, where a new accelerator is one line
// next to its class.
class AcceleratorKind {
 public:
  static const AcceleratorKind kConstant, kAitken, kIqnIls;  // the built-in ones
  constexpr std::string_view name() const { return name_; }
  constexpr bool operator==(const AcceleratorKind& o) const { return name_ == o.name_; }

 private:
  friend class AcceleratorRegistry;
  constexpr explicit AcceleratorKind(std::string_view name) : name_(name) {}
  std::string_view name_;  // a literal of the table
};
inline constexpr AcceleratorKind AcceleratorKind::kConstant{"constant"};
inline constexpr AcceleratorKind AcceleratorKind::kAitken{"aitken"};
inline constexpr AcceleratorKind AcceleratorKind::kIqnIls{"iqn-ils"};

std::string to_string(AcceleratorKind k);
// Any registered name; throws std::invalid_argument naming `what` and the names.
AcceleratorKind parse_accelerator(const std::string& s, const std::string& what);
// The registered names, in the table's order.
std::vector<std::string> accelerator_names();

struct AcceleratorOptions {
  AcceleratorKind kind = AcceleratorKind::kIqnIls;
  // Constant under-relaxation factor; also the first iteration's factor of
  // Aitken (every window) and of IQN-ILS (while it has no columns).
  double relaxation = 0.5;
  int windows_reused = 8;      // IQN-ILS: past windows whose columns are kept
  int max_columns = 100;       // IQN-ILS: columns at most
  double filter_limit = 1e-2;  // IQN-ILS: a column whose orthogonal part is below this
                               // fraction of its norm is dropped (QR filter)
};

class Accelerator {
 public:
  virtual ~Accelerator() = default;
  // A new window begins.
  virtual void start_window() = 0;
  // One positive weight per block (entries of block b are multiplied by
  // weight[b] in least-squares terms); before each next().
  virtual void set_weights(const std::vector<double>& weight);
  // The next iterate from x^k and G(x^k).
  virtual Eigen::VectorXd next(const Eigen::VectorXd& x, const Eigen::VectorXd& gx) = 0;
  // The window converged (IQN-ILS keeps its columns for the next windows).
  virtual void end_window() {}
  // A copy of this accelerator with everything it has learnt (a checkpoint:
  // the faster group of a multirate step re-runs its windows from one).
  virtual std::unique_ptr<Accelerator> clone() const = 0;
};

// `blocks` gives the length of each block; their sum is the vector length.
std::unique_ptr<Accelerator> make_accelerator(const AcceleratorOptions& o, std::vector<int> blocks);

}  // namespace railcosim::engine
