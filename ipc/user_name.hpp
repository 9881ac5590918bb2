// How the socket server and the ring name a user in their messages: "uid 1001 (alice)", or
// "uid 1001" for a user without a name. Header only: both libraries take it.
#pragma once

#include <pwd.h>
#include <sys/types.h>

#include <array>
#include <optional>
#include <string>

namespace tofcomp::ipc {

inline constexpr std::size_t kPasswdBufferBytes = 4096;  // getpwuid_r's strings for one user

inline std::string describe_user(uid_t uid) {
  passwd entry{};
  passwd* found = nullptr;
  std::array<char, kPasswdBufferBytes> buffer{};
  std::string text = "uid " + std::to_string(uid);
  if (::getpwuid_r(uid, &entry, buffer.data(), buffer.size(), &found) == 0 && found != nullptr) {
    text += std::string(" (") + found->pw_name + ")";
  }
  return text;
}

// The uid of the user called name; nullopt when there is none.
inline std::optional<uid_t> user_named(const std::string& name) {
  passwd entry{};
  passwd* found = nullptr;
  std::array<char, kPasswdBufferBytes> buffer{};
  if (::getpwnam_r(name.c_str(), &entry, buffer.data(), buffer.size(), &found) == 0 &&
      found != nullptr) {
    return found->pw_uid;
  }
  return std::nullopt;
}

}  // namespace tofcomp::ipc
