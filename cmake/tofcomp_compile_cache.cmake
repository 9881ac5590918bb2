# Compile once: ccache (Debian's `ccache`) in front of the compilers where it is installed, and
# debug information that does not dominate the link. docs/performance.md, "Building", has the
# figures that chose these.
#
# TOFCOMP_CCACHE (default ON): use ccache when it is found. Its cache is ccache's own
# (~/.cache/ccache, or CCACHE_DIR), outside the checkout, so a fresh clone on the same machine
# reuses what another clone compiled: the source root is ccache's base_dir (paths under it are
# hashed relative to it) and is mapped to "." in the debug information, so that an object file
# does not depend on where the clone is.
option(TOFCOMP_CCACHE "Compile through ccache when it is installed" ON)
if(TOFCOMP_CCACHE)
  find_program(TOFCOMP_CCACHE_PROGRAM ccache)
  find_program(TOFCOMP_ENV_PROGRAM env)
  if(TOFCOMP_CCACHE_PROGRAM AND TOFCOMP_ENV_PROGRAM)
    set(tofcomp_launcher ${TOFCOMP_ENV_PROGRAM} CCACHE_BASEDIR=${CMAKE_SOURCE_DIR}
        ${TOFCOMP_CCACHE_PROGRAM})
    set(CMAKE_C_COMPILER_LAUNCHER ${tofcomp_launcher})
    set(CMAKE_CXX_COMPILER_LAUNCHER ${tofcomp_launcher})
    message(STATUS "tofcomp: compiling through ${TOFCOMP_CCACHE_PROGRAM}")
  endif()
endif()
add_compile_options(-fdebug-prefix-map=${CMAKE_SOURCE_DIR}=.)

# RelWithDebInfo's -g is full DWARF: 242 MB of binaries whose link it dominated. -g1 (line
# tables: backtraces and profiles with file and line, no variables) comes after it on every
# command line and wins; the code generated is the same.
add_compile_options($<$<CONFIG:RelWithDebInfo>:-g1>)
