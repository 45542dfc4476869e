#pragma once
// The convergence plot of an optimization: objective and gradient norm against iteration on
// a log10 y axis (points <= 0 are left out), as written by `tailor run` to DIR/convergence.png.
#include <string>

#include "optimizers/optimizer.hpp"
#include "problems/plot/line_plot.hpp"

namespace tailor {

// Series "objective" (blue) and "gradient norm" (orange) from result.history.
LinePlot convergence_plot(const OptimizerResult& result, const std::string& title);
// Throws std::runtime_error naming the path when it cannot be written.
void write_convergence_png(const std::string& path, const OptimizerResult& result, const std::string& title);

}  // namespace tailor
