#pragma once
// Partitions of a mesh's elements into domains for domain-decomposed reduced models
// (docs/reduction.md, "Domain decomposition"): by METIS (Karypis & Kumar 1998, multilevel
// k-way partitioning of the element dual graph, elements adjacent through a shared facet), or
// from the mesh's element regions.
#include <Eigen/Core>

#include "forward/mesh/mesh.hpp"

namespace tailor {

// element -> domain in [0, domains), every domain non-empty. One domain maps everything to 0.
// Deterministic (METIS with a fixed seed). Throws std::invalid_argument when domains < 1 or
// exceeds the element count, std::runtime_error when METIS fails or leaves a domain empty.
Eigen::VectorXi partition_elements(const Mesh& mesh, int domains);

// element -> domain from mesh.element_regions: the distinct region tags in increasing order
// become domains 0, 1, ... Throws std::invalid_argument when the mesh has no region tags.
Eigen::VectorXi domains_from_regions(const Mesh& mesh);

// The number of domains of an element -> domain map (1 + its largest entry).
int domain_count(const Eigen::VectorXi& element_domain);

}  // namespace tailor
