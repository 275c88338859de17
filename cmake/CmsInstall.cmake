# CmsInstall
# ----------
# How a package library becomes part of the installed, exported cms package
# (doc/architecture.md, "Install layout"; doc/user-guide.md, "Use cms from
# your own project").
#
#   cms_package(cms_<name>)
#
# called in packages/<name>/CMakeLists.txt after add_library and its
# target_include_directories, which must be
#   target_include_directories(cms_<name> PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
#                                                $<INSTALL_INTERFACE:include>)
# (packages/<name>/include while building, <prefix>/include once installed):
#   - exports the library as cms::<name> (EXPORT_NAME <name>), with the same
#     name as an alias in the build tree, so in-tree code and a user's
#     project write the same target_link_libraries;
#   - installs the library and the package's include/ tree (include/cms/<name>);
#   - compiles it with __FILE__ relative to the source tree (below);
#   - records it in the global property CMS_PACKAGE_TARGETS, from which the
#     top-level CMakeLists.txt makes cms::cms, the target linking them all.
include_guard(GLOBAL)
include(GNUInstallDirs)
include(CheckCXXCompilerFlag)

#   cms_relative_file_macros(<target>)
#
# __FILE__ relative to the source tree (packages/eigen/src/X.cpp), so that
# the installed binaries hold no path of the sources: Teuchos' exception
# macros (TEUCHOS_TEST_FOR_EXCEPTION) put __FILE__ into every message.
check_cxx_compiler_flag("-fmacro-prefix-map=/a=b" CMS_HAVE_MACRO_PREFIX_MAP)
function(cms_relative_file_macros target)
  if(CMS_HAVE_MACRO_PREFIX_MAP)
    target_compile_options(${target} PRIVATE "-fmacro-prefix-map=${PROJECT_SOURCE_DIR}/=")
  endif()
endfunction()

function(cms_package target)
  string(REGEX REPLACE "^cms_" "" name "${target}")
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  cms_relative_file_macros(${target})
  add_library(cms::${name} ALIAS ${target})
  install(TARGETS ${target} EXPORT cmsTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  if(EXISTS "${CMAKE_CURRENT_SOURCE_DIR}/include")
    install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
  set_property(GLOBAL APPEND PROPERTY CMS_PACKAGE_TARGETS ${target})
endfunction()

#   cms_export_dependency(<find_package arguments>)
#
# a package found by find_package that the exported targets need (in their
# link interface, even privately: the libraries are static by default), so
# that cmsConfig.cmake finds it with find_dependency(<arguments>).
function(cms_export_dependency)
  string(REPLACE ";" " " args "${ARGN}")
  set_property(GLOBAL APPEND PROPERTY CMS_CONFIG_DEPENDENCIES "find_dependency(${args})")
endfunction()
