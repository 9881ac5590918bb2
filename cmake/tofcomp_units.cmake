# The two systemd units from systemd/tofcompd.service.in: tofcompd.service runs the one daemon on
# CONFDIR/tofcompd.yaml; tofcompd@.service runs instance %i on CONFDIR/%i.yaml with --instance %i
# (its socket /run/tofcompd/%i/tofcompd.sock, ring /tofcompd-%i, state /var/lib/tofcompd/%i).
# Included when installing (daemon/service/CMakeLists.txt), with the install prefix's BINDIR and
# CONFDIR (cmake/tofcomp_install_dirs.cmake), and when configuring, for the tests.
function(tofcomp_configure_units template output_directory bindir confdir)
  file(READ "${template}" text)
  foreach(instance OFF ON)
    if(instance)
      set(TOFCOMP_UNIT_INSTANCE_DESCRIPTION " (instance %i)")
      set(TOFCOMP_UNIT_EXEC_START "${bindir}/tofcompd --config ${confdir}/%i.yaml --instance %i")
      set(TOFCOMP_UNIT_INSTANCE_DIRECTORY "/%i")
      set(name "tofcompd@.service")
    else()
      set(TOFCOMP_UNIT_INSTANCE_DESCRIPTION "")
      set(TOFCOMP_UNIT_EXEC_START "${bindir}/tofcompd --config ${confdir}/tofcompd.yaml")
      set(TOFCOMP_UNIT_INSTANCE_DIRECTORY "")
      set(name "tofcompd.service")
    endif()
    string(CONFIGURE "${text}" unit @ONLY)
    file(WRITE "${output_directory}/${name}" "${unit}")
  endforeach()
endfunction()
