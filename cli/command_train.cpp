// tofcomp train DATA [--datasheet D.yaml] -o CALIBRATION.yaml: thermal identification, the
// Kalman-smoothed junction temperature and EM training (§3, §5) into a calibration file.
// tofcomp train DATA... [--calibration BENCH.yaml] -o CALIBRATION.yaml: training in the field
// (calibration/field_training.hpp): every beam of every record, the still surfaces' distances
// unknown, from the bench calibration's thermal network and structure, or without one from the
// case log. Field training is what a bench calibration, several records, or a record without
// any reference distance asks for.
#include <algorithm>
#include <cstdio>
#include <optional>

#include "calibration/field_training.hpp"
#include "calibration/measured_data_reader.hpp"
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
  std::string bench;              // --calibration
  std::vector<std::string> more;  // records after DATA
};

bool has_reference(const io::MeasurementTable& table) {
  return std::any_of(table.rows.begin(), table.rows.end(),
                     [](const io::MeasurementRow& row) { return row.true_range_mm.has_value(); });
}

CommandResult train_in_field(std::vector<calibration::FieldRecord> records,
                             const FieldOptions& field, const calibration::TrainSettings& settings,
                             const std::string& output, Progress& progress) {
  std::optional<core::Calibration> bench;
  if (!field.bench.empty()) bench = io::read_calibration_file(field.bench);
  for (const std::string& file : field.more) {
    progress.update(0.0, "reading " + file);
    calibration::FieldRecord record{io::read_measured_data_file(file), file};
    for (const auto& w : record.table.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    records.push_back(std::move(record));
  }
  calibration::FieldTrainSettings field_settings;
  field_settings.thermal = settings.thermal;
  const calibration::FieldTraining t = calibration::train_in_field(
      records, bench ? &*bench : nullptr, field_settings,
      [&](double share, const std::string& stage) { progress.update(share, stage); });
  io::write_calibration_file(output, t.calibration);
  progress.done("wrote " + output);
  CommandResult result;
  result.json = field_training_json(t);
  result.json["output"] = output;
  result.text = field_training_text(t) + "wrote " + output + "\n";
  return result;
}

// Field training takes every beam of each record, the basis chosen again over the field's
// temperatures and the modes of the bench calibration (or the data): options that choose one beam
// or fix those would be ignored, so they are refused by name.
void refuse_one_beam_options(const DataOptions& data, const TrainingOptions& training) {
  std::vector<std::string> given;
  if (data.given_beam()) given.push_back("--beam");
  if (training.basis != kAutoChoice) given.push_back("--basis");
  if (training.modes != kAutoChoice) given.push_back("--modes");
  if (given.empty()) return;
  std::string names;
  for (const auto& g : given) names += (names.empty() ? "" : ", ") + g;
  throw core::InvalidInput(
      names +
      ": field training (several records, --calibration, or a record without a "
      "reference distance) uses every beam of each record, chooses the basis over the "
      "records' temperatures and takes the modes from the bench calibration; these "
      "apply to training one beam with a reference");
}

}  // namespace

void register_train(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "train",
      "Train a calibration (thermal model, basis, θ, lasing modes) on data with a known "
      "distance, or on records of still surfaces whose distances are not known (field "
      "training: several records, a record without references, or --calibration), and write "
      "it as a calibration file");
  auto data = add_data_options(*cmd);
  auto field = std::make_shared<FieldOptions>();
  cmd->add_option("more", field->more, "More records: field training on every beam of each")
      ->check(CLI::ExistingFile);
  cmd->add_option("--calibration", field->bench,
                  "Bench calibration (from tofcomp train on a record with a reference): field "
                  "training from its thermal network, basis and modes, its constant matched to "
                  "the bench's; without it the thermal network comes from the records' case log "
                  "and the constant is not determined")
      ->check(CLI::ExistingFile);
  auto training = add_training_options(*cmd);
  auto output = std::make_shared<std::string>();
  cmd->add_option("-o,--output", *output, "Calibration file to write (YAML)")
      ->required()
      ->type_name("FILE");
  auto threads = std::make_shared<int>(0);
  add_parallelism_option(*cmd, "--threads", *threads, "Fits (the structure search's folds) run");
  cmd->callback([&common, &run, data, field, training, output, threads] {
    run = [&common, data, field, training, output, threads] {
      Progress progress("train", !common.quiet);
      // Field training whatever the record holds: its options checked before anything is read.
      if (!field->bench.empty() || !field->more.empty()) refuse_one_beam_options(*data, *training);
      progress.update(0.0, "reading " + data->file);
      calibration::FieldRecord first{io::read_measured_data_file(data->file), data->file};
      for (const auto& w : first.table.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
      calibration::TrainSettings settings = training->settings();
      if (!field->bench.empty() || !field->more.empty() || !has_reference(first.table)) {
        refuse_one_beam_options(*data, *training);
        std::vector<calibration::FieldRecord> records;
        records.push_back(std::move(first));
        return train_in_field(std::move(records), *field, settings, *output, progress);
      }
      const calibration::MeasuredData measured =
          calibration::measured_data_from_table(first.table, data->file, data->beam);
      settings.threads = *threads;
      const calibration::Training t = calibration::train_calibration(
          measured, settings, nullptr,
          [&](double share, const std::string& stage) { progress.update(share, stage); });
      io::write_calibration_file(*output, t.calibration);
      progress.done("wrote " + *output);
      CommandResult result;
      result.json = training_json(t);
      result.json["output"] = *output;
      result.text = thermal_fit_text(t.thermal) + choices_text(t) +
                    calibration_text(t.calibration) + "EM: " + std::to_string(t.em.iterations) +
                    " iterations" + (t.em.converged ? "" : " (cap reached)") + "\nwrote " +
                    *output + "\n";
      return result;
    };
  });
}

}  // namespace tofcomp::cli
