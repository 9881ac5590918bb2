// tofcomp train DATA [--datasheet D.yaml] -o CALIBRATION.yaml: thermal identification, the
// Kalman-smoothed junction temperature and EM training (§3, §5) into a calibration file.
// tofcomp train DATA... --calibration BENCH.yaml -o CALIBRATION.yaml: training in the field
// (calibration/field_training.hpp): every beam of every record, the still surfaces' distances
// unknown, from the bench calibration's thermal network and structure.
#include <cstdio>

#include "calibration/field_training.hpp"
#include "cli/command.hpp"
#include "cli/field_training_format.hpp"
#include "cli/number_checks.hpp"
#include "cli/progress.hpp"
#include "cli/report_format.hpp"
#include "cli/shared_options.hpp"
#include "cli/structure_format.hpp"
#include "io/measured_data_csv.hpp"

namespace tofcomp::cli {
namespace {

struct FieldOptions {
  std::string bench;               // --calibration
  std::vector<std::string> more;   // records after DATA
};

CommandResult train_in_field(const DataOptions& data, const FieldOptions& field,
                             const std::string& output, bool quiet) {
  Progress progress("train", !quiet);
  const core::Calibration bench = io::read_calibration_file(field.bench);
  std::vector<calibration::FieldRecord> records;
  std::vector<std::string> files = {data.file};
  files.insert(files.end(), field.more.begin(), field.more.end());
  for (const std::string& file : files) {
    progress.update(0.0, "reading " + file);
    calibration::FieldRecord record{io::read_measured_data_file(file), file};
    for (const auto& w : record.table.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    records.push_back(std::move(record));
  }
  const calibration::FieldTraining t = calibration::train_in_field(
      records, bench, {}, [&](double share, const std::string& stage) {
        progress.update(share, stage);
      });
  io::write_calibration_file(output, t.calibration);
  progress.done("wrote " + output);
  CommandResult result;
  result.json = field_training_json(t);
  result.json["output"] = output;
  result.text = field_training_text(t) + "wrote " + output + "\n";
  return result;
}

}  // namespace

void register_train(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "train",
      "Train a calibration (thermal model, basis, θ, lasing modes) on data with a known "
      "distance, or with --calibration on records of still surfaces whose distances are not "
      "known (field training), and write it as a calibration file");
  auto data = add_data_options(*cmd);
  auto field = std::make_shared<FieldOptions>();
  cmd->add_option("more", field->more,
                  "More records, for field training (--calibration): every beam of each")
      ->check(CLI::ExistingFile);
  cmd->add_option("--calibration", field->bench,
                  "Bench calibration (from tofcomp train on a record with a reference): train in "
                  "the field from its thermal network, basis and modes, on every beam of the "
                  "records; the still surfaces' distances are fitted, not needed")
      ->check(CLI::ExistingFile);
  auto training = add_training_options(*cmd);
  auto output = std::make_shared<std::string>();
  cmd->add_option("-o,--output", *output, "Calibration file to write (YAML)")->required();
  auto threads = std::make_shared<int>(0);
  cmd->add_option("--threads", *threads,
                  "Fits run at once: the structure search's folds (default: one per core; the "
                  "results do not depend on it)")
      ->check(between(1, kMaxParallelism));
  cmd->callback([&common, &run, data, field, training, output, threads] {
    if (!field->more.empty() && field->bench.empty()) {
      throw CLI::ValidationError("more than one record",
                                 "training on several records is field training: give the bench "
                                 "calibration with --calibration BENCH.yaml");
    }
    run = [&common, data, field, training, output, threads] {
      if (!field->bench.empty()) return train_in_field(*data, *field, *output, common.quiet);
      Progress progress("train", !common.quiet);
      const calibration::MeasuredData measured = data->load();
      calibration::TrainSettings settings = training->settings();
      settings.threads = *threads;
      const calibration::Training t = calibration::train_calibration(
          measured, settings, nullptr,
          [&](double share, const std::string& stage) { progress.update(share, stage); });
      io::write_calibration_file(*output, t.calibration);
      progress.done("wrote " + *output);
      CommandResult result;
      result.json = training_json(t);
      result.json["output"] = *output;
      result.text = thermal_fit_text(t.thermal) + choices_text(t) + calibration_text(t.calibration) +
                    "EM: " + std::to_string(t.em.iterations) + " iterations" +
                    (t.em.converged ? "" : " (cap reached)") + "\nwrote " + *output + "\n";
      return result;
    };
  });
}

}  // namespace tofcomp::cli
