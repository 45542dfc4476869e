#include "problems/plot/convergence_plot.hpp"

namespace tailor {

LinePlot convergence_plot(const OptimizerResult& result, const std::string& title) {
  LinePlot plot;
  plot.title = title;
  plot.x_label = "iteration";
  plot.y_label = "log scale";
  plot.log_y = true;
  LineSeries objective{"objective", {31, 119, 180}, {}, {}};
  LineSeries gradient{"gradient norm", {230, 110, 20}, {}, {}};
  for (const OptimizerIteration& it : result.history) {
    objective.x.push_back(it.iteration);
    objective.y.push_back(it.objective);
    gradient.x.push_back(it.iteration);
    gradient.y.push_back(it.gradient_norm);
  }
  plot.series = {std::move(objective), std::move(gradient)};
  return plot;
}

void write_convergence_png(const std::string& path, const OptimizerResult& result, const std::string& title) {
  write_line_plot_png(path, convergence_plot(result, title));
}

}  // namespace tailor
