#include "io/datasheet_file.hpp"

#include "io/yaml_fields.hpp"

namespace tofcomp::io {

namespace {

core::DatasheetThermalData datasheet_from_yaml(const YAML::Node& document,
                                               const std::string& file) {
  try {
    const YamlMap top(document, "", {"laser", "case", "equilibrium"});
    core::DatasheetThermalData d;
    const YamlMap laser(top.node("laser"), "laser",
                        {"r1_k_per_w", "c1_j_per_k", "diode_volume_m3", "diode_density_kg_per_m3",
                         "diode_specific_heat_j_per_kg_k", "electrical_power_w", "efficiency"});
    d.r1_k_per_w = laser.number("r1_k_per_w");
    if (laser.has("c1_j_per_k")) {
      d.c1_j_per_k = laser.number("c1_j_per_k");
    } else {
      d.diode_volume_m3 = laser.number("diode_volume_m3");
      d.diode_density_kg_per_m3 = laser.number("diode_density_kg_per_m3");
      d.diode_specific_heat_j_per_kg_k = laser.number("diode_specific_heat_j_per_kg_k");
    }
    d.electrical_power_w = laser.number("electrical_power_w");
    d.efficiency = laser.number_or("efficiency", d.efficiency);
    const YamlMap scanner_case(top.node("case"), "case", {"mass_kg", "specific_heat_j_per_kg_k"});
    d.case_mass_kg = scanner_case.number("mass_kg");
    d.case_specific_heat_j_per_kg_k = scanner_case.number("specific_heat_j_per_kg_k");
    const YamlMap eq(top.node("equilibrium"), "equilibrium",
                     {"case_c", "ambient_c", "power_on_fraction"});
    d.equilibrium_case_c = eq.number("case_c");
    d.equilibrium_ambient_c = eq.number("ambient_c");
    d.equilibrium_power_on_fraction = eq.number_or("power_on_fraction", 1.0);
    return d;
  } catch (const YamlSchemaError& e) {
    const std::string what = e.what();
    if (what.rfind(file, 0) == 0) throw;
    throw YamlSchemaError(file + ": " + what);
  }
}

}  // namespace

core::DatasheetThermalData read_datasheet_file(const std::string& file) {
  return datasheet_from_yaml(load_yaml_file(file), file);
}

core::DatasheetThermalData parse_datasheet(const std::string& text, const std::string& source) {
  return datasheet_from_yaml(load_yaml_text(text, source), source);
}

}  // namespace tofcomp::io
