#include "cli/figure_drawing.hpp"

#include <string>

#include "cli/figure_data.hpp"
#include "cli/report_format.hpp"
#include "io/atomic_file.hpp"
#include "io/version.hpp"

namespace tofcomp::cli {

void write_and_draw_figures(const std::filesystem::path& directory, const FigureInputs& inputs,
                            nlohmann::json context, const ReportRenderer& renderer,
                            bool show_progress) {
  const std::filesystem::path data_dir = directory / "data";
  write_figure_data(data_dir.string(), inputs.test, inputs.calibration, inputs.compensation,
                    inputs.windows, inputs.thermal, inputs.training);
  std::vector<long> lengths;
  for (const auto& w : inputs.windows) lengths.push_back(static_cast<long>(w.window));
  context["source"] = inputs.test.source;
  context["beam"] = inputs.test.beam;
  context["software_version"] = std::string("tofcomp ") + io::kVersion;
  context["test_samples"] = inputs.test.range_mm.size();
  context["windows"] = lengths;
  context["stride"] = inputs.stride;
  context["calibration"] = to_json(inputs.calibration);
  if (inputs.thermal != nullptr) context["thermal_fit"] = to_json(*inputs.thermal);
  if (inputs.training != nullptr) context["em_training_iterations"] = inputs.training->iterations;
  io::write_file_atomically(data_dir / "context.json", context.dump(2) + "\n");
  renderer.render(directory, show_progress, Rendering::Figures);
}

}  // namespace tofcomp::cli
