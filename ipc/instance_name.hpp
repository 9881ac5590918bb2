// Several scanners on one host: each tofcompd instance has a name (the systemd template's %i in
// tofcompd@NAME.service), and the name gives the places the instance publishes to, so that its
// clients find it by the name alone (`tofcomp query --instance NAME`). docs/deployment.md,
// "Several scanners".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace tofcomp::ipc {

// The longest instance name: it becomes part of a socket path (107 bytes at most) and of a
// shared-memory name.
inline constexpr std::size_t kMaxInstanceNameBytes = 64;

// What is wrong with an instance name, naming it and the rule, or "" when nothing is: a name is 1
// to kMaxInstanceNameBytes letters, digits, '-' and '_', starting with a letter or a digit (so
// that it needs no escaping in a unit's name, a path or a shared-memory name). The command lines'
// check of --instance.
std::string instance_name_problem(std::string_view name);

// Throws core::InvalidInput with instance_name_problem's message when there is one.
void check_instance_name(std::string_view name);

// The instance's Unix socket: /run/tofcompd/NAME/tofcompd.sock (its own runtime directory,
// RuntimeDirectory=tofcompd/%i in tofcompd@.service). Checks the name.
std::string instance_socket_path(std::string_view name);

// The instance's shared-memory ring: /tofcompd-NAME (/dev/shm/tofcompd-NAME). Checks the name.
std::string instance_ring_name(std::string_view name);

// What the instance's log lines are identified by (SYSLOG_IDENTIFIER in the journal):
// tofcompd@NAME. Checks the name.
std::string instance_log_identity(std::string_view name);

}  // namespace tofcomp::ipc
