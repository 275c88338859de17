# examples_against_install: cms used the way a user uses it.
#   1. cmake --install the build tree to a fresh prefix outside the sources;
#   2. check the layout: headers, libraries, cmsConfig*.cmake, drivers, data;
#   3. configure examples/ as a project of its own (find_package(cms),
#      cms::cms), build ex1_spacecraft and run it;
#   4. run the installed `cms modes` with no scene from a directory outside
#      the source tree: the default scene must come from <prefix>/share/cms;
#   5. the installed cms meshes a .geo scene with the installed helper
#      (<prefix>/libexec/cms/cms-geo-mesher, found from <prefix>/bin/cms);
#   6. no path of the source or build tree in the installed cms nor in
#      libcms_mesh (file(STRINGS), as `strings` would show it): the .geo
#      mesher is found relative to the running program, not compiled in.
# Arguments: -DBUILD_DIR -DSOURCE_DIR -DWORK_DIR -DCXX [-DLAUNCHER] [-DBUILD_TYPE]
foreach(v BUILD_DIR SOURCE_DIR WORK_DIR CXX)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "InstallTest.cmake: -D${v}=... is required")
  endif()
endforeach()
string(FIND "${WORK_DIR}/" "${SOURCE_DIR}/" inside)
if(inside EQUAL 0)
  message(FATAL_ERROR "WORK_DIR ${WORK_DIR} must be outside the source tree ${SOURCE_DIR}")
endif()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err ${RUN_OPTIONS})
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${ARGN}\n${out}\n${err}")
  endif()
  set(RUN_OUTPUT "${out}" PARENT_SCOPE)
  message(STATUS "${what}: ok")
endfunction()

set(prefix "${WORK_DIR}/prefix")
file(REMOVE_RECURSE "${prefix}" "${WORK_DIR}/run" "${WORK_DIR}/examples")
file(MAKE_DIRECTORY "${WORK_DIR}/run")
# Nothing may lead the installed programs to the sources but the install itself.
unset(ENV{CMS_DATA_DIR})
unset(ENV{CMS_GEO_MESHER})

# 1. Install.
run("cmake --install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")

# 2. The layout (doc/architecture.md, "Install layout").
foreach(f include/cms/core/Error.hpp include/cms/scene/Scene.hpp include/cms/synthesis/SynthesizedStructure.hpp
          lib/libcms_core.a lib/cmake/cms/cmsConfig.cmake lib/cmake/cms/cmsConfigVersion.cmake
          lib/cmake/cms/cmsTargets.cmake lib/cmake/cms/FindCHOLMOD.cmake
          bin/cms bin/campbell libexec/cms/cms-geo-mesher
          share/cms/scenes/spacecraft.yaml share/cms/scenes/meshes/blade.geo share/cms/plot_results.py
          share/cms/bench/rotor/rotor.yaml share/cms/bench/blade_hex.geo)
  if(NOT EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "not installed: ${prefix}/${f}")
  endif()
endforeach()
message(STATUS "layout: ok")

# 3. The examples as a project of their own, against the installed package.
set(configure ${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples" -B "${WORK_DIR}/examples"
              "-DCMAKE_PREFIX_PATH=${prefix}" "-DCMAKE_CXX_COMPILER=${CXX}")
if(LAUNCHER)
  list(APPEND configure "-DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}")
endif()
if(BUILD_TYPE)
  list(APPEND configure "-DCMAKE_BUILD_TYPE=${BUILD_TYPE}")
endif()
run("configure examples/ with find_package(cms)" ${configure})
run("build ex1_spacecraft" ${CMAKE_COMMAND} --build "${WORK_DIR}/examples" --target ex1_spacecraft -j 2)
set(RUN_OPTIONS WORKING_DIRECTORY "${WORK_DIR}/run")
run("run ex1_spacecraft" "${WORK_DIR}/examples/ex1_spacecraft" --modes=6)
if(NOT RUN_OUTPUT MATCHES "status: converged")
  message(FATAL_ERROR "ex1_spacecraft did not report a converged solve:\n${RUN_OUTPUT}")
endif()

# 4. The installed cms, default scene, from outside the source tree.
run("installed cms modes (no scene)" "${prefix}/bin/cms" modes)
if(NOT RUN_OUTPUT MATCHES "spacecraft" OR NOT EXISTS "${WORK_DIR}/run/cms-results/spacecraft.json")
  message(FATAL_ERROR "the installed cms did not run the default spacecraft scene:\n${RUN_OUTPUT}")
endif()

# 5. A .geo scene: meshed by the installed helper, which nothing but the
#    install layout leads to (coarse mesh: this checks the lookup, not Gmsh).
run("installed cms modes on a .geo scene" "${prefix}/bin/cms" modes "${prefix}/share/cms/scenes/solid-blade.yaml"
    --mesh-parameters=h=0.05 --output=geo-results)
if(NOT RUN_OUTPUT MATCHES "solid-blade")
  message(FATAL_ERROR "the installed cms did not run the .geo scene:\n${RUN_OUTPUT}")
endif()

# 6. No source or build path compiled into the installed cms or libcms_mesh.
file(GLOB mesh_library "${prefix}/lib*/libcms_mesh.*")
if(NOT mesh_library)
  message(FATAL_ERROR "not installed: ${prefix}/lib/libcms_mesh.*")
endif()
foreach(binary "${prefix}/bin/cms" ${mesh_library})
  file(STRINGS "${binary}" paths REGEX "/")
  set(leaks "")
  foreach(s IN LISTS paths)
    foreach(tree "${SOURCE_DIR}/" "${BUILD_DIR}/")
      string(FIND "${s}" "${tree}" at)
      if(at GREATER_EQUAL 0)
        list(APPEND leaks "${s}")
      endif()
    endforeach()
  endforeach()
  if(leaks)
    list(REMOVE_DUPLICATES leaks)
    message(FATAL_ERROR "source or build paths compiled into ${binary}:\n${leaks}")
  endif()
endforeach()
message(STATUS "no source or build path in the installed cms and libcms_mesh: ok")
file(REMOVE_RECURSE "${prefix}" "${WORK_DIR}/run")
