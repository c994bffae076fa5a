// MuJoCo plant (built with TMPC_WITH_MUJOCO): RK4 at the configured step, state
// mapped to our coordinates after every step.
#include "tmpc/sim/mujoco_plant.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include <mujoco/mujoco.h>

#include "tmpc/sim/mujoco_state_map.hpp"

namespace tmpc {

struct MujocoPlant::Impl {
  mjModel* m = nullptr;
  mjData* d = nullptr;
  DisturbanceProfile disturbance;
  double substep = 0.0;
  double t0 = 0.0;
  long steps = 0;
  int load_body = -1, main_body = -1;
  State20 x = State20::Zero();
  Eigen::VectorXd state = Eigen::VectorXd::Zero(kNx);

  ~Impl() {
    if (d != nullptr) mj_deleteData(d);
    if (m != nullptr) mj_deleteModel(m);
  }
  double time() const { return t0 + static_cast<double>(steps) * substep; }

  void set_state(const State20& s) {
    mujoco_map::Qpos qpos;
    mujoco_map::Qvel qvel;
    mujoco_map::to_mujoco(s, qpos, qvel);
    for (int i = 0; i < mujoco_map::kNqpos; ++i) d->qpos[i] = qpos(i);
    for (int i = 0; i < mujoco_map::kNqvel; ++i) d->qvel[i] = qvel(i);
  }
  void set_inputs(const Eigen::Vector4d& u, const Eigen::Vector3d& f, const Eigen::Vector3d& fb = Eigen::Vector3d::Zero()) {
    for (int i = 0; i < 4; ++i) d->ctrl[i] = u(i);
    mju_zero(d->xfrc_applied, 6 * m->nbody);
    for (int i = 0; i < 3; ++i) d->xfrc_applied[6 * load_body + i] = f(i);
    if (!fb.isZero(0.0)) {
      // xfrc_applied acts at the body's centre of mass (MuJoCo's convention), as ours.
      for (int i = 0; i < 3; ++i) d->xfrc_applied[6 * main_body + i] += fb(i);
    }
  }
  void read_state() {
    mujoco_map::Qpos qpos;
    mujoco_map::Qvel qvel;
    for (int i = 0; i < mujoco_map::kNqpos; ++i) qpos(i) = d->qpos[i];
    for (int i = 0; i < mujoco_map::kNqvel; ++i) qvel(i) = d->qvel[i];
    x = mujoco_map::from_mujoco(qpos, qvel, x(kPsi));
    state = x;
  }
};

namespace {
mjModel* load_model(const std::string& xml) {
  struct VfsDeleter {
    void operator()(mjVFS* v) const {
      mj_deleteVFS(v);
      delete v;
    }
  };
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);  // about 2 MB: never on the stack
  mj_defaultVFS(vfs.get());
  const char* name = "tiltrotor_load.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
    throw std::runtime_error("MuJoCo plant: cannot create the in-memory model file");
  }
  const int i = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[i], xml.data(), xml.size());
  char err[1000] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), err, sizeof err);
  if (m == nullptr) throw std::runtime_error(std::string("MuJoCo rejected the generated model: ") + err);
  return m;
}
}  // namespace

bool mujoco_available() { return true; }

MujocoPlant::MujocoPlant(const VehicleParams& params, DisturbanceProfile disturbance, double substep)
    : impl_(std::make_unique<Impl>()) {
  if (!(substep > 0.0)) throw std::invalid_argument("MujocoPlant: substep must be positive");
  impl_->disturbance = std::move(disturbance);
  impl_->substep = substep;
  impl_->m = load_model(make_mjcf(params, substep));
  const mjModel* m = impl_->m;
  if (m->nq != mujoco_map::kNqpos || m->nv != mujoco_map::kNqvel || m->nu != 4) {
    throw std::runtime_error("MuJoCo plant: unexpected model sizes nq=" + std::to_string(m->nq) +
                             " nv=" + std::to_string(m->nv) + " nu=" + std::to_string(m->nu));
  }
  impl_->load_body = mj_name2id(m, mjOBJ_BODY, "load");
  impl_->main_body = mj_name2id(m, mjOBJ_BODY, "main");
  if (impl_->load_body < 0 || impl_->main_body < 0) throw std::runtime_error("MuJoCo plant: no body 'load' or 'main'");
  impl_->d = mj_makeData(m);
  if (impl_->d == nullptr) throw std::runtime_error("MuJoCo plant: mj_makeData failed");
}

MujocoPlant::~MujocoPlant() = default;

void MujocoPlant::reset(const Eigen::VectorXd& x0, double t0) {
  if (x0.size() != kNx) throw std::invalid_argument("MujocoPlant: reset with the wrong state size");
  mj_resetData(impl_->m, impl_->d);
  impl_->t0 = t0;
  impl_->steps = 0;
  impl_->x = x0;
  impl_->state = x0;
  impl_->set_state(impl_->x);
  impl_->d->time = t0;
}

void MujocoPlant::advance(const Eigen::VectorXd& u_in, double dt) {
  Impl& s = *impl_;
  const Eigen::Vector4d u = u_in.head<kNu>();
  const long n = std::max(1L, static_cast<long>(std::llround(dt / s.substep)));
  for (long i = 0; i < n; ++i) {
    // The disturbance is constant over a sub-step, taken at its midpoint (as in ElPlant).
    const double tm = s.time() + 0.5 * s.substep;
    s.set_inputs(u, s.disturbance.load_force(tm), s.disturbance.body_force(tm));
    mj_step(s.m, s.d);
    ++s.steps;
  }
  s.read_state();
}

const Eigen::VectorXd& MujocoPlant::state() const { return impl_->state; }
double MujocoPlant::time() const { return impl_->time(); }
Eigen::Vector3d MujocoPlant::disturbance() const { return impl_->disturbance.load_force(impl_->time()); }

Vec10 MujocoPlant::acceleration(const State20& x, const Eigen::Vector4d& u, const Eigen::Vector3d& f) {
  Impl& s = *impl_;
  s.set_state(x);
  s.set_inputs(u, f);
  mj_forward(s.m, s.d);
  mujoco_map::Qvel qacc;
  for (int i = 0; i < mujoco_map::kNqvel; ++i) qacc(i) = s.d->qacc[i];
  const Vec10 qdd = mujoco_map::acceleration_from_mujoco(x, qacc);
  s.set_state(s.x);  // leave the simulation state as it was
  return qdd;
}

std::string MujocoPlant::version() { return mj_versionString(); }

}  // namespace tmpc
