# FindCHOLMOD
# -----------
# Finds SuiteSparse's CHOLMOD sparse Cholesky library and defines the
# imported target CHOLMOD::CHOLMOD (include dirs and its SuiteSparse
# dependencies AMD, COLAMD, CAMD, CCOLAMD, SuiteSparse_config attached).
#
# Result variables: CHOLMOD_FOUND, CHOLMOD_INCLUDE_DIR, CHOLMOD_LIBRARY,
# CHOLMOD_VERSION (from cholmod.h).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
foreach(dep amd colamd camd ccolamd suitesparseconfig)
  string(TOUPPER ${dep} DEP)
  find_library(CHOLMOD_${DEP}_LIBRARY ${dep})
  list(APPEND _cholmod_deps CHOLMOD_${DEP}_LIBRARY)
endforeach()

# The version lives in cholmod.h (SuiteSparse >= 7) or cholmod_core.h (older).
foreach(_h cholmod.h cholmod_core.h)
  if(CHOLMOD_INCLUDE_DIR AND EXISTS "${CHOLMOD_INCLUDE_DIR}/${_h}" AND NOT CHOLMOD_VERSION)
    file(STRINGS "${CHOLMOD_INCLUDE_DIR}/${_h}" _v REGEX "#define CHOLMOD_(MAIN|SUB)_VERSION +[0-9]+")
    if(_v)
      string(REGEX REPLACE ".*MAIN_VERSION +([0-9]+).*" "\\1" _maj "${_v}")
      string(REGEX REPLACE ".*SUB_VERSION +([0-9]+).*" "\\1" _min "${_v}")
      set(CHOLMOD_VERSION "${_maj}.${_min}")
    endif()
  endif()
endforeach()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD
  REQUIRED_VARS CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR ${_cholmod_deps}
  VERSION_VAR CHOLMOD_VERSION)

if(CHOLMOD_FOUND AND NOT TARGET CHOLMOD::CHOLMOD)
  add_library(CHOLMOD::CHOLMOD UNKNOWN IMPORTED)
  set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${CHOLMOD_AMD_LIBRARY};${CHOLMOD_COLAMD_LIBRARY};${CHOLMOD_CAMD_LIBRARY};${CHOLMOD_CCOLAMD_LIBRARY};${CHOLMOD_SUITESPARSECONFIG_LIBRARY}")
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY ${_cholmod_deps})
