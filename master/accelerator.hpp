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
#include <vector>

namespace railcosim {

enum class AcceleratorKind { kConstant, kAitken, kIqnIls };

std::string to_string(AcceleratorKind k);
// "constant", "aitken", "iqn-ils"; nullopt-like: throws std::invalid_argument naming `what`.
AcceleratorKind parse_accelerator(const std::string& s, const std::string& what);

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
};

// `blocks` gives the length of each block; their sum is the vector length.
std::unique_ptr<Accelerator> make_accelerator(const AcceleratorOptions& o, std::vector<int> blocks);

}  // namespace railcosim
