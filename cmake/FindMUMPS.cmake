# FindMUMPS
# ---------
# Finds the double-precision parallel MUMPS sparse direct solver (Debian's
# libmumps-dev: dmumps_c.h, libdmumps, libmumps_common) and defines the
# imported target MUMPS::MUMPS. Shared libraries carry their own
# dependencies (ScaLAPACK, BLACS, Open MPI's Fortran bindings, gfortran);
# when only the static archives are found (libdmumps.a), those are added to
# the link interface as well: PORD, ScaLAPACK, Open MPI's mpi_mpifh, gfortran.
#
# Result variables: MUMPS_FOUND, MUMPS_INCLUDE_DIR, MUMPS_LIBRARY,
# MUMPS_COMMON_LIBRARY, MUMPS_VERSION (from dmumps_c.h).
find_path(MUMPS_INCLUDE_DIR dmumps_c.h PATH_SUFFIXES mumps)
find_library(MUMPS_LIBRARY dmumps)
find_library(MUMPS_COMMON_LIBRARY mumps_common)

if(MUMPS_INCLUDE_DIR AND EXISTS "${MUMPS_INCLUDE_DIR}/dmumps_c.h")
  file(STRINGS "${MUMPS_INCLUDE_DIR}/dmumps_c.h" _v REGEX "#define MUMPS_VERSION \"[0-9.]+\"")
  string(REGEX REPLACE ".*\"([0-9.]+)\".*" "\\1" MUMPS_VERSION "${_v}")
endif()

set(_mumps_extra "")
set(_mumps_extra_vars "")
if(MUMPS_LIBRARY MATCHES "\\.a$")
  foreach(dep pord scalapack-openmpi mpi_mpifh gfortran)
    string(TOUPPER "${dep}" DEP)
    string(REPLACE "-" "_" DEP "${DEP}")
    find_library(MUMPS_${DEP}_LIBRARY ${dep})
    list(APPEND _mumps_extra_vars MUMPS_${DEP}_LIBRARY)
    list(APPEND _mumps_extra "${MUMPS_${DEP}_LIBRARY}")
  endforeach()
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(MUMPS
  REQUIRED_VARS MUMPS_LIBRARY MUMPS_COMMON_LIBRARY MUMPS_INCLUDE_DIR ${_mumps_extra_vars}
  VERSION_VAR MUMPS_VERSION)

if(MUMPS_FOUND AND NOT TARGET MUMPS::MUMPS)
  add_library(MUMPS::MUMPS UNKNOWN IMPORTED)
  set_target_properties(MUMPS::MUMPS PROPERTIES
    IMPORTED_LOCATION "${MUMPS_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${MUMPS_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${MUMPS_COMMON_LIBRARY};${_mumps_extra}")
endif()
mark_as_advanced(MUMPS_INCLUDE_DIR MUMPS_LIBRARY MUMPS_COMMON_LIBRARY ${_mumps_extra_vars})
