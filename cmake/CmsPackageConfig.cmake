# CmsPackageConfig
# ----------------
# Writes and installs the CMake package of cms (included once, at the end of
# the top-level CMakeLists.txt, when every package has called cms_package):
#
#   <prefix>/lib/cmake/cms/cmsConfig.cmake          find_dependency of what the
#                                                   targets need, then the targets
#   <prefix>/lib/cmake/cms/cmsConfigVersion.cmake   SameMinorVersion (0.x: minor
#                                                   versions may break the API)
#   <prefix>/lib/cmake/cms/cmsTargets[-release].cmake  cms::cms, cms::<package>
#   <prefix>/lib/cmake/cms/Find{CHOLMOD,MUMPS,ARPACK,Gmsh}.cmake  for find_dependency
include_guard(GLOBAL)
include(CMakePackageConfigHelpers)
include(GNUInstallDirs)

set(CMS_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/cms")
set(CMS_INSTALL_DATADIR "${CMAKE_INSTALL_DATADIR}/cms")

if(BUILD_SHARED_LIBS)
  set(CMS_LIBRARY_KIND shared)
else()
  set(CMS_LIBRARY_KIND static)
endif()
get_property(_deps GLOBAL PROPERTY CMS_CONFIG_DEPENDENCIES)
list(REMOVE_DUPLICATES _deps)
string(REPLACE ";" "\n" CMS_CONFIG_DEPENDENCIES "${_deps}")
string(REPLACE ";" " " CMS_TRILINOS_COMPONENTS "${CMS_TRILINOS_COMPONENTS}")
get_property(_targets GLOBAL PROPERTY CMS_PACKAGE_TARGETS)
string(REGEX REPLACE "(^|;)cms_" "\\1" CMS_PACKAGE_NAMES "${_targets}")
string(REPLACE ";" " " CMS_PACKAGE_NAMES "${CMS_PACKAGE_NAMES}")

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/cmsConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/cmake/cmsConfig.cmake
                              INSTALL_DESTINATION ${CMS_INSTALL_CMAKEDIR}
                              PATH_VARS CMS_INSTALL_DATADIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cmake/cmsConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(EXPORT cmsTargets NAMESPACE cms:: DESTINATION ${CMS_INSTALL_CMAKEDIR})
install(FILES ${PROJECT_BINARY_DIR}/cmake/cmsConfig.cmake ${PROJECT_BINARY_DIR}/cmake/cmsConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindCHOLMOD.cmake ${PROJECT_SOURCE_DIR}/cmake/FindMUMPS.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindARPACK.cmake ${PROJECT_SOURCE_DIR}/cmake/FindSCOTCH.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindGmsh.cmake
        DESTINATION ${CMS_INSTALL_CMAKEDIR})
