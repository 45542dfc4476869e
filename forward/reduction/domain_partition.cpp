#include "forward/reduction/domain_partition.hpp"

#include <metis.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace tailor {

Eigen::VectorXi partition_elements(const Mesh& mesh, int domains) {
  const int elements = mesh.num_elements();
  if (domains < 1 || domains > elements)
    throw std::invalid_argument("partition_elements: " + std::to_string(domains) + " domains for " +
                                std::to_string(elements) + " elements");
  if (domains == 1) return Eigen::VectorXi::Zero(elements);
  const int nodes = static_cast<int>(mesh.elements.cols());
  std::vector<idx_t> eptr(static_cast<std::size_t>(elements) + 1), eind;
  eind.reserve(static_cast<std::size_t>(elements) * nodes);
  for (int e = 0; e < elements; ++e) {
    eptr[static_cast<std::size_t>(e)] = static_cast<idx_t>(eind.size());
    for (int a = 0; a < nodes; ++a) eind.push_back(mesh.elements(e, a));
  }
  eptr.back() = static_cast<idx_t>(eind.size());
  idx_t ne = elements, nn = mesh.num_vertices(), ncommon = mesh.dim(), nparts = domains, objval = 0;
  std::vector<idx_t> epart(static_cast<std::size_t>(elements)), npart(static_cast<std::size_t>(nn));
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 1;
  options[METIS_OPTION_CONTIG] = 1;  // connected domains where the mesh allows
  const int status = METIS_PartMeshDual(&ne, &nn, eptr.data(), eind.data(), nullptr, nullptr, &ncommon, &nparts,
                                        nullptr, options, &objval, epart.data(), npart.data());
  if (status != METIS_OK)
    throw std::runtime_error("partition_elements: METIS_PartMeshDual failed (status " + std::to_string(status) + ")");
  Eigen::VectorXi out(elements);
  std::vector<int> count(static_cast<std::size_t>(domains), 0);
  for (int e = 0; e < elements; ++e) {
    out[e] = static_cast<int>(epart[static_cast<std::size_t>(e)]);
    ++count[static_cast<std::size_t>(out[e])];
  }
  for (int d = 0; d < domains; ++d)
    if (count[static_cast<std::size_t>(d)] == 0)
      throw std::runtime_error("partition_elements: METIS left domain " + std::to_string(d) + " of " +
                               std::to_string(domains) + " empty");
  return out;
}

Eigen::VectorXi domains_from_regions(const Mesh& mesh) {
  if (mesh.element_regions.size() != mesh.num_elements())
    throw std::invalid_argument("domains_from_regions: the mesh has no element regions");
  std::map<int, int> index;
  for (int e = 0; e < mesh.num_elements(); ++e) index.emplace(mesh.element_regions[e], 0);
  int next = 0;
  for (auto& [tag, d] : index) d = next++;
  Eigen::VectorXi out(mesh.num_elements());
  for (int e = 0; e < mesh.num_elements(); ++e) out[e] = index.at(mesh.element_regions[e]);
  return out;
}

int domain_count(const Eigen::VectorXi& element_domain) {
  return element_domain.size() == 0 ? 0 : element_domain.maxCoeff() + 1;
}

}  // namespace tailor
