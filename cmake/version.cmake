# Writes the code version (project version + `git describe`) into version.hpp at build time,
# so that run files name the commit they were built from even when the build directory was
# configured at an older commit. configure_file leaves the header untouched (no rebuild) when
# the version did not change. Called by the jam_version target (sim/CMakeLists.txt).
execute_process(COMMAND git describe --always --dirty --tags
                WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE JAM_GIT_VERSION OUTPUT_STRIP_TRAILING_WHITESPACE
                ERROR_QUIET)
if(NOT JAM_GIT_VERSION)
  set(JAM_GIT_VERSION "unknown")
endif()
set(JAM_VERSION_STRING "${PROJECT_VERSION}+${JAM_GIT_VERSION}")
configure_file(${INPUT} ${OUTPUT} @ONLY)
