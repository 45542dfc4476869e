#pragma once
// VTK XML unstructured-grid output of discrete elastic rods as polylines (one VTK_LINE cell per
// edge) for ParaView. Cell data per edge: the material frame
// vectors "m1", "m2", the twist angle "theta" [rad], the axial strain |e|/L - 1, and per
// interior vertex (point data) the material curvatures "kappa" (2 components, 0 at the ends)
// and the twist "twist" m_i [rad].
#include <string>
#include <vector>

#include "forward/rods/discrete_rod.hpp"
#include "forward/rods/rod_parameters.hpp"

namespace tailor {

struct RodOutput {
  const DiscreteRod* rod;
  RodParameterBlocks blocks;
};

// Writes all rods into one .vtu file. Throws std::runtime_error when the file cannot be written.
void write_rods_vtu(const std::string& path, const std::vector<RodOutput>& rods, const Vector& x,
                    const Vector& p);

}  // namespace tailor
