// The runtime's reference (see reference_source.hpp).
#include "tmpc/runtime/reference_source.hpp"

#include <stdexcept>

#include "tmpc/model/reference.hpp"

namespace tmpc {

namespace {

class TiltrotorReference final : public ReferenceSource {
 public:
  TiltrotorReference(const VehicleParams& v, ReferenceAttitude attitude, std::shared_ptr<const Trajectory> t)
      : model_(v), gen_(model_, std::move(t), attitude), hover_(gen_.equilibrium().u) {}
  bool at(double t, Eigen::VectorXd& x_r, Eigen::VectorXd& u_r) override {
    if (!gen_.try_at(t, r_)) return false;
    x_r.head<kNq>() = r_.q;
    x_r.segment<kNq>(kNq) = r_.qd;
    u_r = feedforward(model_, r_);
    return true;
  }
  const Eigen::VectorXd& hover_input() const override { return hover_; }

 private:
  TiltrotorModel model_;
  ReferenceGenerator gen_;
  Eigen::VectorXd hover_;
  ReferencePoint r_;
};

class OriginReference final : public ReferenceSource {
 public:
  explicit OriginReference(int m) : hover_(Eigen::VectorXd::Zero(m)) {}
  bool at(double, Eigen::VectorXd& x_r, Eigen::VectorXd& u_r) override {
    x_r.setZero();
    u_r.setZero();
    return true;
  }
  const Eigen::VectorXd& hover_input() const override { return hover_; }

 private:
  Eigen::VectorXd hover_;
};

}  // namespace

std::unique_ptr<ReferenceSource> make_reference_source(ModelKind kind, const VehicleParams& vehicle,
                                                       ReferenceAttitude attitude, int inputs,
                                                       std::shared_ptr<const Trajectory> trajectory) {
  if (!trajectory) throw std::invalid_argument("reference: no trajectory");
  if (kind == ModelKind::Tiltrotor) return std::make_unique<TiltrotorReference>(vehicle, attitude, std::move(trajectory));
  const TrajectoryPoint p0 = trajectory->at(0.0), p1 = trajectory->at(1.0);
  if (p0.p.norm() > 0.0 || p1.p.norm() > 0.0 || p0.v.norm() > 0.0) {
    throw std::invalid_argument("reference: a linear model regulates to the origin; its scenario's trajectory must be "
                                "{type: hover, position: [0, 0, 0]} (got " + trajectory->description() + ")");
  }
  return std::make_unique<OriginReference>(inputs);
}

std::unique_ptr<ReferenceSource> make_reference_source(const ControllerArtifact& a,
                                                       std::shared_ptr<const Trajectory> trajectory) {
  return make_reference_source(a.model, a.vehicle, a.attitude, a.m, std::move(trajectory));
}

}  // namespace tmpc
