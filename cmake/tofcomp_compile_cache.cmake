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

# TOFCOMP_UNITY_BUILD (default ON): the product's libraries and programs compile their sources in
# batches of kUnityBatch files, one compiler run each. What dominates a cold build is what every
# unit compiles again, not what it parses: CLI11 2.1 (header-only) generates about 5 s of code
# per unit that includes it, and each unit of Eq. 2-4 instantiates Eigen's matrix exponential.
# In a batch that is done once. A source whose types GCC cannot place in a batch (coroutine
# frames or a class of its header holding types of its anonymous namespace: -Wsubobject-linkage)
# sets SKIP_UNITY_BUILD_INCLUSION. The tests, benchmarks and fuzz targets build file by file
# (tests/CMakeLists.txt): their executables are one source each.
option(TOFCOMP_UNITY_BUILD "Compile the product's sources in batches (a unity build)" ON)
set(CMAKE_UNITY_BUILD ${TOFCOMP_UNITY_BUILD})
set(CMAKE_UNITY_BUILD_BATCH_SIZE 8)
