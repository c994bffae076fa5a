// The linear plant (see plant.hpp): x+ = A_z x + B_z u + D_z d over each advance,
// exactly discretized (ZOH) for the advance's duration (cached).
#include <cmath>
#include <stdexcept>

#include "tmpc/model/error_model.hpp"
#include "tmpc/sim/plant.hpp"

namespace tmpc {

namespace {

class LinearPlant final : public Plant {
 public:
  LinearPlant(Eigen::MatrixXd A, Eigen::MatrixXd B, Eigen::MatrixXd D, DisturbanceProfile d)
      : A_(std::move(A)), B_(std::move(B)), D_(std::move(D)), disturbance_(std::move(d)),
        x_(Eigen::VectorXd::Zero(A_.rows())), next_(x_), d_(Eigen::VectorXd::Zero(D_.cols())) {
    if (A_.rows() != A_.cols() || B_.rows() != A_.rows() || D_.rows() != A_.rows() || D_.cols() > 3) {
      throw std::invalid_argument("linear plant: A, B, D sizes disagree (D at most 3 columns)");
    }
  }
  int states() const override { return static_cast<int>(A_.rows()); }
  int inputs() const override { return static_cast<int>(B_.cols()); }
  void reset(const Eigen::VectorXd& x0, double t0) override {
    if (x0.size() != A_.rows()) throw std::invalid_argument("linear plant: reset with the wrong state size");
    x_ = x0;
    t_ = t0;
  }
  void advance(const Eigen::VectorXd& u, double dt) override {
    if (dt != dt_) {
      discretize(A_, B_, D_, dt, Discretization::Zoh, Az_, Bz_, Dz_);
      dt_ = dt;
    }
    const Eigen::Vector3d f = disturbance_.load_force(t_ + 0.5 * dt);
    for (Eigen::Index i = 0; i < d_.size(); ++i) d_(i) = f(i);
    next_.noalias() = Az_ * x_;
    next_.noalias() += Bz_ * u;
    next_.noalias() += Dz_ * d_;
    x_ = next_;
    t_ += dt;
  }
  const Eigen::VectorXd& state() const override { return x_; }
  double time() const override { return t_; }
  Eigen::Vector3d disturbance() const override { return disturbance_.load_force(t_); }
  std::string name() const override { return "linear"; }

 private:
  Eigen::MatrixXd A_, B_, D_, Az_, Bz_, Dz_;
  DisturbanceProfile disturbance_;
  Eigen::VectorXd x_, next_, d_;
  double t_ = 0.0, dt_ = -1.0;
};

}  // namespace

std::unique_ptr<Plant> make_linear_plant(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& D,
                                         DisturbanceProfile d) {
  return std::make_unique<LinearPlant>(A, B, D, std::move(d));
}

}  // namespace tmpc
