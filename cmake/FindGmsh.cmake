# FindGmsh
# --------
# Finds the Gmsh SDK (Debian: libgmsh-dev) and defines the imported target
# Gmsh::Gmsh, plus GMSH_EXECUTABLE (the gmsh command, used to generate test
# and benchmark meshes from .geo files).
#
# Result variables: Gmsh_FOUND, GMSH_INCLUDE_DIR, GMSH_LIBRARY, Gmsh_VERSION.
find_path(GMSH_INCLUDE_DIR gmsh.h)
find_library(GMSH_LIBRARY gmsh)
find_program(GMSH_EXECUTABLE gmsh)
if(GMSH_INCLUDE_DIR AND EXISTS "${GMSH_INCLUDE_DIR}/gmsh.h")
  file(STRINGS "${GMSH_INCLUDE_DIR}/gmsh.h" _v REGEX "#define GMSH_API_VERSION \"[0-9.]+\"")
  string(REGEX REPLACE ".*\"([0-9.]+)\".*" "\\1" Gmsh_VERSION "${_v}")
endif()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Gmsh REQUIRED_VARS GMSH_LIBRARY GMSH_INCLUDE_DIR VERSION_VAR Gmsh_VERSION)
if(Gmsh_FOUND AND NOT TARGET Gmsh::Gmsh)
  add_library(Gmsh::Gmsh UNKNOWN IMPORTED)
  set_target_properties(Gmsh::Gmsh PROPERTIES
    IMPORTED_LOCATION "${GMSH_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${GMSH_INCLUDE_DIR}")
endif()
mark_as_advanced(GMSH_INCLUDE_DIR GMSH_LIBRARY GMSH_EXECUTABLE)
