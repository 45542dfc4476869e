// p_e = z[region[e]]: one design variable per region (material zone), copied to its entries.
#include "adjoint/parameterizations/checked_map.hpp"

namespace tailor {
namespace {

using detail::concat;

// The Jacobian is the 0/1 incidence matrix with one 1 per row, so the products are a gather
// (direct) and a scatter-add (transpose), both O(num_entries) without forming any matrix.
class RegionScatterMap final : public detail::CheckedMap {
 public:
  RegionScatterMap(std::vector<int> region_of_entry, int num_regions)
      : region_(std::move(region_of_entry)), num_regions_(num_regions) {}
  std::string name() const override {
    return concat("region_scatter(", num_regions_, " -> ", region_.size(), ")");
  }
  int num_design() const override { return num_regions_; }
  int num_params() const override { return static_cast<int>(region_.size()); }

 protected:
  Vector do_apply(const Vector& z) const override { return gather(z); }
  Vector do_jacobian_times(const Vector&, const Vector& dz) const override { return gather(dz); }
  Vector do_jacobian_transpose_times(const Vector&, const Vector& w) const override {
    // Each region receives the sum of the adjoint weights of its entries (zero if it has none).
    Vector out = Vector::Zero(num_regions_);
    for (std::size_t e = 0; e < region_.size(); ++e) out[region_[e]] += w[static_cast<Eigen::Index>(e)];
    return out;
  }

 private:
  Vector gather(const Vector& v) const {
    Vector out(static_cast<Eigen::Index>(region_.size()));
    for (std::size_t e = 0; e < region_.size(); ++e) out[static_cast<Eigen::Index>(e)] = v[region_[e]];
    return out;
  }

  std::vector<int> region_;
  int num_regions_;
};

}  // namespace

ParameterizationPtr region_scatter_map(std::vector<int> region_of_entry, int num_regions) {
  if (num_regions < 0)
    detail::invalid_parameterization("region_scatter_map",
                                     concat("num_regions must be non-negative, got ", num_regions));
  for (std::size_t e = 0; e < region_of_entry.size(); ++e) {
    const int r = region_of_entry[e];
    if (r < 0 || r >= num_regions)
      detail::invalid_parameterization("region_scatter_map",
                                       concat("region index out of range: region_of_entry[", e, "] = ", r,
                                              ", expected 0 <= region < ", num_regions));
  }
  return std::make_shared<RegionScatterMap>(std::move(region_of_entry), num_regions);
}

}  // namespace tailor
