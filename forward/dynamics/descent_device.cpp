#include "forward/dynamics/descent_device.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "forward/dynamics/descent_vertex_blocks.hpp"
#include "tailor_cuda_config.hpp"
#ifdef TAILOR_HAVE_CUDA
#include "forward/dynamics/descent_cuda.hpp"
#endif

namespace tailor {

#ifdef TAILOR_HAVE_CUDA

bool built_with_cuda() { return true; }
bool cuda_device_usable() { return cuda::device_available(); }
std::string cuda_device_name() { return cuda::device_name(); }

namespace {

class DeviceBackend final : public DescentBackend {
 public:
  explicit DeviceBackend(const Model& model)
      : model_(model), rule_(model), host_pass_(rule_), device_(rule_.layout(), model.num_dofs()) {}

  Point start(const Vector& p, const Vector& y) override {
    p_ = p;
    if (rule_.prepare(p, y)) device_.set_parameters(rule_.layout());
    return point(device_.start(rule_.layout(), rule_.start_positions().data()));
  }
  Point try_step(double alpha, double omega, bool& admissible) override {
    admissible = true;  // the rule's terms bound no step (descent_vertex_blocks.hpp)
    return point(device_.try_step(alpha, omega));
  }
  double trapezoid_change() override { return device_.trapezoid_change(); }
  void accept() override { device_.accept(); }
  void restart() override { device_.restart(); }
  void read(Vector& y) const override {
    y.resize(rule_.num_free());
    device_.read(y.data());
  }
  double largest_eigenvalue(int iterations) override {
    // Once per solver: on the host, with the rule's D^-1 at the current point.
    Vector y;
    read(y);
    VertexBlockHostPass::Result at;
    host_pass_.evaluate(y, at, true);
    return power_largest_eigenvalue(model_, p_, y, iterations,
                                    [&](const Vector& g, Vector& d) { host_pass_.apply_inverse(at, g, d); });
  }
  std::string device() const override { return "gpu"; }

 private:
  Point point(const cuda::VertexBlockDevice::Sums& s) const {
    Point q;
    q.energy = s.elastic_energy + rule_.e0() + s.quadratic_energy;
    q.energy_roundoff =
        1e3 * std::numeric_limits<double>::epsilon() * (std::abs(s.elastic_energy) + rule_.constant_magnitude());
    q.residual = std::sqrt(s.gradient_squared);
    return q;
  }
  const Model& model_;
  VertexBlockModel rule_;
  VertexBlockHostPass host_pass_;
  cuda::VertexBlockDevice device_;
  Vector p_;
};

}  // namespace

std::unique_ptr<DescentBackend> make_device_backend(const Model& model) {
  if (!cuda::device_available())
    throw std::runtime_error("descent: solver.device is \"gpu\", but no CUDA device is usable by this process");
  return std::make_unique<DeviceBackend>(model);
}

#else

bool built_with_cuda() { return false; }
bool cuda_device_usable() { return false; }
std::string cuda_device_name() { return ""; }

std::unique_ptr<DescentBackend> make_device_backend(const Model& model) {
  (void)model;
  throw std::runtime_error(
      "descent: solver.device is \"gpu\", but this build has no CUDA path (configure where nvcc is found, "
      "TAILOR_WITH_CUDA AUTO or ON); use \"cpu\" or \"auto\"");
}

#endif

}  // namespace tailor
