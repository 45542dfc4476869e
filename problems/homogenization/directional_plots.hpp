#pragma once
// PNG plots of sampled directional constants, drawn with the line-plot module (problems/plot):
// E(d) as a polar curve (x = E cos(theta), y = E sin(theta); a reference circle of radius
// max E makes both axes span the same range) and nu(d) against the angle in degrees.
#include <string>
#include <vector>

#include "problems/homogenization/homogenize_command.hpp"

namespace tailor {

// Writes <out_dir>/youngs_modulus_polar.png and <out_dir>/poisson_ratio.png.
void write_directional_plots(const std::string& out_dir, const std::string& title,
                             const std::vector<DirectionalSamples>& samples);

}  // namespace tailor
