# Debian packages by CPack's DEB generator, one per install component (docs/deployment.md,
# "Debian packages"):
#   daemon      -> tofcompd               the daemon, its units, sysusers file, configuration
#                                         (/etc/tofcompd/tofcompd.yaml, a real scanner), the
#                                         emulator's example configuration, man pages 8 and 5
#   cli         -> tofcomp                the command line, the report renderer, the scenarios,
#                                         the datasheet and calibration (/usr/share/tofcomp),
#                                         the documentation, man page 1
#   client      -> libtofcomp-client0     the client library (shared)
#   client-dev  -> libtofcomp-client-dev  its headers, static library, pkg-config and CMake files
#   python      -> python3-tofcomp-client the Python module over the shared library (Debian
#                                         keeps Python modules out of library packages)
#   ros2-bridge -> tofcomp-ros2-bridge    the bridge to ROS 2 over DDS, its unit (not enabled)
#                                         and /etc/tofcompd/ros2-bridge.yaml (enabled: false)
#   mqtt-bridge -> tofcomp-mqtt-bridge    the MQTT bridge, its unit template, example
#                                         configuration and man page 8
# A component that no install rule fills is left out, so the list follows what the tree builds.
# Built with `cpack --config build/CPackConfig.cmake -B DIR` (tests/install/packages_test.sh);
# the binaries are stripped as they are packaged.
# Included last by the top-level CMakeLists.txt, after every install rule.
get_cmake_property(TOFCOMP_INSTALL_COMPONENTS COMPONENTS)
set(TOFCOMP_PACKAGE_COMPONENTS)
foreach(component daemon cli client client-dev python ros2-bridge mqtt-bridge)
  if(component IN_LIST TOFCOMP_INSTALL_COMPONENTS)
    list(APPEND TOFCOMP_PACKAGE_COMPONENTS ${component})
  endif()
endforeach()

set(TOFCOMP_PACKAGE_daemon tofcompd)
set(TOFCOMP_PACKAGE_cli tofcomp)
set(TOFCOMP_PACKAGE_client libtofcomp-client0)
set(TOFCOMP_PACKAGE_client-dev libtofcomp-client-dev)
set(TOFCOMP_PACKAGE_python python3-tofcomp-client)
set(TOFCOMP_PACKAGE_ros2-bridge tofcomp-ros2-bridge)
set(TOFCOMP_PACKAGE_mqtt-bridge tofcomp-mqtt-bridge)
set(TOFCOMP_SUMMARY_daemon "LiDAR temperature and mode-hopping compensation daemon")
set(TOFCOMP_SUMMARY_cli "LiDAR temperature and mode-hopping compensation tools")
set(TOFCOMP_SUMMARY_client "client library of the tofcompd LiDAR compensation daemon")
set(TOFCOMP_SUMMARY_client-dev "client library of tofcompd: development files")
set(TOFCOMP_SUMMARY_python "client library of tofcompd: Python 3 module")
set(TOFCOMP_SUMMARY_ros2-bridge "tofcompd's compensated LiDAR scans to ROS 2 over DDS")
set(TOFCOMP_SUMMARY_mqtt-bridge "MQTT bridge of the tofcompd LiDAR compensation daemon")
set(TOFCOMP_DESCRIPTION_daemon
  "tofcompd reads a SICK LMS 200 over its serial link and a thermometer on its
case, compensates each range for the laser's junction temperature and lasing
mode, and publishes the scans to a shared-memory ring and a Unix socket. It
runs as a hardened systemd service, one per scanner (tofcompd@.service).")
set(TOFCOMP_DESCRIPTION_cli
  "tofcomp calibrates the compensation from measured data, evaluates and
diagnoses it, emulates an LMS 200, and queries a running tofcompd over its
socket and shared-memory ring.")
set(TOFCOMP_DESCRIPTION_client
  "The library programs link to read compensated scans from tofcompd.")
set(TOFCOMP_DESCRIPTION_client-dev
  "Headers, static library, pkg-config and CMake files of the tofcompd client library.")
set(TOFCOMP_DESCRIPTION_python
  "The module tofcomp_client reads compensated scans from tofcompd in Python.")
set(TOFCOMP_DESCRIPTION_ros2-bridge
  "tofcomp-ros2-bridge publishes tofcompd's scans as sensor_msgs/msg/LaserScan
and the scanner's health as diagnostic_msgs/msg/DiagnosticArray with Cyclone
DDS, as a ROS 2 node would (rt/scan, rt/diagnostics). Off until configured.")
set(TOFCOMP_DESCRIPTION_mqtt-bridge
  "tofcomp-mqtt-bridge publishes one tofcompd's status, calibration, junction
temperature, diagnosis findings and a summary of its compensated ranges to an
MQTT broker, with a retained online state and TLS, and passes the reload and
recalibrate commands its configuration allows (tofcomp-mqtt-bridge@.service).")

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME tofcomp)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "tofcomp maintainers <maintainers@users.noreply.h-seed-b9bed1ab.example>")
# Each package's summary is the first line of its own description (below): the project-wide
# summary is set to CPack's default, which CPackDeb does not prepend.
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${CMAKE_PROJECT_NAME} built using CMake")
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL ${TOFCOMP_PACKAGE_COMPONENTS})
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
# /etc/tofcompd is outside the prefix: installed through DESTDIR with the prefix /usr.
set(CPACK_SET_DESTDIR ON)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
# Depends: from the libraries the binaries link (dpkg-shlibdeps), and between the components.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://example.invalid/tofcomp")
# The daemon's emulator example plays the scenarios the command line's package ships.
set(CPACK_COMPONENT_DAEMON_DEPENDS cli)
set(CPACK_COMPONENT_CLIENT-DEV_DEPENDS client)
set(CPACK_COMPONENT_PYTHON_DEPENDS client)
# The bridge's unit runs in the tofcompd group that the daemon's package makes.
set(CPACK_COMPONENT_ROS2-BRIDGE_DEPENDS daemon)
# The bridge runs as tofcompd's user, which the daemon's package makes.
set(CPACK_COMPONENT_MQTT-BRIDGE_DEPENDS daemon)
set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS python3)
set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
set(CPACK_DEBIAN_PYTHON_PACKAGE_ARCHITECTURE all)
# A package holding a shared library (libtofcomp-client0) gets a shlibs file, so that programs
# built against it depend on it, and the ldconfig trigger that comes with it; the others hold
# none and get neither.
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY ">=")
set(CPACK_DEBIAN_CLIENT_PACKAGE_SECTION libs)
# dpkg runs ldconfig once after the packages of a run are in (CPackDeb of CMake 3.25 writes no
# trigger itself).
set(CPACK_DEBIAN_CLIENT_PACKAGE_CONTROL_EXTRA ${TOFCOMP_SOURCE_ROOT}/packaging/libtofcomp-client0/triggers)
set(CPACK_DEBIAN_CLIENT_PACKAGE_CONTROL_STRICT_PERMISSION ON)

