#include "forward/fem/linear_simplices.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>

namespace tailor {

template <int Dim>
LinearSimplices<Dim>::LinearSimplices(const Mesh& mesh, std::vector<int> covered, const std::string& owner)
    : elements(std::move(covered)) {
  if (mesh.dim() != Dim || mesh.elements.cols() != kNodes)
    throw std::invalid_argument(owner + "<" + std::to_string(Dim) + ">: the mesh has dimension " +
                                std::to_string(mesh.dim()));
  if (elements.empty()) {
    elements.resize(mesh.num_elements());
    for (int e = 0; e < mesh.num_elements(); ++e) elements[e] = e;
  }
  {
    std::vector<int> sorted = elements;
    std::sort(sorted.begin(), sorted.end());
    const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
    if (twice != sorted.end())
      throw std::invalid_argument(owner + ": element " + std::to_string(*twice) + " is listed twice");
  }
  vertices.resize(elements.size());
  gradients.resize(elements.size());
  volumes.resize(elements.size());
  for (std::size_t k = 0; k < elements.size(); ++k) {
    const int e = elements[k];
    if (e < 0 || e >= mesh.num_elements())
      throw std::invalid_argument(owner + ": element index " + std::to_string(e) + " out of range");
    Mat Dm;
    for (int a = 0; a < Dim; ++a)
      Dm.col(a) =
          (mesh.rest_positions.row(mesh.elements(e, a + 1)) - mesh.rest_positions.row(mesh.elements(e, 0)))
              .transpose();
    const double det = Dm.determinant();
    if (!(det > 0.0))
      throw std::invalid_argument(owner + ": element " + std::to_string(e) +
                                  " is degenerate or inverted at rest (signed measure " +
                                  std::to_string(det) + ")");
    const Mat Dm_inv = Dm.inverse();
    ShapeGradients G;
    G.template bottomRows<Dim>() = Dm_inv;  // grad N_a = row a-1 of Dm^{-1}
    G.row(0) = -Dm_inv.colwise().sum();
    gradients[k] = G;
    volumes[k] = det / (Dim == 3 ? 6.0 : 2.0);
    for (int a = 0; a < kNodes; ++a) vertices[k][a] = mesh.elements(e, a);
  }
  colour_elements();
}

template <int Dim>
void LinearSimplices<Dim>::colour_elements() {
  const int n = size();
  int num_vertices = 0;
  for (const auto& v : vertices) num_vertices = std::max(num_vertices, v.maxCoeff() + 1);
  // The covered elements at each vertex (compressed rows, in element order).
  std::vector<int> start(static_cast<std::size_t>(num_vertices) + 1, 0);
  for (const auto& v : vertices)
    for (int a = 0; a < kNodes; ++a) ++start[static_cast<std::size_t>(v[a]) + 1];
  for (int v = 0; v < num_vertices; ++v) start[v + 1] += start[v];
  std::vector<int> incident(static_cast<std::size_t>(start.back()));
  {
    std::vector<int> next(start.begin(), start.end() - 1);
    for (int k = 0; k < n; ++k)
      for (int a = 0; a < kNodes; ++a) incident[next[vertices[k][a]]++] = k;
  }
  // Greedy: the smallest colour that no earlier element sharing a vertex has.
  std::vector<int> colour(static_cast<std::size_t>(n), -1), taken_by;  // taken_by[c]: last k that saw c
  for (int k = 0; k < n; ++k) {
    for (int a = 0; a < kNodes; ++a) {
      const int v = vertices[k][a];
      for (int i = start[v]; i < start[v + 1]; ++i)
        if (const int c = colour[incident[i]]; c >= 0) taken_by[c] = k;
    }
    int c = 0;
    while (c < static_cast<int>(taken_by.size()) && taken_by[c] == k) ++c;
    if (c == static_cast<int>(taken_by.size())) taken_by.push_back(-1);
    colour[k] = c;
  }
  const int colours = static_cast<int>(taken_by.size());
  std::vector<int> colour_start(static_cast<std::size_t>(colours) + 1, 0);
  for (int c : colour) ++colour_start[static_cast<std::size_t>(c) + 1];
  for (int c = 0; c < colours; ++c) colour_start[c + 1] += colour_start[c];
  colour_order.assign(static_cast<std::size_t>(n), 0);
  {
    std::vector<int> next(colour_start.begin(), colour_start.end() - 1);
    for (int k = 0; k < n; ++k) colour_order[next[colour[k]]++] = k;
  }
  chunk_begin.clear();
  colour_chunks.assign(1, 0);
  for (int c = 0; c < colours; ++c) {
    for (int i = colour_start[c]; i < colour_start[c + 1]; i += kChunk) chunk_begin.push_back(i);
    colour_chunks.push_back(static_cast<int>(chunk_begin.size()));
  }
  chunk_begin.push_back(n);
}

template <int Dim>
typename LinearSimplices<Dim>::Mat LinearSimplices<Dim>::field_gradient(const Vector& x, int k) const {
  Mat F = Mat::Zero();
  for (int a = 0; a < kNodes; ++a)
    F.noalias() += x.template segment<Dim>(Dim * vertices[k][a]) * gradients[k].row(a);
  return F;
}

template <int Dim>
typename LinearSimplices<Dim>::Jacobian LinearSimplices<Dim>::deformation_jacobian(const ShapeGradients& G) {
  Jacobian B = Jacobian::Zero();
  for (int a = 0; a <= Dim; ++a)
    for (int j = 0; j < Dim; ++j)
      for (int i = 0; i < Dim; ++i) B(i + Dim * j, Dim * a + i) = G(a, j);
  return B;
}

template <int Dim>
void LinearSimplices<Dim>::append_hessian_pattern(HessianPattern& pattern) const {
  pattern.reserve(pattern.size() + elements.size() * kLocal * kLocal);
  for (int k = 0; k < size(); ++k)
    for (int r = 0; r < kLocal; ++r)
      for (int c = 0; c < kLocal; ++c) pattern.push_back({dof(k, r), dof(k, c)});
}

template struct LinearSimplices<2>;
template struct LinearSimplices<3>;

}  // namespace tailor
