#include "ipc/instance_name.hpp"

#include <algorithm>
#include <cctype>

#include "core/error.hpp"

namespace tofcomp::ipc {
namespace {

bool letter_or_digit(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0;
}

}  // namespace

std::string instance_name_problem(std::string_view name) {
  const bool allowed =
      !name.empty() && name.size() <= kMaxInstanceNameBytes && letter_or_digit(name.front()) &&
      std::all_of(name.begin(), name.end(),
                  [](char c) { return letter_or_digit(c) || c == '-' || c == '_'; });
  if (allowed) return "";
  return "instance name '" + std::string(name) + "': must be 1 to " +
         std::to_string(kMaxInstanceNameBytes) +
         " letters, digits, '-' and '_', starting with a letter or a digit";
}

void check_instance_name(std::string_view name) {
  if (std::string problem = instance_name_problem(name); !problem.empty()) {
    throw core::InvalidInput(problem);
  }
}

std::string instance_socket_path(std::string_view name) {
  check_instance_name(name);
  return "/run/tofcompd/" + std::string(name) + "/tofcompd.sock";
}

std::string instance_ring_name(std::string_view name) {
  check_instance_name(name);
  return "/tofcompd-" + std::string(name);
}

std::string instance_log_identity(std::string_view name) {
  check_instance_name(name);
  return "tofcompd@" + std::string(name);
}

}  // namespace tofcomp::ipc