set(TOFCOMP_PACKAGING_BINARY_DIR ${PROJECT_BINARY_DIR}/packaging)
string(TIMESTAMP TOFCOMP_PACKAGE_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)
foreach(component ${TOFCOMP_PACKAGE_COMPONENTS})
  string(TOUPPER ${component} upper)
  set(package ${TOFCOMP_PACKAGE_${component}})
  set(CPACK_DEBIAN_${upper}_PACKAGE_NAME ${package})
  set(CPACK_COMPONENT_${upper}_DISPLAY_NAME ${package})
  set(CPACK_DEBIAN_${upper}_DESCRIPTION
    "${TOFCOMP_SUMMARY_${component}}\n${TOFCOMP_DESCRIPTION_${component}}")
  # Every Debian package carries its copyright file and changelog in /usr/share/doc/PACKAGE.
  set(TOFCOMP_PACKAGE_NAME ${package})
  configure_file(${TOFCOMP_SOURCE_ROOT}/packaging/changelog.in
    ${TOFCOMP_PACKAGING_BINARY_DIR}/${package}/changelog @ONLY)
  execute_process(COMMAND gzip -9nf ${TOFCOMP_PACKAGING_BINARY_DIR}/${package}/changelog
    COMMAND_ERROR_IS_FATAL ANY)
  install(FILES ${TOFCOMP_SOURCE_ROOT}/packaging/copyright
                ${TOFCOMP_PACKAGING_BINARY_DIR}/${package}/changelog.gz
    DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${package} COMPONENT ${component})
endforeach()

# The daemon's package: its configuration is a conffile (kept across upgrades when edited), and
# its maintainer scripts make the system user and tell systemd of the units.
set(CPACK_DEBIAN_DAEMON_PACKAGE_CONTROL_EXTRA
  ${TOFCOMP_SOURCE_ROOT}/packaging/tofcompd/conffiles
  ${TOFCOMP_SOURCE_ROOT}/packaging/tofcompd/postinst
  ${TOFCOMP_SOURCE_ROOT}/packaging/tofcompd/postrm)
set(CPACK_DEBIAN_DAEMON_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_DEBIAN_ROS2-BRIDGE_PACKAGE_CONTROL_EXTRA
  ${TOFCOMP_SOURCE_ROOT}/packaging/tofcomp-ros2-bridge/conffiles)
# The bridge's package: systemd learns of its unit template (not enabled).
set(CPACK_DEBIAN_MQTT-BRIDGE_PACKAGE_CONTROL_EXTRA
  ${TOFCOMP_SOURCE_ROOT}/packaging/tofcomp-mqtt-bridge/postinst
  ${TOFCOMP_SOURCE_ROOT}/packaging/tofcomp-mqtt-bridge/postrm)
set(CPACK_DEBIAN_MQTT-BRIDGE_PACKAGE_CONTROL_STRICT_PERMISSION ON)

include(CPack)
