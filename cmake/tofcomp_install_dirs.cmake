# Included by install(CODE) when installing, with the prefix given then (`cmake --install build
# --prefix P`, or CPack's /usr): where the configuration goes and where the unit finds the daemon.
# The configuration goes to /etc/tofcompd with the prefix /usr (the Filesystem Hierarchy
# Standard's place, where a Debian package puts it) and to PREFIX/etc/tofcompd otherwise.
if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(TOFCOMP_CONFDIR "/etc/tofcompd")
else()
  set(TOFCOMP_CONFDIR "${CMAKE_INSTALL_PREFIX}/etc/tofcompd")
endif()
set(TOFCOMP_BINDIR "${CMAKE_INSTALL_PREFIX}/bin")
# tofcomp-mqtt-bridge's configurations (one per instance, with their password files) beside it:
# /etc/tofcomp-mqtt-bridge with the prefix /usr.
if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(TOFCOMP_BRIDGE_CONFDIR "/etc/tofcomp-mqtt-bridge")
else()
  set(TOFCOMP_BRIDGE_CONFDIR "${CMAKE_INSTALL_PREFIX}/etc/tofcomp-mqtt-bridge")
endif()
