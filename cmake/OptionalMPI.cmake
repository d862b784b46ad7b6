# MPI is optional: jam runs campaigns over MPI ranks when it is there, and on one process
# otherwise. Neither its absence nor a broken installation may fail the configure step, and a
# detection that failed must not stick: FindMPI caches its results (MPI_RESULT_*, the header
# and library paths), so a configure after `apt-get install libopenmpi-dev` would otherwise
# keep the old "not found".
#
# Sets JAM_MPI_USABLE (cache, internal) and, when TRUE, MPI::MPI_CXX is safe to link.
# A common broken case: openmpi-bin without libopenmpi-dev. The wrapper mpicxx is there and
# reports an include directory that does not exist; FindMPI then creates MPI::MPI_CXX with that
# path, and generating any target that links it stops with "includes non-existent path".

if(NOT JAM_MPI_USABLE)
  # Forget an earlier detection (not MPI_CXX_COMPILER or MPIEXEC_EXECUTABLE, which a user may
  # have given on the command line).
  get_cmake_property(jam_cached CACHE_VARIABLES)
  foreach(v IN LISTS jam_cached)
    if(v MATCHES "^MPI_RESULT_" OR v MATCHES "^MPI_CXX_(HEADER_DIR|LIB_NAMES|WORKS|COMPILER_INCLUDE_DIRS|ADDITIONAL_INCLUDE_DIRS|COMPILE_OPTIONS|COMPILE_DEFINITIONS|LINK_FLAGS)$" OR
       v MATCHES "^MPI_.*_LIBRARY$")
      unset(${v} CACHE)
    endif()
  endforeach()
endif()

# FindMPI's own test compile stops the configure (a FATAL error) when the wrapper names an
# include directory that does not exist, so the wrapper is asked first: OpenMPI's
# `-showme:incdirs`, MPICH's `-show`; FindMPI runs only when one of the directories it names
# holds mpi.h.
set(jam_mpi_wrapper "${MPI_CXX_COMPILER}")
if(NOT jam_mpi_wrapper)
  find_program(jam_mpi_found_wrapper NAMES mpicxx mpic++ mpiCC NO_CACHE)
  set(jam_mpi_wrapper "${jam_mpi_found_wrapper}")
endif()
set(jam_mpi_header_dir "")
if(jam_mpi_wrapper)
  execute_process(COMMAND "${jam_mpi_wrapper}" -showme:incdirs OUTPUT_VARIABLE jam_out
                  RESULT_VARIABLE jam_rc ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT jam_rc EQUAL 0)
    execute_process(COMMAND "${jam_mpi_wrapper}" -show OUTPUT_VARIABLE jam_show
                    RESULT_VARIABLE jam_rc ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
    string(REGEX MATCHALL "-I[^ ]+" jam_flags "${jam_show}")
    string(REPLACE "-I" "" jam_out "${jam_flags}")
  endif()
  string(REPLACE " " ";" jam_dirs "${jam_out}")
  foreach(d IN LISTS jam_dirs)
    if(d AND EXISTS "${d}/mpi.h")
      set(jam_mpi_header_dir "${d}")
    endif()
  endforeach()
endif()

set(jam_mpi_usable FALSE)
if(CMAKE_DISABLE_FIND_PACKAGE_MPI)
  set(jam_mpi_why "left out (CMAKE_DISABLE_FIND_PACKAGE_MPI)")
elseif(NOT jam_mpi_wrapper)
  set(jam_mpi_why "no MPI C++ compiler wrapper (mpicxx) found (install libopenmpi-dev)")
elseif(NOT jam_mpi_header_dir)
  set(jam_mpi_why "${jam_mpi_wrapper} names no directory holding mpi.h (install libopenmpi-dev)")
else()
  find_package(MPI COMPONENTS CXX QUIET)
  set(jam_mpi_why "${jam_mpi_wrapper} does not compile an MPI program")
endif()
if(jam_mpi_header_dir AND MPI_CXX_FOUND AND TARGET MPI::MPI_CXX)
  set(jam_mpi_usable TRUE)
  get_target_property(jam_mpi_dirs MPI::MPI_CXX INTERFACE_INCLUDE_DIRECTORIES)
  set(jam_mpi_header FALSE)
  foreach(d IN LISTS jam_mpi_dirs)
    if(d AND NOT EXISTS "${d}")
      set(jam_mpi_usable FALSE)
      set(jam_mpi_why "MPI's include directory ${d} does not exist (install libopenmpi-dev)")
    elseif(EXISTS "${d}/mpi.h")
      set(jam_mpi_header TRUE)
    endif()
  endforeach()
  if(jam_mpi_usable AND NOT jam_mpi_header)
    set(jam_mpi_usable FALSE)
    set(jam_mpi_why "no mpi.h in MPI's include directories (install libopenmpi-dev)")
  endif()
endif()

set(JAM_MPI_USABLE ${jam_mpi_usable} CACHE INTERNAL "MPI found and usable at the last configure")
if(JAM_MPI_USABLE)
  message(STATUS "jam: MPI found (${MPI_CXX_COMPILER}); campaigns run over MPI ranks")
else()
  message(STATUS "jam: building without MPI: ${jam_mpi_why}")
endif()
